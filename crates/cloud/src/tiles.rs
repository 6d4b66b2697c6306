//! Spatial tiles: a cubic grid over the cloud, so that every tile's range images stay under
//! their own pixel budget whatever the cloud's extent.
//!
//! Input: positions (relative to the cloud's f64 origin), the origin and a [`TileGrid`].
//! Output: a `TilePlan`: the occupied tiles in key order, each with its *own* points (those
//! inside its bounds) and its *buffer* points (those of neighbouring tiles within
//! [`TileGrid::buffer`] of its bounds), and the points dropped as outliers.
//!
//! A tile is its bounds plus a buffer. Tile `(i, j, k)` owns the world box
//! `anchor + [i·size, (i+1)·size) × [j·size, …) × [k·size, …)`; the pipeline anchors the
//! grid at the cloud's lowest corner (so a compact object is cut by as few tile faces as
//! possible), and a scale-out plan can give its own grid so every run shares it. Its range images are
//! drawn from its own and its buffer points, so surfaces stay continuous across its border
//! (the gap filling, smoothing and cell tests near the border see the neighbour's points),
//! while only its own points are offered to the extraction: every patch is cut to cover
//! points the tile owns, so its *anchor* (the mean of the points it was cut for) lies inside
//! the tile's own bounds, each point is covered by exactly one tile's patches, and tiles join
//! with no seam (the one-cell overlap of neighbouring regions, as between views) and no
//! duplicate.
//!
//! Outliers: a tile holding fewer than [`OUTLIER_TILE_POINTS`] points with its buffer holds
//! no surface worth a patch (a tile is hundreds of pixels wide); its own points are dropped
//! and counted instead of blowing up one image over the whole extent.
//!
//! Invariants: deterministic (tiles in key order, points in index order within a tile);
//! every kept point is the own point of exactly one tile.
//!
//! Cost: one pass over the points and a sort of `(tile, point)` pairs, about `n · (1 + f)`
//! pairs where `f` is the share of points within a buffer of a tile face (12 bytes a pair);
//! memory proportional to the points, never to the bounding box (only occupied tiles exist).

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use spatch_mesh::Aabb;

use crate::PointId;

/// Buffer around a tile, in pixels: covers the gap filling (up to 8 px), the smoothing
/// window and the one-cell dilation of emitted regions, with room to spare.
pub const TILE_BUFFER_PIXELS: f32 = 16.0;

/// A tile holding fewer points than this (with its buffer) is outliers, dropped.
pub const OUTLIER_TILE_POINTS: usize = 16;

/// Tiles per axis at most (21 bits of the packed tile key).
const MAX_TILES_PER_AXIS: i64 = 1 << 20;

/// A cubic grid of tiles with a corner at `anchor`.
///
/// # Guarantees
/// `size > 0`, `0 ≤ buffer < size / 2` (built by [`TileGrid::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TileGrid {
    /// World position of a corner of tile `(0, 0, 0)`.
    pub anchor: DVec3,
    /// Side of a tile (model units).
    pub size: f64,
    /// Width of the buffer around a tile (model units).
    pub buffer: f64,
}

impl TileGrid {
    /// A grid of tiles of side `size` from `anchor` with a buffer of `buffer`, the buffer
    /// clamped below half a tile; `None` unless `size` is positive and finite.
    pub fn new(anchor: DVec3, size: f64, buffer: f64) -> Option<TileGrid> {
        (size.is_finite() && size > 0.0).then(|| TileGrid {
            anchor,
            size,
            buffer: buffer.clamp(0.0, 0.49 * size),
        })
    }

    /// The largest grid whose tiles, with a buffer of [`TILE_BUFFER_PIXELS`], fit `views`
    /// range images of `pixel` within `budget` pixels in total (a cube of side `L` projects
    /// into a rectangle of at most `√3·L` square), and coarse enough that an `extent` wide
    /// cloud spans at most 2^20 tiles per axis; anchored at `anchor`.
    pub fn for_budget(
        anchor: DVec3,
        pixel: f32,
        views: usize,
        budget: usize,
        extent: f64,
    ) -> TileGrid {
        let pixel = f64::from(pixel);
        let per_view = (budget as f64 / views.max(1) as f64).sqrt();
        let buffer = f64::from(TILE_BUFFER_PIXELS) * pixel;
        let side = (per_view - 2.0).max(1.0) * pixel / 3f64.sqrt();
        let size = (side - 2.0 * buffer)
            .max(2.5 * buffer)
            .max(extent / (MAX_TILES_PER_AXIS - 2) as f64);
        TileGrid {
            anchor,
            size,
            buffer: buffer.min(0.49 * size),
        }
    }

