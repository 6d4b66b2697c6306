//! A meshed cube turned about random axes needs no more crease patches and leaves no more
//! holes than the axis-aligned one (issue 22 item 8: turned, the surface patches used to stop
//! a row short of its edges, 0 → 32 crease patches and 257 hole pixels; CAD assemblies hold
//! parts in every orientation).

use glam::{Quat, Vec3};
use spatch_edges::{EdgeOptions, EdgeStats};
use spatch_eval::{hole_fraction, HoleOptions};
use spatch_mesh::TriangleMesh;

use crate::surface::{fit, mesh_of};

/// A rotation about a pseudo-random unit axis by a pseudo-random angle (`seed` picks them).
fn turn(seed: u32) -> Quat {
    let r = |k: u32| {
        let h = seed.wrapping_mul(2_654_435_761).wrapping_add(k * 40_503);
        (h % 1000) as f32 / 1000.0
    };
    let z = 2.0 * r(1) - 1.0;
    let t = std::f32::consts::TAU * r(2);
    let s = (1.0 - z * z).sqrt();
    Quat::from_axis_angle(Vec3::new(s * t.cos(), s * t.sin(), z), 0.3 + 5.0 * r(3))
}

/// The 2 × 2 × 2 cube of 12 × 12 cells per side (as `cad/cube-meshed.ply`), centred on the
/// origin, turned by `q` and moved by `offset`.
fn cube(q: Quat, offset: Vec3) -> TriangleMesh {
    let mut shape = spatch_fixtures::grid_box([12, 12, 12], 1.0 / 6.0);
    for p in &mut shape.positions {
        *p = (q * (Vec3::from(*p) - Vec3::ONE) + offset).to_array();
    }
    mesh_of(&shape)
}

/// Edge and corner patches and hole pixels of `mesh` (6 views at 300² in debug builds).
fn creases_and_holes(mesh: TriangleMesh) -> (EdgeStats, usize) {
    let fitted = fit(mesh);
    let (edges, stats) = fitted.edges(&EdgeOptions::default());
    let mut options = HoleOptions::default();
    if cfg!(debug_assertions) {
        options.views.truncate(6);
        options.size = [300, 300];
    }
    let holes = hole_fraction(&fitted.scene(&edges), &fitted.mesh, &options).unwrap();
    (stats, holes.hole_pixels)
}

#[test]
fn a_turned_cube_needs_no_more_crease_patches_than_an_aligned_one() {
    let (aligned, aligned_holes) = creases_and_holes(cube(Quat::IDENTITY, Vec3::ZERO));
    eprintln!(
        "aligned: {} + {} patches, {aligned_holes} hole pixels",
        aligned.edge_patches, aligned.corner_patches
    );
    assert_eq!(aligned.creases, 12 * 12);
    for seed in 1..=4 {
        let offset = Vec3::new(5.5, 4.4, 0.1) * (seed % 2) as f32;
        let (turned, holes) = creases_and_holes(cube(turn(seed), offset));
        eprintln!(
            "seed {seed}: {} + {} patches ({} covered creases), {holes} hole pixels",
            turned.edge_patches, turned.corner_patches, turned.covered_creases
        );
        assert_eq!(turned.creases, aligned.creases, "seed {seed}");
        assert!(
            turned.edge_patches + turned.corner_patches
                <= aligned.edge_patches + aligned.corner_patches,
            "seed {seed}"
        );
        assert!(holes <= aligned_holes, "seed {seed}: {holes} hole pixels");
    }
}
