//! What can go wrong while measuring, split by whose fault it is.

use std::path::PathBuf;

/// An evaluation or sweep that could not be completed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EvalError {
    /// The source file could not be read as a mesh or a point cloud (the error names it).
    #[error(transparent)]
    Source(#[from] spatch_mesh::MeshError),
    /// The source mesh has no face of non-zero area to measure against.
    #[error("{}: the source has no surface (no face of non-zero area)", path.display())]
    NoSurface {
        /// The source file.
        path: PathBuf,
    },
    /// The point-cloud error could not be measured (too few points, an empty scene, …).
    #[error("{}: {source}", path.display())]
    Cloud {
        /// The source file.
        path: PathBuf,
        /// What the cloud crate reported.
        source: spatch_cloud::CloudError,
    },
    /// The source and the scene are apart: their bounding boxes do not meet, so no distance
    /// between them measures a conversion.
    #[error(
        "{}: does not overlap the scene (source spans {}, scene spans {}): nothing meaningful to measure; is it the scene's source?",
        path.display(), source_box, scene_box
    )]
    NoOverlap {
        /// The source file.
        path: PathBuf,
        /// The source's bounding box, as text (model units).
        source_box: String,
        /// The scene's bounding box, as text (model units).
        scene_box: String,
    },
    /// The scene has no filled node, so there is nothing to measure.
    #[error("the scene has no filled node")]
    EmptyScene,
    /// Rendering for the image error failed.
    #[error("rendering for the image error failed: {0}")]
    Render(#[from] spatch_render::RenderError),
    /// A sweep's conversion failed.
    #[error("converting with {setting}: {source}")]
    Convert {
        /// The sweep setting being converted (`grid 17 / cone 30 / 8-bit`).
        setting: String,
        /// What the pipeline reported.
        source: spatch_convert::ConvertError,
    },
    /// An option is out of range.
    #[error("invalid option `{name}`: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// The valid range.
        reason: &'static str,
    },
    /// Drawing the plot failed (this is a bug: it draws into memory).
    #[error("drawing the sweep plot failed (this is a bug): {0}")]
    Plot(String),
}
