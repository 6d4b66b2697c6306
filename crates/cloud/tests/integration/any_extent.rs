//! Any extent with bounded memory (issue 19, item 4): spatial tiles keep the spacing, far
//! outliers are dropped and counted, a tile over its pixel budget fails unless coarsening is
//! allowed, and the progress counts reach their totals.

use std::collections::HashMap;
use std::sync::Mutex;

use glam::{DVec3, Vec3};
use spatch_cloud::{
    cloud_to_scene, cloud_to_scene_owned, cloud_to_scene_with_progress, CloudError, CloudOptions,
    CloudWarning, Progress, Stage,
};
use spatch_mesh::SplitMix64;

use crate::clouds::{cloud, sphere};

/// A wavy square piece of side `side` sampled at `step` (jittered), starting at `x0`.
fn piece(x0: f32, side: f32, step: f32, seed: u64) -> Vec<Vec3> {
    let n = (side / step) as usize;
    let mut rng = SplitMix64::new(seed);
    let mut jitter = || (rng.next_f64() as f32 - 0.5) * 0.6 * step;
    (0..n * n)
        .map(|k| {
            let (x, y) = (
                (k % n) as f32 * step + jitter(),
                (k / n) as f32 * step + jitter(),
            );
            Vec3::new(x0 + x, y, 0.05 * (3.0 * x).sin() * (2.0 * y).cos())
        })
        .collect()
}

fn nodes(points: Vec<Vec3>, options: &CloudOptions) -> usize {
    let conversion = cloud_to_scene(&cloud(DVec3::ZERO, points), options).unwrap();
    conversion.report.counts.filled_nodes
}

#[test]
fn pieces_2_km_apart_keep_their_spacing() {
    let pieces: Vec<Vec<Vec3>> = (0..3)
        .map(|k| piece(2000.0 * k as f32, 0.5, 0.007, k))
        .collect();
    let options = CloudOptions::default();
    let alone: usize = pieces.iter().map(|p| nodes(p.clone(), &options)).sum();
    let all: Vec<Vec3> = pieces.concat();
    let conversion = cloud_to_scene(&cloud(DVec3::ZERO, all), &options).unwrap();
    let report = &conversion.report;
    assert!(report.tiles >= 3, "{} tiles", report.tiles);
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);
    assert!(report.pixel < 0.02, "pixel {}", report.pixel);
    let together = report.counts.filled_nodes as f64;
    let ratio = together / alone as f64;
    assert!(
        (0.8..=1.2).contains(&ratio),
        "{together} nodes against {alone} alone"
    );
    assert!(report.uncovered_points < 50, "{}", report.uncovered_points);
}

#[test]
fn a_far_outlier_is_dropped_and_counted() {
    let mut points = piece(0.0, 0.5, 0.007, 9);
    let n = points.len();
    points.push(Vec3::new(1e6, 0.0, 0.0));
    let conversion = cloud_to_scene(&cloud(DVec3::ZERO, points), &CloudOptions::default()).unwrap();
    let report = &conversion.report;
    assert_eq!(report.outlier_points, 1);
    assert_eq!(report.points, n + 1);
    assert!(matches!(
        report.warnings[..],
        [CloudWarning::OutliersDropped { points: 1, .. }]
    ));
    assert!(report.pixel < 0.02, "pixel {}", report.pixel);
    assert!(report.uncovered_points < 20, "{}", report.uncovered_points);
}

#[test]
fn clusters_far_apart_cost_memory_for_their_points_only() {
    // Two spheres a million radii apart: before the tiles, one image over the whole extent.
    let mut points = sphere(10_000, 1.0);
    points.extend(sphere(10_000, 1.0).into_iter().map(|p| p + Vec3::X * 1e6));
    let conversion = cloud_to_scene(&cloud(DVec3::ZERO, points), &CloudOptions::default()).unwrap();
    let report = &conversion.report;
    assert!(report.tiles >= 2);
    assert!(report.uncovered_points < 100, "{}", report.uncovered_points);
    assert!(report.pixel < 0.1, "pixel {}", report.pixel);
}

