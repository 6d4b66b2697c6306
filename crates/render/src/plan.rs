//! The per-patch plan: everything decided once per patch and frame before
//! any pixel is touched (as tiny-skia compiles a pipeline before running it).
//!
//! For each patch, in drawing order, on fixed chunks of [`PATCH_CHUNK`]
//! patches (so results and counts do not depend on the thread count):
//! 1. back-face test on the normal cone, then the frustum test of its box
//!    ([`crate::cull`]); partially visible patches are split
//!    ([`crate::split`]);
//! 2. mip level: for whole patches, the coarsest level whose estimated cell
//!    extent (from the projected box) stays below
//!    [`RenderOptions::mip_limit`] pixels
//!    ([`crate::mip`]);
//! 3. node traversal ([`crate::traverse`]): trilinear or exact, into a flat
//!    array of fixed-point nodes;
//! 4. subdivision `nu × nv` from the largest projected cell edges, the
//!    fewest sub-cells that stay below [`SUBPIXEL_LIMIT`] pixel; `1 × 1`
//!    selects the optimized node-placing path;
//! 5. per-node attributes: patch-space normals through the normal buffer,
//!    then either the normal and albedo (Phong), the shaded colour
//!    (Gouraud) or the cell's shaded colour (flat).
//!
//! The output of a chunk is a list of draw items (node ranges with their
//! `n` and screen rows), the nodes they refer to, and projected triangles
//! for the triangle mode, for cells crossing the near plane and for cells
//! too large to subdivide. Scratch vectors live in the chunk and are reused
//! from frame to frame: no allocation per patch once warm.
//!
//! Cost: O(visible nodes) per frame.

use std::time::Instant;

use glam::{Mat3, Vec3};

use crate::camera::View;
use crate::cell_bilinear::MAX_SUBDIVISION;
use crate::cull::{back_culled, cone_faces_away, cone_faces_eye, BoxClass, Frustum, Portal};
use crate::fixed::attr_to_bits;
use crate::mip::MipLevel;
use crate::normal_buffer::{node_differences, reconstruct_normal, NormalBuffer, OUTSIDE_TABLE};
use crate::options::{CellScheme, Projection, RenderMode, RenderOptions, Shading};
use crate::prepare::PreparedPatch;
use crate::shade::{pack_colour, Material, ShadeFrame, WorldLight};
use crate::splat::{drop_undrawn_nodes, footprint_half_widths};
use crate::split::{split_patch, NodeRange};
use crate::stats::Counters;
use crate::traverse::{
    measure_cells, project_nodes_exact, project_nodes_trilinear, Node, NodeXY, Projector,
};
use crate::triangle_raster::{
    clip_and_project, ClipOutcome, ClipVertex, ScreenTriangle, TRI_ATTRS,
};

/// Patches per unit of parallel planning work.
pub(crate) const PATCH_CHUNK: usize = 32;
/// Largest sub-cell extent (pixels, max-norm sum of edges) allowed; below
/// 1 so that rounding never opens a hole.
pub(crate) const SUBPIXEL_LIMIT: f32 = 0.95;
/// Extra subdivision for Catmull-Rom cells, which bulge past their corners.
pub(crate) const SMOOTH_MARGIN: f32 = 1.3;

/// A piece of patch to draw: `cols × rows` nodes starting at `first` in its
/// chunk's node array, cut into `nu × nv` per cell (1 × 1: nodes only).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Item {
    pub(crate) first: u32,
    pub(crate) cols: u16,
    pub(crate) rows: u16,
    pub(crate) nu: u16,
    pub(crate) nv: u16,
    pub(crate) frame: u32,
    /// Index of the piece's first cell flag in its chunk's `cell_flags`.
    pub(crate) flags: u32,
    /// Index of the piece's first row span in its chunk's `row_spans`.
    pub(crate) spans: u32,
    /// Every node has the same albedo (a patch without colours): the
    /// resolve pass takes it as is instead of interpolating it.
    pub(crate) uniform_albedo: bool,
    /// Mip level of the piece (Phong reads the level's prepared normals).
    pub(crate) level: u8,
    /// The piece's first node column and row in its level.
    pub(crate) i0: u16,
    pub(crate) j0: u16,
    /// Pixel rows spanned (inclusive).
    pub(crate) y0: i32,
    pub(crate) y1: i32,
    /// Every used node lies in the image's columns `1..width - 1`, so a
    /// row of cells inside a band needs no clipping at all.
    pub(crate) inside_columns: bool,
    /// Footprint half-widths in x and y (position units) of a splatted
    /// piece ([`crate::splat`]); 0 for every other piece.
    pub(crate) splat: [i32; 2],
}

