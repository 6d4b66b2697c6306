//! A node takes only its region's own sheet of surface: never a layer behind it, never a
//! layer in front of it.

use glam::Vec3;
use spatch_mesh::TriangleMesh;

use crate::support::{add_sheet, faces_where, fit_one, nodes};

/// A sheet folded twice (a "Z" seen from the side), extruded along y: layer A at z = 0 and
/// layer C at z = 0.2 face +z, layer B at z = 0.1 faces −z; walls join A–B at x = 1 and B–C
/// at x = 0. All three layers overlap in projection on the unit square.
fn folded_sheet() -> TriangleMesh {
    let (mut p, mut t) = (Vec::new(), Vec::new());
    let n = 8;
    let y = Vec3::Y;
    add_sheet(&mut p, &mut t, Vec3::ZERO, (Vec3::X, y), n, Vec3::Z);
    add_sheet(
        &mut p,
        &mut t,
        Vec3::new(1.0, 0.0, 0.0),
        (Vec3::Z * 0.1, y),
        n,
        Vec3::X,
    );
    add_sheet(
        &mut p,
        &mut t,
        Vec3::new(0.0, 0.0, 0.1),
        (Vec3::X, y),
        n,
        -Vec3::Z,
    );
    add_sheet(
        &mut p,
        &mut t,
        Vec3::new(0.0, 0.0, 0.1),
        (Vec3::Z * 0.1, y),
        n,
        -Vec3::X,
    );
    add_sheet(
        &mut p,
        &mut t,
        Vec3::new(0.0, 0.0, 0.2),
        (Vec3::X, y),
        n,
        Vec3::Z,
    );
    let mesh = TriangleMesh::new(p, t).unwrap();
    // Weld the sheets' shared rows so adjacency links the fold.
    spatch_mesh::prepare_mesh(&mesh, &spatch_mesh::PrepareOptions::default()).0
}

fn layer(mesh: &TriangleMesh, z: f32, facing: Vec3) -> Vec<spatch_mesh::FaceId> {
    mesh.faces()
        .filter(|&f| {
            (mesh.face_centroid(f).z - z).abs() < 1e-4 && mesh.face_normal(f).dot(facing) > 0.9
        })
        .collect()
}

#[test]
fn the_lower_layer_is_fitted_under_the_upper_one() {
    let mesh = folded_sheet();
    let lower = layer(&mesh, 0.0, Vec3::Z);
    assert_eq!(lower.len(), 128);
    for overlap in [0, 2] {
        let out = fit_one(&mesh, &lower, Vec3::Z, 0.05, |o| o.overlap = overlap);
        let pts = nodes(&out);
        assert!(pts.len() >= 21 * 21);
        for q in pts {
            assert!(
                q.z.abs() < 1e-4,
                "overlap {overlap}: node {q} left the lower layer"
            );
        }
    }
}

#[test]
fn the_middle_layer_seen_from_below_ignores_the_layer_in_front() {
    let mesh = folded_sheet();
    let middle = layer(&mesh, 0.1, -Vec3::Z);
    assert_eq!(middle.len(), 128);
    let out = fit_one(&mesh, &middle, -Vec3::Z, 0.05, |o| o.overlap = 2);
    let pts = nodes(&out);
    assert!(pts.len() >= 21 * 21);
    for q in pts {
        assert!((q.z - 0.1).abs() < 1e-4, "node {q} left the middle layer");
    }
}

#[test]
fn a_thin_slab_never_takes_its_back_face() {
    // A 1 × 1 × 0.002 box: the top's overlap rings run over the rim onto the side walls
    // (edge-on) and the bottom (facing away): none of them may fill a node.
    let shape = spatch_fixtures::shapes::cube(1.0);
    let mut mesh = crate::support::mesh_of(&shape);
    for p in &mut mesh.positions {
        p.z *= 0.002;
    }
    let top = faces_where(&mesh, |n| n.z > 0.9);
    let out = fit_one(&mesh, &top, Vec3::Z, 0.05, |o| o.overlap = 3);
    let pts = nodes(&out);
    // 20 cells per side split into 2 × 2 windows of 11 × 11 nodes sharing their seams.
    assert_eq!(out.patches.len(), 4);
    assert_eq!(pts.len(), 4 * 11 * 11);
    let top_z = mesh.positions.iter().map(|p| p.z).fold(f32::MIN, f32::max);
    for q in pts {
        assert!(
            (q.z - top_z).abs() < 1e-5,
            "node {q} is not on the top face"
        );
    }
}

#[test]
fn a_tilt_limit_keeps_steep_folds_out_of_the_outer_nodes() {
    // The region is the flat staircase below the diagonal; its rectangle is the whole
    // square, so the cells along the diagonal need corners over the falling half. At 85°
    // the fall drops about 11 cells per cell: a node on it makes a chord across the fold (a
    // fin). With a 75° limit those corners stay empty; a 45° fall still fills them, and so
    // does the 85° one without the limit (the default).
    for (tilt, limit, filled) in [(85.0, 75.0, false), (45.0, 75.0, true), (85.0, 90.0, true)] {
        let mesh = crate::support::mesh_of(&spatch_fixtures::shapes::folded_square(8, tilt));
        let flat = faces_where(&mesh, |n| n.z > 0.9999);
        assert_eq!(flat.len(), 56);
        let out = fit_one(&mesh, &flat, Vec3::Z, 0.05, |o| {
            o.max_neighbour_tilt_deg = limit;
        });
        let below = nodes(&out).iter().filter(|q| q.z < -1e-4).count();
        assert_eq!(
            below > 0,
            filled,
            "{tilt}° under {limit}°: {below} nodes below"
        );
    }
}
