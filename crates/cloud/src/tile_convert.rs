//! One tile's conversion: its range images (one per view) and the patches cut from them for
//! the tile's own points.
//!
//! Input: a `TileJob` (the tile's points as coordinate columns, its own points, the bounds
//! its images cover) and the `TileContext` shared by every tile (views, pixel, extraction
//! settings). Output: a `TileOutput`: patches, counts and stage times.
//!
//! Method: the views' `ImageGeometry`s cover the job's bounds with the context's pixel.
//! When their pixels exceed [`PIXEL_BUDGET`], the pixel is enlarged to fit if the options
//! allow coarsening (with a [`CloudWarning::PixelsCoarsened`]), otherwise the conversion
//! fails with [`CloudError::PixelBudgetExceeded`] (the resolution never drops silently).
//! The images are drawn in parallel, one view per task (`range_image.rs`, `gap_fill.rs`,
//! `smooth.rs`); then three passes over the views in order cut patches for the still
//! uncovered own points (`extract.rs`): slope within the preferred limit, then the maximum,
//! then border absorption and regions of any size.
//!
//! Invariants: the output does not depend on the thread count (views built independently
//! and collected in order; the extraction's own guarantees).
//!
//! Cost: O(views · points) for the images and O(uncovered points + touched cells) per view
//! and pass; memory about 9 bytes per pixel over the views plus 8 bytes per point of
//! scratch per worker.

use std::sync::{Mutex, MutexGuard};
use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use spatch_format::{Patch, QuantizerPolicy};
use spatch_mesh::Aabb;

use crate::directions::ViewBasis;
use crate::extract::{
    absorb_border_points, cut_view, extract_view, CellMarks, ExtractCounts, ExtractSettings,
    PassLimits, ViewState,
};
use crate::gap_fill::fill_gaps;
use crate::patch_cut::CutSettings;
use crate::progress::StageCounter;
use crate::range_image::{flush_points, FlushInput, FlushScratch, ImageGeometry, PointColumns};
use crate::smooth::smooth_range_image;
use crate::{
    CloudError, CloudOptions, CloudWarning, PointId, BORDER_TOLERANCE, FRONT_BAND,
    MIN_REGION_CELLS, PIXEL_BUDGET,
};

/// What every tile shares.
pub(crate) struct TileContext<'a> {
    /// The options.
    pub(crate) options: &'a CloudOptions,
    /// Whether the points' normals are turned toward their scanners (a view then draws and
    /// covers only the points facing it).
    pub(crate) oriented: bool,
    /// The views.
    pub(crate) bases: &'a [ViewBasis],
    /// The point spacing (model units).
    pub(crate) spacing: f32,
    /// The pixel size before any coarsening (model units).
    pub(crate) pixel: f32,
    /// Counts drawn range images.
    pub(crate) images_done: &'a StageCounter<'a>,
    /// Counts extracted views and passes.
    pub(crate) views_done: &'a StageCounter<'a>,
}

/// One tile's points.
pub(crate) struct TileJob<'a> {
    /// Positions (relative to the cloud origin) of the tile's own and buffer points.
    pub(crate) positions: &'a [Vec3],
    /// The same points with their normals, as columns.
    pub(crate) points: PointColumns,
    /// Their colours, when the cloud has them.
    pub(crate) colours: Option<&'a [[u8; 4]]>,
    /// Indices (into the above) of the tile's own points: only these are offered to the
    /// extraction; `None` when every point is the tile's own (made only once the images are
    /// drawn, so it does not add to their peak memory).
    pub(crate) own: Option<Vec<PointId>>,
    /// What the range images cover.
    pub(crate) bounds: Aabb,
}

/// What one tile produced.
#[derive(Default)]
pub(crate) struct TileOutput {
    /// Its patches, in view, pass and region order.
    pub(crate) patches: Vec<Patch>,
    /// Split and wide patches, covered points.
    pub(crate) counts: ExtractCounts,
    /// Pixels filled by gap interpolation.
    pub(crate) gap_pixels_filled: usize,
    /// Own points no patch covers.
    pub(crate) uncovered: usize,
    /// The pixel used (larger than the context's when coarsened).
    pub(crate) pixel: f32,
    /// Wall time of the range images (seconds).
    pub(crate) image_seconds: f64,
    /// Wall time of the extraction (seconds).
    pub(crate) extract_seconds: f64,
}

impl TileOutput {
    /// Adds the next tile's `output`: its patches after these, its counts to these, the
    /// larger pixel (its times are the caller's to record).
    pub(crate) fn absorb(&mut self, output: TileOutput) {
        self.patches.extend(output.patches);
        self.counts += output.counts;
        self.gap_pixels_filled += output.gap_pixels_filled;
        self.uncovered += output.uncovered;
        self.pixel = self.pixel.max(output.pixel);
    }
}

/// Converts one tile (see the module documentation).
pub(crate) fn convert_tile(
    job: TileJob<'_>,
    context: &TileContext<'_>,
    warnings: &mut Vec<CloudWarning>,
) -> Result<TileOutput, CloudError> {
    let started = Instant::now();
    let (geometries, pixel) = plan_images(&job.bounds, context, warnings)?;
    let jump = context.options.jump_factor * pixel;
    let (mut views, gap_pixels_filled) = draw_views(&job, &geometries, jump, context);
    // The turned normals stay for the extraction's side test; the rest of the columns go.
    let sides = context.oriented.then(|| job.points.normals());
    drop(job.points);
    let image_seconds = started.elapsed().as_secs_f64();

    let started = Instant::now();
    let settings = extract_settings(context.options, context.spacing, jump);
    let mut uncovered = job
        .own
        .unwrap_or_else(|| (0..job.positions.len() as u32).map(PointId).collect());
    let mut counts = ExtractCounts::default();
    let patches = extract_passes(
        &mut views,
        (job.positions, sides.as_deref()),
        &mut uncovered,
        context.options,
        &settings,
        &mut counts,
        context,
    )?;
    drop(views);
    Ok(TileOutput {
        patches,
        counts,
        gap_pixels_filled,
        uncovered: uncovered.len(),
        pixel,
        image_seconds,
        extract_seconds: started.elapsed().as_secs_f64(),
    })
}

