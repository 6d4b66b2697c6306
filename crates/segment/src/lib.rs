//! The three-stage mesh segmenter of spatch: splits a triangle mesh into connected regions
//! whose normals fit in a narrow cone, so that each region is a height field over the plane
//! normal to its cone's axis and can be sampled by one (or, when large, a few) spatial patches.
//!
//! The stages, each in its own module and callable on its own:
//!
//! 1. [`grow_cones`]: from a seed face, add the adjacent face whose normal deviates least from
//!    the region's, while every normal stays in a cone of half-angle θ1;
//! 2. [`grow_secondary`]: the central face of each preliminary region seeds a simultaneous
//!    growth by surface distance, which gives compact regions;
//! 3. [`merge_regions`]: small regions join a neighbour while the union's normals stay within
//!    θ3 and the union still fits a patch.
//!
//! [`segment`] runs all three and reports [`SegmentStats`]. The result is a [`Segmentation`]:
//! [`Region`]s (sorted faces, cone axis and half-angle, area, central face) and a
//! [`RegionId`] per face. Options are in [`SegmentOptions`]; errors in [`SegmentError`].
//! The normal-cone maths is in [`cone`].
//!
//! ```
//! use glam::Vec3;
//! use spatch_mesh::{build_face_adjacency, TriangleMesh};
//! use spatch_segment::{segment, SegmentOptions};
//!
//! // Two triangles of a square, and a third folded up by 90°.
//! let mesh = TriangleMesh::new(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 1.0)],
//!     vec![[0, 1, 2], [2, 1, 3], [1, 4, 3]],
//! )?;
//! let adjacency = build_face_adjacency(&mesh);
//! let (segmentation, stats) = segment(&mesh, &adjacency, &SegmentOptions::default())?;
//! assert_eq!(segmentation.len(), 2);
//! assert_eq!(segmentation.face_region[0], segmentation.face_region[1]);
//! assert!(segmentation.regions.iter().all(|r| r.half_angle < 30f32.to_radians()));
//! assert_eq!(stats.after_merge, 2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Every stage is deterministic (ties broken by face index), single-threaded, O(n log n), and
//! handles zero-area faces, non-manifold edges, disconnected components and opposite normals.
#![forbid(unsafe_code)]

mod bounding_sphere;
mod central_face;
pub mod cone;
mod cone_growing;
mod error;
mod face_geometry;
mod merge;
mod options;
mod pipeline;
mod priority;
mod region;
mod secondary_growth;

pub use cone_growing::{grow_cones, REKEY_TOLERANCE};
pub use error::{MismatchProblem, SegmentError, SegmentOption};
pub use merge::merge_regions;
pub use options::{
    SegmentOptions, DEFAULT_CONE_ANGLE_DEG, DEFAULT_MAX_EXTENT, DEFAULT_MERGE_ANGLE_DEG,
    DEFAULT_MIN_REGION_FACES, MAX_ANGLE_DEG,
};
pub use pipeline::{segment, SegmentStats};
pub use region::{Region, RegionId, Segmentation};
pub use secondary_growth::{grow_secondary, LEFTOVER_ROUNDS};

pub(crate) use pipeline::check_inputs;
