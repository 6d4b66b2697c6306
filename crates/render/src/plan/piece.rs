//! One piece of a patch, planned: everything about it decided before any
//! pixel is touched.
//!
//! 1. mip level ([`crate::plan::level_choice`]): for whole patches, the
//!    coarsest level whose estimated cell extent (from the projected box)
//!    stays below
//!    [`RenderOptions::mip_limit`](crate::RenderOptions::mip_limit) pixels
//!    ([`crate::prepare::mip`]), or coarser where the tolerances allow;
//! 2. node traversal ([`crate::plan::project`]): trilinear or exact, into
//!    the chunk's flat array of fixed-point nodes, then the cell
//!    measurement ([`crate::plan::measure`]);
//! 3. subdivision `nu × nv` from the largest projected cell edges
//!    ([`crate::plan::subdivision`]); `1 × 1` selects the node-placing
//!    path, pixel-sized cells the splat path ([`crate::raster::splat`]),
//!    cells too large the triangle path;
//!    then the drawer ([`crate::plan::drawer`]: sub-nodes, open sides,
//!    exact outlines, pixel centres);
//! 4. per-node attributes ([`crate::plan::attributes`]), and the draw item.
//!
//! Cost: O(nodes of the piece).

use glam::Vec3;

use crate::fixed::{XY_FRAC_BITS, XY_ONE};
use crate::options::{CellScheme, Projection, RenderMode, RenderOptions};
use crate::plan::attributes::fill_attributes;
use crate::plan::cell_triangles::emit_cell_triangles;
use crate::plan::drawer::{choose_drawer, gap_fill_cut, splat_footprint, Drawer};
use crate::plan::level_choice::{choose_level, LevelChoice};
use crate::plan::measure::{measure_cells, CellMeasure};
use crate::plan::open_sides::{mark_exact_cells, mark_open_sides};
use crate::plan::project::{
    level_map, nearest_box_depth, project_nodes_exact, project_nodes_trilinear, Projector,
};
use crate::plan::quartered::{drop_quartered_corners, gather_quartered};
use crate::plan::split::NodeRange;
use crate::plan::subdivision::{choose_subdivision, SMOOTH_MARGIN, SUBPIXEL_LIMIT};
use crate::plan::work::{ChunkWork, Item, PatchContext, QuarteredRange};
use crate::prepare::mip::MipLevel;
use crate::raster::cell_centres::CENTRE_STEPS;
use crate::raster::gap_fill::GAP_FILL_REACH;
use crate::raster::splat::drop_undrawn_nodes;

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
    if ctx.setup.options.mode == RenderMode::Triangles {
        emit_cell_triangles(work, ctx, 0, piece, None);
        work.counters.setup_ns += work.clock.lap();
        work.counters.mip[0] += 1;
        return;
    }
    let Some(t) = traverse_piece(work, ctx, piece, lift) else {
        return;
    };
    let Some(cut) = cut_piece(work, ctx, piece, &t) else {
        return;
    };
    finish_piece(work, ctx, &t, cut);
}

/// A piece after its traversal: its level, projected nodes and measured
/// cells.
struct Traversed<'a> {
    choice: LevelChoice,
    /// The level's name ([`LevelChoice::named`]).
    named: usize,
    level: &'a MipLevel,
    range: NodeRange,
    /// The range's box heights.
    d: (u16, u16),
    proj: Projector,
    /// Where the piece's nodes, cell flags, row spans and cells by
    /// quarters begin in the chunk's arrays (see [`drop_planned`]).
    marks: [usize; 4],
    measure: CellMeasure,
    /// The largest cell edges in pixels, widened by the cells by quarters.
    edges: [f32; 4],
    smooth: bool,
}

/// Steps 1 and 2 of the module header: the piece's level, its nodes
/// projected and its cells measured (`None`: the level holds no node of
/// the piece).
#[inline(always)]
fn traverse_piece<'a>(
    work: &mut ChunkWork,
    ctx: &PatchContext<'a>,
    piece: NodeRange,
    lift: bool,
) -> Option<Traversed<'a>> {
    let (p, setup) = (ctx.patch, ctx.setup);
    let opts = setup.options;
    let proj0 = Projector {
        map: ctx.map,
        t0: ctx.t0,
        z_scale: setup.z_scale,
        z_offset: setup.z_offset,
    };
    // 1. Mip level. (Stage timers: what follows is charged to traversal
    // at its laps.)
    let choice = choose_level(ctx, &proj0, piece, lift);
    let named = choice.named();
    let m = choice.m;
    let level = p.level(named);
    let range = if m == 0 {
        piece
    } else {
        NodeRange::whole(level)
    };
    let d = range.d_range(level)?;
    work.counters.mip[m] += 1;
    // 2. Traversal.
    let proj = Projector {
        map: level_map(&ctx.map, m),
        ..proj0
    };
    let first = work.nodes.len();
    project_piece(work, opts.projection, level, range, d, &proj);
    let smooth = opts.cells == CellScheme::Smooth;
    let back_sign = back_face_sign(ctx.cell_test && !smooth, &proj);
    let ([flags, spans, quarters], measure, edges) =
        measure_piece(work, level, range, back_sign, choice.quartered_lift);
    Some(Traversed {
        choice,
        named,
        level,
        range,
        d,
        proj,
        marks: [first, flags, spans, quarters],
        measure,
        edges,
        smooth,
    })
}