    /// The tile holding world point `w`.
    pub fn key_of(&self, w: DVec3) -> [i64; 3] {
        let k = ((w - self.anchor) / self.size).floor();
        [k.x as i64, k.y as i64, k.z as i64]
    }

    /// The world bounds a tile owns: `[min, max)` per axis.
    pub fn bounds_of(&self, key: [i64; 3]) -> (DVec3, DVec3) {
        let min = self.anchor + DVec3::new(key[0] as f64, key[1] as f64, key[2] as f64) * self.size;
        (min, min + DVec3::splat(self.size))
    }
}

/// One occupied tile.
#[derive(Clone, Debug)]
pub(crate) struct TilePoints {
    /// Its own and buffer points (cloud indices, increasing).
    pub(crate) members: Vec<u32>,
    /// Positions in `members` of its own points.
    pub(crate) own: Vec<PointId>,
}

/// The tiles of a cloud.
#[derive(Clone, Debug)]
pub(crate) struct TilePlan {
    /// The grid.
    pub(crate) grid: TileGrid,
    /// Occupied tiles (without the outliers'), in key order.
    pub(crate) tiles: Vec<TilePoints>,
    /// Points dropped as outliers.
    pub(crate) outlier_points: usize,
    /// Tiles they occupied.
    pub(crate) outlier_tiles: usize,
}

/// Assigns every point to its tile and to the buffers of the neighbours it is near (see the
/// module documentation).
pub(crate) fn plan_tiles(positions: &[Vec3], origin: DVec3, grid: TileGrid) -> TilePlan {
    let pairs = tile_pairs(positions, origin, grid);
    group_tiles(grid, &pairs)
}

/// One `(packed tile key, point, own)` pair: the point is in the tile, as its own point or
/// (`own` false) a buffer point.
type TilePair = (u64, u32, bool);

/// Every point's pairs with its own tile and the neighbours whose buffers hold it, sorted
/// by packed tile key, then point.
fn tile_pairs(positions: &[Vec3], origin: DVec3, grid: TileGrid) -> Vec<TilePair> {
    let n = positions.len();
    let world = |i: usize| origin + positions[i].as_dvec3();
    let key_min = (0..n)
        .into_par_iter()
        .map(|i| grid.key_of(world(i)))
        .reduce(|| [i64::MAX; 3], |a, b| [0, 1, 2].map(|k| a[k].min(b[k])));
    let near = grid.buffer / grid.size;
    let mut pairs: Vec<TilePair> = (0..n)
        .into_par_iter()
        .flat_map_iter(|i| {
            let w = world(i);
            let key = grid.key_of(w);
            let side = buffer_sides(&grid, near, w, key);
            (0..8u32).filter_map(move |combo| {
                let step = [0, 1, 2].map(|k| if combo & (1 << k) != 0 { side[k] } else { 0 });
                let moves = (0..3).all(|k| combo & (1 << k) == 0 || side[k] != 0);
                moves.then(|| {
                    let tile = [0, 1, 2].map(|k| key[k] + step[k]);
                    (pack_key(tile, key_min), i as u32, combo == 0)
                })
            })
        })
        .collect();
    pairs.par_sort_unstable_by_key(|p| (p.0, p.1));
    pairs
}

/// Per axis, the neighbour of tile `key` whose buffer holds world point `w` (-1, +1) or
/// none (0); `near` is the buffer in tile sides (computed once per plan, not per point).
fn buffer_sides(grid: &TileGrid, near: f64, w: DVec3, key: [i64; 3]) -> [i64; 3] {
    [0, 1, 2].map(|k| {
        let f = (w[k] - grid.anchor[k]) / grid.size - key[k] as f64;
        if f < near {
            -1
        } else if f > 1.0 - near {
            1
        } else {
            0
        }
    })
}

