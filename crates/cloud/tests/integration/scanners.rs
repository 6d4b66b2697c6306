//! Scan sets whose scanners are known (`CloudOptions::scanners`): the two sides of a thin
//! sheet scanned from either side stay apart, the runs of points must match the cloud, a
//! dropped point takes its scan with it, and each scan's offset is taken out before the
//! consensus (`align_scans`).

use glam::{DVec3, Vec3};
use spatch_cloud::{
    cloud_to_scene, measure_cloud_error, CloudError, CloudOptions, Scanner, Scanners,
};

use crate::clouds::{cloud, tilted_plane};

/// Spacing of each side's grid.
const STEP: f32 = 0.01;

/// A sheet `2 · half` thick: its top (`z = +half`) scanned from +z, its bottom from −z.
fn sheet(half: f32) -> (Vec<Vec3>, Scanners) {
    let top: Vec<Vec3> = tilted_plane(60, STEP, 0.0, 1)
        .into_iter()
        .map(|p| p + Vec3::Z * half)
        .collect();
    let bottom: Vec<Vec3> = tilted_plane(60, STEP, 0.0, 2)
        .into_iter()
        .map(|p| p - Vec3::Z * half)
        .collect();
    let scanners = Scanners {
        runs: vec![
            (Scanner::Far(DVec3::Z), top.len()),
            (Scanner::Far(-DVec3::Z), bottom.len()),
        ],
    };
    (top.into_iter().chain(bottom).collect(), scanners)
}

#[test]
fn the_sides_of_a_thin_sheet_stay_apart_with_their_scanners() {
    // 1.5 spacings thick: a view averages both sides into a middle surface unless each
    // point is drawn only by the views its scanner's side faces.
    let (points, scanners) = sheet(0.75 * STEP);
    let input = cloud(DVec3::ZERO, points.clone());
    let mut options = CloudOptions::default();
    options.scanners = Some(scanners.clone());
    let with = cloud_to_scene(&input, &options).unwrap();
    assert_eq!(with.report.normals, "pca+sight");
    let without = cloud_to_scene(&input, &CloudOptions::default()).unwrap();
    assert_eq!(without.report.normals, "pca");
    let spacing = with.report.spacing;
    let rms = |c: &spatch_cloud::CloudConversion| {
        let e = measure_cloud_error(&input, &c.scene, spacing).unwrap();
        e.cloud_to_patch.distance.rms / f64::from(spacing)
    };
    let (rms_with, rms_without) = (rms(&with), rms(&without));
    eprintln!("cloud→patch rms: {rms_with:.3} s with scanners, {rms_without:.3} s without");
    assert!(
        rms_with < 0.2 && rms_without > 0.5,
        "{rms_with} {rms_without}"
    );

    // A non-finite point of the first scan is dropped with its scan: the same file.
    let mut nan_first = vec![Vec3::NAN];
    nan_first.extend(&points);
    let mut runs = scanners.clone();
    runs.runs[0].1 += 1;
    options.scanners = Some(runs);
    let dropped = cloud_to_scene(&cloud(DVec3::ZERO, nan_first), &options).unwrap();
    assert_eq!(dropped.report.dropped_non_finite, 1);
    assert_eq!(dropped.bytes, with.bytes);

    // Runs that do not add up to the cloud are refused.
    options.scanners = Some(scanners);
    let short = cloud(DVec3::ZERO, points[1..].to_vec());
    assert!(matches!(
        cloud_to_scene(&short, &options),
        Err(CloudError::MismatchedAttribute {
            what: "scanner runs",
            ..
        })
    ));
}

#[test]
fn each_scan_moves_by_its_offset_before_the_consensus() {
    // Two scans of one plane seen from above, 0.8 of a merged spacing apart: the
    // alignment moves each about half the offset toward the other.
    let offset = 0.6 * STEP;
    let first = tilted_plane(80, STEP, 0.3, 1);
    let normal = Vec3::new(-0.3, 0.0, 1.0).normalize();
    let second: Vec<Vec3> = tilted_plane(80, STEP, 0.3, 2)
        .into_iter()
        .map(|p| p + normal * offset)
        .collect();
    let up = Scanner::Far(normal.as_dvec3());
    let scanners = Scanners {
        runs: vec![(up, first.len()), (up, second.len())],
    };
    let input = cloud(DVec3::ZERO, first.into_iter().chain(second).collect());
    let mut options = CloudOptions::default();
    options.consensus = true;
    options.scanners = Some(scanners);
    let aligned = cloud_to_scene(&input, &options).unwrap();
    let shift = aligned.report.scan_shift;
    eprintln!("largest scan shift {shift:.5} for an offset of {offset}");
    assert!(
        (shift - f64::from(offset) / 2.0).abs() < 0.2 * f64::from(offset),
        "{shift}"
    );
    options.align_scans = false;
    let plain = cloud_to_scene(&input, &options).unwrap();
    assert_eq!(plain.report.scan_shift, 0.0);
}

#[test]
fn the_sides_of_a_thin_sheet_do_not_pull_their_scans_together() {
    // 1.5 spacings thick, each side scanned from its own side: one plane per block would
    // pull the two scans into each other (the alignment moved them by its 2-spacing cap
    // before stop 33). With one plane per scanner side the scans stay where they are.
    let (points, scanners) = sheet(0.75 * STEP);
    let input = cloud(DVec3::ZERO, points);
    let mut options = CloudOptions::default();
    options.consensus = true;
    options.scanners = Some(scanners);
    let aligned = cloud_to_scene(&input, &options).unwrap();
    let spacing = aligned.report.spacing;
    let shift = aligned.report.scan_shift / f64::from(spacing);
    eprintln!("longest shift {shift:.3} s");
    assert!(
        shift < 0.05,
        "the sides pulled their scans by {shift} spacings"
    );
    assert_eq!(aligned.report.scan_shifts.len(), 2);
    // The sheet keeps its thickness without the consensus, aligned or not.
    options.consensus = false;
    let kept = cloud_to_scene(&input, &options).unwrap();
    let e = measure_cloud_error(&input, &kept.scene, spacing).unwrap();
    let rms = e.cloud_to_patch.distance.rms / f64::from(spacing);
    assert!(rms < 0.2, "rms {rms} spacings: the sides were merged");
}