/// Measures the cells of `range` of `level`, the chunk's last projected
/// nodes (`back_sign` as [`back_face_sign`]), and counts those facing
/// away. Returns where the piece's cell flags, row spans and cells by
/// quarters begin in the chunk's arrays, the measure, and the largest cell
/// edges in pixels, widened by the cells by quarters of a piece lifted by
/// quarters (`quartered_lift`), which it gathers: the cut covers them too.
#[inline(always)]
fn measure_piece(
    work: &mut ChunkWork,
    level: &MipLevel,
    range: NodeRange,
    back_sign: i64,
    quartered_lift: bool,
) -> ([usize; 3], CellMeasure, [f32; 4]) {
    let (flags, spans) = (work.cell_flags.len(), work.row_spans.len());
    let measure = measure_cells(
        level,
        range,
        &mut work.xy,
        back_sign,
        &mut work.cell_flags,
        &mut work.row_spans,
    );
    work.counters.cells_backface += measure.backfacing_cells;
    let quarters = work.quartered.len();
    let edges = if quartered_lift {
        widen_by_quartered(work, level, range.size().0, back_sign, measure.edges)
    } else {
        measure.edges
    };
    let edges = edges.map(|e| e as f32 / XY_ONE);
    ([flags, spans, quarters], measure, edges)
}

/// How a piece is drawn: its cut, splat footprint, item pads and drawer.
struct PieceCut {
    /// Sub-cells per cell `(nu, nv)`.
    cut: (u32, u32),
    /// The splat footprint's half widths (0: no splats).
    splat: [i32; 2],
    /// The item box's pads ([`item_pads`]).
    pads: [i32; 2],
    drawer: Drawer,
}

/// Step 3 of the module header: the piece's cut `nu × nv` and drawer, its
/// cells marked for the drawer. `None` when the piece is done: nothing to
/// draw or outside the image's rows (dropped), or planned again another
/// way (the triangle path, or without its lift).
#[inline(always)]
fn cut_piece(
    work: &mut ChunkWork,
    ctx: &PatchContext<'_>,
    piece: NodeRange,
    t: &Traversed<'_>,
) -> Option<PieceCut> {
    let (setup, opts) = (ctx.setup, ctx.setup.options);
    let (measure, marks) = (&t.measure, t.marks);
    let (m, quartered_lift) = (t.choice.m, t.choice.quartered_lift);
    let (split, splat) = choose_cut(opts, t.smooth, t.edges);
    let pads = item_pads(t.smooth, splat);
    let [x0, y0, x1, y1] = measure.bbox;
    // (A lifted piece may draw by quarters only: a small patch whose one
    // level-1 cell holds three of its four level-0 cells.)
    let nothing = measure.drawable_cells == 0 && work.quartered.len() == marks[3];
    if nothing || y1 + pads[1] < 0 || y0 - pads[1] >= setup.view.height as i32 {
        drop_planned(work, marks);
        work.counters.traverse_ns += work.clock.lap();
        return None;
    }
    let replan = (marks, m, measure.backfacing_cells);
    let Some((nu, nv)) = split else {
        if t.choice.lifted < m {
            replan_unlifted(work, ctx, piece, replan);
        } else {
            plan_oversized(work, ctx, (t.named, t.range), marks);
        }
        return None;
    };
    let cut = (t.smooth, splat);
    let drawer = choose_drawer(opts, ctx.patch, t.level, cut, (nu, nv), measure);
    // The sub-node drawers (with or without open sides) also draw the cells
    // by quarters; a lifted piece that another would take keeps the
    // limit's level.
    if quartered_lift && (!drawer.bilinear || drawer.centres.is_some()) {
        replan_unlifted(work, ctx, piece, replan);
        return None;
    }
    if drawer.exact {
        mark_exact_cells(&mut work.cell_flags[marks[1]..]);
    } else if drawer.open_sides {
        mark_open_sides(t.level, t.range, &mut work.cell_flags[marks[1]..]);
    }
    let inside = x0 >= GAP_FILL_REACH && x1 < setup.view.width as i32 - GAP_FILL_REACH;
    let (nu, nv) = gap_fill_cut(opts, &drawer, inside, t.edges, (nu, nv));
    if quartered_lift && (nu, nv) == (1, 1) {
        nodes_without_quarters(work, marks, t.range.size().0);
    }
    work.counters.traverse_ns += work.clock.lap();
    Some(PieceCut {
        cut: (nu, nv),
        splat,
        pads,
        drawer,
    })
}

