//! How well registered scans line up: for each scan, the distance from its points to the
//! nearest point of any other scan, where the scans overlap.
//!
//! Input: the merged cloud and its [`ScanSummary`]s. Output: one [`ScanAlignment`] per scan:
//! the median nearest-other-scan distance over the sampled points that have another scan's
//! point within `overlap_radius` (points farther away see a surface no other scan saw), and the
//! share of sampled points that do. Well-registered scans give a median about the scanner's
//! noise and sampling spacing; a wrong pose convention gives medians near `overlap_radius`
//! and little overlap.
//!
//! Cost: one kd-tree per scan (O(n log n) in all), then `samples_per_scan` nearest-point
//! queries per other scan; scans in parallel.

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;
use spatch_mesh::PointCloud;

use crate::ScanSummary;

/// The overlap of one scan with the others.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScanAlignment {
    /// Median distance (model units) from the scan's overlapping sampled points to the nearest
    /// point of another scan; `None` when no sampled point overlaps.
    pub median: Option<f64>,
    /// Share of the sampled points with another scan's point within the overlap radius.
    pub overlap: f64,
    /// Points sampled (evenly through the scan's points).
    pub sampled: usize,
}

/// Measures every scan against the others; see the module docs. Scans with no points, and
/// sets of fewer than two scans, give `overlap` 0 and no median.
pub fn measure_alignment(
    cloud: &PointCloud,
    scans: &[ScanSummary],
    overlap_radius: f64,
    samples_per_scan: usize,
) -> Vec<ScanAlignment> {
    let trees: Vec<Option<ImmutableKdTree<f32, 3>>> = scans
        .par_iter()
        .map(|scan| {
            let points: Vec<[f32; 3]> = cloud.positions[scan.points.clone()]
                .iter()
                .map(|p| p.to_array())
                .collect();
            ImmutableKdTree::new_from_slice(&points).ok()
        })
        .collect();
    (0..scans.len())
        .into_par_iter()
        .map(|i| {
            let own = &cloud.positions[scans[i].points.clone()];
            let stride = own.len().div_ceil(samples_per_scan.max(1)).max(1);
            let sample: Vec<Vec3> = own.iter().step_by(stride).copied().collect();
            let mut near: Vec<f64> = sample
                .iter()
                .filter_map(|&p| nearest_other(&trees, i, p))
                .filter(|&d| d <= overlap_radius)
                .collect();
            near.sort_by(f64::total_cmp);
            ScanAlignment {
                median: near.get(near.len() / 2).copied(),
                overlap: if sample.is_empty() {
                    0.0
                } else {
                    near.len() as f64 / sample.len() as f64
                },
                sampled: sample.len(),
            }
        })
        .collect()
}

/// Distance from `p` to the nearest point of any scan but `skip`.
fn nearest_other(trees: &[Option<ImmutableKdTree<f32, 3>>], skip: usize, p: Vec3) -> Option<f64> {
    trees
        .iter()
        .enumerate()
        .filter(|&(j, _)| j != skip)
        .filter_map(|(_, tree)| tree.as_ref())
        .map(|tree| {
            let hit = tree
                .query(&p.to_array())
                .nearest_one::<SquaredEuclidean<f32>>()
                .execute();
            f64::from(hit.distance).sqrt()
        })
        .min_by(f64::total_cmp)
}
