//! Triangle meshes and point clouds for spatch: loading, preparation, adjacency and spatial
//! queries.
//!
//! The main types:
//!
//! - [`TriangleMesh`]: f32 positions relative to an f64 origin, triangles, optional per-corner
//!   UVs, vertex colours, vertex normals and [`Material`]s (with [`Texture`]s);
//! - [`PointCloud`]: positions with optional colours and normals;
//! - [`FaceAdjacency`]: faces sharing each edge, in CSR form ([`build_face_adjacency`]);
//! - [`Bvh`]: ray casting ([`Bvh::ray_cast`], [`Bvh::ray_cast_filtered`]) and closest-point
//!   queries ([`Bvh::closest_point`]);
//! - loading: [`load_mesh`] and [`load_point_cloud`] (OBJ, glTF, PLY, OFF, STL, XYZ), then
//!   [`prepare_mesh`] to weld and clean, [`orient_faces`] to wind every piece outward; [`sample_surface`] for area-uniform samples;
//! - [`triangulate_polygon`]: polygon faces to triangles (fan when convex, else ear clipping);
//! - typed ids [`FaceId`], [`VertexId`], [`MaterialId`], [`EdgeId`];
//! - [`MeshError`]: the one error type, naming the file and the element at fault.
//!
//! ```
//! use glam::Vec3;
//! use spatch_mesh::{build_face_adjacency, FaceId, TriangleMesh};
//!
//! let mesh = TriangleMesh::new(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
//!     vec![[0, 1, 2], [2, 1, 3]],
//! )?;
//! let adjacency = build_face_adjacency(&mesh);
//! assert_eq!(adjacency.neighbours(FaceId(0)), &[FaceId(1)]);
//! assert_eq!(mesh.face_normal(FaceId(1)), Vec3::Z);
//! # Ok::<(), spatch_mesh::MeshError>(())
//! ```
#![forbid(unsafe_code)]

mod adjacency;
mod bvh;
mod closest_point;
mod error;
mod ids;
pub mod load;
pub mod material;
mod mesh;
mod orient;
mod point_cloud;
mod prepare;
mod ray;
mod robust_centre;
mod sample;
mod triangulate;
mod warning;

pub use adjacency::{build_face_adjacency, Edge, FaceAdjacency, FULL_LINK_LIMIT};
pub use bvh::{Bvh, BIN_COUNT, MAX_DEPTH, MAX_LEAF_SIZE};
pub use closest_point::ClosestPoint;
pub use error::{
    BufferProblem, Element, ElementKind, GltfAttribute, GltfProblem, MeshArray, MeshError,
    MeshProblem, OutsideReason, PlyProblem, SyntaxProblem,
};
pub use ids::{EdgeId, FaceId, MaterialId, VertexId};
pub use load::{load_mesh, load_point_cloud, FileFormat, LoadedMesh, LoadedPointCloud, MAX_EXTENT};
pub use material::{Material, Texture};
pub use mesh::{Aabb, TriangleMesh};
pub use orient::{orient_faces, OrientReport, FLAT_VOLUME};
pub use point_cloud::PointCloud;
pub use prepare::{prepare_mesh, PrepareOptions, PrepareReport, WeldMode};
pub use ray::{RayHit, EDGE_TOLERANCE};
pub use robust_centre::{robust_centre, CENTRE_SAMPLES};
pub use sample::{band_of, sample_surface, SplitMix64, SurfaceSample, SurfaceSampler};
pub use triangulate::{triangulate_polygon, PolygonSplit};
pub use warning::LoadWarning;
