//! One piece of a patch, planned: everything about it decided before any
//! pixel is touched.
//!
//! 1. mip level: for whole patches, the coarsest level whose estimated cell
//!    extent (from the projected box) stays below
//!    [`RenderOptions::mip_limit`](crate::RenderOptions::mip_limit) pixels
//!    ([`crate::prepare::mip`]), or coarser for full grids whose coarser
//!    levels move the surface by at most
//!    [`RenderOptions::mip_tolerance`](crate::RenderOptions::mip_tolerance);
//! 2. node traversal ([`crate::plan::project`]): trilinear or exact, into
//!    the chunk's flat array of fixed-point nodes, then the cell
//!    measurement ([`crate::plan::measure`]);
//! 3. subdivision `nu × nv` from the largest projected cell edges
//!    ([`crate::plan::subdivision`]); `1 × 1` selects the node-placing
//!    path, pixel-sized cells the splat path ([`crate::raster::splat`]),
//!    cells too large the triangle path;
//! 4. per-node attributes ([`crate::plan::attributes`]).
//!
//! Cost: O(nodes of the piece).

use glam::Vec3;

use crate::fixed::{XY_FRAC_BITS, XY_ONE};
use crate::options::{CellScheme, Projection, RenderMode, RenderOptions, Shading};
use crate::plan::attributes::fill_attributes;
use crate::plan::cell_triangles::emit_cell_triangles;
use crate::plan::measure::measure_cells;
use crate::plan::open_sides::{exact_outlines, mark_exact_cells, mark_open_sides, OPEN_SIDE_CUT};
use crate::plan::project::{
    level_map, nearest_box_depth, project_nodes_exact, project_nodes_trilinear, Projector,
};
use crate::plan::quartered::{drop_quartered_corners, gather_quartered};
use crate::plan::split::NodeRange;
use crate::plan::subdivision::{choose_subdivision, GAP_FILL_LIMIT, SMOOTH_MARGIN, SUBPIXEL_LIMIT};
use crate::plan::work::{ChunkWork, Item, PatchContext, QuarteredRange};
use crate::prepare::mip::MipLevel;
use crate::prepare::patch::{PreparedPatch, QUARTERED_ONE};
use crate::raster::cell_centres::CENTRE_STEPS;
use crate::raster::centre_piece::CentreStyle;
use crate::raster::gap_fill::GAP_FILL_REACH;
use crate::raster::splat::{drop_undrawn_nodes, footprint_half_widths};

/// Plans one piece of the patch of `ctx`: its mip level, its nodes'
/// traversal and cell measurement, its subdivision (or the splat or
/// triangle path), its attributes, and pushes its draw item to `work`
/// (nothing when no cell is drawn or it lies outside the image's rows).
/// Why inlined: its one caller, [`plan_chunk`](crate::plan::chunk::plan_chunk),
/// kept it inline until the coarse-geometry choice made it longer
/// (0.1 M instructions per bunny frame; callgrind, 500²); always, so that
/// it runs in the chunk's instruction set ([`crate::isa`]).
#[inline(always)]
pub(crate) fn plan_piece(work: &mut ChunkWork, ctx: &PatchContext<'_>, piece: NodeRange) {
    plan_piece_with(work, ctx, piece, true);
}

/// Drops a piece planned at a level `m` past the mip limit (`marks` as
/// for [`drop_planned`]; `backfacing` its cells counted as facing away)
/// and plans it again with [`plan_piece_with`] without those levels: the
/// rare piece lifted too far, or lifted by quarters where a drawer without
/// quarters would take it. Why out of line: a call back into the inlined
/// planner kept the compiler from laying out its common path as before
/// (bunny 500²: 45.5 → 47.1 M instructions per frame).
#[inline(never)]
#[cold]
fn replan_unlifted(
    work: &mut ChunkWork,
    ctx: &PatchContext<'_>,
    piece: NodeRange,
    (marks, m, backfacing): ([usize; 4], usize, u64),
) {
    drop_planned(work, marks);
    work.counters.mip[m] -= 1;
    work.counters.cells_backface -= backfacing;
    work.counters.traverse_ns += work.clock.lap();
    plan_piece_with(work, ctx, piece, false);
}

