//! The point cloud → scene pipeline: filter, sort, spacing, normals, consensus, tiles, range
//! images, extraction, encoding, each a named stage function, each timed.
//!
//! Input: a [`PointCloud`] and [`CloudOptions`]. Output: a [`CloudConversion`] (the scene,
//! its encoded bytes and a [`CloudReport`]).
//!
//! Stages (3–5 in `surface_stages.rs`; each timed on the clock of `stage_laps.rs`):
//! 1. `filter` (`keep_finite`, `finite.rs`): points with a non-finite coordinate or normal
//!    are dropped and counted.
//! 2. `sort` (`sort_spatially`): the points are put in Morton order, so that every later
//!    pass over them (one per view) reads and writes the images in a cache-friendly order.
//! 3. `spacing` (`measure_spacing`): the spacing `s` from 12 nearest neighbours
//!    (`spacing.rs`), unless given.
//! 4. `normals` (`estimate_surface`): the file's normals when it has them, else PCA
//!    normals over voxel blocks (`normals.rs`); with [`CloudOptions::scanners`] the PCA
//!    normals turned to the side of each point's scanner.
//! 5. `consensus` (`apply_consensus`): every point moved onto its voxel block's
//!    least-squares plane (`consensus.rs`), so overlapping scans give one surface (unless
//!    turned off).
//! 6. `tiles` (`plan_conversion`): when the views' range images over the whole cloud fit
//!    [`PIXEL_BUDGET`], the cloud is one tile; otherwise a grid of spatial tiles, each with
//!    a buffer and its own images under the budget (`tiles.rs`), and the points of nearly
//!    empty tiles dropped as outliers.
//! 7. `range_images` and 8. `extract`, tile by tile in key order (`tile_convert.rs`): one
//!    orthographic z-buffer per view with pixel size `pixel_factor · s`, gap filling and, if
//!    asked, smoothing; then three passes over the views cutting patches for the tile's own
//!    uncovered points (`extract.rs`).
//! 9. `encode`: the `.spatch` bytes.
//!
//! Invariants: the output is byte-identical for any thread count (parallel work is per view,
//! per chunk of points or per tile cell, and collected in order; views, passes and tiles run
//! in order). The pixel size never changes silently: a tile over its budget fails with
//! [`CloudError::PixelBudgetExceeded`] unless [`CloudOptions::allow_coarsening`] is set.
//!
//! Cost: O(n log n) for the tree and normals; O(views · n) for the z-buffers; memory about
//! `9 · views · pixels per view` bytes for one tile's images (at most [`PIXEL_BUDGET`]
//! pixels) plus about 60 bytes per point for the cloud, its normals and columns.
//!
//! Based on: the point-cloud path of the spatial-patch paper (range images from directions
//! spread over a sphere, gap interpolation, smoothing, rectangular regions).

use std::borrow::Cow;
use std::time::Instant;

use glam::Vec3;
use rayon::prelude::*;
use spatch_format::{encode_scene, ColourChannel, Patch, Scene};
use spatch_mesh::{Aabb, PointCloud};

use crate::directions::view_directions;
use crate::finite::{check_extent, keep_finite};
use crate::morton_order::{morton_order, PointOrder};
use crate::progress::{ProgressFn, Stage, StageCounter};
use crate::range_image::{ImageGeometry, PointColumns};
use crate::scanners::PointScans;
use crate::stage_laps::StageLaps;
use crate::surface_stages::{shape_surface, ShapedSurface, SIGHT_SOURCE};
use crate::tile_convert::{convert_tile, TileContext, TileJob, TileOutput};
use crate::tiles::{bounds_of_members, plan_tiles, TileGrid, TilePlan, TilePoints};
use crate::{CloudError, CloudOptions, CloudReport, CloudWarning, Counts, TILE_BUFFER_PIXELS};

/// Largest total number of range-image pixels over all views of one tile (about 150 MB of
/// images). A cloud whose images fit is converted as one tile.
pub const PIXEL_BUDGET: usize = 16_000_000;

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
    /// The conversion's spatial (Morton) order of the points, which
    /// [`measure_cloud_error_in_order`] starts from. Kept when the cloud was borrowed and no
    /// point was dropped (`None` otherwise: the indices would not be the caller's); 4 bytes
    /// a point.
    ///
    /// [`measure_cloud_error_in_order`]: crate::measure_cloud_error_in_order
    pub point_order: Option<PointOrder>,
}

