//! Scan sets as a stream of posed points: a Stanford `.conf` (each `bmesh` line a scan file
//! and its pose) or an E57 file (each scan with its own pose).
//!
//! A `.conf`'s scans in the streamed formats (PLY, LAS/LAZ, XYZ/TXT/PTS) are streamed a
//! chunk at a time, each chunk moved into the common frame by the scan's pose (positions
//! and normals); an E57 file's scans are streamed likewise by `spatch_scan::stream_e57`, each
//! chunk moved by its scan's own pose (then by the `.conf`'s pose, for a `.conf` that lists
//! E57 scans). The chunks of a set carry
//! colours (and normals) exactly when its first scan does; a later scan that differs is
//! refused, so that chunks concatenate. Each chunk carries its scan's index over the set
//! (`PointChunk::scan`: the `.conf`'s entries in order, an E57 entry counting each of its
//! scans), the order of `spatch_scan::scan_viewpoints`.

use std::path::Path;

use spatch_scan::{read_conf, E57Chunk, Pose};

use crate::stream::{stream_points, PointChunk, Visit, CHUNK_POINTS};
use crate::TilingError;

/// Which attributes the set's chunks carry, fixed by its first chunk.
#[derive(Default)]
struct Attributes(Option<(bool, bool)>);

impl Attributes {
    /// Checks `chunk` against the attributes seen first.
    fn check(&mut self, path: &Path, chunk: &PointChunk) -> Result<(), TilingError> {
        let has = (chunk.colours.is_some(), chunk.normals.is_some());
        match self.0 {
            None => self.0 = Some(has),
            Some(first) if first != has => {
                return Err(TilingError::malformed(
                    path,
                    "its scans differ in having colours or normals; a plan needs them alike",
                ))
            }
            Some(_) => {}
        }
        Ok(())
    }
}

/// Streams the scans of the `.conf` at `path`, posed; returns the points read.
pub(crate) fn stream_conf(path: &Path, visit: &mut Visit<'_>) -> Result<u64, TilingError> {
    let set = read_conf(path).map_err(|e| TilingError::malformed(path, e.to_string()))?;
    let mut attributes = Attributes::default();
    let mut read = 0;
    // The first scan of the entry being streamed, counted over the set.
    let mut first = 0;
    for entry in &set.scans {
        let mut check = |chunk: &PointChunk| {
            attributes.check(path, chunk)?;
            visit(chunk)
        };
        let (points, scans) = if is_e57(&entry.path) {
            // Posed once, by each scan's pose then the entry's.
            stream_e57_posed(&entry.path, &entry.pose, first, &mut check)?
        } else {
            let mut posed = |chunk: &PointChunk| {
                let mut moved = posed_chunk(chunk, &entry.pose);
                moved.scan += first;
                check(&moved)
            };
            (stream_points(&entry.path, &mut posed)?, 1)
        };
        read += points;
        first += scans;
    }
    Ok(read)
}

/// Streams the scans of the E57 file at `path`, each by its own pose.
pub(crate) fn stream_e57(path: &Path, visit: &mut Visit<'_>) -> Result<u64, TilingError> {
    let mut attributes = Attributes::default();
    let (points, _) = stream_e57_posed(path, &Pose::IDENTITY, 0, &mut |chunk: &PointChunk| {
        attributes.check(path, chunk)?;
        visit(chunk)
    })?;
    Ok(points)
}

/// Whether `path` is an E57 file (by extension).
fn is_e57(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("e57"))
}

/// The scans of an E57 file, each moved by its own pose and then by `pose`, streamed a
/// chunk at a time by [`spatch_scan::stream_e57`], the scans numbered from `first`; gives
/// the points read and the file's scans.
fn stream_e57_posed(
    path: &Path,
    pose: &Pose,
    first: usize,
    visit: &mut Visit<'_>,
) -> Result<(u64, usize), TilingError> {
    let streamed = spatch_scan::stream_e57(path, CHUNK_POINTS, &mut |chunk: &E57Chunk<'_>| {
        let total = pose.after(chunk.pose);
        visit(&PointChunk {
            positions: chunk
                .positions
                .iter()
                .map(|&p| total.apply_point(p))
                .collect(),
            colours: chunk.colours.map(<[[u8; 4]]>::to_vec),
            normals: None,
            scan: first + chunk.scan,
        })
    })?;
    Ok((streamed.points, streamed.scans))
}

/// `chunk` moved by `pose` (positions, and normals by its rotation).
fn posed_chunk(chunk: &PointChunk, pose: &Pose) -> PointChunk {
    PointChunk {
        positions: chunk
            .positions
            .iter()
            .map(|&p| pose.apply_point(p))
            .collect(),
        colours: chunk.colours.clone(),
        normals: chunk.normals.as_ref().map(|n| {
            n.iter()
                .map(|v| pose.apply_vector(v.as_dvec3()).as_vec3())
                .collect()
        }),
        scan: chunk.scan,
    }
}
