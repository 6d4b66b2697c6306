//! Region → spatial patches: the patch fitter of spatch.
//!
//! [`fit_regions`] takes a mesh, its face adjacency and a list of regions ([`FitRegion`]: the
//! faces of one piece of surface and the axis of their normal cone, as the segmenter makes
//! them) and returns patches ([`FitOutput`]):
//!
//! - the frame's z axis is the cone axis, x and y follow the smallest rectangle around the
//!   region's projection (rotating calipers over the convex hull);
//! - nodes lie on a lattice of the requested spacing ([`FitOptions::spacing`], by default
//!   [`default_spacing`] from the source's triangle size; a thin region that would give no
//!   patch at that spacing is fitted again at a finer one, see [`MAX_REFINEMENTS`]); regions
//!   wider than [`FitOptions::grid`] nodes are split into patches on one shared lattice;
//! - each node takes the height of the first hit of a ray along −z that lands on the region or
//!   on its neighbourhood (faces connected to it across edges and facing the axis), so a layer
//!   of the model behind or in front of the region is never taken; nodes with no such hit are
//!   empty;
//! - patches reach into their neighbours by the cells the region touches, plus
//!   [`FitOptions::overlap`] rings, so that no crack shows between them;
//! - displacements get 8-bit codes with the step from the region's height range, 16-bit only
//!   where half that step would exceed [`FitOptions::max_step_error`];
//! - colour comes from the source (texture, vertex colours, material), and a source without
//!   colour gets no colour channel;
//! - a region whose faces carry a texture gets a node spacing from the texture's own
//!   resolution ([`FitOptions::texels_per_node`]), within a node budget
//!   ([`FitOptions::texture_budget`]); [`FitOutput::texture`] says how much detail was kept;
//!   where the texture is still finer than the nodes, the patch gets a colour grid
//!   ([`FitOptions::colour_grid_texels`]).
//!
//! ```
//! use glam::Vec3;
//! use spatch_fit::{fit_regions, FitOptions, FitRegion};
//! use spatch_mesh::{build_face_adjacency, FaceId, TriangleMesh};
//!
//! // A unit square of two triangles, seen from +z.
//! let mesh = TriangleMesh::new(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
//!     vec![[0, 1, 2], [2, 1, 3]],
//! )?;
//! let adjacency = build_face_adjacency(&mesh);
//! let faces = [FaceId(0), FaceId(1)];
//! let mut options = FitOptions::default();
//! options.spacing = Some(0.25);
//! let out = fit_regions(&mesh, &adjacency, &[FitRegion { faces: &faces, axis: Vec3::Z }], &options)?;
//! assert_eq!(out.patches.len(), 1);
//! assert_eq!(out.stats.filled_nodes, 25); // 5 × 5 nodes cover the square exactly
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod boundary_reach;
mod colour;
mod colour_grid;
mod error;
mod fit;
mod frame_fit;
mod lattice;
mod node_cast;
mod options;
mod overlap;
mod quantize;
mod texture_spacing;

pub use colour::{choose_channel, sample_colour};
pub use colour_grid::{quantize_sample, COLOUR_GRID_STEP};
pub use error::FitError;
pub use fit::{
    fit_regions, fit_regions_counted, FitOutput, FitRegion, FitStats, MAX_REFINEMENTS,
    THIN_REGION_CELLS,
};
pub use options::{default_spacing, FitOptions, SPACING_PER_TRIANGLE_SIZE};
pub use quantize::{choose_quantizer, quantize_height};
pub use texture_spacing::{TextureBudget, TextureDetail};
