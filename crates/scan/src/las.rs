//! ASPRS LAS 1.0-1.4 and LAZ (compressed LAS) lidar files, through the `las` crate (with its
//! `laz` feature, the laz-rs decoder).
//!
//! Input: a `.las` or `.laz` file. Output: one [`PosedScan`] (identity pose: LAS coordinates
//! are already in the project's frame, scaled and offset by the header; they are kept in f64
//! so georeferenced coordinates in the millions stay exact before centring).
//!
//! Colours: point formats with RGB (2, 3, 5, 7, 8, 10) give colours. LAS stores 16-bit
//! channels; files whose every channel is at most 255 were written with 8-bit values and are
//! taken as they are, otherwise the high byte is used. Formats without RGB give the intensity
//! as a grey level (scaled so the file's largest intensity is white) with a
//! [`ScanWarning::IntensityAsGrey`]; a file whose intensities are all zero has no colour.
//!
//! Invariants: points are read in chunks of [`LAS_CHUNK`], so a header that claims more points
//! than the file holds costs no allocation beyond one chunk and ends in
//! [`ScanError::Truncated`]. Non-finite coordinates cannot occur (LAS stores integers).
//!
//! Cost: one pass over the point records; memory 24 bytes (f64 position) + 4 (colour) + 2
//! (intensity, while reading) per point.

use std::path::Path;

use glam::DVec3;

use crate::{Pose, PosedScan, ScanError, ScanWarning};

/// Points decoded per call into the `las` reader (fewer for long records: at most 16 MiB
/// of records per call).
pub const LAS_CHUNK: u64 = 1 << 16;

/// The most bytes of point records decoded per call: the `las` reader allocates a chunk's
/// records before reading them, so a header announcing 58 KB records (extra bytes) would
/// otherwise allocate 3.8 GB for one chunk of a 301-byte file (found by `las_load`).
pub(crate) const LAS_CHUNK_BYTES: u64 = 1 << 24;

/// Refuses a header whose point records (legacy or 1.4 count × record length, after the
/// point data offset) would end past `u64::MAX`, before the `las` crate computes that end
/// unchecked (found by `las_load`). Leaves the file at its start.
fn check_point_extent(path: &Path, file: &mut std::fs::File) -> Result<(), ScanError> {
    let header = read_header_start(path, file)?;
    let (Some(offset), Some(record_len), Some(legacy)) = (
        u32_at(&header, 96),
        u16_at(&header, 105),
        u32_at(&header, 107),
    ) else {
        return Ok(()); // too short: the las reader refuses it
    };
    let records = PointRecords { offset, record_len };
    // The header size must hold the version's own fields (227, 235 or 375 bytes): the `las`
    // crate allocates the difference unchecked.
    let minor = header.get(25).copied().unwrap_or(0);
    if u16_at(&header, 94).is_some_and(|size| size < header_size_needed(minor)) {
        return Err(records.refuse(path, u64::from(legacy)));
    }
    // The 64-bit count exists from LAS 1.4 (version minor at byte 25).
    let large = header
        .get(247..255)
        .filter(|_| header.get(25).is_some_and(|&minor| minor >= 4))
        .map(|b| u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]));
    if minor >= 4 {
        check_extended_records(path, file, &header)?;
    }
    records.check_ends(path, [Some(u64::from(legacy)), large])
}

/// The first 255 bytes of the file (fewer when it is shorter): every header field the
/// checks read. Leaves the file at its start.
fn read_header_start(path: &Path, file: &mut std::fs::File) -> Result<Vec<u8>, ScanError> {
    use std::io::{Read, Seek, SeekFrom};
    let io = |source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut header = Vec::new();
    file.by_ref()
        .take(255)
        .read_to_end(&mut header)
        .map_err(io)?;
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    Ok(header)
}

/// The little-endian u16 at byte `k` of `header`, if it holds it.
fn u16_at(header: &[u8], k: usize) -> Option<u16> {
    header
        .get(k..k + 2)
        .map(|b| u16::from_le_bytes([b[0], b[1]]))
}

