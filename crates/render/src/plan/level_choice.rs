//! The mip level a piece is drawn at, decided from its projected box
//! before any node is projected: for whole patches the coarsest level whose
//! estimated cell extent stays below
//! [`RenderOptions::mip_limit`](crate::RenderOptions::mip_limit) (or its
//! splat and pixel-centre variants), then the levels past it that
//! [`RenderOptions::mip_tolerance`] and
//! [`RenderOptions::level_one_limit`] allow, and the shading level under
//! [`RenderOptions::geometry_limit`](crate::RenderOptions::geometry_limit).
//!
//! Cost: O(1) per piece (eight projected box corners; four more for the
//! tolerances).

use glam::Vec3;

use crate::options::{CellScheme, RenderOptions, Shading};
use crate::plan::project::Projector;
use crate::plan::split::NodeRange;
use crate::plan::work::PatchContext;
use crate::prepare::patch::{PreparedPatch, QUARTERED_ONE};

/// The levels a piece is planned with.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LevelChoice {
    /// The level whose nodes are drawn.
    pub(crate) m: usize,
    /// 1 when the level below `m` shades (coarse geometry, or a lifted
    /// patch with node colours), else 0.
    pub(crate) shift: usize,
    /// The level the mip limit alone chose when the tolerance went past
    /// it, else `usize::MAX`.
    pub(crate) lifted: usize,
    /// Level 1 taken past the limit, its outline kept by quarters.
    pub(crate) quartered_lift: bool,
}

impl LevelChoice {
    /// The level the draw item names: `m`, or [`QUARTERED_ONE`] for level
    /// 1 with its outline by quarters.
    #[inline(always)]
    pub(crate) fn named(&self) -> usize {
        if self.quartered_lift {
            QUARTERED_ONE
        } else {
            self.m
        }
    }
}

/// The levels of `piece` of the patch of `ctx` (`proj0` its level-0
/// projection), with or without the levels past the mip limit (`lift`).
#[inline(always)]
pub(crate) fn choose_level(
    ctx: &PatchContext<'_>,
    proj0: &Projector,
    piece: NodeRange,
    lift: bool,
) -> LevelChoice {
    let (p, opts) = (ctx.patch, ctx.setup.options);
    let (mut m, mut shift) = (0, 0);
    // Level 1 taken past the limit, its outline kept by quarters.
    let mut quartered_lift = false;
    // The level the mip limit alone chose, when the tolerance went past it.
    let mut lifted = usize::MAX;
    if ctx.whole && opts.mip && p.level_count() > 1 {
        let extent = estimate_extent(proj0, piece, p.base_d_range());
        m = coarsest_level_within(p.level_count(), extent, extent_limit(opts));
        // Only from level 0: the bunny's 26 pieces that went from level 1
        // to levels 2-3 cost 0.7 % more per 500² frame (larger cuts).
        if lift && m == 0 {
            if let Some((past, by_quarters)) = lift_past_limit(ctx, proj0, piece, extent) {
                (m, lifted, quartered_lift) = (past, 0, by_quarters);
            }
        }
        if !quartered_lift {
            shift = coarse_geometry_shift(opts, p, extent, m);
        }
    }
    // A lifted patch with node colours is shaded from level 0 (Phong reads
    // level 0's normals and colours at the samples' places, as coarse
    // geometry does): level 1's colours are averages over twice the span
    // (the mannequin at 500²: 25.78 → 26.37 dB, frame 0.79 → 0.85 of the
    // default's). Uncoloured ones keep level 1's normals (the bunny at
    // 1000²: 27.67 dB, 27.34 from level 0's).
    if quartered_lift && opts.shading == Shading::Phong && p.has_node_colours() {
        shift = 1;
    }
    let m = if quartered_lift { 1 } else { m + shift };
    LevelChoice {
        m,
        shift,
        lifted,
        quartered_lift,
    }
}

/// The largest estimated cell extent (pixels) a level may have to be drawn
/// without subdivision: the mip limit, or the splat path's or the
/// pixel-centre cells' reach when larger. Why the splat path's: it covers
/// cells whose extent (the max-norm sum of their edges) is up to twice
/// its half-width, so a level whose nodes still land within that reach
/// needs no subdivision.
#[inline(always)]
fn extent_limit(opts: &RenderOptions) -> f32 {
    if opts.splat_limit > 0.0 && opts.cells == CellScheme::Bilinear {
        opts.mip_limit.max(2.0 * opts.splat_limit)
    } else if centre_cells(opts) {
        opts.mip_limit.max(opts.centre_limit)
    } else {
        opts.mip_limit
    }
}

