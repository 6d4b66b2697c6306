//! Colour only where the source has it, and the same bytes whatever the thread count.

use glam::Vec3;
use spatch_fit::{fit_regions, FitOptions, FitRegion};
use spatch_format::{encode_scene, ColourChannel, Scene, WriteOptions};
use spatch_mesh::build_face_adjacency;

use crate::support::{faces_where, fit_one, mesh_of, square};

#[test]
fn a_colourless_source_gets_no_colour_channel() {
    let mesh = square(4, 0.0);
    let faces = faces_where(&mesh, |_| true);
    let out = fit_one(&mesh, &faces, Vec3::Z, 0.1, |_| {});
    assert_eq!(out.channel, ColourChannel::None);
    assert!(out.patches.iter().all(|p| p.colours().is_none()));
}

#[test]
fn vertex_colours_are_interpolated_at_the_nodes() {
    let mut mesh = square(1, 0.0);
    // Red along x = 0, blue along x = 1: linear in x across the square.
    mesh.vertex_colours = Some(
        mesh.positions
            .iter()
            .map(|p| {
                if p.x < 0.5 {
                    [255, 0, 0, 255]
                } else {
                    [0, 0, 255, 255]
                }
            })
            .collect(),
    );
    let faces = faces_where(&mesh, |_| true);
    let out = fit_one(&mesh, &faces, Vec3::Z, 0.25, |_| {});
    assert_eq!(out.channel, ColourChannel::Rgb8);
    let p = &out.patches[0];
    let colours = p.colours().unwrap();
    for (k, (_, _, q)) in p.filled_nodes().enumerate() {
        let c = colours[k];
        if q.x < 1e-4 {
            assert_eq!(c, [255, 0, 0, 255]);
        } else if q.x > 1.0 - 1e-4 {
            assert_eq!(c, [0, 0, 255, 255]);
        } else {
            assert!(c[0] > 0 && c[2] > 0, "{q} {c:?} should mix red and blue");
        }
    }
    let mut off = FitOptions::default();
    off.spacing = Some(0.25);
    off.colour = false;
    let adjacency = build_face_adjacency(&mesh);
    let region = FitRegion {
        faces: &faces,
        axis: Vec3::Z,
    };
    let out = fit_regions(&mesh, &adjacency, &[region], &off).unwrap();
    assert_eq!(out.channel, ColourChannel::None);
}

#[test]
fn one_and_two_threads_give_identical_bytes() {
    let mesh = mesh_of(&spatch_fixtures::shapes::icosphere(1.0, 3));
    let adjacency = build_face_adjacency(&mesh);
    // Six regions around the axes, overlapping at their rims.
    let axes = [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let region_faces: Vec<Vec<_>> = axes
        .iter()
        .map(|&a| faces_where(&mesh, |n| n.dot(a) > 0.6))
        .collect();
    let regions: Vec<FitRegion<'_>> = region_faces
        .iter()
        .zip(axes)
        .map(|(faces, axis)| FitRegion { faces, axis })
        .collect();
    let mut options = FitOptions::default();
    options.spacing = Some(0.04);
    let bytes = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let out = pool
            .install(|| fit_regions(&mesh, &adjacency, &regions, &options))
            .unwrap();
        let scene = Scene::new(mesh.origin, out.channel, out.patches).unwrap();
        encode_scene(&scene, &WriteOptions::default()).unwrap()
    };
    assert_eq!(bytes(1), bytes(2));
}
