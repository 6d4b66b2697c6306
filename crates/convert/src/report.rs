//! What a conversion reports: stage timings and counts.

use serde::Serialize;
pub use spatch_report::{Counts, StageTime};

/// What preparation changed (see `spatch_mesh::PrepareReport`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct PrepareCounts {
    /// Vertices and faces before.
    pub input_vertices: usize,
    /// Faces before.
    pub input_faces: usize,
    /// Vertices merged into an identical one.
    pub welded_vertices: usize,
    /// Faces dropped for a repeated vertex.
    pub dropped_degenerate: usize,
    /// Faces dropped for zero area.
    pub dropped_zero_area: usize,
    /// Faces dropped because an earlier face has the same three vertices (either winding).
    pub dropped_duplicate: usize,
    /// Of `dropped_duplicate`, those wound against the face they repeat (a two-sided export).
    pub dropped_mirrored: usize,
    /// Repeated faces kept because dropping them would open the surface (a flap of copies).
    pub kept_repeats: usize,
    /// Vertices after.
    pub output_vertices: usize,
    /// Faces after.
    pub output_faces: usize,
}

/// What orientation changed (see `spatch_mesh::OrientReport`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct OrientCounts {
    /// Connected pieces of the surface.
    pub pieces: usize,
    /// Faces whose winding was turned over.
    pub flipped_faces: usize,
    /// Pieces the file wound inward (most of their area turned over).
    pub inward_pieces: usize,
    /// Whether the file wound most of its surface inward: the scene's patches are then
    /// marked two-sided (it may be a room seen from inside).
    pub wound_inward: bool,
    /// Edges whose two faces no winding makes agree (a non-orientable seam): the scene's
    /// patches are then marked two-sided.
    pub conflicting_edges: usize,
}

impl From<spatch_mesh::OrientReport> for OrientCounts {
    fn from(r: spatch_mesh::OrientReport) -> Self {
        Self {
            pieces: r.pieces,
            flipped_faces: r.flipped_faces,
            inward_pieces: r.inward_pieces,
            wound_inward: r.wound_inward,
            conflicting_edges: r.conflicting_edges,
        }
    }
}

/// Timings and counts of one conversion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConvertReport {
    /// Sizes of the scene and of its encoded `.spatch` (serialized as the
    /// keys `patches`, `nodes`, `filled_nodes` and `bytes`).
    #[serde(flatten)]
    pub counts: Counts,
    /// Total wall time of the stages, in seconds.
    pub seconds: f64,
    /// Each stage's wall time, in pipeline order: `load`, `prepare`,
    /// `adjacency`, `orient`, `segment`, `fit`, `edges`, `sides`, `encode`.
    pub stages: Vec<StageTime>,
    /// Worker threads available to the parallel stages.
    pub threads: usize,
    /// Node spacing used (model units).
    pub spacing: f32,
    /// Source triangles (after preparation).
    pub triangles: usize,
    /// Regions found by the segmenter.
    pub regions: usize,
    /// Regions split into several patches by the fitter.
    pub split_regions: usize,
    /// Thin regions that gave no patch at the target spacing and were fitted at a finer one
    /// (`spatch_fit::MAX_REFINEMENTS`).
    pub refined_regions: usize,
    /// Patches with 16-bit displacements.
    pub wide_patches: usize,
    /// How much texture detail the fit kept (texels per node, texels, estimated nodes
    /// against the budget), or `None` when no region is textured.
    pub texture: Option<spatch_fit::TextureDetail>,
    /// What the colour grids kept (patches, samples, factor, bytes against the budget), or
    /// `None` when no patch has one.
    pub colour_grids: Option<crate::ColourGridReport>,
    /// Colour channel of the scene: `none`, `rgb8` or `rgba8`.
    pub colour: &'static str,
    /// Length of the source's bounding-box diagonal (model units).
    pub diagonal: f64,
    /// What preparation changed.
    pub prepare: PrepareCounts,
    /// What orientation changed, or `None` when it did not run (turned off, or a tile's
    /// part).
    pub orient: Option<OrientCounts>,
    /// What the loader worked around, as readable sentences.
    pub warnings: Vec<String>,
    /// What the sharp-edge stage found and made, or `None` when it was off.
    pub edges: Option<spatch_edges::EdgeStats>,
    /// Bytes the edge patches add to the file (the scene encoded with them minus without).
    pub edge_bytes: usize,
    /// Visible sides: boundary edges and openings of the source, patches that may be seen
    /// from behind.
    pub sides: crate::SideCounts,
}

impl ConvertReport {
    /// The seconds of the stage called `name`, if it ran.
    pub fn stage_seconds(&self, name: &str) -> Option<f64> {
        self.stages
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.seconds)
    }
}