/// The packed key of tile `key`, one axis per 21 bits, shifted so the lowest occupied tile
/// `key_min` (less one, for buffers) is 0.
fn pack_key(key: [i64; 3], key_min: [i64; 3]) -> u64 {
    let axis = |k: usize| ((key[k] - key_min[k] + 1).clamp(0, (1 << 21) - 1)) as u64;
    (axis(2) << 42) | (axis(1) << 21) | axis(0)
}

/// The plan from the sorted `pairs`: each run of one tile key is a tile, or outliers when
/// it holds fewer than [`OUTLIER_TILE_POINTS`] points (tiles with no own point are left out).
fn group_tiles(grid: TileGrid, pairs: &[TilePair]) -> TilePlan {
    let mut tiles = Vec::new();
    let (mut outlier_points, mut outlier_tiles) = (0, 0);
    let mut start = 0;
    while start < pairs.len() {
        let packed = pairs[start].0;
        let end = start + pairs[start..].partition_point(|p| p.0 == packed);
        let group = &pairs[start..end];
        let own: Vec<PointId> = (0..group.len())
            .filter(|&k| group[k].2)
            .map(|k| PointId(k as u32))
            .collect();
        if group.len() < OUTLIER_TILE_POINTS {
            outlier_points += own.len();
            outlier_tiles += usize::from(!own.is_empty());
        } else if !own.is_empty() {
            tiles.push(TilePoints {
                members: group.iter().map(|p| p.1).collect(),
                own,
            });
        }
        start = end;
    }
    TilePlan {
        grid,
        tiles,
        outlier_points,
        outlier_tiles,
    }
}

/// The bounds of `positions[members]`.
pub(crate) fn bounds_of_members(positions: &[Vec3], members: &[u32]) -> Aabb {
    Aabb::from_points(members.iter().map(|&i| positions[i as usize]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_is_owned_once_and_buffers_reach_across() {
        // A 40 x 40 grid of points over [0, 4) x [0, 4) at z = 0.5, tiles of 1 with a 0.1
        // buffer.
        let positions: Vec<Vec3> = (0..1600)
            .map(|k| {
                Vec3::new(
                    (k % 40) as f32 * 0.1 + 0.05,
                    (k / 40) as f32 * 0.1 + 0.05,
                    0.5,
                )
            })
            .collect();
        let grid = TileGrid::new(DVec3::ZERO, 1.0, 0.1).unwrap();
        let plan = plan_tiles(&positions, DVec3::ZERO, grid);
        assert_eq!(plan.tiles.len(), 16);
        assert_eq!(plan.outlier_points, 0);
        let owned: usize = plan.tiles.iter().map(|t| t.own.len()).sum();
        assert_eq!(owned, 1600);
        for tile in &plan.tiles {
            let first = positions[tile.members[tile.own[0].index()] as usize].as_dvec3();
            let (lo, hi) = grid.bounds_of(grid.key_of(first));
            for &own in &tile.own {
                let p = positions[tile.members[own.index()] as usize].as_dvec3();
                assert!(p.cmpge(lo).all() && p.cmplt(hi).all(), "{p} in {lo}..{hi}");
            }
            // Points at 0.05 from a shared face are in the neighbour's buffer.
            assert!(tile.members.len() > tile.own.len());
        }
    }

    #[test]
    fn a_lone_point_is_an_outlier() {
        let mut positions: Vec<Vec3> = (0..400)
            .map(|k| Vec3::new((k % 20) as f32 * 0.01, (k / 20) as f32 * 0.01, 0.0))
            .collect();
        positions.push(Vec3::new(500.0, 0.0, 0.0));
        let plan = plan_tiles(
            &positions,
            DVec3::ZERO,
            TileGrid::new(DVec3::ZERO, 1.0, 0.05).unwrap(),
        );
        assert_eq!(plan.outlier_points, 1);
        assert_eq!(plan.outlier_tiles, 1);
        assert_eq!(plan.tiles.len(), 1);
        assert_eq!(plan.tiles[0].own.len(), 400);
    }
}