/// Everything about the frame that planning needs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameSetup<'a> {
    pub(crate) view: &'a View,
    pub(crate) frustum: Frustum,
    pub(crate) light: WorldLight,
    pub(crate) material: Material,
    pub(crate) options: &'a RenderOptions,
    pub(crate) z_scale: f32,
    pub(crate) z_offset: f32,
    pub(crate) base_colour: Vec3,
    /// The scene's openings (automatic culling); empty for meshes.
    pub(crate) portals: &'a [Portal],
}

/// The output and scratch space of one chunk.
#[derive(Debug, Default)]
pub(crate) struct ChunkWork {
    pub(crate) nodes: Vec<Node>,
    pub(crate) items: Vec<Item>,
    pub(crate) triangles: Vec<ScreenTriangle>,
    /// One flag byte per cell of each item ([`crate::traverse::CELL_DRAW`], …).
    pub(crate) cell_flags: Vec<u8>,
    /// Pixel rows spanned by each row of cells of each item (see
    /// [`crate::traverse::measure_cells`]).
    pub(crate) row_spans: Vec<[i32; 2]>,
    pub(crate) counters: Counters,
    /// Screen positions of the piece being planned (see [`NodeXY`]).
    xy: NodeXY,
    normals: NormalBuffer,
    stack: Vec<NodeRange>,
    pieces: Vec<NodeRange>,
    cells: Vec<(usize, usize)>,
    vertices: Vec<ClipVertex>,
    /// Scratch of [`drop_undrawn_nodes`].
    splat_scratch: Vec<u8>,
}

impl ChunkWork {
    /// Clears the outputs for a new frame (keeps the allocations).
    pub(crate) fn reset(&mut self) {
        self.nodes.clear();
        self.items.clear();
        self.triangles.clear();
        self.cell_flags.clear();
        self.row_spans.clear();
        self.counters = Counters::default();
        self.normals.clear();
        self.normals.counts = Default::default();
    }
}

fn nanos(since: Instant) -> u64 {
    since.elapsed().as_nanos() as u64
}

/// Plans the patches of one chunk; `first_index` is the drawing index of
/// `patches[0]` and `frames` receives one shade frame per patch.
pub(crate) fn plan_chunk(
    work: &mut ChunkWork,
    patches: &[PreparedPatch],
    first_index: u32,
    frames: &mut [ShadeFrame],
    setup: &FrameSetup<'_>,
) {
    work.reset();
    let eye = setup.view.eye;
    for (local, p) in patches.iter().enumerate() {
        let index = first_index + local as u32;
        work.counters.patches += 1;
        let start = Instant::now();
        let mode = (setup.options.culling, p.sides);
        let culled = back_culled(mode, setup.portals, eye, p.centre, p.radius);
        if culled && cone_faces_away(&p.cone, p.centre, p.radius, eye) {
            work.counters.culled_backface += 1;
            work.counters.cull_ns += nanos(start);
            continue;
        }
        let facing_away = p.cone.axis.dot(eye - p.centre) < 0.0;
        // No cell of a patch facing the eye entirely can face away.
        let cell_test = culled && !cone_faces_eye(&p.cone, p.centre, p.radius, eye);
        frames[local] = setup.light.frame_in(&p.rotation, facing_away);
        let (map, t0) = setup.view.local_map(p.origin, p.axes);
        let level0 = &p.base;
        let root = NodeRange::whole(level0);
        let (lo, hi) = root.local_box(level0.d_range);
        let class = setup.frustum.classify(&map, t0, lo, hi);
        work.counters.cull_ns += nanos(start);
        work.pieces.clear();
        work.cells.clear();
        match class {
            BoxClass::Outside => {
                work.counters.culled_frustum += 1;
                continue;
            }
            BoxClass::Inside => work.pieces.push(root),
            BoxClass::Partial => {
                let start = Instant::now();
                work.counters.split += 1;
                let counts = split_patch(
                    level0,
                    &setup.frustum,
                    &map,
                    t0,
                    root,
                    &mut work.stack,
                    &mut work.pieces,
                    &mut work.cells,
                );
                work.counters.split_pieces += work.pieces.len() as u64;
                work.counters.pieces_dropped += counts.dropped as u64;
                work.counters.split_ns += nanos(start);
            }
        }
        work.normals.begin_patch();
        let whole = class == BoxClass::Inside;
        let pieces = std::mem::take(&mut work.pieces);
        for &piece in &pieces {
            plan_piece(
                work,
                p,
                piece,
                whole,
                cell_test,
                &map,
                t0,
                index,
                &frames[local],
                setup,
            );
        }
        work.pieces = pieces;
        if !work.cells.is_empty() {
            let start = Instant::now();
            let cells = std::mem::take(&mut work.cells);
            for &(i, j) in &cells {
                let range = NodeRange {
                    i0: i,
                    j0: j,
                    i1: i + 1,
                    j1: j + 1,
                };
                let emitted =
                    emit_cell_triangles(work, p, 0, range, &map, t0, index, &frames[local], setup);
                work.counters.clipped_cells += (emitted > 0) as u64;
            }
            work.cells = cells;
            work.counters.setup_ns += nanos(start);
        }
    }
    work.counters.normals = work.normals.counts;
}