/// The little-endian u32 at byte `k` of `header`, if it holds it.
fn u32_at(header: &[u8], k: usize) -> Option<u32> {
    header
        .get(k..k + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// The least header size of LAS 1.`minor`: the bytes of that version's own fields.
fn header_size_needed(minor: u8) -> u16 {
    match minor {
        0..=2 => 227,
        3 => 235,
        _ => 375,
    }
}

/// Where a header says the point records lie: after byte `offset`, `record_len` bytes each.
struct PointRecords {
    offset: u32,
    record_len: u16,
}

impl PointRecords {
    /// The [`ScanError::LasSize`] of these records with `points` of them.
    fn refuse(&self, path: &Path, points: u64) -> ScanError {
        ScanError::LasSize {
            path: path.to_path_buf(),
            points,
            record_len: self.record_len,
            offset: self.offset,
        }
    }

    /// Refuses the first of the point `counts` (the ones given) whose records would end
    /// past `u64::MAX`.
    fn check_ends(&self, path: &Path, counts: [Option<u64>; 2]) -> Result<(), ScanError> {
        for points in counts.into_iter().flatten() {
            let end = points
                .checked_mul(u64::from(self.record_len))
                .and_then(|bytes| bytes.checked_add(u64::from(self.offset)));
            if end.is_none() {
                return Err(self.refuse(path, points));
            }
        }
        Ok(())
    }
}

/// Refuses a LAS 1.4 header whose extended variable-length records (start at byte 235,
/// count at 243, each a 60-byte header with its u64 length at byte 20) reach past the end
/// of the file: the `las` crate allocates each declared length before reading it (found
/// by `las_load`). The walk ends at the file's end, so it costs at most one read per 60
/// bytes of file. Leaves the file at its start.
fn check_extended_records(
    path: &Path,
    file: &mut std::fs::File,
    header: &[u8],
) -> Result<(), ScanError> {
    use std::io::{Read, Seek, SeekFrom};
    let io = |source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    };
    let (Some(start), Some(count)) = (header.get(235..243), header.get(243..247)) else {
        return Ok(()); // too short: the las reader refuses it
    };
    let mut at = u64::from_le_bytes(start.try_into().expect("8 bytes"));
    let count = u32::from_le_bytes(count.try_into().expect("4 bytes"));
    let file_len = file.metadata().map_err(io)?.len();
    let refuse = |start: u64, length: u64| ScanError::LasExtendedRecord {
        path: path.to_path_buf(),
        start,
        length,
        file_len,
    };
    for _ in 0..count {
        let mut record = [0u8; 60];
        if at.checked_add(60).is_none_or(|end| end > file_len) {
            return Err(refuse(at, 0));
        }
        file.seek(SeekFrom::Start(at)).map_err(io)?;
        file.read_exact(&mut record).map_err(io)?;
        let length = u64::from_le_bytes(record[20..28].try_into().expect("8 bytes"));
        match (at + 60).checked_add(length) {
            Some(end) if end <= file_len => at = end,
            _ => return Err(refuse(at, length)),
        }
    }
    file.seek(SeekFrom::Start(0)).map_err(io)?;
    Ok(())
}

/// Points per call for records of `record_len` bytes: at most [`LAS_CHUNK`] and
/// `LAS_CHUNK_BYTES` worth, at least one.
fn chunk_points(record_len: u16) -> u64 {
    (LAS_CHUNK_BYTES / u64::from(record_len).max(1)).clamp(1, LAS_CHUNK)
}

/// Reads a LAS or LAZ file; see the module docs.
pub fn read_las(path: &Path) -> Result<(PosedScan, Vec<ScanWarning>), ScanError> {
    let mut reader = open_las(path)?;
    let points = LasPoints::read(path, &mut reader)?;
    if points.positions.is_empty() {
        return Err(ScanError::NoPoints {
            path: path.to_path_buf(),
        });
    }
    let mut warnings = Vec::new();
    let colours = points.colours(path, &mut warnings);
    let scan = PosedScan {
        path: path.to_path_buf(),
        index: 0,
        positions: points.positions,
        colours,
        normals: None,
        viewpoint: None,
        pose: Pose::IDENTITY,
        dropped_non_finite: 0,
    };
    Ok((scan, warnings))
}

/// Opens a LAS or LAZ file and reads its header, once [`check_point_extent`] has passed it.
fn open_las(path: &Path) -> Result<las::Reader, ScanError> {
    let file = std::fs::File::open(path).map_err(|source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let refuse = |source| las_error(path, source);
    let mut file = file;
    check_point_extent(path, &mut file)?;
    las::Reader::new(std::io::BufReader::new(file)).map_err(refuse)
}

/// The point records of a file as read: positions, and the 16-bit colours of formats with
/// RGB or else the intensities.
struct LasPoints {
    positions: Vec<DVec3>,
    rgb: Vec<[u16; 3]>,
    intensity: Vec<u16>,
}

impl LasPoints {
    /// Reads every point of `reader`, in chunks (module docs); an early end of the file is
    /// [`ScanError::Truncated`].
    fn read(path: &Path, reader: &mut las::Reader) -> Result<LasPoints, ScanError> {
        let declared = reader.header().number_of_points();
        let chunk = chunk_points(reader.header().point_format().len());
        let mut data = las::PointDataBuilder::new()
            .for_header(reader.header())
            .build();
        let mut points = LasPoints {
            positions: Vec::new(),
            rgb: Vec::new(),
            intensity: Vec::new(),
        };
        loop {
            let n = reader.fill_points(chunk, &mut data).map_err(|source| {
                truncation_or(path, source, declared, points.positions.len() as u64)
            })?;
            if n == 0 {
                break;
            }
            points.append(&data);
        }
        Ok(points)
    }

    /// Appends the points of one chunk.
    fn append(&mut self, data: &las::PointData) {
        self.positions.extend(
            data.x()
                .zip(data.y())
                .zip(data.z())
                .map(|((x, y), z)| DVec3::new(x, y, z)),
        );
        match data.rgb() {
            Some(colours) => self.rgb.extend(colours.map(|(r, g, b)| [r, g, b])),
            None => self.intensity.extend(data.intensity()),
        }
    }

    /// The points' colours as bytes: the RGB when the format has it, else the intensity as
    /// grey (with a [`ScanWarning::IntensityAsGrey`] into `warnings`), `None` when every
    /// intensity is zero.
    fn colours(&self, path: &Path, warnings: &mut Vec<ScanWarning>) -> Option<Vec<[u8; 4]>> {
        if !self.rgb.is_empty() {
            return Some(rgb16_to_bytes(&self.rgb));
        }
        let grey = intensity_to_grey(&self.intensity);
        if grey.is_some() {
            warnings.push(ScanWarning::IntensityAsGrey {
                path: path.to_path_buf(),
            });
        }
        grey
    }
}

/// A `las` error as this crate's: file system errors as [`ScanError::Io`], the rest as
/// [`ScanError::Las`].
fn las_error(path: &Path, source: las::Error) -> ScanError {
    match source {
        las::Error::Io(source) if source.kind() != std::io::ErrorKind::UnexpectedEof => {
            ScanError::Io {
                path: path.to_path_buf(),
                source,
            }
        }
        source => ScanError::Las {
            path: path.to_path_buf(),
            source: Box::new(source),
        },
    }
}

/// An end of file while reading points is a truncated file; anything else as [`las_error`].
fn truncation_or(path: &Path, source: las::Error, declared: u64, read: u64) -> ScanError {
    match &source {
        las::Error::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            ScanError::Truncated {
                path: path.to_path_buf(),
                declared,
                read,
            }
        }
        _ => las_error(path, source),
    }
}

/// 16-bit LAS colours to bytes: as they are when every channel fits a byte (an 8-bit writer),
/// else the high byte.
pub fn rgb16_to_bytes(rgb: &[[u16; 3]]) -> Vec<[u8; 4]> {
    let max = rgb.iter().flatten().copied().max().unwrap_or(0);
    let shift = if max <= 255 { 0 } else { 8 };
    rgb.iter()
        .map(|c| {
            [
                (c[0] >> shift) as u8,
                (c[1] >> shift) as u8,
                (c[2] >> shift) as u8,
                255,
            ]
        })
        .collect()
}

/// Intensities as grey levels, the largest white; `None` when every intensity is zero.
pub fn intensity_to_grey(intensity: &[u16]) -> Option<Vec<[u8; 4]>> {
    let max = u32::from(intensity.iter().copied().max()?);
    if max == 0 {
        return None;
    }
    Some(
        intensity
            .iter()
            .map(|&i| {
                let g = ((u32::from(i) * 255 + max / 2) / max) as u8;
                [g, g, g, 255]
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chunk_of_long_records_stays_within_its_byte_budget() {
        assert_eq!(chunk_points(20), LAS_CHUNK);
        assert_eq!(chunk_points(58_368), LAS_CHUNK_BYTES / 58_368);
        assert!(chunk_points(u16::MAX) * u64::from(u16::MAX) <= LAS_CHUNK_BYTES);
        assert_eq!(chunk_points(0), LAS_CHUNK);
    }

    #[test]
    fn eight_bit_colours_stay_and_sixteen_bit_take_the_high_byte() {
        assert_eq!(rgb16_to_bytes(&[[255, 0, 10]]), vec![[255, 0, 10, 255]]);
        assert_eq!(
            rgb16_to_bytes(&[[65535, 256, 0x1234]]),
            vec![[255, 1, 0x12, 255]]
        );
    }

    #[test]
    fn intensity_scales_to_the_largest() {
        assert_eq!(
            intensity_to_grey(&[0, 2000, 4000]),
            Some(vec![
                [0, 0, 0, 255],
                [128, 128, 128, 255],
                [255, 255, 255, 255]
            ])
        );
        assert_eq!(intensity_to_grey(&[0, 0]), None);
        assert_eq!(intensity_to_grey(&[]), None);
    }
}
