//! Which drawer takes a planned piece, from its cut, its patch and the
//! options: sub-nodes, open sides, exact outlines, pixel centres or
//! splats; and the cut the gap fill draws instead.
//!
//! Cost: O(1) per piece.

use crate::fixed::XY_ONE;
use crate::options::RenderOptions;
use crate::plan::level_choice::centre_cells;
use crate::plan::measure::CellMeasure;
use crate::plan::open_sides::{exact_outlines, OPEN_SIDE_CUT};
use crate::plan::subdivision::{choose_subdivision, GAP_FILL_LIMIT};
use crate::prepare::mip::MipLevel;
use crate::prepare::patch::PreparedPatch;
use crate::raster::centre_piece::CentreStyle;
use crate::raster::splat::footprint_half_widths;

/// Which drawer takes a piece cut `nu × nv` (see [`choose_drawer`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Drawer {
    /// Bilinear cells drawn by sub-nodes or pixel centres (not smooth, not
    /// splatted).
    pub(crate) bilinear: bool,
    /// Drawn by pixel-centre coverage, and how.
    pub(crate) centres: Option<CentreStyle>,
    /// Sub-quads with exact outlines (`--exact-outlines`).
    pub(crate) exact: bool,
    /// Sub-nodes with exact outlines where the surface folds away.
    pub(crate) open_sides: bool,
}

/// The drawer of a piece of `level` of patch `p` cut `nu × nv`
/// (`smooth` cells, `splat` footprint, `measure` its cells). Outlines of
/// magnified cells are drawn exactly where the surface folds away (see
/// `open_sides` and `raster::cell_edges`); the cells of patches with a
/// colour grid by pixel-centre coverage (`raster::centre_piece`), or by
/// sub-quads (`raster::cell_exact`) with `--exact-outlines`, which also
/// takes the other coloured ones.
#[inline(always)]
pub(crate) fn choose_drawer(
    opts: &RenderOptions,
    p: &PreparedPatch,
    level: &MipLevel,
    (smooth, splat): (bool, [i32; 2]),
    (nu, nv): (u32, u32),
    measure: &CellMeasure,
) -> Drawer {
    let bilinear = !smooth && splat[0] == 0;
    let grid_centres = opts.exact_grid_outlines
        && !opts.exact_outlines
        && p.colour_grid.is_some()
        && nu.max(nv) >= GRID_EXACT_CUT;
    let centres = if !bilinear || (nu, nv) == (1, 1) {
        None
    } else if centre_cells(opts) && nu.max(nv) <= CENTRE_CUT {
        Some(CentreStyle::Cells)
    } else if grid_centres {
        Some(CentreStyle::Grid)
    } else {
        None
    };
    let exact = bilinear
        && centres.is_none()
        && opts.exact_outlines
        && (nu, nv) != (1, 1)
        && exact_outlines(level);
    let open_sides = exact
        || (bilinear
            && centres.is_none()
            && nu.max(nv) > OPEN_SIDE_CUT
            && measure.backfacing_cells > 0);
    Drawer {
        bilinear,
        centres,
        exact,
        open_sides,
    }
}

/// The cut of a piece the gap fill (`raster::gap_fill`) draws: plain
/// sub-node pieces (`drawer`) leave it small gaps, cut under
/// [`GAP_FILL_LIMIT`] instead of `cut` (about half the samples on
/// magnified cells). The other drawers keep their own coverage, and so do
/// pieces not `inside` the image's columns by the fill's reach: past the
/// image no sample is drawn to close a gap against.
#[inline(always)]
pub(crate) fn gap_fill_cut(
    opts: &RenderOptions,
    drawer: &Drawer,
    inside: bool,
    edges: [f32; 4],
    cut: (u32, u32),
) -> (u32, u32) {
    let plain = drawer.bilinear && drawer.centres.is_none() && !drawer.open_sides;
    if plain && inside && opts.fills_gaps() {
        choose_subdivision(edges, GAP_FILL_LIMIT).unwrap_or(cut)
    } else {
        cut
    }
}

/// The footprint half-widths (position units) with which the nodes of a
/// piece whose cells have the largest edges `edges` cover them, when the
/// splatting path draws it (bilinear cells the nodes alone do not cover,
/// within [`RenderOptions::splat_limit`]); `[0, 0]` otherwise.
pub(crate) fn splat_footprint(
    opts: &RenderOptions,
    smooth: bool,
    split: Option<(u32, u32)>,
    edges: [f32; 4],
) -> [i32; 2] {
    if smooth || opts.splat_limit == 0.0 || split == Some((1, 1)) {
        return [0, 0];
    }
    let half = footprint_half_widths(edges);
    let limit = opts.splat_limit * XY_ONE;
    if half[0] as f32 > limit || half[1] as f32 > limit {
        return [0, 0];
    }
    half
}

/// Least cut per side of the pieces of a patch with a colour grid drawn by
/// pixel-centre coverage under [`RenderOptions::exact_grid_outlines`]. Why 4:
/// fuze (unlit, 14 views) 30.26 dB from a cut of 2, 29.95 dB from 6; pieces
/// cut 2-3 cost the drawer most (docs/algorithms/render.md).
const GRID_EXACT_CUT: u32 = 4;

/// Largest cut per side (of the sub-node path) of pieces drawn by
/// pixel-centre coverage when [`RenderOptions::centre_limit`] is on:
/// cells of up to about 4 px; larger cells keep sub-nodes.
const CENTRE_CUT: u32 = 4;
