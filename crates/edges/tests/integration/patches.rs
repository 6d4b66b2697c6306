//! Edge patches lie on the source and cover the strip along the crease.

use spatch_edges::{generate_edge_patches, EdgeError, EdgeOptions};
use spatch_fixtures::shapes;
use spatch_mesh::{build_face_adjacency, Bvh};

use crate::surface::mesh_of;

#[test]
fn cube_edge_patches_lie_on_the_cube_and_see_both_faces() {
    let mesh = mesh_of(&shapes::cube(2.0));
    let adjacency = build_face_adjacency(&mesh);
    // Edges of length 2 fit one piece (at most 32 cells of the edge spacing, 0.2 / resolution).
    let spacing = 0.2;
    let options = EdgeOptions::default();
    let (patches, stats) =
        generate_edge_patches(&mesh, &adjacency, &[], spacing, &options).unwrap();
    assert_eq!(stats.pieces, 12);
    assert_eq!(stats.edge_patches, 12);
    assert_eq!(stats.corner_patches, 8);
    assert_eq!(patches.len(), 20);
    assert!((stats.spacing - spacing / options.resolution).abs() < 1e-6);
    let bvh = Bvh::new(&mesh);
    for patch in &patches[..12] {
        let [ax, _, az] = patch.frame().unit_axes();
        // x along a cube edge, z along a face-pair bisector (two components of 1/√2).
        assert!(ax.abs().max_element() > 0.999, "x = {ax}");
        let mut z = az.abs().to_array();
        z.sort_by(f32::total_cmp);
        assert!(z[0] < 1e-4 && (z[1] - z[2]).abs() < 1e-4, "z = {az}");
        // The two faces of the edge are the cube faces along the two axes z leans on.
        let axes: Vec<usize> = (0..3).filter(|&i| az[i].abs() > 0.5).collect();
        let mut sides = [false; 2];
        for (_, _, p) in patch.filled_nodes() {
            let hit = bvh.closest_point(p, f32::INFINITY).unwrap();
            let error = (hit.point - p).length();
            assert!(error < 0.02 * spacing, "node {p} is {error} off the cube");
            let on = |i: usize| (p[i].abs() - 1.0).abs() < 1e-3;
            for (side, (&a, &b)) in axes.iter().zip(axes.iter().rev()).enumerate() {
                if on(a) && !on(b) {
                    sides[side] = true;
                }
            }
        }
        assert!(sides[0] && sides[1], "the patch must reach both faces");
        // The strip reaches `strip_width` surface spacings onto each face.
        let (lo, hi) = patch.bounds().unwrap();
        let reach = (hi - lo).min_element();
        assert!(
            reach >= options.strip_width * spacing * 0.99,
            "reach {reach}"
        );
    }
}

#[test]
fn bad_inputs_are_refused() {
    let mesh = mesh_of(&shapes::cube(2.0));
    let adjacency = build_face_adjacency(&mesh);
    let mut options = EdgeOptions::default();
    options.crease_angle_deg = 0.0;
    assert!(matches!(
        generate_edge_patches(&mesh, &adjacency, &[], 0.1, &options),
        Err(EdgeError::InvalidOption {
            name: "crease_angle_deg",
            ..
        })
    ));
    assert!(matches!(
        generate_edge_patches(&mesh, &adjacency, &[], f32::NAN, &EdgeOptions::default()),
        Err(EdgeError::InvalidSpacing { .. })
    ));
    let other = build_face_adjacency(&mesh_of(&shapes::cylinder(1.0, 1.0, 8)));
    assert!(matches!(
        generate_edge_patches(&mesh, &other, &[], 0.1, &EdgeOptions::default()),
        Err(EdgeError::AdjacencyMismatch { .. })
    ));
}