/// The local map of mip level `m` (node spacing `2^m`).
fn level_map(map: &Mat3, m: usize) -> Mat3 {
    let s = (1u32 << m) as f32;
    Mat3::from_cols(map.x_axis * s, map.y_axis * s, map.z_axis)
}

/// Estimated level-0 cell extent in pixels from the projected box corners.
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

#[allow(clippy::too_many_arguments)] // per-patch values computed once by the caller
fn plan_piece(
    work: &mut ChunkWork,
    p: &PreparedPatch,
    piece: NodeRange,
    whole: bool,
    cell_test: bool,
    map: &Mat3,
    t0: Vec3,
    index: u32,
    frame: &ShadeFrame,
    setup: &FrameSetup<'_>,
) {
    let opts = setup.options;
    let proj0 = Projector {
        map: *map,
        t0,
        z_scale: setup.z_scale,
        z_offset: setup.z_offset,
    };
    if opts.mode == RenderMode::Triangles {
        let start = Instant::now();
        emit_cell_triangles(work, p, 0, piece, map, t0, index, frame, setup);
        work.counters.setup_ns += nanos(start);
        work.counters.mip[0] += 1;
        return;
    }
    let start = Instant::now();
    // 2. Mip level.
    let mut m = 0;
    if whole && opts.mip && p.level_count() > 1 {
        let extent = estimate_extent(&proj0, piece, p.base.d_range);
        // The splat path covers cells whose extent (the max-norm sum of
        // their edges) is up to twice its half-width: a level whose nodes
        // still land within that reach needs no subdivision.
        let limit = if opts.splat_limit > 0.0 && opts.cells == CellScheme::Bilinear {
            opts.mip_limit.max(2.0 * opts.splat_limit)
        } else {
            opts.mip_limit
        };
        while m + 1 < p.level_count() && extent * ((1u32 << (m + 1)) as f32) < limit {
            m += 1;
        }
    }
    let level = p.level(m);
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
        map: level_map(map, m),
        ..proj0
    };
    let first = work.nodes.len();
    match opts.projection {
        Projection::Trilinear => {
            project_nodes_trilinear(level, range, d, &proj, &mut work.nodes, &mut work.xy)
        }
        Projection::Exact => {
            project_nodes_exact(level, range, &proj, &mut work.nodes, &mut work.xy)
        }
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
    let edges = measure.edges.map(|e| e as f32 / crate::fixed::XY_ONE);
    let mut split = choose_subdivision(edges, 1.0);
    if smooth && split != Some((1, 1)) {
        split = choose_subdivision(edges, SMOOTH_MARGIN);
    }
    let splat = splat_footprint(opts, smooth, split, edges);
    if splat[0] > 0 {
        split = Some((1, 1));
    }
    work.counters.traverse_ns += nanos(start);
    let height = setup.view.height as i32;
    let [x0, y0, x1, y1] = measure.bbox;
    let pad = if smooth {
        2
    } else {
        (splat[1] + crate::fixed::XY_ONE as i32 - 1) >> crate::fixed::XY_FRAC_BITS
    };
    if measure.drawable_cells == 0 || y1 + pad < 0 || y0 - pad >= height {
        work.nodes.truncate(first);
        work.cell_flags.truncate(flags);
        work.row_spans.truncate(spans);
        return;
    }
    let Some((nu, nv)) = split else {
        work.nodes.truncate(first);
        work.cell_flags.truncate(flags);
        work.row_spans.truncate(spans);
        work.counters.oversized_pieces += 1;
        let start = Instant::now();
        emit_cell_triangles(work, p, m, range, map, t0, index, frame, setup);
        work.counters.setup_ns += nanos(start);
        return;
    };
    // 5. Attributes.
    let start = Instant::now();
    fill_attributes(work, p, m, range, first, frame, setup);
    work.counters.normals_ns += nanos(start);
    // After the attributes, which it keeps: only positions are dropped.
    if splat[0] > 0 && measure.drawable_cells < ((cols - 1) * (rows - 1)) as u64 {
        let start = Instant::now();
        let nodes = &mut work.nodes[first..];
        let cells = &work.cell_flags[flags..];
        drop_undrawn_nodes(nodes, cells, cols, rows, &mut work.splat_scratch);
        work.counters.traverse_ns += nanos(start);
    }
    work.counters.patch_nodes += measure.used_nodes;
    if splat[0] > 0 {
        work.counters.splatted += 1;
    } else if (nu, nv) == (1, 1) {
        work.counters.optimized += 1;
    } else {
        work.counters.interpolated += 1;
        let refined = measure.refined_nodes(nu as u64, nv as u64);
        work.counters.interpolated_nodes += refined.saturating_sub(measure.used_nodes);
    }
    work.items.push(Item {
        first: first as u32,
        cols: cols as u16,
        rows: rows as u16,
        nu: nu as u16,
        nv: nv as u16,
        frame: index,
        flags: flags as u32,
        spans: spans as u32,
        uniform_albedo: level.colours.is_none(),
        level: m as u8,
        i0: range.i0 as u16,
        j0: range.j0 as u16,
        y0: y0 - pad,
        y1: y1 + pad,
        inside_columns: x0 > 0 && x1 < setup.view.width as i32 - 1,
        splat,
    });
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
    let limit = opts.splat_limit * crate::fixed::XY_ONE;
    if half[0] as f32 > limit || half[1] as f32 > limit {
        return [0, 0];
    }
    half
}