#[test]
fn a_tile_over_its_budget_fails_unless_coarsening_is_allowed() {
    let mut points = piece(0.0, 0.5, 0.007, 1);
    points.extend(piece(300.0, 0.5, 0.007, 2));
    let mut options = CloudOptions::default();
    options.tile_size = Some(1000.0);
    let c = cloud(DVec3::ZERO, points);
    let err = cloud_to_scene(&c, &options).unwrap_err();
    assert!(
        matches!(err, CloudError::PixelBudgetExceeded { pixels, budget } if pixels > budget),
        "{err}"
    );
    options.allow_coarsening = true;
    let conversion = cloud_to_scene(&c, &options).unwrap();
    assert!(matches!(
        conversion.report.warnings[..],
        [CloudWarning::PixelsCoarsened { factor, .. }] if factor > 1.0
    ));
}

#[test]
fn small_tiles_join_without_seams() {
    // A sphere of radius 1 cut into tiles of 0.6 (23 pixels, smaller than a patch: a
    // worst case): every point is still covered; the cut patches cost nodes (measured
    // 1.65 times the single tile's; tiles sized to the budget are about 480 pixels wide).
    let points = sphere(30_000, 1.0);
    let whole = cloud_to_scene(
        &cloud(DVec3::ZERO, points.clone()),
        &CloudOptions::default(),
    )
    .unwrap()
    .report;
    let mut options = CloudOptions::default();
    options.tile_size = Some(0.6);
    let tiled = cloud_to_scene(&cloud(DVec3::ZERO, points), &options)
        .unwrap()
        .report;
    assert!(tiled.tiles >= 27, "{} tiles", tiled.tiles);
    assert!(
        tiled.uncovered_points <= whole.uncovered_points + 30,
        "{} against {}",
        tiled.uncovered_points,
        whole.uncovered_points
    );
    let ratio = tiled.counts.filled_nodes as f64 / whole.counts.filled_nodes as f64;
    assert!((0.9..=1.8).contains(&ratio), "ratio {ratio}");
}

#[test]
fn tiled_output_does_not_depend_on_the_thread_count() {
    let mut options = CloudOptions::default();
    options.tile_size = Some(0.7);
    let c = cloud(DVec3::new(1.0, 2.0, 3.0), sphere(20_000, 1.0));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| cloud_to_scene(&c, &options).unwrap().bytes)
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn an_owned_cloud_converts_to_the_same_file_as_a_borrowed_one() {
    // Colours, file normals and a non-finite point: every array the owned path frees early
    // and the filter that copies the cloud.
    let mut c = cloud(DVec3::new(1.0, 2.0, 3.0), sphere(30_000, 1.0));
    c.positions.push(Vec3::new(f32::NAN, 0.0, 0.0));
    c.normals = Some(c.positions.iter().map(|p| p.normalize_or_zero()).collect());
    c.colours = Some(
        (0..c.positions.len())
            .map(|k| [(k % 256) as u8, (k / 256 % 256) as u8, 7, 255])
            .collect(),
    );
    let options = CloudOptions::default();
    let borrowed = cloud_to_scene(&c, &options).unwrap();
    let owned = cloud_to_scene_owned(c, &options, &|_| {}).unwrap();
    assert_eq!(owned.report.dropped_non_finite, 1);
    assert_eq!(owned.bytes, borrowed.bytes);
}

#[test]
fn progress_counts_reach_their_totals() {
    let seen: Mutex<HashMap<Stage, (usize, usize, usize)>> = Mutex::new(HashMap::new());
    let record = |p: Progress| {
        let mut seen = seen.lock().unwrap();
        let entry = seen.entry(p.stage).or_insert((0, p.total, 0));
        assert_eq!(entry.1, p.total, "{p:?}");
        entry.0 = entry.0.max(p.done);
        entry.2 += 1;
    };
    let mut options = CloudOptions::default();
    options.tile_size = Some(0.8);
    let c = cloud(DVec3::ZERO, sphere(20_000, 1.0));
    let report = cloud_to_scene_with_progress(&c, &options, &record)
        .unwrap()
        .report;
    let seen = seen.into_inner().unwrap();
    let views = options.views * report.tiles;
    assert_eq!(seen[&Stage::RangeImages], (views, views, views));
    assert_eq!(seen[&Stage::Extract], (3 * views, 3 * views, 3 * views));
    for stage in [Stage::Filter, Stage::Spacing, Stage::Tiles, Stage::Encode] {
        assert_eq!(seen[&stage], (1, 1, 1), "{stage:?}");
    }
}