/// Step 4 of the module header: the piece's attributes, its counts and
/// its draw item.
#[inline(always)]
fn finish_piece(work: &mut ChunkWork, ctx: &PatchContext<'_>, t: &Traversed<'_>, cut: PieceCut) {
    let opts = ctx.setup.options;
    let (measure, marks, range) = (&t.measure, t.marks, t.range);
    let [first, flags, ..] = marks;
    let (cols, rows) = range.size();
    let PieceCut {
        cut,
        splat,
        pads,
        drawer,
    } = cut;
    fill_attributes(work, ctx, t.named, range, first);
    work.counters.normals_ns += work.clock.lap();
    // After the attributes, which it keeps: only positions are dropped.
    if splat[0] > 0 && measure.drawable_cells < ((cols - 1) * (rows - 1)) as u64 {
        let nodes = &mut work.nodes[first..];
        let cells = &work.cell_flags[flags..];
        drop_undrawn_nodes(nodes, cells, cols, rows, &mut work.splat_scratch);
        work.counters.traverse_ns += work.clock.lap();
    }
    count_piece(work, measure, splat, cut, drawer.centres.is_some());
    let z_near = if t.smooth || !opts.occlusion_skip {
        i32::MIN
    } else {
        nearest_box_depth(range, t.d, &t.proj)
    };
    let parts = ItemParts {
        marks,
        levels: (t.named, t.choice.shift),
        range,
        cut,
        bbox: measure.bbox,
        pads,
        z_near,
        splat,
        drawer,
    };
    push_item(work, ctx, t.level, parts);
}

/// Projects the nodes of `range` (box heights `d`) of `level` into the
/// chunk's node array: trilinearly when `projection` asks for it and the
/// shortcut's error stays within [`TRILINEAR_LIMIT_PX`], else exactly. Why
/// exact past the limit: a textured box's faces seen at a slant (cells of
/// 40-60 px in the eval's views, errors of about 25 px) were drawn far from
/// their depth, 2.9 % of the pixels behind the source (`trilinear_error`).
#[inline(always)]
fn project_piece(
    work: &mut ChunkWork,
    projection: Projection,
    level: &MipLevel,
    range: NodeRange,
    d: (u16, u16),
    proj: &Projector,
) {
    let trilinear = projection == Projection::Trilinear
        && trilinear_error(proj, range, d) <= TRILINEAR_LIMIT_PX;
    if trilinear {
        project_nodes_trilinear(level, range, d, proj, &mut work.nodes, &mut work.xy)
    } else {
        project_nodes_exact(level, range, proj, &mut work.nodes, &mut work.xy)
    }
}

/// The sign a cell's screen cross product has when it faces away under
/// the projection `proj` (that of its map's determinant), or 0 when cells
/// are not tested (`test` false, or a degenerate map). Why cells are
/// tested: 12 % of the sphere's samples were on cells facing away
/// (callgrind, `profile_sphere 500 1`); smooth cells are not, a Catmull-Rom
/// cell not being bounded by its corners.
#[inline(always)]
fn back_face_sign(test: bool, proj: &Projector) -> i64 {
    let det = proj.map.determinant();
    if !test || det == 0.0 {
        0
    } else if det > 0.0 {
        1
    } else {
        -1
    }
}

/// The cut `nu × nv` of cells whose largest edges are `edges` pixels
/// (`None`: too large for sub-nodes, the triangle path) and the splat
/// footprint (`[0, 0]` unless the splat path draws them, cut `1 × 1`).
#[inline(always)]
fn choose_cut(
    opts: &RenderOptions,
    smooth: bool,
    edges: [f32; 4],
) -> (Option<(u32, u32)>, [i32; 2]) {
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
    (split, splat)
}

/// How many pixels a piece's draw item reaches past its nodes' box, in x
/// and y: the splat footprint's half-widths rounded up, or 2 for smooth
/// cells, which bulge past their corners.
#[inline(always)]
fn item_pads(smooth: bool, splat: [i32; 2]) -> [i32; 2] {
    if smooth {
        return [2, 2];
    }
    splat.map(|half| (half + XY_ONE as i32 - 1) >> XY_FRAC_BITS)
}