/// The cheapest cut `nu × nv` of cells whose largest edges are
/// `[ux, uy, vx, vy]` pixels (times `margin`) such that sub-cells satisfy
/// `ux/nu + vx/nv < SUBPIXEL_LIMIT` and `uy/nu + vy/nv < SUBPIXEL_LIMIT`;
/// `None` when more than [`MAX_SUBDIVISION`] per side would be needed.
pub(crate) fn choose_subdivision(edges: [f32; 4], margin: f32) -> Option<(u32, u32)> {
    let [ux, uy, vx, vy] = edges.map(|e| e * margin);
    let mut best: Option<(u32, u32)> = None;
    for nv in 1..=MAX_SUBDIVISION {
        // Every later cut has at least `nv` sub-cells: none can beat the
        // best once `nv` reaches its count. Why: cells wider than the limit
        // never reach `nu = 1` and walked all 64 rows (≈ 2.5k instructions
        // per piece; callgrind, `profile_sphere 500 1`).
        if best.is_some_and(|(bu, bv)| nv >= bu * bv) {
            break;
        }
        let (rx, ry) = (
            SUBPIXEL_LIMIT - vx / nv as f32,
            SUBPIXEL_LIMIT - vy / nv as f32,
        );
        if rx <= 0.0 || ry <= 0.0 {
            continue;
        }
        let nu = (ux / rx).max(uy / ry).floor() as u32 + 1;
        if nu > MAX_SUBDIVISION {
            continue;
        }
        if best.is_none_or(|(bu, bv)| nu * nv < bu * bv) {
            best = Some((nu, nv));
        }
        if nu == 1 {
            break;
        }
    }
    best
}

