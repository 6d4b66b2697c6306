//! The one error type of the edge-patch generator.

use spatch_fit::FitError;
use spatch_format::FormatError;

/// What can go wrong while generating edge patches.
///
/// `Invalid*` variants are the caller's values; `AdjacencyMismatch` is a caller passing the
/// adjacency of another mesh; `PatchBuild` is a bug in this crate.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EdgeError {
    /// An [`EdgeOptions`](crate::EdgeOptions) field is out of its documented range.
    #[error("invalid edge option `{name}`: {reason}")]
    InvalidOption {
        /// The field's name.
        name: &'static str,
        /// The documented range it broke.
        reason: &'static str,
    },
    /// The surface node spacing is not a positive finite number.
    #[error("invalid surface spacing {spacing}: must be positive and finite")]
    InvalidSpacing {
        /// The spacing given.
        spacing: f32,
    },
    /// The face adjacency was built for another mesh.
    #[error("the face adjacency has {adjacency_faces} faces but the mesh has {mesh_faces}")]
    AdjacencyMismatch {
        /// Faces the adjacency knows.
        adjacency_faces: usize,
        /// Faces of the mesh.
        mesh_faces: usize,
    },
    /// Choosing the displacement step of an edge patch failed.
    #[error("quantizing edge patch {patch} failed")]
    Quantize {
        /// Index of the edge patch (pieces first, then corners).
        patch: usize,
        /// The fitter's error.
        source: FitError,
    },
    /// A frame, grid or patch the generator built was refused (this is a bug in spatch-edges).
    #[error("building edge patch {patch} failed (this is a bug in spatch-edges)")]
    PatchBuild {
        /// Index of the edge patch (pieces first, then corners).
        patch: usize,
        /// The format crate's error.
        source: FormatError,
    },
}
