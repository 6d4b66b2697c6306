//! Export of spatch scenes to binary little-endian PLY, the interchange
//! format MeshLab, CloudCompare and Blender read.
//!
//! - [`export_nodes_ply`]: every non-empty node as a point with `x y z`
//!   (float, model space), `nx ny nz` (float, the normal reconstructed from
//!   displacement differences, see [`spatch_format::Patch::node_normal`]) and
//!   `red green blue` (uchar) when the scene has colour.
//! - [`export_cells_ply`]: the drawable cells as a triangle mesh (two
//!   triangles per cell, split along the `(i, j)`–`(i+1, j+1)` diagonal),
//!   vertices with positions, normals and colour as above; vertices are not
//!   shared between patches.
//!
//! ```
//! let scene = spatch_sphere::build_sphere(&Default::default())?.scene;
//! let ply = spatch_export::export_nodes_ply(&scene);
//! assert!(ply.starts_with(b"ply\nformat binary_little_endian 1.0\n"));
//! # Ok::<(), spatch_sphere::SphereError>(())
//! ```
#![forbid(unsafe_code)]

mod ply;

pub use ply::{export_cells_ply, export_nodes_ply};
