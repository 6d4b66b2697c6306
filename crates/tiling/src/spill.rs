//! One streamed pass that spills every tile's points (its own and its buffer's) into a file
//! per tile, so a local run reads the input once instead of once per tile.
//!
//! Method: each point's own tile and, per axis, whether it lies within the buffer of its
//! tile's lower or upper face ([`crate::select`]'s membership) give the up to 8 tiles it is
//! a member of; for each of those that the run converts, the point is appended to that
//! tile's in-memory buffer as a fixed-size record: its position relative to the tile's
//! lowest corner (f32, exactly what [`crate::read_tile_points`] computes), then its colour
//! and normal when the file has them. When the buffers together pass the byte budget, every
//! buffer is appended to its tile's file (opened, written, closed: no limit on open files).
//! Points keep file order within a tile, so [`read_spilled_tile`] gives the same cloud, bit
//! for bit, as [`crate::read_tile_points`].
//!
//! Memory: one chunk plus the budget (plus a small count per tile). Disk: the input's points
//! times `1 + f` records (`f`: the share within a buffer of a tile face), 12 to 28 bytes a
//! record.

use std::collections::HashMap;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};
use spatch_cloud::TileGrid;
use spatch_mesh::PointCloud;

use crate::select::member_offsets;
use crate::stream::{stream_points, PointChunk};
use crate::TilingError;

/// Default byte budget of the in-memory buffers of a spill.
pub const SPILL_BUDGET: usize = 16 << 20;

/// Which attributes every record holds after its position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpillLayout {
    /// An sRGB RGBA8 colour (4 bytes).
    pub colours: bool,
    /// A normal (3 × f32).
    pub normals: bool,
}

impl SpillLayout {
    /// Bytes of one record.
    pub fn record_bytes(&self) -> usize {
        12 + 4 * usize::from(self.colours) + 12 * usize::from(self.normals)
    }
}

/// One tile's spill file.
#[derive(Clone, Debug, PartialEq)]
pub struct SpilledTile {
    /// Its grid key.
    pub key: [i64; 3],
    /// Its file (absent when it received no point).
    pub path: PathBuf,
    /// Records in the file (own and buffer points).
    pub points: u64,
    /// Of these, the points it owns.
    pub own: u64,
    /// Its records of each scan of the input (`PointChunk::scan`), indexed by scan: the
    /// file holds them as consecutive runs in scan order (scans stream in order, and a
    /// tile keeps file order).
    pub scan_points: Vec<u64>,
}

/// What a spill wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Spill {
    /// The grid the tiles belong to.
    pub grid: TileGrid,
    /// The records' layout (the same in every file).
    pub layout: SpillLayout,
    /// The tiles, in the order they were asked for.
    pub tiles: Vec<SpilledTile>,
}

/// The in-memory side of a spill in progress.
struct Spiller {
    grid: TileGrid,
    slot: HashMap<[i64; 3], usize>,
    tiles: Vec<SpilledTile>,
    buffers: Vec<Vec<u8>>,
    started: Vec<bool>,
    buffered: usize,
    budget: usize,
    layout: Option<SpillLayout>,
}

/// Streams `input` once and writes, into `dir` (which must exist), one file per tile of
/// `keys` holding its own and buffer points (see the module documentation), with buffers of
/// at most about `budget` bytes in memory. Non-finite points are skipped.
///
/// Errors: the readers' errors, [`TilingError::Io`] on the spill files,
/// [`TilingError::Malformed`] when a chunk's attributes differ from the first chunk's.
pub fn spill_tiles(
    input: &Path,
    grid: &TileGrid,
    keys: &[[i64; 3]],
    dir: &Path,
    budget: usize,
) -> Result<Spill, TilingError> {
    let mut spiller = Spiller {
        grid: *grid,
        slot: keys.iter().enumerate().map(|(i, k)| (*k, i)).collect(),
        tiles: keys
            .iter()
            .enumerate()
            .map(|(i, &key)| SpilledTile {
                key,
                path: dir.join(format!("spill_{i:05}.bin")),
                points: 0,
                own: 0,
                scan_points: Vec::new(),
            })
            .collect(),
        buffers: vec![Vec::new(); keys.len()],
        started: vec![false; keys.len()],
        buffered: 0,
        budget: budget.max(1),
        layout: None,
    };
    stream_points(input, &mut |chunk: &PointChunk| spiller.take(input, chunk))?;
    spiller.flush()?;
    for (tile, started) in spiller.tiles.iter().zip(&spiller.started) {
        if !started {
            remove_stale(&tile.path)?;
        }
    }
    Ok(Spill {
        grid: *grid,
        layout: spiller.layout.unwrap_or_default(),
        tiles: spiller.tiles,
    })
}

