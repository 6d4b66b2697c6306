//! The per-patch plan: everything decided once per patch and frame before
//! any pixel is touched (as tiny-skia compiles a pipeline before running it).
//!
//! For each patch, in drawing order, on fixed chunks of
//! [`PATCH_CHUNK`](crate::plan::work::PATCH_CHUNK) patches (so results and
//! counts do not depend on the thread count):
//! 1. back-face test on the normal cone, then the frustum test of its box
//!    ([`crate::plan::cull`]); partially visible patches are split
//!    ([`crate::plan::split`]);
//! 2. the patch's context ([`PatchContext`]: local map, shade frame,
//!    whether its cells are face-tested), then each piece is planned
//!    ([`plan_piece`]: mip level, traversal, subdivision, attributes);
//! 3. single cells crossing the near plane go to the triangle path
//!    ([`crate::plan::cell_triangles`]).
//!
//! The output of a chunk is a list of draw items (node ranges with their
//! `n` and screen rows), the nodes they refer to, and projected triangles
//! ([`ChunkWork`]).
//!
//! Cost: O(visible nodes) per frame.

use glam::{Mat3, Vec3};

use crate::lighting::ShadeFrame;
use crate::plan::cell_triangles::emit_cell_triangles;
use crate::plan::cull::{cone_faces_away, cone_faces_eye, BoxClass};
use crate::plan::piece::plan_piece;
use crate::plan::sides::back_culled;
use crate::plan::split::{split_patch, NodeRange};
use crate::plan::work::{ChunkWork, FrameSetup, PatchContext};
use crate::prepare::patch::PreparedPatch;

/// Plans the patches of one chunk; `first_index` is the drawing index of
/// `patches[0]` and `frames` receives one shade frame per patch.
#[inline(always)]
pub(crate) fn plan_chunk(
    work: &mut ChunkWork,
    patches: &[PreparedPatch],
    first_index: u32,
    frames: &mut [ShadeFrame],
    setup: &FrameSetup<'_>,
) {
    work.reset(setup.options.stage_times);
    reserve_level_zero(work, patches);
    let eye = setup.view.eye;
    for (local, p) in patches.iter().enumerate() {
        let index = first_index + local as u32;
        work.counters.patches += 1;
        let mode = (
            setup.options.culling,
            p.sides,
            setup.two_sided_through_openings,
        );
        // A patch whose cone faces the eye entirely shows only its front,
        // whatever the openings: its back is culled without the portal
        // test (a raw scan spent about half its planning on that test).
        let facing_eye = cone_faces_eye(&p.cone, p.centre, p.radius, eye);
        let culled = facing_eye || back_culled(mode, setup.portals, p.centre, p.radius);
        if culled && cone_faces_away(&p.cone, p.centre, p.radius, eye) {
            work.counters.culled_backface += 1;
            work.counters.cull_ns += work.clock.lap();
            continue;
        }
        // Lit two-sided (each sample facing away flipped) only where the
        // patch's back may show. A patch whose back is culled shows its
        // front even where its cone's axis faces away: an edge patch bent
        // over a crease, or a patch whose margin overlaps the next face
        // (dark specks along fandisk's creases, issue 21 item 3).
        let to_eye = (!culled).then(|| eye - p.centre);
        // No cell of a patch facing the eye entirely can face away.
        let cell_test = culled && !facing_eye;
        frames[local] = setup.light.frame_in(&p.rotation, to_eye);
        let (map, t0) = setup.view.local_map(p.origin, p.axes);
        let class = frustum_pieces(work, setup, p, (&map, t0));
        if class == BoxClass::Outside {
            continue;
        }
        work.normals.begin_patch();
        let ctx = PatchContext {
            patch: p,
            index,
            map,
            t0,
            frame: &frames[local],
            whole: class == BoxClass::Inside,
            cell_test,
            setup,
        };
        let pieces = std::mem::take(&mut work.split.pieces);
        for &piece in &pieces {
            plan_piece(work, &ctx, piece);
        }
        work.split.pieces = pieces;
        if !work.split.cells.is_empty() {
            plan_single_cells(work, &ctx);
        }
    }
    work.counters.normals = work.normals.counts;
}

/// Classifies the box of patch `p` (local map and translation `map`)
/// against the frustum and leaves in `work.split` what to plan of it: the
/// whole patch when inside, the pieces and single cells of splitting when
/// partly outside ([`split_patch`]), nothing when outside (counted).
#[inline(always)]
fn frustum_pieces(
    work: &mut ChunkWork,
    setup: &FrameSetup<'_>,
    p: &PreparedPatch,
    (map, t0): (&Mat3, Vec3),
) -> BoxClass {
    let root = NodeRange::of_grid(p.grid);
    let (lo, hi) = root.local_box(p.base_d_range());
    let class = setup.frustum.classify(map, t0, lo, hi);
    work.counters.cull_ns += work.clock.lap();
    work.split.pieces.clear();
    work.split.cells.clear();
    match class {
        BoxClass::Outside => work.counters.culled_frustum += 1,
        BoxClass::Inside => work.split.pieces.push(root),
        BoxClass::Partial => {
            work.counters.split += 1;
            let counts = split_patch(p.level(0), &setup.frustum, (map, t0), root, &mut work.split);
            work.counters.split_pieces += work.split.pieces.len() as u64;
            work.counters.pieces_dropped += counts.dropped as u64;
            work.counters.split_ns += work.clock.lap();
        }
    }
    class
}

/// Draws the single cells splitting left of the patch of `ctx` (cells that
/// still cross the near plane or the guard band) as triangles, clipped.
fn plan_single_cells(work: &mut ChunkWork, ctx: &PatchContext<'_>) {
    let cells = std::mem::take(&mut work.split.cells);
    for &(i, j) in &cells {
        let range = NodeRange {
            i0: i,
            j0: j,
            i1: i + 1,
            j1: j + 1,
        };
        let emitted = emit_cell_triangles(work, ctx, 0, range, None);
        work.counters.clipped_cells += (emitted > 0) as u64;
    }
    work.split.cells = cells;
    work.counters.setup_ns += work.clock.lap();
}

/// Reserves room for every level-0 node and cell of `patches` (an upper
/// bound of what a frame plans, splits' shared rows aside), so a chunk's
/// first frame grows its vectors once instead of doubling them. Why: the
/// growth copied the nodes planned so far (7.5 M of the 265 M instructions
/// of a one-frame bunny render; callgrind, `spatch render bunny.spatch -o
/// out.png --threads 1`); once warm it is a no-op.
fn reserve_level_zero(work: &mut ChunkWork, patches: &[PreparedPatch]) {
    let (nodes, cells) = patches.iter().fold((0, 0), |(n, c), p| {
        let [cols, rows] = p.grid;
        (n + cols * rows, c + (cols - 1) * (rows - 1))
    });
    work.nodes.reserve(nodes);
    work.cell_flags.reserve(cells);
}