/// [`plan_piece`], with or without the levels past the mip limit that
/// [`RenderOptions::mip_tolerance`] allows (`lift`). A piece lifted so far
/// that its cells need the triangle path is planned again without: the
/// box's estimate of its cells is an average, and a near patch's largest
/// cells exceed it.
#[inline(always)]
fn plan_piece_with(work: &mut ChunkWork, ctx: &PatchContext<'_>, piece: NodeRange, lift: bool) {
    let (p, setup, whole, cell_test) = (ctx.patch, ctx.setup, ctx.whole, ctx.cell_test);
    let opts = setup.options;
    let proj0 = Projector {
        map: ctx.map,
        t0: ctx.t0,
        z_scale: setup.z_scale,
        z_offset: setup.z_offset,
    };
    if opts.mode == RenderMode::Triangles {
        emit_cell_triangles(work, ctx, 0, piece, None);
        work.counters.setup_ns += work.clock.lap();
        work.counters.mip[0] += 1;
        return;
    }
    // 2. Mip level.
    // (Stage timers: what follows is charged to traversal at its laps.)
    let (mut m, mut shift) = (0, 0);
    // Level 1 taken past the limit, its outline kept by quarters.
    let mut quartered_lift = false;
    // The level the mip limit alone chose, when the tolerance went past it.
    let mut lifted = usize::MAX;
    if whole && opts.mip && p.level_count() > 1 {
        let extent = estimate_extent(&proj0, piece, p.base_d_range());
        // The splat path covers cells whose extent (the max-norm sum of
        // their edges) is up to twice its half-width: a level whose nodes
        // still land within that reach needs no subdivision.
        let limit = if opts.splat_limit > 0.0 && opts.cells == CellScheme::Bilinear {
            opts.mip_limit.max(2.0 * opts.splat_limit)
        } else if centre_cells(opts) {
            opts.mip_limit.max(opts.centre_limit)
        } else {
            opts.mip_limit
        };
        while m + 1 < p.level_count() && extent * ((1u32 << (m + 1)) as f32) < limit {
            m += 1;
        }
        // Only from level 0: the bunny's 26 pieces that went from level 1
        // to levels 2-3 cost 0.7 % more per 500² frame (larger cuts).
        if lift && exact_levels(opts) && m == 0 {
            let coarser = coarser_exact_level(ctx, &proj0, piece, extent, m);
            if coarser > m {
                (m, lifted) = (coarser, m);
            }
        }
        if lift && m == 0 && quarter_lift(opts, p) && extent * 2.0 < opts.level_one_limit {
            let gaps = p.quartered_gaps();
            let scale = pixels_per_code(&proj0, piece, p.base_d_range());
            if gaps.rms * scale <= LEVEL_ONE_TOLERANCE && gaps.most * scale <= LEVEL_ONE_MOST {
                (m, lifted, quartered_lift) = (1, 0, true);
            }
        }
        // Coarse geometry: the level above draws, this one shades.
        if coarse_geometry(opts) && !quartered_lift && m + 1 < p.level_count() {
            let near = extent * ((2u32 << m) as f32) < opts.geometry_limit;
            let tol = opts.geometry_tolerance;
            shift = (near && (tol == 0.0 || p.coarse_error(m + 1) <= tol)) as usize;
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
    // The level the item names: level 1 with its outline by quarters when
    // lifted so.
    let named = if quartered_lift { QUARTERED_ONE } else { m };
    let level = p.level(named);
    let range = if m == 0 {
        piece
    } else {
        NodeRange::whole(level)
    };
    let Some(d) = range.d_range(level) else {
        return;
    };
    work.counters.mip[m] += 1;
    // 3. Traversal.
    let proj = Projector {
        map: level_map(&ctx.map, m),
        ..proj0
    };
    let first = work.nodes.len();
    // Why exact past TRILINEAR_LIMIT_PX: a textured box's faces seen at a
    // slant (cells of 40-60 px in the eval's views, errors of about 25 px)
    // were drawn far from their depth, 2.9 % of the pixels behind the
    // source (`trilinear_error`).
    let trilinear = opts.projection == Projection::Trilinear
        && trilinear_error(&proj, range, d) <= TRILINEAR_LIMIT_PX;
    if trilinear {
        project_nodes_trilinear(level, range, d, &proj, &mut work.nodes, &mut work.xy)
    } else {
        project_nodes_exact(level, range, &proj, &mut work.nodes, &mut work.xy)
    }
    let (cols, rows) = (range.i1 - range.i0 + 1, range.j1 - range.j0 + 1);
    // 4. Subdivision.
    let smooth = opts.cells == CellScheme::Smooth;
    // Back faces of bilinear cells are skipped per cell (a Catmull-Rom cell
    // is not bounded by its corners, so smooth cells keep them). Why: 12 %
    // of the sphere's samples were on cells facing away (callgrind,
    // `profile_sphere 500 1`).
    let det = proj.map.determinant();
    let back_sign = if cell_test && !smooth && det != 0.0 {
        if det > 0.0 {
            1
        } else {
            -1
        }
    } else {
        0
    };
    let flags = work.cell_flags.len();
    let spans = work.row_spans.len();
    let measure = measure_cells(
        level,
        range,
        &mut work.xy,
        back_sign,
        &mut work.cell_flags,
        &mut work.row_spans,
    );
    work.counters.cells_backface += measure.backfacing_cells;
    // A lifted piece's cells by quarters: the cut covers them too.
    let quarters = work.quartered.len();
    let edges = if quartered_lift {
        widen_by_quartered(work, level, cols, back_sign, measure.edges)
    } else {
        measure.edges
    };
    let edges = edges.map(|e| e as f32 / XY_ONE);
    let mut split = choose_subdivision(edges, SUBPIXEL_LIMIT);
    if smooth && split != Some((1, 1)) {
        split = choose_subdivision(edges, SUBPIXEL_LIMIT / SMOOTH_MARGIN);
    }
    let splat = splat_footprint(opts, smooth, split, edges);
    if splat[0] > 0 {
        split = Some((1, 1));
    }
    if !smooth && split.is_some_and(|(nu, nv)| nu.max(nv) > TRIANGLE_CUT) {
        split = None;
    }
    let height = setup.view.height as i32;
    let [x0, y0, x1, y1] = measure.bbox;
    let pad = if smooth {
        2
    } else {
        (splat[1] + XY_ONE as i32 - 1) >> XY_FRAC_BITS
    };
    let pad_x = if smooth {
        2
    } else {
        (splat[0] + XY_ONE as i32 - 1) >> XY_FRAC_BITS
    };
    let marks = [first, flags, spans, quarters];
    // (A lifted piece may draw by quarters only: a small patch whose one
    // level-1 cell holds three of its four level-0 cells.)
    let nothing = measure.drawable_cells == 0 && work.quartered.len() == quarters;
    if nothing || y1 + pad < 0 || y0 - pad >= height {
        drop_planned(work, marks);
        work.counters.traverse_ns += work.clock.lap();
        return;
    }
    let Some((nu, nv)) = split else {
        if lifted < m {
            return replan_unlifted(work, ctx, piece, (marks, m, measure.backfacing_cells));
        }
        // The flags stay for the triangles below.
        drop_planned(work, [first, work.cell_flags.len(), spans, quarters]);
        work.counters.traverse_ns += work.clock.lap();
        work.counters.oversized_pieces += 1;
        // The measured flags choose the cells: those facing away are left
        // out. Why: fandisk's 51 oversized pieces drew 2,954 such cells
        // beside 3,858 facing the eye (43 % of their triangles).
        emit_cell_triangles(work, ctx, named, range, Some(flags));
        work.cell_flags.truncate(flags);
        work.counters.setup_ns += work.clock.lap();
        return;
    };
    // Outlines of magnified cells are drawn exactly where the surface
    // folds away (see `open_sides` and `raster::cell_edges`); the cells of
    // patches with a colour grid by pixel-centre coverage
    // (`raster::centre_piece`), or by sub-quads (`raster::cell_exact`)
    // with `--exact-outlines`, which also takes the other coloured ones.
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
    // The sub-node drawers (with or without open sides) also draw the cells
    // by quarters; a lifted piece that another would take keeps the
    // limit's level.
    if quartered_lift && (!bilinear || centres.is_some()) {
        return replan_unlifted(work, ctx, piece, (marks, m, measure.backfacing_cells));
    }
    if exact {
        mark_exact_cells(&mut work.cell_flags[flags..]);
    } else if open_sides {
        mark_open_sides(level, range, &mut work.cell_flags[flags..]);
    }
    // With the gap fill (`raster::gap_fill`), plain sub-node pieces leave
    // small gaps to its pass: about half the samples on magnified cells.
    // The other drawers keep their own coverage, and so do pieces at the
    // image's left or right side: past it no sample is drawn to close a
    // gap against.
    let inside = x0 >= GAP_FILL_REACH && x1 < setup.view.width as i32 - GAP_FILL_REACH;
    let plain = bilinear && centres.is_none() && !open_sides;
    let (nu, nv) = if plain && inside && opts.fills_gaps() {
        choose_subdivision(edges, GAP_FILL_LIMIT).unwrap_or((nu, nv))
    } else {
        (nu, nv)
    };
    if quartered_lift && (nu, nv) == (1, 1) {
        nodes_without_quarters(work, marks, cols);
    }
    work.counters.traverse_ns += work.clock.lap();
    // 5. Attributes.
    fill_attributes(work, ctx, named, range, first);
    work.counters.normals_ns += work.clock.lap();
    // After the attributes, which it keeps: only positions are dropped.
    if splat[0] > 0 && measure.drawable_cells < ((cols - 1) * (rows - 1)) as u64 {
        let nodes = &mut work.nodes[first..];
        let cells = &work.cell_flags[flags..];
        drop_undrawn_nodes(nodes, cells, cols, rows, &mut work.splat_scratch);
        work.counters.traverse_ns += work.clock.lap();
    }
    work.counters.patch_nodes += measure.used_nodes;
    if splat[0] > 0 {
        work.counters.splatted += 1;
    } else if (nu, nv) == (1, 1) {
        work.counters.optimized += 1;
    } else if centres.is_some() {
        work.counters.interpolated += 1;
    } else {
        work.counters.interpolated += 1;
        let refined = measure.refined_nodes(nu as u64, nv as u64);
        work.counters.interpolated_nodes += refined.saturating_sub(measure.used_nodes);
    }
    // Pixel-centre cells record their pixels' places on a grid of
    // `CENTRE_STEPS` per side, which the resolve reads as a cut.
    let (nu, nv) = if centres.is_some() {
        (CENTRE_STEPS, CENTRE_STEPS)
    } else {
        (nu, nv)
    };
    if work.quartered.len() > quarters {
        work.quartered_ranges.push(QuarteredRange {
            item: work.items.len() as u32,
            cells: [quarters as u32, work.quartered.len() as u32],
        });
    }
    work.items.push(Item {
        first: first as u32,
        cols: cols as u16,
        rows: rows as u16,
        nu: nu as u16,
        nv: nv as u16,
        frame: ctx.index,
        flags: flags as u32,
        spans: spans as u32,
        uniform_albedo: level.colours.is_none(),
        level: named as u8,
        shade_shift: shift as u8,
        i0: range.i0 as u16,
        j0: range.j0 as u16,
        y0: y0 - pad,
        y1: y1 + pad,
        x0: x0 - pad_x,
        x1: x1 + pad_x,
        z_near: if smooth || !opts.occlusion_skip {
            i32::MIN
        } else {
            nearest_box_depth(range, d, &proj)
        },
        inside_columns: x0 > 0 && x1 < setup.view.width as i32 - 1,
        splat,
        open_sides,
        centres,
    });
}

/// The measured `edges` of a piece lifted to level 1 by quarters, widened
/// by those of its cells by quarters that do not face away, which it
/// keeps in `work` ([`gather_quartered`]). Why out of line, and the one
/// below: the planner is inlined, and its common path's layout moves the
/// frame (see [`replan_unlifted`]).
#[inline(never)]
fn widen_by_quartered(
    work: &mut ChunkWork,
    level: &MipLevel,
    cols: usize,
    back_sign: i64,
    edges: [i64; 4],
) -> [i64; 4] {
    let q = gather_quartered(
        &level.quartered,
        &work.xy,
        cols,
        back_sign,
        &mut work.quartered,
    );
    [0, 1, 2, 3].map(|k| edges[k].max(q[k]))
}

/// A lifted piece cut 1 × 1 (cells under a pixel where the box's estimate
/// said otherwise) places its nodes, not its cells: empties those only its
/// cells by quarters use (they lie past the patch's data) and forgets the
/// cells (`marks` as for [`drop_planned`]; `cols` nodes a row).
#[inline(never)]
#[cold]
fn nodes_without_quarters(
    work: &mut ChunkWork,
    [first, flags, _, quarters]: [usize; 4],
    cols: usize,
) {
    let cells = &work.quartered[quarters..];
    drop_quartered_corners(
        cells,
        &work.cell_flags[flags..],
        cols,
        &mut work.nodes[first..],
    );
    work.quartered.truncate(quarters);
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

/// Forgets what planning pushed for a piece it drops: the chunk's nodes,
/// cell flags, row spans and quartered cells from the lengths `marks`
/// they had before it.
fn drop_planned(work: &mut ChunkWork, [nodes, flags, spans, quarters]: [usize; 4]) {
    work.nodes.truncate(nodes);
    work.cell_flags.truncate(flags);
    work.row_spans.truncate(spans);
    work.quartered.truncate(quarters);
}

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
fn centre_cells(opts: &RenderOptions) -> bool {
    opts.centre_limit > 0.0 && opts.cells == CellScheme::Bilinear && opts.splat_limit == 0.0
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

/// Whether whole patches may draw the level above their shading level
/// ([`RenderOptions::geometry_limit`]): Phong (the resolve pass
/// interpolates the shading level's normals), bilinear cells, no splats.
fn coarse_geometry(opts: &RenderOptions) -> bool {
    opts.geometry_limit > 0.0
        && opts.shading == Shading::Phong
        && opts.cells == CellScheme::Bilinear
        && opts.splat_limit == 0.0
}

/// Largest screen error (pixels) allowed of the trilinear projection of a
/// piece; past it the piece is projected exactly. Below it the shortcut
/// stays the documented trade-off (`--stats` `shortcuts`): the default
/// sphere at 500² has pieces near 1.8 px, whose images are unchanged.
const TRILINEAR_LIMIT_PX: f32 = 2.0;

/// Largest cut per side of bilinear cells: cells cut finer (15 px and
/// more) go to the triangle path, which covers exactly the pixel centres
/// inside a cell and interpolates perspective-correctly (colour grids
/// included). Why: a textured box's faces (cells of 40-60 px in the eval's
/// views) were drawn a pixel wide of their outline (the sub-nodes'
/// half-pixel reach) and their colour grids mapped affinely in screen
/// space; at that size a triangle's set-up costs less than the cell's
/// sub-nodes.
const TRIANGLE_CUT: u32 = 16;

/// How far (pixels) the trilinear projection of `range` (box heights `d`)
/// places a node from its exact projection, estimated from the box's
/// corners: a point's exact position is the mean of the corners' positions
/// weighted by its trilinear weights times the corners' `W`, the trilinear
/// one the mean with the weights alone; along one axis across a span of
/// `L` pixels whose `W` grows by `k × W_min` the largest difference is
/// about `L k / 4` (in the middle). Infinite when a corner is not in front
/// of the eye.
#[inline(always)]
fn trilinear_error(proj: &Projector, range: NodeRange, d: (u16, u16)) -> f32 {
    let (lo, hi) = range.local_box(d);
    let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for k in 0..8 {
        let p = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let c = proj.map * p + proj.t0;
        let s = Vec3::new(c.x / c.z, c.y / c.z, c.z);
        (min, max) = (min.min(s), max.max(s));
    }
    if min.z.is_nan() || min.z <= 0.0 {
        return f32::INFINITY;
    }
    let span = (max.x - min.x).max(max.y - min.y);
    0.25 * span * (max.z - min.z) / min.z
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

/// The footprint half-widths (position units) with which the nodes of a
/// piece whose cells have the largest edges `edges` cover them, when the
/// splatting path draws it (bilinear cells the nodes alone do not cover,
/// within [`RenderOptions::splat_limit`]); `[0, 0]` otherwise.
fn splat_footprint(
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
