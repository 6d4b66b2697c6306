//! Measuring spatch scenes against their source.
//!
//! For now: the geometric error of DESIGN §6 ([`geometric`]):
//!
//! - [`node_to_surface`]: every filled node to the nearest point of the source surface;
//! - [`surface_to_patch`]: points sampled uniformly on the source to the nearest point of the
//!   patch surface (drawable cells as bilinear quads), which reveals holes and cracks;
//! - [`geometric_error`]: both, with the sample count of DESIGN §6
//!   (`max(100_000, 10 × faces)`).
//!
//! Each gives an [`ErrorStats`] (max, RMS, 95th percentile, absolute and relative to the
//! source's bounding-box diagonal), serializable with serde.
//!
//! ```
//! use glam::Vec3;
//! use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
//! use spatch_mesh::{Bvh, TriangleMesh};
//!
//! // A unit square and one patch lying exactly on it.
//! let mesh = TriangleMesh::new(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
//!     vec![[0, 1, 2], [2, 1, 3]],
//! )?;
//! let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01)?;
//! let patch = Patch::new(frame, GridSize::new(2, 2)?, vec![0; 4], None)?;
//! let scene = Scene::new(mesh.origin, ColourChannel::None, vec![patch])?;
//! let error = spatch_eval::geometric_error(&scene, &mesh, 7);
//! assert!(error.node_to_surface.max < 1e-6);
//! assert!(error.surface_to_patch.max < 1e-6);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod cell_grid;
pub mod geometric;

pub use geometric::{
    geometric_error, node_to_surface, sample_count, surface_to_patch, ErrorStats, GeometricError,
};