/// Turns a point cloud into a scene of patches (see the module documentation).
///
/// Errors: [`CloudError::InvalidOption`], [`CloudError::MismatchedAttribute`],
/// [`CloudError::EmptyCloud`], [`CloudError::TooFewPoints`], [`CloudError::NoExtent`],
/// [`CloudError::NoSurface`], [`CloudError::PixelBudgetExceeded`]; [`CloudError::Bug`] /
/// [`CloudError::Internal`] are bugs.
pub fn cloud_to_scene(
    cloud: &PointCloud,
    options: &CloudOptions,
) -> Result<CloudConversion, CloudError> {
    cloud_to_scene_with_progress(cloud, options, &|_| {})
}

/// [`cloud_to_scene`], calling `progress` as units of work end (see
/// [`Progress`](crate::Progress)).
pub fn cloud_to_scene_with_progress(
    cloud: &PointCloud,
    options: &CloudOptions,
    progress: ProgressFn<'_>,
) -> Result<CloudConversion, CloudError> {
    convert_cloud(Cow::Borrowed(cloud), options, progress)
}

/// [`cloud_to_scene_with_progress`] for a cloud the caller no longer needs: its arrays are
/// freed as soon as their spatially sorted copies exist, instead of living beside them for
/// the whole conversion (12 bytes a point for the positions, more with colours or normals).
/// Gives the same result.
pub fn cloud_to_scene_owned(
    cloud: PointCloud,
    options: &CloudOptions,
    progress: ProgressFn<'_>,
) -> Result<CloudConversion, CloudError> {
    convert_cloud(Cow::Owned(cloud), options, progress)
}

/// The pipeline of the module documentation over a borrowed or owned cloud.
fn convert_cloud(
    cloud: Cow<'_, PointCloud>,
    options: &CloudOptions,
    progress: ProgressFn<'_>,
) -> Result<CloudConversion, CloudError> {
    options.validate()?;
    let mut clock = StageLaps::new(progress);
    let mut sorted = filter_and_sort(cloud, options, &mut clock)?;
    let scans = sorted.scans.take();
    let (shaped, normals) = shape_surface(&mut sorted.cloud, scans, options, &mut clock)?;
    let mut tiled = convert_planned(&sorted, normals, &shaped, options, &mut clock)?;

    let started = Instant::now();
    let patches = std::mem::take(&mut tiled.output.patches);
    let scene = build_scene(&sorted.cloud, patches, sorted.cloud.len())?;
    clock.record(Stage::Extract.name(), started.elapsed().as_secs_f64());

    let bytes = encode_scene(&scene, &options.write)?;
    clock.lap(Stage::Encode);

    let report = cloud_report(
        &sorted,
        &shaped,
        tiled,
        (&scene, bytes.len()),
        options,
        clock,
    );
    Ok(CloudConversion {
        scene,
        bytes,
        report,
        point_order: sorted.point_order,
    })
}

/// The cloud after the `filter` and `sort` stages, with what they measured.
struct SortedCloud {
    /// The finite points, in Morton order.
    cloud: PointCloud,
    /// Points in the input, before the filter.
    input_points: usize,
    /// Points dropped for a non-finite coordinate or normal.
    dropped: u64,
    /// Bounds of the finite points.
    bounds: Aabb,
    /// The input index of each sorted point, for a borrowed cloud (see
    /// [`CloudConversion::point_order`]).
    point_order: Option<PointOrder>,
    /// The scan of each sorted point, for a cloud whose scanners are known (taken out by the
    /// `normals` stage, which drops it).
    scans: Option<PointScans>,
}

/// The `filter` and `sort` stages: the finite points (with their scans, when the scanners
/// are known) in spatial order.
fn filter_and_sort(
    cloud: Cow<'_, PointCloud>,
    options: &CloudOptions,
    clock: &mut StageLaps<'_>,
) -> Result<SortedCloud, CloudError> {
    let input_points = cloud.len();
    // The scan of each point (1-2 bytes a point), for a cloud whose scanners are known.
    let scans = match &options.scanners {
        Some(scanners) if cloud.normals.is_none() => Some(PointScans::of(scanners, cloud.len())?),
        _ => None,
    };
    let (cloud, dropped, scans) = keep_finite(cloud, scans)?;
    let bounds = check_extent(&cloud, dropped)?;
    clock.lap(Stage::Filter);

    let (cloud, point_order, scans) = sort_spatially(cloud, &bounds, scans);
    clock.lap(Stage::Sort);
    Ok(SortedCloud {
        cloud,
        input_points,
        dropped,
        bounds,
        point_order,
        scans,
    })
}

