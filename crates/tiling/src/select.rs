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
    let near = grid.buffer / grid.size;
    (0..3).all(|k| {
        let f = (w[k] - grid.anchor[k]) / grid.size - own[k] as f64;
        match own[k] - key[k] {
            0 => true,
            1 => f < near,
            -1 => f > 1.0 - near,
            _ => false,
        }
    })
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
    let (origin, _) = grid.bounds_of(key);
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
    Ok((cloud, own))
}
