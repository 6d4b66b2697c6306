//! The point cloud → scene pipeline: filter, spacing, normals, range images, extraction,
//! encoding, each timed.
//!
//! Input: a [`PointCloud`] and [`CloudOptions`]. Output: a [`CloudConversion`] (the scene,
//! its encoded bytes and a [`CloudReport`]).
//!
//! Stages:
//! 1. `filter`: points with a non-finite coordinate or normal are dropped and counted.
//! 2. `sort`: the points are put in Morton order, so that every later pass over them (one
//!    per view) reads and writes the images in a cache-friendly order.
//! 3. `spacing`: a kd-tree over (a thinned subset of) the points; the spacing `s` from 12
//!    nearest neighbours (`spacing.rs`), unless given.
//! 4. `normals`: the file's normals when it has them, else PCA normals over voxel blocks
//!    (`normals.rs`).
//! 5. `consensus`: every point moved onto its voxel block's least-squares plane
//!    (`consensus.rs`), so overlapping scans give one surface (unless turned off).
//! 6. `range_images`: one orthographic z-buffer per view direction (`directions.rs`,
//!    `range_image.rs`) with pixel size `pixel_factor · s`, then gap filling (`gap_fill.rs`)
//!    and, if asked, smoothing (`smooth.rs`). Views are independent and built in parallel.
//! 7. `extract`: two passes over the views in order, the first accepting surfaces within the
//!    preferred slope, the second within the maximum slope; each view adds patches only where
//!    points are still uncovered (`extract.rs`).
//! 8. `encode`: the `.spatch` bytes.
//!
//! Invariants: the output is byte-identical for any thread count (parallel work is per view
//! or per chunk of points and collected in order; extraction is sequential).
//!
//! Cost: O(n log n) for the tree and normals; O(views · n) for the z-buffers; memory about
//! `9 · views · pixels per view` bytes for the images plus the cloud and its tree. The total
//! pixel count is capped at [`PIXEL_BUDGET`] by enlarging the pixel (with a warning).
//!
//! Based on: the point-cloud path of the spatial-patch paper (range images from directions
//! spread over a sphere, gap interpolation, smoothing, rectangular regions).

use std::borrow::Cow;
use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use spatch_format::{encode_scene, ColourChannel, Scene};
use spatch_mesh::{Aabb, PointCloud};

use crate::bucket_sort::sort_pairs;
use crate::consensus::{project_to_consensus, ConsensusLimits};
use crate::directions::view_directions;
use crate::extract::{
    absorb_border_points, extract_view, ExtractCounts, ExtractSettings, PassLimits, ViewState,
};
use crate::gap_fill::fill_gaps;
use crate::normals::estimate_planes;
use crate::range_image::{flush_points, FlushInput, FlushScratch, ImageGeometry, PointColumns};
use crate::smooth::smooth_range_image;
use crate::spacing::estimate_spacing;
use crate::{CloudError, CloudOptions, CloudReport, Counts, PointId, StageTime};

/// Largest total number of range-image pixels over all views (about 360 MB of images).
pub const PIXEL_BUDGET: usize = 40_000_000;

/// Needed cells a region must have to become patches in the first two passes (the third
/// pass takes any size).
pub const MIN_REGION_CELLS: usize = 4;

/// Distance (in spacings) from a patch's extended surface within which a point just beside
/// the patch counts as covered by it before the last pass.
pub const BORDER_TOLERANCE: f32 = 1.0;

/// Heights within this many spacings of a pixel's front-most point are averaged into it.
pub const FRONT_BAND: f32 = 2.0;

/// What [`cloud_to_scene`] produces.
#[derive(Clone, Debug)]
pub struct CloudConversion {
    /// The patches, placed at the cloud's origin.
    pub scene: Scene,
    /// The encoded `.spatch` bytes.
    pub bytes: Vec<u8>,
    /// Counts and timings.
    pub report: CloudReport,
}

/// Times consecutive stages.
struct StageClock {
    last: Instant,
    stages: Vec<StageTime>,
}

impl StageClock {
    fn new() -> StageClock {
        StageClock {
            last: Instant::now(),
            stages: Vec::new(),
        }
    }

    fn lap(&mut self, name: &'static str) {
        let now = Instant::now();
        self.stages.push(StageTime {
            name,
            seconds: (now - self.last).as_secs_f64(),
        });
        self.last = now;
    }
}

