//! Sharp-edge patches: closing the gaps where two surfaces meet at a crease.
//!
//! Surface patches are fitted per region and seen along the region's mean normal. Where two
//! regions meet at a sharp edge (a cylinder's rim, a cube's edge) neither patch can see the
//! other face, and each ends at its last node on its own face: a strip up to one cell wide
//! along the edge is left empty, as the corners of a rasterized disc are. This crate finds
//! those edges and adds small patches of higher resolution seen from between the two faces:
//!
//! - [`detect_sharp_edges`]: edges whose faces' normals differ by at least the crease angle,
//!   chained into polylines ([`CreaseChain`]) that stop at corners (three or more creases)
//!   and ends ([`SharpEdges`]);
//! - [`generate_edge_patches`]: the creases the surface patches already cover set aside (a
//!   crease inside a region, or one a fitted rectangle ends on exactly), the other creases'
//!   chains cut into nearly straight pieces; one patch per
//!   piece with x along the edge and z along the bisector of the two faces' normals, covering
//!   a strip on both faces at `resolution` times the surface node density; pieces meeting
//!   at a crease vertex joined into one patch where it covers all they covered; one patch
//!   per corner; nodes ray-cast against the source and quantized and coloured as the fitter does
//!   (`spatch-fit`). [`EdgeStats`] counts what was found and made;
//! - [`generate_part_edge_patches`]: the same for one tile of a tiled mesh, making only the
//!   creases and corners the tile owns, so that every crease is covered by one tile.
//!
//! Options are in [`EdgeOptions`]; errors in [`EdgeError`].
//!
//! ```
//! use glam::Vec3;
//! use spatch_edges::{generate_edge_patches, EdgeOptions};
//! use spatch_mesh::{build_face_adjacency, TriangleMesh};
//!
//! // Two squares folded 90° along the x axis: one crease.
//! let mesh = TriangleMesh::new(
//!     vec![
//!         Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0),
//!         Vec3::Z, Vec3::new(1.0, 0.0, 1.0),
//!     ],
//!     vec![[0, 1, 2], [2, 1, 3], [1, 0, 4], [1, 4, 5]],
//! )?;
//! let adjacency = build_face_adjacency(&mesh);
//! // No surface patches yet, so the crease is a gap to close.
//! let (patches, stats) = generate_edge_patches(&mesh, &adjacency, &[], 0.1, &EdgeOptions::default())?;
//! assert_eq!(stats.creases, 1);
//! assert_eq!(stats.chains, 1);
//! assert!(!patches.is_empty());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod chain_runs;
mod corner_patch;
mod coverage;
mod covered_pieces;
mod edge_patch;
mod error;
mod generate;
mod joined_pieces;
mod lattice_cast;
mod lattice_raster;
mod options;
mod part;
mod sharp_edges;

pub use coverage::{
    COVER_TOLERANCE, MAX_FACING_ANGLE_DEG, MAX_PROBES_ALONG, PROBE_OFFSETS, SOFT_COVER_TOLERANCE,
};
pub use error::EdgeError;
pub use generate::{generate_edge_patches, generate_part_edge_patches, EdgeStats};
pub use options::{
    EdgeOptions, DEFAULT_CREASE_ANGLE_DEG, DEFAULT_MAX_COLS, DEFAULT_MAX_STRAY,
    DEFAULT_MAX_TURN_DEG, DEFAULT_RESOLUTION, DEFAULT_SOFT_CREASE_DEG, DEFAULT_STRIP_WIDTH,
};
pub use part::OwnsPoint;
pub use sharp_edges::{detect_sharp_edges, Crease, CreaseChain, SharpEdges, KNIFE_ANGLE_DEG};