/// The coarsest of `levels` levels whose cells stay under `limit` pixels,
/// level 0's measuring `extent` (each level doubles it).
#[inline(always)]
fn coarsest_level_within(levels: usize, extent: f32, limit: f32) -> usize {
    let mut m = 0;
    while m + 1 < levels && extent * ((1u32 << (m + 1)) as f32) < limit {
        m += 1;
    }
    m
}

/// The level past the mip limit a whole patch drawn at level 0 (its cells
/// measuring `extent` pixels) may take, and whether by quarters: a coarser
/// exact level within [`RenderOptions::mip_tolerance`], else level 1 by
/// quarters within [`RenderOptions::level_one_limit`] (`None`: level 0
/// stays).
#[inline(always)]
fn lift_past_limit(
    ctx: &PatchContext<'_>,
    proj0: &Projector,
    piece: NodeRange,
    extent: f32,
) -> Option<(usize, bool)> {
    let (p, opts) = (ctx.patch, ctx.setup.options);
    if exact_levels(opts) {
        let coarser = coarser_exact_level(ctx, proj0, piece, extent, 0);
        if coarser > 0 {
            return Some((coarser, false));
        }
    }
    if quarter_lift(opts, p) && extent * 2.0 < opts.level_one_limit {
        let gaps = p.quartered_gaps();
        let scale = pixels_per_code(proj0, piece, p.base_d_range());
        if gaps.rms * scale <= LEVEL_ONE_TOLERANCE && gaps.most * scale <= LEVEL_ONE_MOST {
            return Some((1, true));
        }
    }
    None
}

/// Coarse geometry ([`RenderOptions::geometry_limit`]): 1 when the level
/// above `m` draws and `m` shades (its cells, measuring `extent` pixels at
/// level 0, near enough and the coarser level within
/// [`RenderOptions::geometry_tolerance`]), else 0.
#[inline(always)]
fn coarse_geometry_shift(opts: &RenderOptions, p: &PreparedPatch, extent: f32, m: usize) -> usize {
    if !coarse_geometry(opts) || m + 1 >= p.level_count() {
        return 0;
    }
    let near = extent * ((2u32 << m) as f32) < opts.geometry_limit;
    let tol = opts.geometry_tolerance;
    (near && (tol == 0.0 || p.coarse_error(m + 1) <= tol)) as usize
}

/// Whether the patch `p` may take level 1 past the mip limit, its
/// outline kept by quarters ([`RenderOptions::level_one_limit`]): the
/// limit set above the mip limit, bilinear cells drawn by sub-nodes (no
/// splats, pixel-centre cells or gap fill, whose drawers do not draw by
/// quarters), no colour grid (drawn by pixel centres), and node colours
/// only under Phong, which shades a lifted patch from level 0. Why: flat,
/// Gouraud and unlit shading interpolate the drawn level's colours, and
/// level 1's are averages over twice the span (a checkerboard of node
/// colours seen unlit, 24.51 → 20.77 dB).
fn quarter_lift(opts: &RenderOptions, p: &PreparedPatch) -> bool {
    opts.level_one_limit > opts.mip_limit
        && opts.cells == CellScheme::Bilinear
        && opts.splat_limit == 0.0
        && !centre_cells(opts)
        && !opts.fills_gaps()
        && p.colour_grid.is_none()
        && (opts.shading == Shading::Phong || !p.has_node_colours())
}

/// How far (pixels, root mean square over level 0's nodes) level 1 drawn
/// by quarters may move a patch's surface for
/// [`RenderOptions::level_one_limit`] to lift it. Why 0.25 px and the mean:
/// the largest distance is a scan's noise (bound as `--mip-tolerance`
/// bounds it, it kept every bunny patch at level 0), so the mean bounds
/// the surface's move and [`LEVEL_ONE_MOST`] only what level 1 cuts
/// off; with both, 1,564 of the bunny's 1,884 pieces at 1000² lift
/// (without a test fandisk scored 2.65 dB lower; docs/algorithms/render.md,
/// "Level 1 past the limit").
const LEVEL_ONE_TOLERANCE: f32 = 0.25;

/// How far (pixels) level 1 drawn by quarters may move all but the
/// farthest 2 % of level 0's nodes
/// ([`Gaps::most`](crate::prepare::coarse_fit::Gaps::most)) for
/// [`RenderOptions::level_one_limit`] to lift the patch. Why: the mean
/// alone lifted fandisk's patches whose creases level 1 cuts off, and its
/// holes at 500² went 0.020 → 0.080 %; with this bound 0.021 %. Why not the
/// largest distance: a scan's scattered noise then kept 494 of the bunny's
/// 1,884 pieces at 1000² at level 0 (315 with this one; fandisk's holes
/// the same 0.020 %).
const LEVEL_ONE_MOST: f32 = 0.5;

