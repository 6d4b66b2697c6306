//! The error type of the pipeline: one variant per stage, each wrapping that stage's error.

use spatch_fit::FitError;
use spatch_format::FormatError;
use spatch_mesh::MeshError;
use spatch_segment::SegmentError;

/// Why a conversion failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConvertError {
    /// The mesh could not be loaded (the file's fault or the system's; the error names the
    /// file).
    #[error(transparent)]
    Load(#[from] MeshError),
    /// Nothing is left to convert once degenerate and zero-area faces are dropped.
    #[error("the mesh has no surface: all {faces} faces are degenerate or have zero area")]
    NoSurface {
        /// Faces before preparation.
        faces: usize,
    },
    /// Not one patch could be fitted: the surface is thinner than the node lattice can sample
    /// even after the fitter refined the spacing of its thin regions, or hidden along every
    /// region's axis. A smaller spacing is the option to change.
    #[error(
        "no patches: the surface is too thin to sample at node spacing {spacing} (also \
         refined up to {refinements} times); set a smaller spacing with --spacing"
    )]
    NoPatches {
        /// The target node spacing (model units).
        spacing: f32,
        /// How many times the fitter refined thin regions (`spatch_fit::MAX_REFINEMENTS`).
        refinements: u32,
    },
    /// The segmenter refused its input or options.
    #[error("segmentation failed: {0}")]
    Segment(#[from] SegmentError),
    /// The fitter refused its input or options.
    #[error("fitting failed: {0}")]
    Fit(#[from] FitError),
    /// The sharp-edge patch generator refused its options.
    #[error("sharp-edge patches failed: {0}")]
    Edges(#[from] spatch_edges::EdgeError),
    /// The scene could not be built or encoded (a bug: the fitter's patches are valid by
    /// construction).
    #[error("encoding failed (this is a bug): {0}")]
    Encode(#[from] FormatError),
}