/// What the `tiles`, `range_images` and `extract` stages produced.
struct PlannedOutput {
    /// The tiles' patches and counts, summed.
    output: TileOutput,
    /// Points of nearly empty tiles dropped as outliers.
    outlier_points: usize,
    /// Tiles converted.
    tiles: usize,
    /// Side of the tiles' grid (model units).
    grid_size: f64,
    /// Warnings of the planning and the tiles.
    warnings: Vec<CloudWarning>,
}

/// The `tiles` stage, then the `range_images` and `extract` stages over every planned tile
/// (`normals`: one per sorted point, dropped as soon as no tile needs them).
fn convert_planned(
    sorted: &SortedCloud,
    normals: Vec<Vec3>,
    shaped: &ShapedSurface,
    options: &CloudOptions,
    clock: &mut StageLaps<'_>,
) -> Result<PlannedOutput, CloudError> {
    let (cloud, bounds) = (&sorted.cloud, &sorted.bounds);
    let positions: &[Vec3] = &cloud.positions;
    let spacing = shaped.spacing;
    let pixel = spacing * options.pixel_factor;
    let plan = plan_conversion(positions, cloud, bounds, pixel, options);
    clock.lap(Stage::Tiles);

    let mut warnings = Vec::new();
    if plan.outlier_points > 0 {
        warnings.push(CloudWarning::OutliersDropped {
            points: plan.outlier_points,
            tiles: plan.outlier_tiles,
        });
    }
    let (outlier_points, tiles, grid) = (plan.outlier_points, plan.tiles.len(), plan.grid);
    let output = convert_tiles(
        plan,
        &TiledCloud {
            positions,
            colours: cloud.colours.as_deref(),
            bounds,
        },
        normals,
        (options, shaped.source == SIGHT_SOURCE),
        (spacing, pixel),
        clock,
        &mut warnings,
    )?;
    Ok(PlannedOutput {
        output,
        outlier_points,
        tiles,
        grid_size: grid.size,
        warnings,
    })
}

/// The conversion's report from the stages' findings, the encoded `scene` (with its byte
/// count) and the stage times.
fn cloud_report(
    sorted: &SortedCloud,
    shaped: &ShapedSurface,
    tiled: PlannedOutput,
    (scene, bytes): (&Scene, usize),
    options: &CloudOptions,
    clock: StageLaps<'_>,
) -> CloudReport {
    let tile_count = tiled.tiles;
    CloudReport {
        input_points: sorted.input_points,
        dropped_non_finite: sorted.dropped,
        points: sorted.cloud.len(),
        counts: Counts::of(scene, bytes),
        seconds: clock.clock.total(),
        stages: clock.clock.into_stages(),
        threads: rayon::current_num_threads(),
        spacing: shaped.spacing,
        mean_nearest: shaped.mean_nearest,
        pixel: tiled.output.pixel,
        views: options.views,
        normals: shaped.source,
        gap_pixels_filled: tiled.output.gap_pixels_filled,
        uncovered_points: tiled.output.uncovered,
        outlier_points: tiled.outlier_points,
        tiles: tile_count,
        tile_size: (tile_count > 1 || options.tile_size.is_some() || options.tile_grid.is_some())
            .then_some(tiled.grid_size),
        consensus_points: shaped.consensus_points,
        scan_shift: shaped
            .scan_shifts
            .iter()
            .map(|t| t.length())
            .fold(0.0, f64::max),
        scan_shifts: shaped.scan_shifts.iter().map(|t| t.to_array()).collect(),
        split_tiles: tiled.output.counts.split_tiles,
        wide_patches: tiled.output.counts.wide_patches,
        smoothed: options.smooth.is_some(),
        colour: scene.channel().name(),
        diagonal: f64::from(sorted.bounds.diagonal()),
        warnings: tiled.warnings,
        error: None,
    }
}