/// Whether whole patches with exact levels may go past the mip limit
/// ([`RenderOptions::mip_tolerance`]): bilinear cells drawn by sub-nodes
/// (no splats, no pixel-centre cells).
fn exact_levels(opts: &RenderOptions) -> bool {
    opts.mip_tolerance > 0.0
        && opts.cells == CellScheme::Bilinear
        && opts.splat_limit == 0.0
        && !centre_cells(opts)
}

/// The coarsest level from `m` up that the patch of `ctx`, whose level-0
/// cells measure `extent` pixels on screen, may draw under
/// [`RenderOptions::mip_tolerance`]: while the next level keeps the
/// outline exactly ([`PreparedPatch::exact_level`](crate::prepare::patch::PreparedPatch::exact_level)),
/// its cells stay within [`RenderOptions::EXACT_LEVEL_CAP`] times the mip
/// limit, and its gap moves the surface by at most the tolerance on screen.
fn coarser_exact_level(
    ctx: &PatchContext<'_>,
    proj: &Projector,
    piece: NodeRange,
    extent: f32,
    mut m: usize,
) -> usize {
    let (p, opts) = (ctx.patch, ctx.setup.options);
    // A coarser level's colours are averages over twice the span: the
    // tolerance measures geometry only, so coloured patches keep theirs.
    if p.colour_grid.is_some() || p.has_node_colours() {
        return m;
    }
    let cap = RenderOptions::EXACT_LEVEL_CAP * opts.mip_limit;
    let mut per_code = None;
    while m + 1 < p.level_count()
        && extent * ((1u32 << (m + 1)) as f32) < cap
        && p.exact_level(m + 1)
    {
        let scale = *per_code.get_or_insert_with(|| pixels_per_code(proj, piece, p.base_d_range()));
        if p.coarse_gap(m + 1) * scale > opts.mip_tolerance {
            break;
        }
        m += 1;
    }
    m
}

/// How far (pixels, the larger screen axis, largest over the four lower
/// corners of the piece's box) one displacement code moves a point of
/// the piece on screen. Why 64 codes and a division: a one-code step is
/// lost in the rounding of screen coordinates.
fn pixels_per_code(proj: &Projector, range: NodeRange, d: (u16, u16)) -> f32 {
    const STEP: f32 = 64.0;
    let (lo, hi) = range.local_box(d);
    let mut worst = 0f32;
    for k in 0..4 {
        let c = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            lo.z,
        );
        let (a, b) = (proj.screen(c), proj.screen(c + Vec3::new(0.0, 0.0, STEP)));
        worst = worst.max((b.x - a.x).abs().max((b.y - a.y).abs()));
    }
    worst / STEP
}

/// Whether pixel-sized bilinear cells are drawn by pixel-centre coverage
/// ([`RenderOptions::centre_limit`]; not with splats or smooth cells).
pub(crate) fn centre_cells(opts: &RenderOptions) -> bool {
    opts.centre_limit > 0.0 && opts.cells == CellScheme::Bilinear && opts.splat_limit == 0.0
}

/// Whether whole patches may draw the level above their shading level
/// ([`RenderOptions::geometry_limit`]): Phong (the resolve pass
/// interpolates the shading level's normals), bilinear cells, no splats.
fn coarse_geometry(opts: &RenderOptions) -> bool {
    opts.geometry_limit > 0.0
        && opts.shading == Shading::Phong
        && opts.cells == CellScheme::Bilinear
        && opts.splat_limit == 0.0
}

/// Estimated level-0 cell extent in pixels from the projected box corners.
#[inline(always)]
fn estimate_extent(proj: &Projector, range: NodeRange, d: (u16, u16)) -> f32 {
    let (lo, hi) = range.local_box(d);
    let c: [Vec3; 8] = std::array::from_fn(|k| {
        proj.screen(Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        ))
    });
    let (ci, cj) = ((range.i1 - range.i0) as f32, (range.j1 - range.j0) as f32);
    let (mut ux, mut uy, mut vx, mut vy) = (0f32, 0f32, 0f32, 0f32);
    for k in 0..8 {
        if k & 1 == 0 {
            let e = c[k + 1] - c[k];
            ux = ux.max(e.x.abs() / ci);
            uy = uy.max(e.y.abs() / ci);
        }
        if k & 2 == 0 {
            let e = c[k + 2] - c[k];
            vx = vx.max(e.x.abs() / cj);
            vy = vy.max(e.y.abs() / cj);
        }
    }
    (ux + vx).max(uy + vy)
}
