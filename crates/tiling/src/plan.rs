//! Tile plans: the grid every tile of a scale-out run shares, the occupied tiles with their
//! bounds and counts, and the options every tile must convert with (spacing, pixel), written
//! as JSON (the schema is in `docs/scale.md`).
//!
//! Method: three streamed passes over the input, each holding one chunk: the bounds (the
//! grid's anchor is their lowest corner, as in an untiled run); each point's tile (counts
//! per occupied tile); and, unless the spacing is given, the points of the most populous
//! tile, whose 12-nearest-neighbour spacing is the plan's (a contiguous, full-density
//! sample, bounded by the tile). Memory: one chunk plus one counter per occupied tile (plus
//! the sampled tile).

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};
use spatch_cloud::{estimate_spacing, TileGrid, TILE_BUFFER_PIXELS};

use crate::stream::{stream_points, PointChunk};
use crate::TilingError;

/// The plan format's version (the `version` field).
pub const PLAN_VERSION: u32 = 1;

/// An axis-aligned box in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorldBox {
    /// Lowest corner.
    pub min: [f64; 3],
    /// Highest corner.
    pub max: [f64; 3],
}

impl WorldBox {
    /// The box from `min` to `max`.
    pub fn new(min: DVec3, max: DVec3) -> WorldBox {
        WorldBox {
            min: min.to_array(),
            max: max.to_array(),
        }
    }

    /// The box grown by `d` on every side.
    pub fn grown(&self, d: f64) -> WorldBox {
        WorldBox::new(
            DVec3::from_array(self.min) - d,
            DVec3::from_array(self.max) + d,
        )
    }
}

/// The shared grid, as the plan stores it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanGrid {
    /// World position of the lowest corner of tile `[0, 0, 0]`.
    pub anchor: [f64; 3],
    /// Side of a tile (model units).
    pub size: f64,
    /// Buffer around a tile (model units).
    pub buffer: f64,
}

impl PlanGrid {
    /// The grid as the cloud pipeline takes it.
    pub fn tile_grid(&self) -> Option<TileGrid> {
        TileGrid::new(DVec3::from_array(self.anchor), self.size, self.buffer)
    }
}

/// One occupied tile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanTile {
    /// Its position in the plan's list (`--tile K`).
    pub index: usize,
    /// Its grid key (see `TileGrid::key_of`).
    pub key: [i64; 3],
    /// The box it owns (`[min, max)` per axis).
    pub bounds: WorldBox,
    /// The box its conversion reads (its bounds grown by the buffer).
    pub buffered: WorldBox,
    /// Points it owns.
    pub points: u64,
}

/// A tile plan (see the module documentation).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// [`PLAN_VERSION`].
    pub version: u32,
    /// The input's file name (as given to `spatch plan`).
    pub input: String,
    /// Finite points read.
    pub points: u64,
    /// Points skipped for a non-finite coordinate.
    pub skipped_non_finite: u64,
    /// The finite points' bounds.
    pub bounds: WorldBox,
    /// The point spacing every tile converts with (model units).
    pub spacing: f32,
    /// The pixel factor every tile converts with (pixel = spacing × factor).
    pub pixel_factor: f32,
    /// The grid.
    pub grid: PlanGrid,
    /// Occupied tiles in key order (z, then y, then x).
    pub tiles: Vec<PlanTile>,
    /// For a scan set whose scanners are known (`spatch_scan::scan_viewpoints`): the
    /// translation of each scan (in stream order) that aligns it with the others, computed
    /// once over every tile so that the tiles agree at their seams; every tile's conversion
    /// moves its points of scan `k` by `scan_shifts[k]`. Absent (`null` or missing) for other
    /// inputs and plans made without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scan_shifts: Option<Vec<[f64; 3]>>,
}

/// What a plan is made from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanOptions {
    /// Side of a tile (model units, positive).
    pub tile: f64,
    /// Buffer (model units); `None`: [`TILE_BUFFER_PIXELS`] pixels.
    pub buffer: Option<f64>,
    /// Spacing (model units); `None`: estimated on the most populous tile.
    pub spacing: Option<f32>,
    /// Pixel factor (as `CloudOptions::pixel_factor`).
    pub pixel_factor: f32,
}