/// The `tiles` stage: one tile when the whole cloud's images fit [`PIXEL_BUDGET`] (and no
/// tile size is asked for), else the tiles of a grid sized to the budget (or to
/// [`CloudOptions::tile_size`]).
fn plan_conversion(
    positions: &[Vec3],
    cloud: &PointCloud,
    bounds: &Aabb,
    pixel: f32,
    options: &CloudOptions,
) -> TilePlan {
    let extent = f64::from(bounds.size().max_element());
    let anchor = cloud.origin + bounds.min.as_dvec3();
    let buffer = f64::from(TILE_BUFFER_PIXELS * pixel);
    let grid = match (options.tile_grid, options.tile_size) {
        (Some(grid), _) => Some(grid),
        (None, Some(size)) => TileGrid::new(anchor, f64::from(size).max(extent / 1e6), buffer),
        (None, None) => {
            let whole: usize = view_directions(options.views)
                .iter()
                .map(|&b| ImageGeometry::covering(b, bounds, pixel).pixel_count())
                .sum();
            (whole > PIXEL_BUDGET)
                .then(|| TileGrid::for_budget(anchor, pixel, options.views, PIXEL_BUDGET, extent))
        }
    };
    match grid {
        Some(grid) => {
            let mut plan = plan_tiles(positions, cloud.origin, grid);
            if let Some(key) = options.only_tile {
                keep_only_tile(&mut plan, positions, cloud.origin, key);
            }
            plan
        }
        None => TilePlan {
            grid: TileGrid {
                anchor,
                size: extent,
                buffer: 0.0,
            },
            // No members: the whole cloud, every point its own.
            tiles: vec![TilePoints {
                members: Vec::new(),
                own: Vec::new(),
            }],
            outlier_points: 0,
            outlier_tiles: 0,
        },
    }
}

/// Keeps the one tile of `plan` whose own points lie in the tile `key` (see
/// [`CloudOptions::only_tile`]); the others' points are only its buffer.
fn keep_only_tile(plan: &mut TilePlan, positions: &[Vec3], origin: glam::DVec3, key: [i64; 3]) {
    let grid = plan.grid;
    plan.tiles.retain(|tile| {
        let first = tile.members[tile.own[0].index()] as usize;
        grid.key_of(origin + positions[first].as_dvec3()) == key
    });
}

/// The cloud as the tiles read it.
struct TiledCloud<'a> {
    /// Positions after the consensus.
    positions: &'a [Vec3],
    /// Colours, when the cloud has them.
    colours: Option<&'a [[u8; 4]]>,
    /// Bounds of the cloud as loaded (the images of a single tile cover them).
    bounds: &'a Aabb,
}

/// The `range_images` and `extract` stages over every tile in order, with their counts
/// summed. `normals` (unit, zero where unknown; `oriented` when turned toward the points'
/// scanners) go as soon as no tile needs them.
fn convert_tiles(
    plan: TilePlan,
    cloud: &TiledCloud<'_>,
    normals: Vec<Vec3>,
    (options, oriented): (&CloudOptions, bool),
    (spacing, pixel): (f32, f32),
    clock: &mut StageLaps<'_>,
    warnings: &mut Vec<CloudWarning>,
) -> Result<TileOutput, CloudError> {
    let bases = view_directions(options.views);
    let tiles = plan.tiles.len();
    let images_done = StageCounter::new(Stage::RangeImages, tiles * bases.len(), clock.progress);
    let views_done = StageCounter::new(Stage::Extract, 3 * tiles * bases.len(), clock.progress);
    let context = TileContext {
        options,
        oriented,
        bases: &bases,
        spacing,
        pixel,
        images_done: &images_done,
        views_done: &views_done,
    };
    let mut total = TileOutput {
        pixel,
        ..TileOutput::default()
    };
    let mut normals = Some(normals);
    for tile in plan.tiles {
        let output = if tile.members.is_empty() {
            let normals = normals.take().unwrap_or_default();
            convert_whole_cloud(cloud, normals, &context, warnings)?
        } else {
            let normals = normals.as_deref().unwrap_or_default();
            convert_member_tile(tile, cloud, normals, &context, warnings)?
        };
        clock.record(Stage::RangeImages.name(), output.image_seconds);
        clock.record(Stage::Extract.name(), output.extract_seconds);
        total.absorb(output);
    }
    Ok(total)
}

