use glam::Vec3;
use spatch_fixtures::shapes;
use spatch_mesh::{build_face_adjacency, TriangleMesh};
use spatch_segment::{segment, SegmentOptions};

use crate::{assert_valid, mesh_of};

fn check(mesh: &TriangleMesh) -> usize {
    let adjacency = build_face_adjacency(mesh);
    let options = SegmentOptions::default();
    let (seg, _) = segment(mesh, &adjacency, &options).expect("segments");
    assert_valid(mesh, &adjacency, &seg, options.merge_angle_deg.to_radians());
    seg.len()
}

#[test]
fn sliver_fan_is_one_region() {
    let (mesh, _) = mesh_of(&shapes::sliver_fan(200));
    assert_eq!(check(&mesh), 1);
}

#[test]
fn zero_area_faces_land_in_exactly_one_region() {
    // A strip of quads with collinear and point-like triangles wedged between them, plus an
    // isolated point triangle and a face whose corners are all one vertex.
    let mut positions = vec![];
    let mut triangles = vec![];
    for i in 0..10u32 {
        let x = i as f32;
        positions.extend([Vec3::new(x, 0.0, 0.0), Vec3::new(x, 1.0, 0.0)]);
        if i > 0 {
            let (a, b, c, d) = (2 * i - 2, 2 * i - 1, 2 * i, 2 * i + 1);
            triangles.extend([[a, c, b], [b, c, d]]);
            triangles.push([a, c, a]); // repeated vertex
        }
    }
    let m = positions.len() as u32;
    positions.extend([Vec3::new(0.5, 0.0, 0.0), Vec3::splat(5.0)]);
    triangles.push([0, m, 2]); // collinear, shares edges with the strip
    triangles.push([m + 1, m + 1, m + 1]); // a point
    let mesh = TriangleMesh::new(positions, triangles).expect("valid");
    check(&mesh);

    // Only degenerate faces.
    let flat = TriangleMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
        vec![[0, 1, 2], [0, 0, 1]],
    )
    .expect("valid");
    check(&flat);
}

#[test]
fn bow_tie_vertex_and_non_manifold_edge() {
    // Two triangles touching at one vertex (no shared edge): two components.
    let bow_tie = TriangleMesh::new(
        vec![
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
            Vec3::new(-1.0, -1.0, 0.0),
        ],
        vec![[0, 2, 1], [0, 3, 4]],
    )
    .expect("valid");
    assert_eq!(check(&bow_tie), 2);
    let (book, _) = mesh_of(&shapes::non_manifold_fan(7));
    check(&book);
}

#[test]
fn opposite_normals_across_an_edge() {
    // The same triangle twice with opposite winding, and a folded-over pair.
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(0.9, 0.9, 1e-6)];
    let mesh = TriangleMesh::new(positions, vec![[0, 1, 2], [0, 2, 1], [1, 3, 2], [1, 2, 3]])
        .expect("valid");
    assert!(check(&mesh) >= 2);
}

#[test]
fn single_triangle_empty_mesh_and_disconnected_components() {
    let (one, _) = mesh_of(&shapes::single_triangle());
    assert_eq!(check(&one), 1);
    let empty = TriangleMesh::new(vec![], vec![]).expect("valid");
    assert_eq!(check(&empty), 0);
    let mut two = shapes::cube(1.0);
    let other = shapes::cube(1.0).translated([5.0, 0.0, 0.0]);
    let base = two.positions.len() as u32;
    two.positions.extend(other.positions);
    two.triangles
        .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    let (mesh, _) = mesh_of(&two);
    assert_eq!(check(&mesh), 12);
}
