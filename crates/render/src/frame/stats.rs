//! Rendering statistics: the rows of the original work's rendering table,
//! what culling, splitting, the optimized path and the mip pyramid did, and
//! time per stage. Serialized as the `--stats` JSON (keys documented in
//! `docs/algorithms/render.md`).
//!
//! Counts are gathered per chunk of patches (fixed chunks, independent of
//! the thread count) and summed, so they are deterministic. Stage times
//! inside parallel stages are CPU time summed over threads; `*_wall` times
//! are elapsed time.

use serde::Serialize;

use crate::options::RenderOptions;
use crate::plan::counters::Counters;

/// Time per stage, milliseconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StageTimes {
    /// Frustum and normal-cone tests (CPU time over threads).
    pub cull: f64,
    /// Splitting partially visible patches (CPU).
    pub split: f64,
    /// Node projection and cell measuring (CPU).
    pub traverse: f64,
    /// Normals (through the buffer) and per-node shading attributes (CPU).
    pub normals: f64,
    /// Triangle set-up: transform, clip, project (CPU; triangle paths).
    pub triangle_setup: f64,
    /// Placing nodes and subdividing cells into the tiles (CPU).
    pub cells: f64,
    /// Scan-line filling of triangles (CPU).
    pub triangles: f64,
    /// Per-pixel resolve: deferred Phong shading and depth (CPU).
    pub resolve: f64,
    /// The whole per-patch planning stage (elapsed).
    pub plan_wall: f64,
    /// Sorting work into tiles (elapsed).
    pub bin_wall: f64,
    /// Rasterizing and resolving all tiles (elapsed).
    pub raster_wall: f64,
    /// Assembling the image and supersampling reduction (elapsed).
    pub gather_wall: f64,
    /// The frame from start to finish (elapsed).
    pub total_wall: f64,
}

/// One band of rows of the framebuffer: where it lies, what was binned to
/// it and how long its thread took over it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct BandStats {
    /// First row (internal resolution).
    pub y0: u32,
    /// Rows.
    pub rows: u32,
    /// Draw items (pieces) binned to the band.
    pub items: u32,
    /// Triangles binned to the band.
    pub triangles: u32,
    /// The planned work that decides the order in which threads take the
    /// bands (heaviest first), in estimated samples.
    pub work: f64,
    /// Drawing and resolving the band, milliseconds (one thread).
    pub ms: f64,
    /// Index of the pool thread that drew it (varies from run to run).
    pub thread: usize,
}

/// What one frame did (see the module header).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct RenderStats {
    /// Image width × height in pixels.
    pub image: [u32; 2],
    /// Internal (supersampled) width × height.
    pub internal: [u32; 2],
    /// Near and far planes used.
    pub near_far: [f64; 2],
    /// Worker threads.
    pub threads: usize,
    /// The instruction set the frame's kernels ran with: `"x86-64-v3"`
    /// (AVX2 and FMA, detected at run time) or `"base"` (the portable
    /// build's; [`RenderOptions::simd`] false or no AVX2).
    pub kernels: &'static str,
    /// Tiles (bands of rows) rendered.
    pub tiles: usize,
    /// Each band, top to bottom.
    pub bands: Vec<BandStats>,
    /// Patches considered (with at least one drawable cell).
    pub patches: u64,
    /// Patches outside the view frustum.
    pub patches_culled_frustum: u64,
    /// Patches whose normal cone faces away from the eye.
    pub patches_culled_backface: u64,
    /// Cells of drawn patches skipped because they face away from the eye
    /// everywhere (`--cull back`, bilinear cells).
    pub cells_culled_backface: u64,
    /// Patches split because they were partially visible.
    pub patches_split: u64,
    /// Pieces drawn from split patches.
    pub split_pieces: u64,
    /// Pieces of split patches dropped as outside.
    pub split_pieces_dropped: u64,
    /// Single cells clipped against the near plane by the triangle path.
    pub clipped_cells: u64,
    /// Pieces whose cells were too large to subdivide (drawn as triangles).
    pub oversized_pieces: u64,
    /// Pieces drawn by the optimized path (nodes only, no interpolation).
    pub patches_optimized: u64,
    /// Pieces drawn with cell interpolation.
    pub patches_interpolated: u64,
    /// Pieces drawn by splatting their nodes (pixel-sized cells, see
    /// `RenderOptions::splat_limit`).
    pub patches_splatted: u64,
    /// Pieces drawn per mip level (index = level).
    pub mip_levels: Vec<u64>,
    /// Nodes projected.
    pub patch_nodes: u64,
    /// Sub-nodes placed by cell interpolation (beyond the nodes).
    pub interpolated_nodes: u64,
    /// Normals needed (one per projected node when shading needs them).
    pub normals_needed: u64,
    /// Normals computed with a normal buffer cleared per patch, in % of needed.
    pub normals_computed_with_buffer_percent: f64,
    /// Normals computed with the buffer kept across patches ordered by
    /// ratio, in % of needed.
    pub normals_computed_with_ordering_percent: f64,
    /// Triangles rasterized (triangle mode, clipped or oversized cells, meshes).
    pub triangles: u64,
    /// Triangles cut by the near plane.
    pub triangles_clipped: u64,
    /// Mesh triangles dropped by back-face culling.
    pub triangles_culled: u64,
    /// Pixels showing a surface.
    pub covered_pixels: u64,
    /// Pieces (in (piece, band) pairs) left out by the occlusion skip:
    /// hidden behind the pixels already drawn in their band
    /// ([`RenderOptions::occlusion_skip`]).
    pub pieces_skipped_hidden: u64,
    /// Time per stage.
    pub times_ms: StageTimes,
    /// The options used.
    pub options: Option<RenderOptions>,
}

impl RenderStats {
    /// Fills the counters from summed chunk counters.
    pub(crate) fn set_counters(&mut self, c: &Counters) {
        self.patches = c.patches;
        self.patches_culled_frustum = c.culled_frustum;
        self.patches_culled_backface = c.culled_backface;
        self.cells_culled_backface = c.cells_backface;
        self.patches_split = c.split;
        self.split_pieces = c.split_pieces;
        self.split_pieces_dropped = c.pieces_dropped;
        self.clipped_cells = c.clipped_cells;
        self.oversized_pieces = c.oversized_pieces;
        self.patches_optimized = c.optimized;
        self.patches_interpolated = c.interpolated;
        self.patches_splatted = c.splatted;
        let used = c.mip.iter().rposition(|&v| v > 0).map_or(0, |k| k + 1);
        self.mip_levels = c.mip[..used].to_vec();
        self.patch_nodes = c.patch_nodes;
        self.interpolated_nodes = c.interpolated_nodes;
        self.normals_needed = c.normals.needed;
        let pct = |v: u64| {
            if c.normals.needed == 0 {
                0.0
            } else {
                100.0 * v as f64 / c.normals.needed as f64
            }
        };
        self.normals_computed_with_buffer_percent = pct(c.normals.computed_per_patch_buffer);
        self.normals_computed_with_ordering_percent = pct(c.normals.computed_ordered_buffer);
        self.triangles = c.triangles;
        self.triangles_clipped = c.triangles_clipped;
        self.triangles_culled = c.triangles_culled;
        let ms = |ns: u64| ns as f64 / 1e6;
        self.times_ms.cull = ms(c.cull_ns);
        self.times_ms.split = ms(c.split_ns);
        self.times_ms.traverse = ms(c.traverse_ns);
        self.times_ms.normals = ms(c.normals_ns);
        self.times_ms.triangle_setup = ms(c.setup_ns);
    }
}