/// Turns a point cloud into a scene of patches (see the module documentation).
///
/// Errors: [`CloudError::InvalidOption`], [`CloudError::MismatchedAttribute`],
/// [`CloudError::EmptyCloud`], [`CloudError::TooFewPoints`], [`CloudError::NoExtent`],
/// [`CloudError::NoSurface`]; [`CloudError::Bug`] / [`CloudError::Internal`] are bugs.
pub fn cloud_to_scene(
    cloud: &PointCloud,
    options: &CloudOptions,
) -> Result<CloudConversion, CloudError> {
    options.validate()?;
    let mut clock = StageClock::new();
    let input_points = cloud.len();
    let (cloud, dropped) = keep_finite(cloud)?;
    let n = cloud.len();
    if n == 0 {
        return Err(CloudError::EmptyCloud {
            dropped_non_finite: dropped,
        });
    }
    if n < 3 {
        return Err(CloudError::TooFewPoints {
            found: n,
            needed: 3,
        });
    }
    let bounds = cloud.bounds();
    if bounds.diagonal().is_nan() || bounds.diagonal() <= 0.0 {
        return Err(CloudError::NoExtent {
            points: n,
            extent: 0.0,
        });
    }
    clock.lap("filter");

    let cloud = sort_spatially(&cloud, &bounds);
    clock.lap("sort");

    let positions = &cloud.positions;
    let (spacing, mean_nearest) = match options.spacing {
        Some(s) => (s, 0.0),
        None => {
            let estimate = estimate_spacing(positions)?;
            (estimate.spacing, estimate.mean_nearest)
        }
    };
    clock.lap("spacing");

    let planes = (options.consensus || cloud.normals.is_none())
        .then(|| estimate_planes(positions, options.normal_voxel * spacing));
    let (normals, normals_source): (Cow<'_, [Vec3]>, &'static str) = match (&cloud.normals, &planes)
    {
        (Some(given), _) => (
            Cow::Owned(given.iter().map(|n| n.normalize_or_zero()).collect()),
            "file",
        ),
        (None, Some(planes)) => (
            Cow::Owned(
                planes
                    .point_voxel
                    .par_iter()
                    .map(|&v| planes.planes[v as usize].normal)
                    .collect(),
            ),
            "pca",
        ),
        (None, None) => {
            return Err(CloudError::Internal {
                what: "normals without planes",
            })
        }
    };
    clock.lap("normals");

    let mut consensus_points = 0;
    let moved = match (&planes, options.consensus) {
        (Some(planes), true) => {
            let limits = ConsensusLimits {
                max_spread: CloudOptions::CONSENSUS_MAX_SPREAD * spacing,
                max_move: CloudOptions::CONSENSUS_MAX_MOVE * spacing,
            };
            let (moved, count) = project_to_consensus(positions, planes, limits);
            consensus_points = count;
            Some(moved)
        }
        _ => None,
    };
    drop(planes);
    let positions: &[Vec3] = moved.as_deref().unwrap_or(positions);
    clock.lap("consensus");

    let mut warnings = Vec::new();
    let image_bounds = robust_bounds(positions, &bounds);
    if image_bounds != bounds {
        let outside = positions
            .iter()
            .filter(|p| !image_bounds.contains(**p))
            .count();
        warnings.push(format!(
            "{outside} points lie far outside the bulk of the cloud (outliers?): the range \
             images leave them out, so no patch covers them"
        ));
    }
    let bases = view_directions(options.views);
    let mut pixel = spacing * options.pixel_factor;
    let mut geometries: Vec<ImageGeometry> = bases
        .iter()
        .map(|&b| ImageGeometry::covering(b, &image_bounds, pixel))
        .collect();
    let total: usize = geometries.iter().map(ImageGeometry::pixel_count).sum();
    if total > PIXEL_BUDGET {
        let grow = (total as f64 / PIXEL_BUDGET as f64).sqrt() as f32 * 1.02;
        warnings.push(format!(
            "the range images would need {total} pixels (more than {PIXEL_BUDGET}): the pixel \
             size was enlarged {grow:.2} times, to {:.3e}; the cloud's extent is large for its \
             spacing (outliers far from the surface?)",
            pixel * grow
        ));
        pixel *= grow;
        geometries = bases
            .iter()
            .map(|&b| ImageGeometry::covering(b, &image_bounds, pixel))
            .collect();
    }
    let jump = options.jump_factor * pixel;
    let points = PointColumns::new(positions, &normals);
    drop(normals);
    let flush = FlushInput {
        points: &points,
        colours: cloud.colours.as_deref(),
        band: FRONT_BAND * spacing,
        jump,
    };
    let built: Vec<(ViewState, usize)> = geometries
        .par_iter()
        .map_init(FlushScratch::default, |scratch, &geometry| {
            let mut image = flush_points(&flush, geometry, scratch);
            let filled = fill_gaps(&mut image, options.max_gap, jump);
            if let Some(smooth) = &options.smooth {
                smooth_range_image(&mut image, smooth, spacing, jump);
            }
            (ViewState::new(image), filled)
        })
        .collect();
    let gap_pixels_filled = built.iter().map(|b| b.1).sum();
    let mut views: Vec<ViewState> = built.into_iter().map(|b| b.0).collect();
    drop(points);
    clock.lap("range_images");

    let settings = ExtractSettings {
        jump,
        tolerance: options.cover_tolerance * spacing,
        tile: options.grid as usize - 1,
        target_step: options.displacement_step * spacing,
        max_step: CloudOptions::DEFAULT_MAX_DISPLACEMENT_STEP * spacing,
    };
    let preferred = PassLimits {
        max_tan: options.preferred_slope_degrees.to_radians().tan(),
        min_cells: MIN_REGION_CELLS,
    };
    let relaxed = PassLimits {
        max_tan: options.max_slope_degrees.to_radians().tan(),
        min_cells: MIN_REGION_CELLS,
    };
    let last = PassLimits {
        min_cells: 1,
        ..relaxed
    };
    let mut uncovered: Vec<PointId> = (0..n as u32).map(PointId).collect();
    let mut counts = ExtractCounts::default();
    let mut patches = Vec::new();
    for (index, pass) in [preferred, relaxed, last].iter().enumerate() {
        if index == 2 {
            // Before small patches are made for the last points, let those at the border of
            // an existing patch count as covered by it.
            for view in &views {
                counts.covered += absorb_border_points(
                    view,
                    positions,
                    &mut uncovered,
                    BORDER_TOLERANCE * spacing,
                    &settings,
                );
            }
        }
        for view in &mut views {
            if uncovered.is_empty() {
                break;
            }
            let found = extract_view(
                view,
                positions,
                &mut uncovered,
                pass,
                &settings,
                &mut counts,
            )?;
            patches.extend(found);
        }
    }
    drop(views);
    if patches.is_empty() {
        return Err(CloudError::NoSurface { points: n });
    }
    let channel = match &cloud.colours {
        None => ColourChannel::None,
        Some(c) if c.iter().all(|c| c[3] == 255) => ColourChannel::Rgb8,
        Some(_) => ColourChannel::Rgba8,
    };
    // A cloud says nothing of what is closed: every patch may be seen from
    // behind, so automatic culling draws them all from both sides.
    let patches = patches
        .into_iter()
        .map(|p| p.with_sides(spatch_format::Sides::Both))
        .collect();
    let scene = Scene::new(cloud.origin, channel, patches)?;
    clock.lap("extract");

    let bytes = encode_scene(&scene, &options.write)?;
    clock.lap("encode");

    let report = CloudReport {
        input_points,
        dropped_non_finite: dropped,
        points: n,
        counts: Counts::of(&scene, bytes.len()),
        seconds: clock.stages.iter().map(|s| s.seconds).sum(),
        stages: clock.stages,
        threads: rayon::current_num_threads(),
        spacing,
        mean_nearest,
        pixel,
        views: options.views,
        normals: normals_source,
        gap_pixels_filled,
        uncovered_points: uncovered.len(),
        consensus_points,
        split_tiles: counts.split_tiles,
        wide_patches: counts.wide_patches,
        smoothed: options.smooth.is_some(),
        colour: channel.name(),
        diagonal: f64::from(bounds.diagonal()),
        warnings,
        error: None,
    };
    Ok(CloudConversion {
        scene,
        bytes,
        report,
    })
}

