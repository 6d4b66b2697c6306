//! Issue 19, item 3: two scans of one surface offset from each other (registration error)
//! must give one surface. The consensus projection (which `spatch from-cloud` turns on for several scans) puts the nodes on the
//! mid-surface between the two layers; without it each pixel averages whichever layer its
//! points came from, and the nodes scatter between them.

use glam::{DVec3, Vec3};
use spatch_cloud::{cloud_to_scene, CloudOptions};
use spatch_format::Scene;

use crate::clouds::{cloud, tilted_plane};

/// Slope of the test planes (z = SLOPE · x).
const SLOPE: f32 = 0.3;

/// The planes' unit normal.
fn plane_normal() -> Vec3 {
    Vec3::new(-SLOPE, 0.0, 1.0).normalize()
}

/// Two jittered samplings of the plane z = 0.3 x (different seeds), the second moved by
/// `offset` along the normal: two registered scans of one surface that disagree by `offset`.
fn two_offset_scans(offset: f32) -> Vec<Vec3> {
    let shift = plane_normal() * offset;
    let first = tilted_plane(150, 0.01, SLOPE, 1);
    let second = tilted_plane(150, 0.01, SLOPE, 2);
    first
        .into_iter()
        .chain(second.into_iter().map(|p| p + shift))
        .collect()
}

/// RMS of the filled nodes' distance from the mid-surface between the two scans, away from
/// the border of the sampled square.
fn node_rms_from_mid_surface(scene: &Scene, offset: f32) -> f64 {
    let n = plane_normal().as_dvec3();
    let (mut sum, mut count) = (0.0, 0usize);
    for patch in scene.patches() {
        for (_, _, p) in patch.filled_nodes() {
            let p = scene.offset() + p.as_dvec3();
            if !((0.1..1.4).contains(&p.x) && (0.1..1.4).contains(&p.y)) {
                continue;
            }
            let d = p.dot(n) - f64::from(offset) / 2.0;
            sum += d * d;
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt()
}

#[test]
fn issue_19_offset_scans_give_one_surface() {
    // Two scans of spacing 0.01 merge into a cloud of spacing about 0.007; they disagree by
    // 0.006, most of a merged spacing.
    let offset = 0.006;
    let points = cloud(DVec3::ZERO, two_offset_scans(offset));
    let mut options = CloudOptions::default();
    options.consensus = true;
    let with = cloud_to_scene(&points, &options).unwrap();
    let without = cloud_to_scene(&points, &CloudOptions::default()).unwrap();
    let (rms_with, rms_without) = (
        node_rms_from_mid_surface(&with.scene, offset),
        node_rms_from_mid_surface(&without.scene, offset),
    );
    eprintln!(
        "offset {offset}: node rms from the mid-surface {rms_with:.5} with consensus, \
         {rms_without:.5} without; {} of {} points moved",
        with.report.consensus_points,
        points.len()
    );
    assert!(with.report.consensus_points > points.len() * 9 / 10);
    assert_eq!(without.report.consensus_points, 0);
    assert!(
        rms_with < 0.6 * rms_without,
        "consensus {rms_with} vs {rms_without}"
    );
}
