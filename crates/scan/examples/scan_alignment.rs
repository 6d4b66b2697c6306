//! How far apart the scans of a registered scan set lie, relative to their own sampling, so
//! that real and synthetic scan sets can be compared (docs/algorithms/cloud.md, "Scan sets
//! of other objects").
//!
//! ```sh
//! cargo run --release -p spatch-scan --example scan_alignment -- SET.conf [OVERLAP]
//! ```
//!
//! Prints, over every scan's sampled points that have another scan's point within `OVERLAP`
//! (model units, default 1/50 of the cloud's bounding-box diagonal): the median distance to
//! the nearest point of another scan (`measure_alignment`), the median distance to the
//! nearest other point of the same scan (the scan's own sampling step), and their ratio. Two
//! perfectly registered scans of one surface sampled at step `h` give a ratio of about 0.4
//! (the nearest of another, unrelated sampling); misregistration raises it.

use std::path::PathBuf;

use kiddo::{ImmutableKdTree, SquaredEuclidean};
use spatch_scan::{load_scans, measure_alignment, ScanOptions};

/// Points sampled per scan.
const SAMPLES: usize = 3000;

/// The point itself and its nearest other point.
const TWO: std::num::NonZeroUsize = std::num::NonZeroUsize::MIN.saturating_add(1);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(conf) = args.first() else {
        return Err("usage: scan_alignment SET.conf [OVERLAP]".into());
    };
    let loaded = load_scans(&[PathBuf::from(conf)], &ScanOptions::default())?;
    let diagonal = f64::from(loaded.cloud.bounds().diagonal());
    let overlap: f64 = args.get(1).map_or(Ok(diagonal / 50.0), |v| v.parse())?;
    let alignment = measure_alignment(&loaded.cloud, &loaded.scans, overlap, SAMPLES);
    let mut others: Vec<f64> = alignment.iter().filter_map(|a| a.median).collect();
    let mut steps: Vec<f64> = loaded
        .scans
        .iter()
        .filter_map(|scan| own_step(&loaded.cloud.positions[scan.points.clone()]))
        .collect();
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
    };
    let (other, step) = (median(&mut others), median(&mut steps));
    println!(
        "{} scans, {} points: nearest other scan {:.4e}, own step {:.4e}, ratio {:.3} (medians over scans)",
        loaded.scans.len(),
        loaded.cloud.len(),
        other,
        step,
        other / step
    );
    Ok(())
}

/// Median distance from a scan's sampled points to the nearest other point of the same scan.
fn own_step(points: &[glam::Vec3]) -> Option<f64> {
    let coords: Vec<[f32; 3]> = points.iter().map(|p| p.to_array()).collect();
    let tree = ImmutableKdTree::<f32, 3>::new_from_slice(&coords).ok()?;
    let stride = points.len().div_ceil(SAMPLES).max(1);
    let mut d: Vec<f64> = coords
        .iter()
        .step_by(stride)
        .map(|p| {
            let found = tree
                .query(p)
                .nearest_n::<SquaredEuclidean<f32>>(TWO)
                .execute();
            f64::from(found[1].distance).sqrt()
        })
        .collect();
    d.sort_by(f64::total_cmp);
    d.get(d.len() / 2).copied()
}