/// Attributes of node `(i, j)` of `level` for the shading model.
#[allow(clippy::too_many_arguments)] // per-node values of the attribute pass
#[inline]
fn node_attributes(
    normals: &mut NormalBuffer,
    p: &PreparedPatch,
    m: usize,
    level: &MipLevel,
    i: usize,
    j: usize,
    frame: &ShadeFrame,
    setup: &FrameSetup<'_>,
) -> [f32; TRI_ATTRS] {
    let k = j * level.cols + i;
    let albedo = match &level.colours {
        Some(c) => Vec3::new(c[k][0] as f32, c[k][1] as f32, c[k][2] as f32),
        None => setup.base_colour,
    };
    let ratios = p.ratios_at(m);
    let node_normal = |normals: &mut NormalBuffer| {
        let (gi, gj) = node_differences(
            &level.displacements,
            level.cols,
            level.rows,
            i,
            j,
            spatch_format::EMPTY,
        );
        normals.normal(m, ratios, gi, gj)
    };
    match setup.options.shading {
        Shading::Phong => {
            let n = node_normal(normals);
            [n.x, n.y, n.z, albedo.x, albedo.y, albedo.z]
        }
        Shading::Gouraud => {
            let c = setup.material.shade(node_normal(normals), frame, albedo);
            [c.x, c.y, c.z, 0.0, 0.0, 0.0]
        }
        Shading::Flat => {
            let (ci, cj) = (i.min(level.cols - 2), j.min(level.rows - 2));
            let n = if level.cell_is_drawable(ci, cj) {
                let d = |a: usize, b: usize| level.displacements[b * level.cols + a] as i32;
                let du = d(ci + 1, cj) + d(ci + 1, cj + 1) - d(ci, cj) - d(ci, cj + 1);
                let dv = d(ci, cj + 1) + d(ci + 1, cj + 1) - d(ci, cj) - d(ci + 1, cj);
                reconstruct_normal(du, dv, ratios.0, ratios.1)
            } else {
                node_normal(normals)
            };
            let c = setup.material.shade(n, frame, albedo);
            [c.x, c.y, c.z, 0.0, 0.0, 0.0]
        }
    }
}

fn fill_attributes(
    work: &mut ChunkWork,
    p: &PreparedPatch,
    m: usize,
    range: NodeRange,
    first: usize,
    frame: &ShadeFrame,
    setup: &FrameSetup<'_>,
) {
    if setup.options.shading == Shading::Phong {
        fill_phong_attributes(work, p, m, range, first);
        return;
    }
    let level = p.level(m);
    let mut k = first;
    for j in range.j0..=range.j1 {
        for i in range.i0..=range.i1 {
            if work.nodes[k][0] != crate::fixed::EMPTY_NODE {
                let a = node_attributes(&mut work.normals, p, m, level, i, j, frame, setup);
                for (dst, src) in work.nodes[k][3..].iter_mut().zip(a) {
                    *dst = attr_to_bits(src);
                }
            }
            k += 1;
        }
    }
}

/// The Phong attributes of a piece: none. The resolve pass reads the
/// normals and albedos of the prepared level
/// ([`crate::prepare::LevelShading`]); this only counts the normal-buffer
/// lookups the nodes make (the statistics keep their meaning; a level drawn
/// whole, whose non-empty nodes are its used nodes, is counted from its
/// prepared slot set). Why: copying three normal words (and the albedo)
/// into every node cost ~50 instructions per node, 7.4 M per 500² sphere
/// frame (callgrind, `profile_sphere 500 1`).
fn fill_phong_attributes(
    work: &mut ChunkWork,
    p: &PreparedPatch,
    m: usize,
    range: NodeRange,
    first: usize,
) {
    let level = p.level(m);
    // The level's shading inputs are built here on a frame's first use, on
    // the planning threads.
    let shading = p.shading(m);
    let normals = &mut work.normals;
    normals.select(m, p.ratios_at(m));
    if range.i0 == 0 && range.j0 == 0 && range.i1 + 1 == level.cols && range.j1 + 1 == level.rows {
        // The whole level: its used nodes, whose slots preparation found.
        normals.touch_all(m, &shading.slots);
        return;
    }
    let width = range.i1 - range.i0 + 1;
    let height = range.j1 - range.j0 + 1;
    let piece = &work.nodes[first..first + width * height];
    for (j, out) in (range.j0..=range.j1).zip(piece.chunks_exact(width)) {
        let row = j * level.cols + range.i0;
        let slots = &level.normal_slots[row..row + width];
        for (node, &slot) in out.iter().zip(slots) {
            if node[0] == crate::fixed::EMPTY_NODE {
                continue;
            }
            if slot != OUTSIDE_TABLE {
                normals.touch_at(m, slot);
            } else {
                normals.touch_outside();
            }
        }
    }
}

