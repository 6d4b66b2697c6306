//! Streamed reading of point files: chunks of at most [`CHUNK_POINTS`] points handed to a
//! visitor, so memory follows the chunk, never the file.
//!
//! Formats by extension: `.ply` (ASCII, binary little- or big-endian; `ply_stream.rs`),
//! `.las`/`.laz` (`las_stream.rs`), `.xyz`/`.txt`/`.pts` (`xyz_stream.rs`); scan sets,
//! posed: `.conf` and `.e57` (`scan_stream.rs`). Every chunk has
//! colours exactly when the file does (and normals likewise), so chunks concatenate.
//! Points with a non-finite coordinate are skipped by the readers' users, not here.

use std::path::Path;

use glam::{DVec3, Vec3};

use crate::TilingError;

/// Points per chunk at most.
pub const CHUNK_POINTS: usize = 1 << 16;

/// A run of consecutive points of a file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointChunk {
    /// World positions.
    pub positions: Vec<DVec3>,
    /// sRGB RGBA8 colours, when the file has them.
    pub colours: Option<Vec<[u8; 4]>>,
    /// Normals as given, when the file has them.
    pub normals: Option<Vec<Vec3>>,
    /// The scan its points belong to, counted from 0 over the input in stream order
    /// (always 0 for a single-scan file; a chunk never spans two scans).
    pub scan: usize,
}

impl PointChunk {
    /// Empties the chunk, keeping which attributes it has.
    pub(crate) fn clear(&mut self) {
        self.positions.clear();
        if let Some(c) = &mut self.colours {
            c.clear();
        }
        if let Some(n) = &mut self.normals {
            n.clear();
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether it holds no point.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }
}

/// What a visitor of chunks returns.
pub type Visit<'a> = dyn FnMut(&PointChunk) -> Result<(), TilingError> + 'a;

/// Streams `path`'s points to `visit` in file order; returns how many were read.
///
/// Errors: [`TilingError::UnsupportedFormat`], the readers' I/O and format errors, and
/// whatever `visit` returns.
pub fn stream_points(path: &Path, visit: &mut Visit<'_>) -> Result<u64, TilingError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "ply" => crate::ply_stream::stream_ply(path, visit),
        "las" | "laz" => crate::las_stream::stream_las(path, visit),
        "xyz" | "txt" | "pts" => crate::xyz_stream::stream_xyz(path, visit),
        "conf" => crate::scan_stream::stream_conf(path, visit),
        "e57" => crate::scan_stream::stream_e57(path, visit),
        _ => Err(TilingError::UnsupportedFormat {
            path: path.to_path_buf(),
        }),
    }
}
