//! Generated clouds: planes and spheres.

use glam::{DVec3, Vec3};
use spatch_cloud::CloudOptions;
use spatch_format::ColourChannel;

use crate::clouds::{assert_targets, cloud, convert_and_measure, sphere, tilted_plane};

#[test]
fn tilted_plane_is_covered_and_flat() {
    let points = tilted_plane(150, 0.01, 0.7, 1);
    let c = cloud(DVec3::ZERO, points);
    let (conversion, error) = convert_and_measure(&c, &CloudOptions::default());
    assert_targets("plane", &c, &conversion, &error);
    // Every node lies on the plane up to quantization and f32 rounding.
    let scene = &conversion.scene;
    for patch in scene.patches() {
        let step = patch.frame().lengths()[2];
        for (_, _, p) in patch.filled_nodes() {
            let off = (p.z - 0.7 * p.x).abs() / (1.0f32 + 0.49).sqrt();
            assert!(off <= step + 1e-5, "node {p} is {off} off the plane");
        }
    }
    assert_eq!(conversion.report.uncovered_points, 0);
    // Inside, points sit on the surface; the worst are border points just beyond the last
    // cell, which count as covered within the border tolerance.
    assert!(
        error.cloud_to_patch.distance.p95 < 0.02 * error.spacing,
        "{error:?}"
    );
    assert!(
        error.cloud_to_patch.distance.max < 1.5 * error.spacing,
        "{error:?}"
    );
}

#[test]
fn sphere_nodes_stay_on_the_sphere() {
    let c = cloud(DVec3::ZERO, sphere(40_000, 1.0));
    let (conversion, error) = convert_and_measure(&c, &CloudOptions::default());
    assert_targets("sphere", &c, &conversion, &error);
    let spacing = conversion.report.spacing;
    for patch in conversion.scene.patches() {
        for (_, _, p) in patch.filled_nodes() {
            assert!(
                (p.length() - 1.0).abs() < 0.25 * spacing,
                "node at radius {}",
                p.length()
            );
        }
    }
}

#[test]
fn far_from_the_origin_the_scene_keeps_the_offset() {
    let origin = DVec3::new(1.0e6, -2.0e6, 5.0e5);
    let c = cloud(origin, sphere(20_000, 2.0));
    let (conversion, error) = convert_and_measure(&c, &CloudOptions::default());
    assert_eq!(conversion.scene.offset(), origin);
    assert_targets("far sphere", &c, &conversion, &error);
}

#[test]
fn colours_are_carried_to_the_nodes() {
    let points = tilted_plane(100, 0.01, 0.0, 3);
    let colours = points
        .iter()
        .map(|p| [(p.x * 255.0).clamp(0.0, 255.0) as u8, 40, 200, 255])
        .collect();
    let mut c = cloud(DVec3::ZERO, points);
    c.colours = Some(colours);
    let (conversion, _) = convert_and_measure(&c, &CloudOptions::default());
    assert_eq!(conversion.scene.channel(), ColourChannel::Rgb8);
    assert_eq!(conversion.report.colour, "rgb8");
    for patch in conversion.scene.patches() {
        let colours = patch.colours().expect("patches have colours");
        for (i, j, p) in patch.filled_nodes() {
            let c = colours[j * usize::from(patch.grid().cols()) + i];
            let expected = p.x * 255.0;
            assert!(
                (f32::from(c[0]) - expected).abs() < 6.0,
                "red {} at x {}",
                c[0],
                p.x
            );
            assert_eq!((c[1], c[2], c[3]), (40, 200, 255));
        }
    }
}

#[test]
fn file_normals_are_used_when_present() {
    let points = tilted_plane(80, 0.01, 0.0, 4);
    let mut c = cloud(DVec3::ZERO, points);
    c.normals = Some(vec![Vec3::Z; c.len()]);
    let (conversion, error) = convert_and_measure(&c, &CloudOptions::default());
    assert_eq!(conversion.report.normals, "file");
    assert_targets("plane with normals", &c, &conversion, &error);
}