/// The largest buffer as a share of the tile side: under half a tile, so that a point lies
/// in the buffer of at most one neighbour per axis.
const BUFFER_SHARE: f64 = 0.49;

/// Whether `buffer` fits tiles of side `tile`: finite, 0 or more and under
/// [`BUFFER_SHARE`] of the side.
pub(crate) fn buffer_fits(buffer: f64, tile: f64) -> bool {
    buffer.is_finite() && buffer >= 0.0 && buffer < BUFFER_SHARE * tile
}

/// The error of a buffer the user gave that does not fit the tile ([`buffer_fits`]).
pub(crate) fn given_buffer_too_wide() -> TilingError {
    TilingError::InvalidOption {
        option: "buffer",
        reason: "must be 0 or more and under half the tile size".to_string(),
    }
}

/// The error of a tile too small for the default buffer (`buffer`, from `spacing`): the
/// user gave no buffer, so the message says which one was taken and what to change.
fn default_buffer_too_wide(buffer: f64, spacing: f32, tile: f64) -> TilingError {
    TilingError::InvalidOption {
        option: "tile size",
        reason: format!(
            "{tile} is too small for the default buffer of {TILE_BUFFER_PIXELS} pixels \
             ({buffer:.4} at the spacing {spacing:.4e}), which must be under half a tile: \
             take a tile of more than about {:.4} or give a smaller buffer",
            buffer / BUFFER_SHARE
        ),
    }
}

/// Streams `input` and plans its tiles (see the module documentation).
///
/// Errors: the readers' errors, [`TilingError::NoPoints`], [`TilingError::InvalidOption`]
/// (a tile size or buffer out of range, a spacing that cannot be estimated).
pub fn make_plan(input: &Path, options: &PlanOptions) -> Result<Plan, TilingError> {
    let invalid = |option, reason: &str| TilingError::InvalidOption {
        option,
        reason: reason.to_string(),
    };
    if !(options.tile.is_finite() && options.tile > 0.0) {
        return Err(invalid("tile size", "must be a positive number"));
    }
    let (lo, hi, points, skipped) = stream_bounds(input)?;
    let provisional = TileGrid::new(lo, options.tile, 0.0)
        .ok_or_else(|| invalid("tile size", "must be a positive number"))?;
    let counts = count_tiles(input, &provisional)?;
    let spacing = match options.spacing {
        Some(s) if s.is_finite() && s > 0.0 => s,
        Some(_) => return Err(invalid("spacing", "must be a positive number")),
        None => sample_spacing(input, &provisional, &counts)?,
    };
    let buffer = options.buffer.unwrap_or(f64::from(
        TILE_BUFFER_PIXELS * spacing * options.pixel_factor,
    ));
    if !buffer_fits(buffer, options.tile) {
        return Err(match options.buffer {
            Some(_) => given_buffer_too_wide(),
            None => default_buffer_too_wide(buffer, spacing, options.tile),
        });
    }
    let grid =
        TileGrid::new(lo, options.tile, buffer).ok_or_else(|| invalid("buffer", "out of range"))?;
    let tiles = tiles_of_counts(&counts, &grid, buffer);
    Ok(Plan {
        version: PLAN_VERSION,
        input: input.display().to_string(),
        points,
        skipped_non_finite: skipped,
        bounds: WorldBox::new(lo, hi),
        spacing,
        pixel_factor: options.pixel_factor,
        grid: PlanGrid {
            anchor: lo.to_array(),
            size: grid.size,
            buffer: grid.buffer,
        },
        tiles,
        scan_shifts: None,
    })
}

/// Pass 1: the finite points' bounds and count, and the non-finite ones skipped.
fn stream_bounds(input: &Path) -> Result<(DVec3, DVec3, u64, u64), TilingError> {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let (mut points, mut skipped) = (0u64, 0u64);
    stream_points(input, &mut |chunk: &PointChunk| {
        for p in &chunk.positions {
            if p.is_finite() {
                lo = lo.min(*p);
                hi = hi.max(*p);
                points += 1;
            } else {
                skipped += 1;
            }
        }
        Ok(())
    })?;
    if points == 0 {
        return Err(TilingError::NoPoints {
            path: input.to_path_buf(),
        });
    }
    Ok((lo, hi, points, skipped))
}