/// The cloud with its points in Morton (Z-order) order of their position in `bounds`, so
/// that consecutive points are near each other: every later pass over the points (one per
/// view) then touches the images and grids in a cache-friendly order.
fn sort_spatially(cloud: &PointCloud, bounds: &Aabb) -> PointCloud {
    let scale =
        Vec3::splat(f32::from(u16::MAX)) / bounds.size().max(Vec3::splat(f32::MIN_POSITIVE));
    let spread = |v: u64| {
        // Interleave the low 16 bits with two zero bits between each.
        let mut x = v & 0xFFFF;
        x = (x | (x << 16)) & 0x0000_FF00_00FF;
        x = (x | (x << 8)) & 0x00F0_0F00_F00F;
        x = (x | (x << 4)) & 0x0C30_C30C_30C3;
        (x | (x << 2)) & 0x2492_4924_9249
    };
    let order: Vec<(u64, u32)> = cloud
        .positions
        .par_iter()
        .enumerate()
        .map(|(i, &p)| {
            let q = ((p - bounds.min) * scale).clamp(Vec3::ZERO, Vec3::splat(f32::from(u16::MAX)));
            let code = spread(q.x as u64) | (spread(q.y as u64) << 1) | (spread(q.z as u64) << 2);
            (code, i as u32)
        })
        .collect();
    // Buckets of the top 18 code bits (cells of 1/64 of the box), then short runs: cheaper
    // than one sort of the whole list (rayon's parallel sort and a radix sort were slower
    // than `sort_unstable` on the shared machine).
    let order = sort_pairs(order, 30);
    let pick = |i: &(u64, u32)| i.1 as usize;
    PointCloud {
        origin: cloud.origin,
        positions: order.par_iter().map(|i| cloud.positions[pick(i)]).collect(),
        colours: cloud
            .colours
            .as_ref()
            .map(|c| order.par_iter().map(|i| c[pick(i)]).collect()),
        normals: cloud
            .normals
            .as_ref()
            .map(|v| order.par_iter().map(|i| v[pick(i)]).collect()),
    }
}

