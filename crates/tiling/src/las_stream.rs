//! Streamed LAS and LAZ points through the `las` crate's chunked reader.
//!
//! Colours: 16-bit LAS colours become bytes by their high byte, unless every channel of the
//! first chunk fits a byte (an 8-bit writer), which are then taken as they are for the
//! whole file (the whole-file reader decides over every point; a stream cannot). Intensity
//! is not read.

use std::path::Path;

use glam::DVec3;

use crate::stream::{PointChunk, Visit, CHUNK_POINTS};
use crate::TilingError;

/// Streams a LAS or LAZ file (see the module documentation).
pub(crate) fn stream_las(path: &Path, visit: &mut Visit<'_>) -> Result<u64, TilingError> {
    let file = std::fs::File::open(path).map_err(|e| TilingError::io(path, e))?;
    let refuse = |e: las::Error| TilingError::malformed(path, e.to_string());
    let mut reader =
        las::Reader::new(std::io::BufReader::with_capacity(1 << 20, file)).map_err(refuse)?;
    let declared = reader.header().number_of_points();
    let mut data = las::PointDataBuilder::new()
        .for_header(reader.header())
        .build();
    let mut chunk = PointChunk::default();
    let mut shift: Option<u32> = None;
    let mut read = 0u64;
    loop {
        let n = reader
            .fill_points(CHUNK_POINTS as u64, &mut data)
            .map_err(|e| match e {
                las::Error::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
                    TilingError::Truncated {
                        path: path.to_path_buf(),
                        declared,
                        read,
                    }
                }
                e => refuse(e),
            })?;
        if n == 0 {
            break;
        }
        chunk.clear();
        chunk.positions.extend(
            data.x()
                .zip(data.y())
                .zip(data.z())
                .map(|((x, y), z)| DVec3::new(x, y, z)),
        );
        if let Some(rgb) = data.rgb() {
            let rgb: Vec<(u16, u16, u16)> = rgb.collect();
            let s = *shift.get_or_insert_with(|| {
                let max = rgb.iter().map(|c| c.0.max(c.1).max(c.2)).max().unwrap_or(0);
                if max <= 255 {
                    0
                } else {
                    8
                }
            });
            let byte = |v: u16| (v >> s) as u8;
            chunk
                .colours
                .get_or_insert_with(Vec::new)
                .extend(rgb.iter().map(|c| [byte(c.0), byte(c.1), byte(c.2), 255]));
        }
        read += n;
        visit(&chunk)?;
    }
    Ok(read)
}
