//! Face adjacency on generated shapes.

use spatch_fixtures::shapes;
use spatch_mesh::{build_face_adjacency, FaceId};

use crate::mesh_from_shape;

#[test]
fn closed_shapes_have_three_neighbours_per_face() {
    for shape in [
        shapes::cube(1.0),
        shapes::icosphere(1.0, 2),
        shapes::torus(2.0, 0.5, 16, 8),
        shapes::uv_sphere(1.0, 12, 6),
    ] {
        let mesh = mesh_from_shape(&shape);
        let adj = build_face_adjacency(&mesh);
        assert_eq!(adj.boundary_edge_count(), 0);
        assert_eq!(adj.non_manifold_edge_count(), 0);
        assert_eq!(adj.edge_count() * 2, mesh.triangles.len() * 3);
        for f in mesh.faces() {
            assert_eq!(adj.neighbours(f).len(), 3, "{f:?}");
            for &g in adj.neighbours(f) {
                assert!(adj.neighbours(g).contains(&f), "asymmetric {f:?} {g:?}");
            }
        }
    }
}

#[test]
fn non_manifold_fan_links_every_wing() {
    let mesh = mesh_from_shape(&shapes::non_manifold_fan(5));
    let adj = build_face_adjacency(&mesh);
    assert_eq!(adj.non_manifold_edge_count(), 1);
    assert_eq!(adj.boundary_edge_count(), 10);
    for f in mesh.faces() {
        let expected: Vec<FaceId> = mesh.faces().filter(|&g| g != f).collect();
        assert_eq!(adj.neighbours(f), expected.as_slice());
    }
    let (v0, v1, faces) = adj.edges().find(|e| e.2.len() == 5).unwrap();
    assert_eq!((v0.0, v1.0), (0, 1));
    assert_eq!(faces.len(), 5);
}

#[test]
fn flipped_faces_still_neighbour() {
    let mut shape = shapes::cube(1.0);
    // Flip every other face: winding is now inconsistent across many edges.
    for t in shape.triangles.iter_mut().step_by(2) {
        t.swap(1, 2);
    }
    let adj = build_face_adjacency(&mesh_from_shape(&shape));
    assert!((0..12).all(|f| adj.neighbours(FaceId(f)).len() == 3));
}
