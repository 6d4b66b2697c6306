//! The error type of the fitter.

use spatch_format::FormatError;

/// Why regions could not be fitted.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FitError {
    /// An option is out of its documented range (the caller's fault).
    #[error("invalid fit options: {reason}")]
    InvalidOptions {
        /// Which rule was broken.
        reason: &'static str,
    },
    /// The mesh has no face of non-zero area, so no spacing can be derived and nothing can be
    /// fitted.
    #[error("the mesh has no surface (every face has zero area)")]
    NoSurface,
    /// A region's cone axis is not a finite unit vector (the caller's fault).
    #[error("region {region}: the cone axis is not a finite non-zero vector")]
    InvalidAxis {
        /// Index of the region in the input list.
        region: usize,
    },
    /// A region names a face the mesh does not have (the caller's fault).
    #[error("region {region}: face {face} is out of range (the mesh has {face_count} faces)")]
    FaceOutOfRange {
        /// Index of the region in the input list.
        region: usize,
        /// The face index.
        face: u32,
        /// Faces in the mesh.
        face_count: usize,
    },
    /// The spacing is so fine for this region that its node lattice would be too large.
    #[error(
        "region {region} would need {nodes} nodes at spacing {spacing} (limit {limit}): \
         use a larger spacing"
    )]
    TooManyNodes {
        /// Index of the region in the input list.
        region: usize,
        /// Lattice nodes the region would need.
        nodes: u64,
        /// The node spacing in use.
        spacing: f32,
        /// [`FitOptions::max_region_nodes`](crate::FitOptions::max_region_nodes).
        limit: usize,
    },
    /// A frame, grid or patch the fitter built was refused by `spatch-format`: this is a bug.
    #[error("internal error while building a patch (this is a bug): {0}")]
    Bug(#[from] FormatError),
}