/// The range image of each of `geometries` (in parallel, one view per task: drawn, its
/// gaps filled and, if asked, smoothed), each as a view with no emitted cell; and the
/// pixels the gap filling filled, over all views.
fn draw_views(
    job: &TileJob<'_>,
    geometries: &[ImageGeometry],
    jump: f32,
    context: &TileContext<'_>,
) -> (Vec<ViewState>, usize) {
    let (options, spacing) = (context.options, context.spacing);
    let flush = FlushInput {
        points: &job.points,
        colours: job.colours,
        band: FRONT_BAND * spacing,
        jump,
        oriented: context.oriented,
    };
    let scratches = (0..rayon::current_num_threads())
        .map(|_| FlushScratch::with_capacity(job.points.len()))
        .collect();
    let pool = Mutex::new(scratches);
    let built: Vec<(ViewState, usize)> = geometries
        .par_iter()
        .map(|&geometry| {
            let mut scratch = lock(&pool).pop().unwrap_or_default();
            let mut image = flush_points(&flush, geometry, &mut scratch);
            lock(&pool).push(scratch);
            let filled = fill_gaps(&mut image, options.max_gap, jump);
            if let Some(smooth) = &options.smooth {
                smooth_range_image(&mut image, smooth, spacing, jump);
            }
            context.images_done.step();
            (ViewState::new(image), filled)
        })
        .collect();
    drop(pool);
    let gap_pixels_filled = built.iter().map(|b| b.1).sum();
    (built.into_iter().map(|b| b.0).collect(), gap_pixels_filled)
}

/// The extraction's settings for points of spacing `spacing` and images of discontinuity
/// threshold `jump`.
fn extract_settings(options: &CloudOptions, spacing: f32, jump: f32) -> ExtractSettings {
    ExtractSettings {
        jump,
        tolerance: options.cover_tolerance * spacing,
        cut: CutSettings {
            grid: options.grid as usize,
            quantizer: QuantizerPolicy {
                target_step: options.displacement_step * spacing,
                max_step: CloudOptions::DEFAULT_MAX_DISPLACEMENT_STEP * spacing,
                fine_step: options.displacement_step * spacing,
            },
        },
    }
}

/// The pool of flush scratches, made by the calling thread (one per worker; a view takes
/// one and puts it back). A poisoned lock only means another view panicked, and that panic
/// is the one rayon reports.
fn lock(pool: &Mutex<Vec<FlushScratch>>) -> MutexGuard<'_, Vec<FlushScratch>> {
    pool.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The views' image geometries over `bounds`, and the pixel they use: the context's, or
/// enlarged to fit the budget when coarsening is allowed.
fn plan_images(
    bounds: &Aabb,
    context: &TileContext<'_>,
    warnings: &mut Vec<CloudWarning>,
) -> Result<(Vec<ImageGeometry>, f32), CloudError> {
    let cover = |pixel: f32| -> Vec<ImageGeometry> {
        context
            .bases
            .iter()
            .map(|&b| ImageGeometry::covering(b, bounds, pixel))
            .collect()
    };
    let pixel = context.pixel;
    let geometries = cover(pixel);
    let total: usize = geometries.iter().map(ImageGeometry::pixel_count).sum();
    if total <= PIXEL_BUDGET {
        return Ok((geometries, pixel));
    }
    if !context.options.allow_coarsening {
        return Err(CloudError::PixelBudgetExceeded {
            pixels: total,
            budget: PIXEL_BUDGET,
        });
    }
    let factor = (total as f64 / PIXEL_BUDGET as f64).sqrt() as f32 * 1.02;
    warnings.push(CloudWarning::PixelsCoarsened {
        pixels: total,
        budget: PIXEL_BUDGET,
        factor,
        pixel: pixel * factor,
    });
    Ok((cover(pixel * factor), pixel * factor))
}

/// The three extraction passes over the views in order (see the module documentation).
fn extract_passes(
    views: &mut [ViewState],
    points: (&[Vec3], Option<&[Vec3]>),
    uncovered: &mut Vec<PointId>,
    options: &CloudOptions,
    settings: &ExtractSettings,
    counts: &mut ExtractCounts,
    context: &TileContext<'_>,
) -> Result<Vec<Patch>, CloudError> {
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
    let mut patches = Vec::new();
    let mut marks = CellMarks::default();
    for (index, pass) in [preferred, relaxed, last].iter().enumerate() {
        if index == 2 {
            // Before small patches are made for the last points, let those at the border of
            // an existing patch count as covered by it.
            for view in views.iter() {
                counts.covered += absorb_border_points(
                    view,
                    points,
                    uncovered,
                    BORDER_TOLERANCE * context.spacing,
                    settings,
                );
            }
        }
        for view in views.iter_mut() {
            if !uncovered.is_empty() {
                extract_view(view, points, uncovered, pass, settings, counts, &mut marks)?;
            }
            context.views_done.step();
        }
    }
    // Each view's cells of every pass are cut together, so a region that grew over several
    // passes becomes whole patches.
    let cut: Vec<_> = views
        .par_iter()
        .map(|view| cut_view(view, settings))
        .collect();
    for result in cut {
        let (found, cut_counts) = result?;
        *counts += cut_counts;
        patches.extend(found);
    }
    Ok(patches)
}