/// The bounds the range images cover: per axis, the 0.1 % and 99.9 % quantiles of the
/// coordinates widened by a quarter of their distance on each side, clipped to `full`. On a
/// cloud without far outliers this is `full` itself; a handful of points thousands of
/// spacings away no longer blow the images (and the pixel budget) up.
fn robust_bounds(positions: &[Vec3], full: &Aabb) -> Aabb {
    let n = positions.len();
    let (lo_rank, hi_rank) = (n / 1000, n - 1 - n / 1000);
    // The three axes are independent selections: one task each.
    let quantiles: Vec<(f32, f32)> = (0..3)
        .into_par_iter()
        .map(|axis| {
            let mut values: Vec<f32> = positions.iter().map(|p| p[axis]).collect();
            let lo = *values.select_nth_unstable_by(lo_rank, f32::total_cmp).1;
            let hi = *values.select_nth_unstable_by(hi_rank, f32::total_cmp).1;
            (lo, hi)
        })
        .collect();
    let mut bounds = *full;
    for (axis, &(lo, hi)) in quantiles.iter().enumerate() {
        let margin = 0.25 * (hi - lo);
        bounds.min[axis] = (lo - margin).max(full.min[axis]);
        bounds.max[axis] = (hi + margin).min(full.max[axis]);
    }
    bounds
}

/// The cloud without its non-finite points (borrowed when there are none), and how many were
/// dropped.
fn keep_finite(cloud: &PointCloud) -> Result<(Cow<'_, PointCloud>, u64), CloudError> {
    let n = cloud.len();
    if let Some(c) = &cloud.colours {
        if c.len() != n {
            return Err(CloudError::MismatchedAttribute {
                what: "colours",
                found: c.len(),
                expected: n,
            });
        }
    }
    if let Some(normals) = &cloud.normals {
        if normals.len() != n {
            return Err(CloudError::MismatchedAttribute {
                what: "normals",
                found: normals.len(),
                expected: n,
            });
        }
    }
    let is_finite = |i: usize| {
        cloud.positions[i].is_finite()
            && cloud
                .normals
                .as_ref()
                .is_none_or(|normals| normals[i].is_finite())
    };
    if (0..n).all(is_finite) {
        return Ok((Cow::Borrowed(cloud), 0));
    }
    let keep: Vec<usize> = (0..n).filter(|&i| is_finite(i)).collect();
    let filtered = PointCloud {
        origin: cloud.origin,
        positions: keep.iter().map(|&i| cloud.positions[i]).collect(),
        colours: cloud
            .colours
            .as_ref()
            .map(|c| keep.iter().map(|&i| c[i]).collect()),
        normals: cloud
            .normals
            .as_ref()
            .map(|v| keep.iter().map(|&i| v[i]).collect()),
    };
    Ok((Cow::Owned(filtered), (n - keep.len()) as u64))
}
