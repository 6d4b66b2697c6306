//! The Stanford bunny scan set: every scan is read, posed, and the scans line up.

use spatch_fixtures::require_shared;
use spatch_scan::{load_scans, measure_alignment, ScanOptions};

/// Overlap radius for the alignment check: 2 mm (the bunny is in metres, about 150 mm wide).
const OVERLAP_RADIUS: f64 = 0.002;

#[test]
fn bunny_conf_scans_line_up() {
    let conf = require_shared!("bunny/data/bun.conf");
    let loaded = load_scans(&[conf], &ScanOptions::default()).unwrap();
    assert_eq!(loaded.scans.len(), 10, "one scan per bmesh line");
    assert_eq!(loaded.cloud.len(), 362_272, "every point of the ten scans");
    assert!(loaded.camera.is_some(), "the camera line is a viewpoint");
    let alignment = measure_alignment(&loaded.cloud, &loaded.scans, OVERLAP_RADIUS, 3000);
    let mut medians = Vec::new();
    for (scan, a) in loaded.scans.iter().zip(&alignment) {
        let median = a.median.expect("every bunny scan overlaps another");
        eprintln!(
            "{}: median {:.3} mm over {:.0} % of {} points",
            scan.path.display(),
            median * 1e3,
            a.overlap * 100.0,
            a.sampled
        );
        // Wrong conventions give medians of 1 mm and more, over a few per cent of the points.
        assert!(median < 0.4e-3, "{}: {median}", scan.path.display());
        assert!(a.overlap > 0.6, "{}: {}", scan.path.display(), a.overlap);
        medians.push(median);
    }
    medians.sort_by(f64::total_cmp);
    assert!(medians[5] < 0.3e-3, "{medians:?}");
}