/// The whole cloud as one tile: no copy; the `normals` go once the columns hold them.
fn convert_whole_cloud(
    cloud: &TiledCloud<'_>,
    normals: Vec<Vec3>,
    context: &TileContext<'_>,
    warnings: &mut Vec<CloudWarning>,
) -> Result<TileOutput, CloudError> {
    let job = TileJob {
        positions: cloud.positions,
        points: PointColumns::new(cloud.positions, &normals),
        colours: cloud.colours,
        own: None,
        bounds: *cloud.bounds,
    };
    drop(normals);
    convert_tile(job, context, warnings)
}

/// One tile of a grid: its members' points gathered, then converted.
fn convert_member_tile(
    tile: TilePoints,
    cloud: &TiledCloud<'_>,
    normals: &[Vec3],
    context: &TileContext<'_>,
    warnings: &mut Vec<CloudWarning>,
) -> Result<TileOutput, CloudError> {
    let pick = |i: &u32| *i as usize;
    let positions: Vec<Vec3> = tile
        .members
        .iter()
        .map(|i| cloud.positions[pick(i)])
        .collect();
    let tile_normals: Vec<Vec3> = tile.members.iter().map(|i| normals[pick(i)]).collect();
    let colours: Option<Vec<[u8; 4]>> = cloud
        .colours
        .map(|c| tile.members.iter().map(|i| c[pick(i)]).collect());
    let job = TileJob {
        positions: &positions,
        points: PointColumns::new(&positions, &tile_normals),
        colours: colours.as_deref(),
        bounds: bounds_of_members(cloud.positions, &tile.members),
        own: Some(tile.own),
    };
    drop(tile_normals);
    convert_tile(job, context, warnings)
}

/// The scene of the patches, every one drawn from both sides (a cloud says nothing of what
/// is closed, so automatic culling draws them all from both sides).
fn build_scene(
    cloud: &PointCloud,
    patches: Vec<Patch>,
    points: usize,
) -> Result<Scene, CloudError> {
    if patches.is_empty() {
        return Err(CloudError::NoSurface { points });
    }
    let channel = match &cloud.colours {
        None => ColourChannel::None,
        Some(c) if c.iter().all(|c| c[3] == 255) => ColourChannel::Rgb8,
        Some(_) => ColourChannel::Rgba8,
    };
    let patches = patches
        .into_iter()
        .map(|p| p.with_sides(spatch_format::Sides::Both))
        .collect();
    Ok(Scene::new(cloud.origin, channel, patches)?)
}

/// The cloud with its points in Morton (Z-order) order of their position in `bounds`
/// (`morton_order.rs`), so that consecutive points are near each other: every later pass
/// over the points (one per view) then touches the images and grids in a cache-friendly
/// order. Also gives that order (the input index of each sorted point) for a borrowed
/// cloud, which the caller still holds and may measure the error against, and the points'
/// `scans` in the sorted order.
fn sort_spatially(
    cloud: Cow<'_, PointCloud>,
    bounds: &Aabb,
    scans: Option<PointScans>,
) -> (PointCloud, Option<PointOrder>, Option<PointScans>) {
    let order = morton_order(&cloud.positions, bounds);
    let scans = scans.map(|s| s.pick(order.par_iter().map(|o| o.1 as usize)));
    let (cloud, order) = match cloud {
        Cow::Borrowed(cloud) => {
            let sorted = PointCloud {
                origin: cloud.origin,
                positions: reorder(&cloud.positions, &order),
                colours: cloud.colours.as_deref().map(|c| reorder(c, &order)),
                normals: cloud.normals.as_deref().map(|v| reorder(v, &order)),
            };
            (sorted, Some(PointOrder::of_pairs(&order)))
        }
        // Each array is dropped once its sorted copy exists.
        Cow::Owned(PointCloud {
            origin,
            positions,
            colours,
            normals,
        }) => {
            let sorted = PointCloud {
                origin,
                positions: reorder(&positions, &order),
                colours: colours.map(|c| reorder(&c, &order)),
                normals: normals.map(|v| reorder(&v, &order)),
            };
            (sorted, None)
        }
    };
    (cloud, order, scans)
}

/// `values` in the order of the indices of `order`.
fn reorder<T: Copy + Send + Sync>(values: &[T], order: &[(u64, u32)]) -> Vec<T> {
    order.par_iter().map(|i| values[i.1 as usize]).collect()
}
