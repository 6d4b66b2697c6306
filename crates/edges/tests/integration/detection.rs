//! Sharp edges, chains and corners of simple shapes.

use spatch_edges::{detect_sharp_edges, DEFAULT_CREASE_ANGLE_DEG};
use spatch_fixtures::shapes;
use spatch_mesh::build_face_adjacency;

use crate::surface::mesh_of;

#[test]
fn a_cube_has_twelve_creases_and_eight_corners() {
    let mesh = mesh_of(&shapes::cube(2.0));
    let adjacency = build_face_adjacency(&mesh);
    let sharp = detect_sharp_edges(&mesh, &adjacency, DEFAULT_CREASE_ANGLE_DEG);
    assert_eq!(sharp.creases.len(), 12);
    assert!(sharp
        .creases
        .iter()
        .all(|c| (c.angle_deg - 90.0).abs() < 1e-3));
    assert_eq!(sharp.corners.len(), 8);
    assert!(sharp.ends.is_empty());
    // Chains stop at corners: one per cube edge, each from corner to corner.
    assert_eq!(sharp.chains.len(), 12);
    for chain in &sharp.chains {
        assert!(!chain.closed);
        assert_eq!(chain.creases.len(), 1);
        assert!(sharp.corners.contains(&chain.vertices[0]));
        assert!(sharp.corners.contains(chain.vertices.last().unwrap()));
    }
}

#[test]
fn a_cylinder_has_two_closed_rim_loops() {
    let segments = 48;
    let mesh = mesh_of(&shapes::cylinder(1.0, 2.0, segments));
    let adjacency = build_face_adjacency(&mesh);
    let sharp = detect_sharp_edges(&mesh, &adjacency, DEFAULT_CREASE_ANGLE_DEG);
    assert_eq!(sharp.creases.len(), 2 * segments as usize);
    assert!(sharp.corners.is_empty());
    assert_eq!(sharp.chains.len(), 2);
    for chain in &sharp.chains {
        assert!(chain.closed);
        assert_eq!(chain.creases.len(), segments as usize);
        assert_eq!(chain.vertices.first(), chain.vertices.last());
    }
    // Above the rim's 90°, nothing is sharp.
    assert!(detect_sharp_edges(&mesh, &adjacency, 95.0)
        .creases
        .is_empty());
}

#[test]
fn a_smooth_sphere_has_none() {
    for shape in [shapes::uv_sphere(1.0, 48, 24), shapes::icosphere(1.0, 3)] {
        let mesh = mesh_of(&shape);
        let adjacency = build_face_adjacency(&mesh);
        let sharp = detect_sharp_edges(&mesh, &adjacency, DEFAULT_CREASE_ANGLE_DEG);
        assert!(sharp.creases.is_empty());
        assert!(sharp.chains.is_empty());
    }
}

#[test]
fn an_inverted_face_does_not_make_creases() {
    let mut shape = shapes::cylinder(1.0, 2.0, 48);
    // Wind one side face the other way: its normal flips, its edges must not turn sharp.
    shape.triangles[0].swap(1, 2);
    let mesh = mesh_of(&shape);
    let adjacency = build_face_adjacency(&mesh);
    let sharp = detect_sharp_edges(&mesh, &adjacency, DEFAULT_CREASE_ANGLE_DEG);
    assert_eq!(sharp.creases.len(), 96);
}
