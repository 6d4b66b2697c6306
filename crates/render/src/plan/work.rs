//! What planning produces and reads: the draw items of a chunk of patches
//! with their nodes, flags and triangles ([`ChunkWork`], the contract
//! between planning and the bands), the frame's constants
//! ([`FrameSetup`]) and the values planning decides once per patch
//! ([`PatchContext`]).
//!
//! Scratch vectors live in the chunk and are reused from frame to frame:
//! no allocation per patch once warm.

use glam::{Mat3, Vec3};

use crate::camera::View;
use crate::fixed::{Node, NodeAttributes};
use crate::grid::QuarteredCell;
use crate::lighting::{Material, ShadeFrame, WorldLight};
use crate::options::RenderOptions;
use crate::plan::counters::{Counters, StageClock};
use crate::plan::cull::Frustum;
use crate::plan::node_xy::NodeXY;
use crate::plan::sides::PortalsInView;
use crate::plan::split::SplitWork;
use crate::prepare::normal_buffer::NormalBuffer;
use crate::prepare::patch::PreparedPatch;
use crate::raster::centre_piece::CentreStyle;
use crate::raster::triangle_raster::{ClipVertex, ScreenTriangle};

/// Patches per unit of parallel planning work.
pub(crate) const PATCH_CHUNK: usize = 32;

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
    /// Mip level of the piece's nodes (Phong reads the prepared normals
    /// of level `level - shade_shift`).
    pub(crate) level: u8,
    /// 1 when the piece's positions come from the level above its shading
    /// level (coarse geometry, [`crate::RenderOptions::geometry_limit`]),
    /// else 0.
    pub(crate) shade_shift: u8,
    /// The piece's first node column and row in its level.
    pub(crate) i0: u16,
    pub(crate) j0: u16,
    /// Pixel rows spanned (inclusive).
    pub(crate) y0: i32,
    pub(crate) y1: i32,
    /// Pixel columns spanned (inclusive; like the rows, footprints
    /// included).
    pub(crate) x0: i32,
    pub(crate) x1: i32,
    /// A lower bound of the depth of every sample the piece places (fixed
    /// point; `i32::MIN` when none is known): the occlusion skip's key
    /// ([`crate::frame::occlusion_skip`]).
    pub(crate) z_near: i32,
    /// Every used node lies in the image's columns `1..width - 1`, so a
    /// row of cells inside a band needs no clipping at all.
    pub(crate) inside_columns: bool,
    /// Footprint half-widths in x and y (position units) of a splatted
    /// piece ([`crate::raster::splat`]); 0 for every other piece.
    pub(crate) splat: [i32; 2],
    /// Some cell has an open side ([`crate::plan::open_sides`]).
    pub(crate) open_sides: bool,
    /// The cells are drawn by pixel-centre coverage in this style
    /// ([`crate::raster::centre_piece`]); `nu × nv` is then the resolve's
    /// grid of recorded places, not a cut.
    pub(crate) centres: Option<CentreStyle>,
}

/// The cells by quarters of one draw item: a range of its chunk's
/// [`ChunkWork::quartered`]. Why beside the items rather than in
/// [`Item`]: two more words made every item 72 bytes instead of 64, and
/// the default frame, which has none, 1–2 % slower (bunny 500²).
#[derive(Debug, Clone, Copy)]
pub(crate) struct QuarteredRange {
    /// The item's index in its chunk.
    pub(crate) item: u32,
    pub(crate) cells: [u32; 2],
}

#[cfg(test)]
impl Item {
    /// A 2 × 2-node piece of frame 0 at the origin, drawn by its nodes alone and
    /// covering nothing: tests set the fields they are about.
    pub(crate) fn for_tests() -> Self {
        Item {
            first: 0,
            cols: 2,
            rows: 2,
            nu: 1,
            nv: 1,
            frame: 0,
            flags: 0,
            spans: 0,
            uniform_albedo: true,
            level: 0,
            shade_shift: 0,
            i0: 0,
            j0: 0,
            y0: 0,
            y1: 0,
            x0: 0,
            x1: 0,
            z_near: i32::MIN,
            inside_columns: true,
            splat: [0, 0],
            open_sides: false,
            centres: None,
        }
    }
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
    /// The scene's openings seen from this frame's eye (automatic
    /// culling); none for meshes.
    pub(crate) portals: &'a PortalsInView,
    /// The eye lies outside the scene's inside box: two-sided patches show
    /// their backs only through openings this frame
    /// ([`spatch_format::InsideBox`]).
    pub(crate) two_sided_through_openings: bool,
}

