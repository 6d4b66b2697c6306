//! ASTM E57 scanner files read as a stream: every scan's points handed out in chunks of at
//! most a given size, in the scan's own frame with its pose, so memory follows the chunk,
//! never the file.
//!
//! The points, colours and poses are those [`read_e57`](crate::read_e57) gives, in the same
//! order (the same `e57` reader settings and the same per-point rules: a point without a
//! valid finite Cartesian position is dropped and counted; colour, or intensity as grey,
//! as bytes). A chunk never spans two scans and is never empty.
//!
//! Cost: one pass over each scan's points; the `e57` reader holds one data packet at a time
//! and this reader one chunk.

use std::path::Path;

use glam::DVec3;

use crate::e57::{finite_position, point_colour, scan_pose};
use crate::{Pose, ScanError, ScanWarning};

/// A run of consecutive points of one scan of an E57 file.
#[derive(Clone, Copy, Debug)]
pub struct E57Chunk<'a> {
    /// Which scan of the file (from 0, in file order).
    pub scan: usize,
    /// The scan's pose: its own frame to the file's frame.
    pub pose: &'a Pose,
    /// Finite positions in the scan's own frame.
    pub positions: &'a [DVec3],
    /// sRGB RGBA8 colours (or intensity as grey), when the scan has either.
    pub colours: Option<&'a [[u8; 4]]>,
}

/// What a streamed E57 file held.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct E57Streamed {
    /// Points handed out (finite, valid Cartesian positions).
    pub points: u64,
    /// Scans (point clouds) in the file, empty ones included: the next file's scans are
    /// numbered from here in a set of several.
    pub scans: usize,
    /// Points dropped: no valid Cartesian position, or a non-finite one.
    pub dropped_non_finite: u64,
    /// One [`ScanWarning::IntensityAsGrey`] per scan whose intensity became its colour.
    pub warnings: Vec<ScanWarning>,
}

/// Streams every scan of the E57 file at `path` to `visit`, in chunks of at most
/// `chunk_points` points (at least 1); see the module docs.
///
/// Errors: [`ScanError::Io`], [`ScanError::E57`], [`ScanError::BadScanPose`] (converted
/// into `E`), and whatever `visit` returns. A file with no point is not an error here: the
/// caller sees `points == 0`.
pub fn stream_e57<E: From<ScanError>>(
    path: &Path,
    chunk_points: usize,
    visit: &mut dyn FnMut(&E57Chunk<'_>) -> Result<(), E>,
) -> Result<E57Streamed, E> {
    let file = std::fs::File::open(path).map_err(|source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let refuse = |source| ScanError::E57 {
        path: path.to_path_buf(),
        source: Box::new(source),
    };
    let mut reader = e57::E57Reader::new(std::io::BufReader::new(file)).map_err(refuse)?;
    let mut streamed = E57Streamed::default();
    let chunk_points = chunk_points.max(1);
    let pointclouds = reader.pointclouds();
    streamed.scans = pointclouds.len();
    for (index, pc) in pointclouds.into_iter().enumerate() {
        let pose = scan_pose(path, &pc)?;
        let grey = !pc.has_color() && pc.has_intensity();
        let mut chunk = ChunkBuffer {
            scan: index,
            pose,
            positions: Vec::with_capacity(chunk_points.min(1 << 20)),
            colours: (pc.has_color() || grey).then(Vec::new),
        };
        let mut points = reader.pointcloud_simple(&pc).map_err(refuse)?;
        points.apply_pose(false);
        points.intensity_to_color(false);
        for point in points {
            let point = point.map_err(refuse)?;
            let Some(p) = finite_position(&point) else {
                streamed.dropped_non_finite += 1;
                continue;
            };
            chunk.positions.push(p);
            if let Some(colours) = chunk.colours.as_mut() {
                colours.push(point_colour(&point, grey));
            }
            if chunk.positions.len() == chunk_points {
                streamed.points += chunk.flush(visit)?;
            }
        }
        streamed.points += chunk.flush(visit)?;
        if grey {
            streamed.warnings.push(ScanWarning::IntensityAsGrey {
                path: path.to_path_buf(),
            });
        }
    }
    Ok(streamed)
}

/// The chunk being filled, of one scan.
struct ChunkBuffer {
    scan: usize,
    pose: Pose,
    positions: Vec<DVec3>,
    colours: Option<Vec<[u8; 4]>>,
}

impl ChunkBuffer {
    /// Hands the points gathered to `visit` (none: no call) and empties the buffer; returns
    /// how many it handed out.
    fn flush<E>(
        &mut self,
        visit: &mut dyn FnMut(&E57Chunk<'_>) -> Result<(), E>,
    ) -> Result<u64, E> {
        let n = self.positions.len();
        if n == 0 {
            return Ok(0);
        }
        visit(&E57Chunk {
            scan: self.scan,
            pose: &self.pose,
            positions: &self.positions,
            colours: self.colours.as_deref(),
        })?;
        self.positions.clear();
        if let Some(c) = &mut self.colours {
            c.clear();
        }
        Ok(n as u64)
    }
}
