//! The cloud pipeline's scanners from the scans' viewpoints, shared by
//! `spatch from-cloud` and its tiled runs.

use spatch_cloud::{Scanner, Scanners};

/// The cloud pipeline's scanner for a scan's viewpoint.
pub(crate) fn scanner_of(viewpoint: spatch_scan::Viewpoint) -> Scanner {
    match viewpoint {
        spatch_scan::Viewpoint::Direction(d) => Scanner::Far(d),
        spatch_scan::Viewpoint::Position(at) => Scanner::At(at),
    }
}

/// The scanners of scans that all have a viewpoint (`LoadedScans::sight_lines`), with the
/// run of points each saw.
pub(crate) fn scanners_of(scans: &[spatch_scan::ScanSummary]) -> Scanners {
    let runs = scans
        .iter()
        .filter_map(|scan| Some((scanner_of(scan.viewpoint?), scan.points.len())))
        .collect();
    Scanners { runs }
}
