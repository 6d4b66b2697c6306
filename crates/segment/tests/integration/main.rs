//! Integration tests of spatch-segment, one binary (each test binary links separately, which
//! matters on a 2-core machine). Shared checks live here; the modules:

/// Stage 1 on its own: cone bound θ1, refusals, seeds.
mod cone_growing;
/// Degenerate inputs: sliver fan, zero-area faces, bow-tie vertex, opposite normals, …
mod degenerate;
/// Stage 3 on its own: θ3, `max_extent`, `min_region_faces`.
mod merge;
/// The whole pipeline: cube, sphere, determinism, errors, the bunny from shared data.
mod pipeline;
/// Property tests on random soups and perturbed shapes.
mod properties;
/// Stage 2 on its own: compactness against stage 1, bound θ1, leftovers.
mod secondary_growth;

use std::collections::VecDeque;

use glam::Vec3;
use spatch_fixtures::Shape;
use spatch_mesh::{build_face_adjacency, FaceAdjacency, FaceId, TriangleMesh};
use spatch_segment::{RegionId, Segmentation};

/// A mesh from a fixture shape, with its adjacency.
pub(crate) fn mesh_of(shape: &Shape) -> (TriangleMesh, FaceAdjacency) {
    let positions = shape.positions.iter().map(|&p| Vec3::from(p)).collect();
    let mesh = TriangleMesh::new(positions, shape.triangles.clone()).expect("valid fixture");
    let adjacency = build_face_adjacency(&mesh);
    (mesh, adjacency)
}

/// The unit normal of a face, or `None` when it is (numerically) degenerate, judged the same
/// way as the crate: in f64, relative to the longest edge.
pub(crate) fn normal_of(mesh: &TriangleMesh, face: FaceId) -> Option<Vec3> {
    let [a, b, c] = mesh.face_positions(face).map(Vec3::as_dvec3);
    let cross = (b - a).cross(c - a);
    let longest = (b - a)
        .length_squared()
        .max((c - b).length_squared())
        .max((a - c).length_squared());
    (cross.length() > 1e-9 * longest && cross.length() > 0.0)
        .then(|| (cross / cross.length()).as_vec3())
}

/// Checks everything a segmentation promises, with every region's half-angle at most
/// `max_half_angle` radians.
pub(crate) fn assert_valid(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    seg: &Segmentation,
    max_half_angle: f32,
) {
    let n = mesh.face_count();
    assert_eq!(seg.face_region.len(), n, "one label per face");
    let mut seen = vec![false; n];
    for (r, region) in seg.regions.iter().enumerate() {
        assert!(!region.faces.is_empty(), "region {r} is empty");
        assert!(
            region.faces.windows(2).all(|w| w[0] < w[1]),
            "region {r} faces not sorted ascending"
        );
        assert!(
            region.faces.binary_search(&region.seed).is_ok(),
            "seed of {r} outside"
        );
        assert!(
            (region.axis.length() - 1.0).abs() < 1e-4,
            "axis of {r} not unit"
        );
        assert!(
            region.half_angle <= max_half_angle + 1e-5,
            "region {r}: half-angle {}° above {}°",
            region.half_angle.to_degrees(),
            max_half_angle.to_degrees()
        );
        for &f in &region.faces {
            assert!(!seen[f.index()], "{f:?} in two regions");
            seen[f.index()] = true;
            assert_eq!(seg.face_region[f.index()], RegionId(r as u32));
            if let Some(normal) = normal_of(mesh, f) {
                let angle = spatch_segment::cone::angle_between(region.axis, normal);
                assert!(
                    angle <= region.half_angle + 1e-5,
                    "{f:?} normal {}° from the axis of region {r} (half-angle {}°)",
                    angle.to_degrees(),
                    region.half_angle.to_degrees()
                );
            }
        }
        assert_connected(adjacency, seg, r);
    }
    assert!(seen.iter().all(|&s| s), "a face is in no region");
}

/// Checks that region `r` is connected through the adjacency.
fn assert_connected(adjacency: &FaceAdjacency, seg: &Segmentation, r: usize) {
    let region = &seg.regions[r];
    let id = RegionId(r as u32);
    let mut reached = std::collections::HashSet::new();
    let mut queue = VecDeque::from([region.faces[0]]);
    reached.insert(region.faces[0]);
    while let Some(f) = queue.pop_front() {
        for &g in adjacency.neighbours(f) {
            if seg.face_region[g.index()] == id && reached.insert(g) {
                queue.push_back(g);
            }
        }
    }
    assert_eq!(
        reached.len(),
        region.faces.len(),
        "region {r} is not connected"
    );
}

/// `perimeter² / area` of a region (a disc gives 4π ≈ 12.6, a square 16, a 1×n strip about
/// 4n): the perimeter is the length of the edges shared with other regions or on the mesh
/// boundary.
pub(crate) fn isoperimetric_ratio(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    seg: &Segmentation,
    r: usize,
) -> f32 {
    let id = RegionId(r as u32);
    let mut perimeter = 0.0;
    for (v0, v1, faces) in adjacency.edges() {
        let inside = faces
            .iter()
            .filter(|f| seg.face_region[f.index()] == id)
            .count();
        if inside > 0 && inside < faces.len().max(2) {
            perimeter += mesh.positions[v0.index()].distance(mesh.positions[v1.index()]);
        }
    }
    perimeter * perimeter / seg.regions[r].area
}