/// The output and scratch space of one chunk.
#[derive(Debug, Default)]
pub(crate) struct ChunkWork {
    pub(crate) nodes: Vec<Node>,
    /// Flat and Gouraud: the attributes of each node of [`Self::nodes`],
    /// by the same index (empty for Phong).
    pub(crate) node_attributes: Vec<NodeAttributes>,
    pub(crate) items: Vec<Item>,
    pub(crate) triangles: Vec<ScreenTriangle>,
    /// One flag byte per cell of each item ([`crate::grid::CELL_DRAW`], …).
    pub(crate) cell_flags: Vec<u8>,
    /// Pixel rows spanned by each row of cells of each item (see
    /// [`crate::plan::measure::measure_cells`]).
    pub(crate) row_spans: Vec<[i32; 2]>,
    /// The level-1 cells drawn by quarters of the items that have some
    /// ([`crate::plan::quartered`]).
    pub(crate) quartered: Vec<QuarteredCell>,
    /// Which items have cells by quarters, in item order.
    pub(crate) quartered_ranges: Vec<QuarteredRange>,
    pub(crate) counters: Counters,
    /// The clock of the stage timers in `counters`.
    pub(crate) clock: StageClock,
    /// Screen positions of the piece being planned (see [`NodeXY`]).
    pub(crate) xy: NodeXY,
    /// The normal buffer of the chunk (cleared per frame).
    pub(crate) normals: NormalBuffer,
    /// Splitting's pieces, single cells and stack.
    pub(crate) split: SplitWork,
    /// Scratch of [`emit_cell_triangles`](crate::plan::cell_triangles::emit_cell_triangles).
    pub(crate) vertices: Vec<ClipVertex>,
    /// Scratch of [`drop_undrawn_nodes`](crate::raster::splat::drop_undrawn_nodes).
    pub(crate) splat_scratch: Vec<u8>,
    /// Gouraud: the nodes of the piece being planned to shade (their index
    /// in [`Self::node_attributes`] and in their level's arrays).
    pub(crate) to_shade: Vec<(u32, u32)>,
}

impl ChunkWork {
    /// Clears the outputs for a new frame (keeps the allocations); the
    /// stage clock runs when `stage_times`
    /// ([`crate::RenderOptions::stage_times`]).
    pub(crate) fn reset(&mut self, stage_times: bool) {
        self.nodes.clear();
        self.node_attributes.clear();
        self.items.clear();
        self.triangles.clear();
        self.cell_flags.clear();
        self.row_spans.clear();
        self.quartered.clear();
        self.quartered_ranges.clear();
        self.counters = Counters::default();
        self.clock = StageClock::new(stage_times);
        self.normals.clear();
        self.normals.counts = Default::default();
    }
}

/// What planning decided about one patch before its pieces: computed once
/// per patch by [`plan_chunk`](crate::plan::chunk::plan_chunk) and read by
/// every piece, cell and node of it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PatchContext<'a> {
    pub(crate) patch: &'a PreparedPatch,
    /// Drawing index of the patch (the index of its shade frame).
    pub(crate) index: u32,
    /// Level 0's local map: `(i, j, d)` to window clip `(X, Y, W)` is
    /// `map · (i, j, d) + t0`.
    pub(crate) map: Mat3,
    pub(crate) t0: Vec3,
    /// The light and half vectors in patch space.
    pub(crate) frame: &'a ShadeFrame,
    /// The patch lies wholly inside the guard band (not split): its pieces
    /// may take a coarser mip level.
    pub(crate) whole: bool,
    /// Its cells are tested for facing away (back-face culling on, and the
    /// normal cone does not face the eye entirely).
    pub(crate) cell_test: bool,
    pub(crate) setup: &'a FrameSetup<'a>,
}
