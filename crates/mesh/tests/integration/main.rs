//! Integration tests of spatch-mesh, one binary (each test binary links separately, which
//! matters on a 2-core machine).
//!
//! Modules:
//! - `load_real`: the real files of `../shared/data` (skipped politely when absent);
//! - `load_errors`: hostile and broken inputs written to a temporary folder: NaN, truncation,
//!   bad indices, missing materials and textures; never a panic;
//! - `gltf_compressed`: gltfpack's quantized and meshopt files against the f32 original;
//!   hostile URIs and accessor indices;
//! - `issue_22_triangulation`: polygon faces: convex ones fanned as before, concave ones ear
//!   clipped (area kept, none inverted), self-crossing ones reported;
//! - `issue_20_loaders`: BOM, CR-only PLY headers, extents beyond f32, outside references;
//! - `regression_inputs`: the STL, glTF and tristrips fuzz inputs kept in testdata/regression;
//! - `adjacency`: face adjacency on generated shapes, non-manifold fans, winding;
//! - `prepare`: welding and cleaning counts;
//! - `ply_points`: the direct binary PLY cloud reader against the general one;
//! - `stl`: the STL reader on files written by stl_io and by hand;
//! - `tristrips`: PLY triangle strips against the same mesh as a face list;
//! - `queries`: BVH ray casts and closest points against brute force; surface sampling.

mod adjacency;
mod gltf_compressed;
mod issue_20_loaders;
mod issue_22_triangulation;
mod load_errors;
mod load_real;
mod ply_points;
mod prepare;
mod queries;
mod regression_inputs;
mod stl;
mod tristrips;

use spatch_fixtures::Shape;
use spatch_mesh::TriangleMesh;

/// A generated shape as a mesh with origin zero.
pub(crate) fn mesh_from_shape(shape: &Shape) -> TriangleMesh {
    TriangleMesh::new(
        shape
            .positions
            .iter()
            .map(|&p| glam::Vec3::from_array(p))
            .collect(),
        shape.triangles.clone(),
    )
    .expect("generated shapes are valid meshes")
}