/// Draws a piece whose cells are too large for sub-nodes as triangles:
/// forgets its planned nodes (`marks` as for [`drop_planned`]) but keeps
/// its measured flags, which choose the cells. Why the flags: cells facing
/// away are left out (fandisk's 51 oversized pieces drew 2,954 such cells
/// beside 3,858 facing the eye, 43 % of their triangles).
fn plan_oversized(
    work: &mut ChunkWork,
    ctx: &PatchContext<'_>,
    (named, range): (usize, NodeRange),
    [first, flags, spans, quarters]: [usize; 4],
) {
    drop_planned(work, [first, work.cell_flags.len(), spans, quarters]);
    work.counters.traverse_ns += work.clock.lap();
    work.counters.oversized_pieces += 1;
    emit_cell_triangles(work, ctx, named, range, Some(flags));
    work.cell_flags.truncate(flags);
    work.counters.setup_ns += work.clock.lap();
}

/// Adds a planned piece to the chunk's counters: its used nodes, and the
/// path that draws it (splats, placed nodes, pixel centres, or sub-nodes
/// with the interpolated ones they add for the cut `nu × nv`).
#[inline(always)]
fn count_piece(
    work: &mut ChunkWork,
    measure: &CellMeasure,
    splat: [i32; 2],
    (nu, nv): (u32, u32),
    centres: bool,
) {
    let c = &mut work.counters;
    c.patch_nodes += measure.used_nodes;
    if splat[0] > 0 {
        c.splatted += 1;
    } else if (nu, nv) == (1, 1) {
        c.optimized += 1;
    } else if centres {
        c.interpolated += 1;
    } else {
        c.interpolated += 1;
        let refined = measure.refined_nodes(nu as u64, nv as u64);
        c.interpolated_nodes += refined.saturating_sub(measure.used_nodes);
    }
}

/// What a planned piece's draw item is made of besides its patch and level.
#[derive(Debug, Clone, Copy)]
struct ItemParts {
    /// Where the piece's nodes, flags, spans and quartered cells start in
    /// the chunk's arrays (see [`drop_planned`]).
    marks: [usize; 4],
    /// The level the item names and its shading shift ([`LevelChoice`]).
    levels: (usize, usize),
    range: NodeRange,
    /// The sub-node cut `nu × nv`.
    cut: (u32, u32),
    /// The nodes' pixel box `[x0, y0, x1, y1]`.
    bbox: [i32; 4],
    /// How far the item reaches past the box ([`item_pads`]).
    pads: [i32; 2],
    /// The nearest depth of the piece's box, or `i32::MIN` (no occlusion
    /// skip).
    z_near: i32,
    splat: [i32; 2],
    drawer: Drawer,
}

/// Pushes the draw item of a piece of `level` of the patch of `ctx` (and
/// its range of cells by quarters, when it has some).
#[inline(always)]
fn push_item(work: &mut ChunkWork, ctx: &PatchContext<'_>, level: &MipLevel, parts: ItemParts) {
    let [first, flags, spans, quarters] = parts.marks;
    if work.quartered.len() > quarters {
        work.quartered_ranges.push(QuarteredRange {
            item: work.items.len() as u32,
            cells: [quarters as u32, work.quartered.len() as u32],
        });
    }
    // Pixel-centre cells record their pixels' places on a grid of
    // `CENTRE_STEPS` per side, which the resolve reads as a cut.
    let cut = match parts.drawer.centres {
        Some(_) => (CENTRE_STEPS, CENTRE_STEPS),
        None => parts.cut,
    };
    let (range, [x0, y0, x1, y1], [pad_x, pad_y]) = (parts.range, parts.bbox, parts.pads);
    let ((cols, rows), (named, shift)) = (range.size(), parts.levels);
    work.items.push(Item {
        first: first as u32,
        cols: cols as u16,
        rows: rows as u16,
        nu: cut.0 as u16,
        nv: cut.1 as u16,
        frame: ctx.index,
        flags: flags as u32,
        spans: spans as u32,
        uniform_albedo: level.colours.is_none(),
        level: named as u8,
        shade_shift: shift as u8,
        i0: range.i0 as u16,
        j0: range.j0 as u16,
        y0: y0 - pad_y,
        y1: y1 + pad_y,
        x0: x0 - pad_x,
        x1: x1 + pad_x,
        z_near: parts.z_near,
        inside_columns: x0 > 0 && x1 < ctx.setup.view.width as i32 - 1,
        splat: parts.splat,
        open_sides: parts.drawer.open_sides,
        centres: parts.drawer.centres,
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

/// Forgets what planning pushed for a piece it drops: the chunk's nodes,
/// cell flags, row spans and quartered cells from the lengths `marks`
/// they had before it.
fn drop_planned(work: &mut ChunkWork, [nodes, flags, spans, quarters]: [usize; 4]) {
    work.nodes.truncate(nodes);
    work.cell_flags.truncate(flags);
    work.row_spans.truncate(spans);
    work.quartered.truncate(quarters);
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
