//! The error type of the renderer.

/// What is wrong with a camera.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum CameraProblem {
    /// A coordinate or angle is NaN or infinite.
    #[error("a coordinate or angle is not a finite number")]
    NotFinite,
    /// The eye and the target are the same point.
    #[error("eye and target are the same point")]
    EyeIsTarget,
    /// An eye or target coordinate is beyond [`crate::Camera::MAX_COORDINATE`].
    #[error(
        "the eye or the target is too far from the origin: each coordinate must be within ±1e15"
    )]
    TooFar,
    /// The up vector is zero or parallel to the viewing direction.
    #[error("the up vector is zero or parallel to the viewing direction")]
    UpParallelToView,
    /// The vertical field of view is outside (0, 180) degrees.
    #[error("the field of view must be in (0, 180) degrees")]
    FieldOfView,
    /// Width or height is zero or larger than the supported maximum.
    #[error("the image size must be 1..={max} pixels per side (after supersampling)")]
    ImageSize {
        /// The largest supported side.
        max: u32,
    },
    /// The near plane is not positive or not in front of the far plane.
    #[error("near must be positive and smaller than far")]
    ClipPlanes,
    /// The bounding sphere given for framing is empty or degenerate.
    #[error("nothing to frame: the scene is empty")]
    NothingToFrame,
}

/// Why rendering failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// The camera is unusable (caller's input).
    #[error("invalid camera: {0}")]
    InvalidCamera(CameraProblem),
    /// An option is out of its valid range (caller's input).
    #[error("invalid render option {name}: {reason}")]
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// What the valid range is.
        reason: &'static str,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error(
        "triangle {triangle} refers to vertex {vertex}, but the mesh has {vertex_count} vertices"
    )]
    TriangleIndexOutOfRange {
        /// The triangle's index.
        triangle: usize,
        /// The offending vertex index.
        vertex: u32,
        /// The number of vertices.
        vertex_count: usize,
    },
    /// A mesh position is NaN or infinite.
    #[error("mesh vertex {vertex} is not finite")]
    NonFiniteVertex {
        /// The vertex index.
        vertex: usize,
    },
    /// The colour array of a mesh does not match its vertices or corners.
    #[error("mesh colours: expected {expected} entries ({what}), found {found}")]
    MeshColourCount {
        /// "one per vertex" or "one per triangle corner".
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// The worker thread pool could not be started.
    #[error("could not start {threads} render threads: {source}")]
    ThreadPool {
        /// The requested thread count.
        threads: usize,
        /// The cause.
        source: rayon::ThreadPoolBuildError,
    },
    /// Encoding a PNG failed.
    #[error("could not encode {what} PNG: {source}")]
    Encode {
        /// "colour" or "depth".
        what: &'static str,
        /// The cause.
        source: image::ImageError,
    },
    /// An internal invariant failed: this is a bug in spatch-render.
    #[error("internal error in the renderer (this is a bug): {0}")]
    Bug(&'static str),
}

/// Not `#[from]`: that would also make the problem the error's source, and a
/// report of the whole chain would then say it twice ("invalid camera: X: X").
impl From<CameraProblem> for RenderError {
    fn from(problem: CameraProblem) -> Self {
        RenderError::InvalidCamera(problem)
    }
}