impl Spiller {
    /// Spills one chunk.
    fn take(&mut self, input: &Path, chunk: &PointChunk) -> Result<(), TilingError> {
        let layout = SpillLayout {
            colours: chunk.colours.is_some(),
            normals: chunk.normals.is_some(),
        };
        if *self.layout.get_or_insert(layout) != layout {
            return Err(TilingError::malformed(
                input,
                "a chunk's colours or normals differ from the first chunk's",
            ));
        }
        for (i, &w) in chunk.positions.iter().enumerate() {
            if !w.is_finite() {
                continue;
            }
            let own = self.grid.key_of(w);
            let axes = [0, 1, 2].map(|k| member_offsets(&self.grid, own, w, k));
            for dz in axes[2].0..=axes[2].1 {
                for dy in axes[1].0..=axes[1].1 {
                    for dx in axes[0].0..=axes[0].1 {
                        let key = [own[0] + dx, own[1] + dy, own[2] + dz];
                        if let Some(&slot) = self.slot.get(&key) {
                            self.push(slot, w, (dx, dy, dz) == (0, 0, 0), chunk, i);
                        }
                    }
                }
            }
        }
        if self.buffered > self.budget {
            self.flush()?;
        }
        Ok(())
    }

    /// Appends point `i` of `chunk` (world position `w`) to tile `slot`'s buffer.
    fn push(&mut self, slot: usize, w: DVec3, own: bool, chunk: &PointChunk, i: usize) {
        let (origin, _) = self.grid.bounds_of(self.tiles[slot].key);
        let buffer = &mut self.buffers[slot];
        let before = buffer.len();
        for v in (w - origin).as_vec3().to_array() {
            buffer.extend_from_slice(&v.to_le_bytes());
        }
        if let Some(c) = &chunk.colours {
            buffer.extend_from_slice(&c[i]);
        }
        if let Some(n) = &chunk.normals {
            for v in n[i].to_array() {
                buffer.extend_from_slice(&v.to_le_bytes());
            }
        }
        self.buffered += buffer.len() - before;
        let tile = &mut self.tiles[slot];
        tile.points += 1;
        tile.own += u64::from(own);
        count_scan(&mut tile.scan_points, chunk.scan);
    }

    /// Appends every non-empty buffer to its file.
    fn flush(&mut self) -> Result<(), TilingError> {
        for ((buffer, tile), started) in self
            .buffers
            .iter_mut()
            .zip(&self.tiles)
            .zip(&mut self.started)
        {
            if buffer.is_empty() {
                continue;
            }
            let path = &tile.path;
            let mut file = std::fs::OpenOptions::new()
                .create(true)
                .write(true)
                .append(*started)
                .truncate(!*started)
                .open(path)
                .map_err(|e| TilingError::io(path, e))?;
            file.write_all(buffer)
                .map_err(|e| TilingError::io(path, e))?;
            *started = true;
            buffer.clear();
        }
        self.buffered = 0;
        Ok(())
    }
}

/// Counts one point of scan `scan` in `scan_points` (one count per scan, grown as needed).
pub(crate) fn count_scan(scan_points: &mut Vec<u64>, scan: usize) {
    if scan_points.len() <= scan {
        scan_points.resize(scan + 1, 0);
    }
    scan_points[scan] += 1;
}

/// Removes a spill file left by an earlier run at `path`, if any.
fn remove_stale(path: &Path) -> Result<(), TilingError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(TilingError::io(path, e)),
        _ => Ok(()),
    }
}

/// Records decoded per read of a spill file.
const READ_RECORDS: usize = 1 << 14;

/// Tile `index` of `spill` as a cloud placed at the tile's lowest corner, with how many of
/// its points it owns: the same cloud as [`crate::read_tile_points`] on the input.
///
/// Errors: [`TilingError::Io`] (a missing or short file).
pub fn read_spilled_tile(spill: &Spill, index: usize) -> Result<(PointCloud, u64), TilingError> {
    let tile = &spill.tiles[index];
    let (origin, _) = spill.grid.bounds_of(tile.key);
    let n = usize::try_from(tile.points).unwrap_or(usize::MAX);
    let layout = spill.layout;
    let mut cloud = PointCloud {
        origin,
        positions: Vec::with_capacity(n),
        colours: (layout.colours && n > 0).then(|| Vec::with_capacity(n)),
        normals: (layout.normals && n > 0).then(|| Vec::with_capacity(n)),
    };
    if n == 0 {
        return Ok((cloud, tile.own));
    }
    let path = &tile.path;
    let mut file = std::fs::File::open(path).map_err(|e| TilingError::io(path, e))?;
    let size = layout.record_bytes();
    let mut bytes = vec![0u8; size * READ_RECORDS];
    let mut left = n;
    while left > 0 {
        let count = left.min(READ_RECORDS);
        let run = &mut bytes[..count * size];
        file.read_exact(run).map_err(|e| TilingError::io(path, e))?;
        for record in run.chunks_exact(size) {
            decode(record, &mut cloud);
        }
        left -= count;
    }
    Ok((cloud, tile.own))
}

/// Appends one record to `cloud`.
fn decode(record: &[u8], cloud: &mut PointCloud) {
    let f = |at: usize| {
        f32::from_le_bytes([record[at], record[at + 1], record[at + 2], record[at + 3]])
    };
    cloud.positions.push(Vec3::new(f(0), f(4), f(8)));
    let mut at = 12;
    if let Some(colours) = &mut cloud.colours {
        colours.push([record[at], record[at + 1], record[at + 2], record[at + 3]]);
        at += 4;
    }
    if let Some(normals) = &mut cloud.normals {
        normals.push(Vec3::new(f(at), f(at + 4), f(at + 8)));
    }
}