/// Pass 2: points per occupied tile, keyed `(z, y, x)` so the map is in key order.
fn count_tiles(
    input: &Path,
    grid: &TileGrid,
) -> Result<BTreeMap<(i64, i64, i64), u64>, TilingError> {
    let mut counts = BTreeMap::new();
    stream_points(input, &mut |chunk: &PointChunk| {
        for p in chunk.positions.iter().filter(|p| p.is_finite()) {
            let k = grid.key_of(*p);
            *counts.entry((k[2], k[1], k[0])).or_insert(0u64) += 1;
        }
        Ok(())
    })?;
    Ok(counts)
}

/// Pass 3: the spacing of the most populous tile's points.
fn sample_spacing(
    input: &Path,
    grid: &TileGrid,
    counts: &BTreeMap<(i64, i64, i64), u64>,
) -> Result<f32, TilingError> {
    let (&(z, y, x), _) = counts
        .iter()
        .max_by_key(|(k, &n)| (n, std::cmp::Reverse(**k)))
        .ok_or_else(|| TilingError::NoPoints {
            path: input.to_path_buf(),
        })?;
    let key = [x, y, z];
    let (corner, _) = grid.bounds_of(key);
    let mut sample: Vec<Vec3> = Vec::new();
    stream_points(input, &mut |chunk: &PointChunk| {
        sample.extend(
            chunk
                .positions
                .iter()
                .filter(|p| p.is_finite() && grid.key_of(**p) == key)
                .map(|p| (*p - corner).as_vec3()),
        );
        Ok(())
    })?;
    estimate_spacing(&sample)
        .map(|e| e.spacing)
        .map_err(|e| TilingError::InvalidOption {
            option: "spacing",
            reason: format!("cannot be estimated on the densest tile ({e}); give --spacing"),
        })
}

impl Plan {
    /// Reads a plan written by [`Plan::to_json`].
    ///
    /// Errors: [`TilingError::Io`], [`TilingError::BadJson`] (not JSON of this shape, another
    /// version, a grid out of range).
    pub fn read(path: &Path) -> Result<Plan, TilingError> {
        let text = std::fs::read_to_string(path).map_err(|e| TilingError::io(path, e))?;
        let bad = |reason: String| TilingError::BadJson {
            path: path.to_path_buf(),
            reason,
        };
        let plan: Plan =
            serde_json::from_str(&text).map_err(|e| bad(format!("not a plan: {e}")))?;
        if plan.version != PLAN_VERSION {
            return Err(bad(format!(
                "plan version {} (this spatch reads {PLAN_VERSION})",
                plan.version
            )));
        }
        if plan.grid.tile_grid().is_none() || !(plan.spacing.is_finite() && plan.spacing > 0.0) {
            return Err(bad("the grid or spacing is out of range".to_string()));
        }
        Ok(plan)
    }

    /// The plan as pretty JSON with a final newline.
    pub fn to_json(&self) -> String {
        let mut text = serde_json::to_string_pretty(self).unwrap_or_default();
        text.push('\n');
        text
    }

    /// Tile `index`, or [`TilingError::NoSuchTile`].
    pub fn tile(&self, index: usize) -> Result<&PlanTile, TilingError> {
        self.tiles.get(index).ok_or(TilingError::NoSuchTile {
            tile: index,
            tiles: self.tiles.len(),
        })
    }
}

/// The plan's tiles from the count of points (or faces) per occupied tile key `(z, y, x)`,
/// in key order: each tile's own box on `grid` and that box grown by `buffer`.
pub(crate) fn tiles_of_counts(
    counts: &BTreeMap<(i64, i64, i64), u64>,
    grid: &TileGrid,
    buffer: f64,
) -> Vec<PlanTile> {
    counts
        .iter()
        .enumerate()
        .map(|(index, (&(z, y, x), &points))| {
            let key = [x, y, z];
            let (min, max) = grid.bounds_of(key);
            let bounds = WorldBox::new(min, max);
            PlanTile {
                index,
                key,
                bounds,
                buffered: bounds.grown(buffer),
                points,
            }
        })
        .collect()
}
