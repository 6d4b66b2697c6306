//! The error type of this crate.
//!
//! Split by party at fault: the caller's options ([`SegmentError::InvalidOption`]), the caller's
//! inputs not belonging together ([`SegmentError::AdjacencyMismatch`],
//! [`SegmentError::SegmentationMismatch`]), and this crate ([`SegmentError::Internal`], always a
//! bug). A mesh's geometry is never an error: zero-area faces, non-manifold edges and opposite
//! normals are handled.

use std::fmt;

/// An option of [`SegmentOptions`](crate::SegmentOptions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SegmentOption {
    /// [`SegmentOptions::cone_angle_deg`](crate::SegmentOptions::cone_angle_deg).
    ConeAngle,
    /// [`SegmentOptions::merge_angle_deg`](crate::SegmentOptions::merge_angle_deg).
    MergeAngle,
    /// [`SegmentOptions::max_extent`](crate::SegmentOptions::max_extent).
    MaxExtent,
}

impl fmt::Display for SegmentOption {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SegmentOption::ConeAngle => "cone_angle_deg",
            SegmentOption::MergeAngle => "merge_angle_deg",
            SegmentOption::MaxExtent => "max_extent",
        })
    }
}

/// Everything that can go wrong segmenting a mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SegmentError {
    /// An option is NaN or outside its documented range.
    #[error("segment option {option} = {value} is out of range (expected {expected})")]
    InvalidOption {
        /// Which option.
        option: SegmentOption,
        /// The value given.
        value: f32,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// The face adjacency was built for a mesh with a different number of faces.
    #[error("the face adjacency has {adjacency_faces} faces but the mesh has {mesh_faces}")]
    AdjacencyMismatch {
        /// Faces of the mesh.
        mesh_faces: usize,
        /// Faces the adjacency was built for.
        adjacency_faces: usize,
    },
    /// A segmentation handed to a later stage does not partition this mesh's faces.
    #[error("the input segmentation does not fit the mesh: {problem}")]
    SegmentationMismatch {
        /// What is wrong.
        problem: MismatchProblem,
    },
    /// An internal invariant failed: this is a bug in spatch-segment.
    #[error("internal error in spatch-segment (this is a bug): {what}")]
    Internal {
        /// The invariant that failed.
        what: &'static str,
    },
}

/// Why a [`Segmentation`](crate::Segmentation) does not fit a mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum MismatchProblem {
    /// `face_region` has the wrong length.
    FaceCount {
        /// Faces of the mesh.
        mesh_faces: usize,
        /// Length of `face_region`.
        labelled: usize,
    },
    /// A face names a region that does not exist (or is `INVALID`).
    RegionOutOfRange {
        /// The face.
        face: u32,
        /// The region it names.
        region: u32,
        /// Number of regions.
        regions: usize,
    },
}

impl fmt::Display for MismatchProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            MismatchProblem::FaceCount {
                mesh_faces,
                labelled,
            } => write!(
                f,
                "face_region has {labelled} entries but the mesh has {mesh_faces} faces"
            ),
            MismatchProblem::RegionOutOfRange {
                face,
                region,
                regions,
            } => write!(
                f,
                "face f#{face} is in region {region}, but there are {regions} regions"
            ),
        }
    }
}
