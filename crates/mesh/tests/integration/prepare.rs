//! Welding and cleaning on real and generated meshes.

use spatch_fixtures::{require_shared, shapes};
use spatch_mesh::{build_face_adjacency, load_mesh, prepare_mesh, PrepareOptions, TriangleMesh};

use crate::mesh_from_shape;

#[test]
fn bunny_keeps_its_referenced_vertices() {
    let mesh = load_mesh(require_shared!("bunny/reconstruction/bun_zipper.ply"))
        .unwrap()
        .mesh;
    let (out, report) = prepare_mesh(&mesh, &PrepareOptions::default());
    assert_eq!(report.input_vertices, 35_947);
    assert_eq!(report.welded_vertices, 0);
    assert_eq!(report.dropped_degenerate + report.dropped_zero_area, 0);
    assert_eq!(report.unreferenced_vertices, 35_947 - 34_834);
    assert_eq!(out.positions.len(), 34_834);
    assert_eq!(out.triangles.len(), 69_451);
}

#[test]
fn split_vertices_are_welded_back_into_a_closed_surface() {
    // Give every triangle its own three vertices, as an exporter with per-face normals does.
    let cube = shapes::cube(2.0);
    let positions: Vec<glam::Vec3> = cube
        .triangles
        .iter()
        .flat_map(|t| t.map(|i| glam::Vec3::from_array(cube.positions[i as usize])))
        .collect();
    let triangles = (0..cube.triangles.len() as u32)
        .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
        .collect();
    let soup = TriangleMesh::new(positions, triangles).unwrap();
    assert_eq!(build_face_adjacency(&soup).boundary_edge_count(), 36);
    let (welded, report) = prepare_mesh(&soup, &PrepareOptions::default());
    assert_eq!(report.welded_vertices, 36 - 8);
    assert_eq!(welded.positions.len(), 8);
    assert_eq!(build_face_adjacency(&welded).boundary_edge_count(), 0);
}

#[test]
fn sliver_fans_survive_and_true_degenerates_go() {
    let mut shape = shapes::sliver_fan(50);
    // A repeated-index face and an exactly collinear face.
    shape.triangles.push([0, 0, 1]);
    shape.positions.push([2.0, 0.0, 0.0]);
    let last = shape.positions.len() as u32 - 1;
    shape.triangles.push([0, 1, last]);
    let (out, report) = prepare_mesh(&mesh_from_shape(&shape), &PrepareOptions::default());
    assert_eq!(report.dropped_degenerate, 1);
    assert_eq!(report.dropped_zero_area, 1);
    assert_eq!(out.triangles.len(), 50, "slivers have area and must stay");
}