/// Emits every drawable cell of `range` (level `m`) as two triangles,
/// clipped against the near plane. Returns the triangles emitted.
#[allow(clippy::too_many_arguments)] // per-patch values computed once by the caller
fn emit_cell_triangles(
    work: &mut ChunkWork,
    p: &PreparedPatch,
    m: usize,
    range: NodeRange,
    map: &Mat3,
    t0: Vec3,
    index: u32,
    frame: &ShadeFrame,
    setup: &FrameSetup<'_>,
) -> u64 {
    let level = p.level(m);
    let lmap = level_map(map, m);
    let (cols, rows) = (range.i1 - range.i0 + 1, range.j1 - range.j0 + 1);
    let mut vertices = std::mem::take(&mut work.vertices);
    vertices.clear();
    let mut used = 0;
    for j in range.j0..=range.j1 {
        for i in range.i0..=range.i1 {
            let k = j * level.cols + i;
            let d = level.displacements[k];
            let v = if level.used[k] {
                used += 1;
                ClipVertex {
                    clip: lmap * Vec3::new(i as f32, j as f32, d as f32) + t0,
                    attrs: node_attributes(&mut work.normals, p, m, level, i, j, frame, setup),
                }
            } else {
                ClipVertex {
                    clip: Vec3::ZERO,
                    attrs: [0.0; TRI_ATTRS],
                }
            };
            vertices.push(v);
        }
    }
    work.counters.patch_nodes += used;
    let near = setup.view.near as f32;
    let size = (setup.view.width as f32, setup.view.height as f32);
    let mut emitted = 0;
    for cj in 0..rows - 1 {
        for ci in 0..cols - 1 {
            if !level.cell_is_drawable(range.i0 + ci, range.j0 + cj) {
                continue;
            }
            let k = cj * cols + ci;
            let (v00, v10, v01, v11) = (
                vertices[k],
                vertices[k + 1],
                vertices[k + cols],
                vertices[k + cols + 1],
            );
            let a = v00.attrs;
            let flat = pack_colour(Vec3::new(a[0], a[1], a[2]));
            for tri in [[v00, v10, v11], [v00, v11, v01]] {
                match clip_and_project(&tri, near, size, index, flat, &mut work.triangles) {
                    ClipOutcome::Dropped => {}
                    ClipOutcome::Whole => emitted += 1,
                    ClipOutcome::Clipped(c) => {
                        emitted += c as u64;
                        work.counters.triangles_clipped += 1;
                    }
                }
            }
        }
    }
    work.counters.triangles += emitted;
    work.vertices = vertices;
    emitted
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subdivision_is_anisotropic_and_keeps_sub_cells_below_a_pixel() {
        assert_eq!(choose_subdivision([0.3, 0.2, 0.2, 0.4], 1.0), Some((1, 1)));
        // Foreshortened along v: cut along u only.
        let (nu, nv) = choose_subdivision([3.0, 0.0, 0.0, 0.4], 1.0).unwrap();
        assert_eq!(nv, 1);
        assert!(3.0 / (nu as f32) < SUBPIXEL_LIMIT && nu <= 4);
        let (nu, nv) = choose_subdivision([2.0, 2.0, 2.0, 2.0], 1.0).unwrap();
        assert!(2.0 / (nu as f32) + 2.0 / (nv as f32) < SUBPIXEL_LIMIT);
        assert_eq!(choose_subdivision([500.0, 0.0, 0.0, 1.0], 1.0), None);
    }
}
