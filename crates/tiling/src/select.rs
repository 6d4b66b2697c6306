//! One tile's points: a streamed filter keeping the points of a tile and of its buffer,
//! as a cloud placed at the tile's lowest corner.
//!
//! Membership is the cloud pipeline's (`tiles.rs`): a point belongs to tile `K` when its
//! own tile is `K`, or a neighbour of `K` (faces, edges and corners) and it lies within the
//! buffer of `K`'s shared faces. So the pipeline, given these points and the plan's grid
//! with `only_tile = K`, sees exactly the members an untiled run would give `K`. Memory:
//! one chunk plus the tile's points (about 16 bytes a point, 20 with colours, 28 with
//! normals).

use std::path::Path;

use glam::DVec3;
use spatch_cloud::TileGrid;
use spatch_mesh::PointCloud;

use crate::stream::{stream_points, PointChunk};
use crate::TilingError;

/// Whether world point `w` is a member of tile `key` (its own point or its buffer's).
pub fn is_member(grid: &TileGrid, key: [i64; 3], w: DVec3) -> bool {
    let own = grid.key_of(w);
    (0..3).all(|k| {
        let (lo, hi) = member_offsets(grid, own, w, k);
        (lo..=hi).contains(&(key[k] - own[k]))
    })
}

/// Along axis `k`, the offsets `lo..=hi` (each -1, 0 or 1) from `w`'s own tile `own` of the
/// tiles `w` is a member of: -1 when it lies within the buffer of its tile's lower face,
/// +1 within that of its upper face (never both: the buffer is under half a tile).
pub(crate) fn member_offsets(grid: &TileGrid, own: [i64; 3], w: DVec3, k: usize) -> (i64, i64) {
    let near = grid.buffer / grid.size;
    let f = (w[k] - grid.anchor[k]) / grid.size - own[k] as f64;
    (-i64::from(f < near), i64::from(f > 1.0 - near))
}

/// The points of tile `key` and its buffer from `input`, relative to the tile's lowest
/// corner (the cloud's origin); with how many of them the tile owns.
///
/// Errors: the readers' errors.
pub fn read_tile_points(
    input: &Path,
    grid: &TileGrid,
    key: [i64; 3],
) -> Result<(PointCloud, u64), TilingError> {
    read_tile(input, grid, key).map(|t| (t.cloud, t.own))
}

/// One tile's points as [`read_tile`] gives them.
#[derive(Clone, Debug, PartialEq)]
pub struct TileCloud {
    /// Its own and buffer points, placed at the tile's lowest corner.
    pub cloud: PointCloud,
    /// How many of them it owns.
    pub own: u64,
    /// Its points of each scan of the input (`PointChunk::scan`), indexed by scan; they are
    /// consecutive runs of the cloud in scan order.
    pub scan_points: Vec<u64>,
}

/// [`read_tile_points`] with the tile's points counted per scan (for scan sets whose
/// scanners are known: the runs of `spatch_cloud::Scanners`).
///
/// Errors: the readers' errors.
pub fn read_tile(input: &Path, grid: &TileGrid, key: [i64; 3]) -> Result<TileCloud, TilingError> {
    let (origin, _) = grid.bounds_of(key);
    let mut scan_points = Vec::new();
    let mut cloud = PointCloud {
        origin,
        positions: Vec::new(),
        colours: None,
        normals: None,
    };
    let mut own = 0u64;
    stream_points(input, &mut |chunk: &PointChunk| {
        for (i, p) in chunk.positions.iter().enumerate() {
            if !p.is_finite() || !is_member(grid, key, *p) {
                continue;
            }
            own += u64::from(grid.key_of(*p) == key);
            crate::spill::count_scan(&mut scan_points, chunk.scan);
            cloud.positions.push((*p - origin).as_vec3());
            if let Some(c) = &chunk.colours {
                cloud.colours.get_or_insert_with(Vec::new).push(c[i]);
            }
            if let Some(n) = &chunk.normals {
                cloud.normals.get_or_insert_with(Vec::new).push(n[i]);
            }
        }
        Ok(())
    })?;
    Ok(TileCloud {
        cloud,
        own,
        scan_points,
    })
}
