//! Streamed XYZ, TXT and PTS text clouds, one point a line.
//!
//! Layout (guessed from the first point line, as there is no header to trust): `x y z`
//! first; with 6 columns or more whose 4th to 6th are integers 0..=255, those are `r g b`;
//! with 7 columns whose 5th to 7th are such integers (the Leica `.pts` layout `x y z i r g
//! b`), those are. Other columns are ignored. A first line holding one integer (the `.pts`
//! point count) and lines starting with `//` or `#` are skipped.

use std::io::{BufRead, BufReader};
use std::path::Path;

use glam::DVec3;

use crate::stream::{PointChunk, Visit, CHUNK_POINTS};
use crate::TilingError;

/// Where the colour columns start, if any, judged from one line's values.
fn colour_start(values: &[f64]) -> Option<usize> {
    let byte = |v: &f64| v.fract() == 0.0 && (0.0..=255.0).contains(v);
    if values.len() == 7 && values[4..7].iter().all(byte) {
        Some(4)
    } else if values.len() >= 6 && values[3..6].iter().all(byte) {
        Some(3)
    } else {
        None
    }
}

/// Streams a text cloud (see the module documentation).
pub(crate) fn stream_xyz(path: &Path, visit: &mut Visit<'_>) -> Result<u64, TilingError> {
    let file = std::fs::File::open(path).map_err(|e| TilingError::io(path, e))?;
    let reader = BufReader::with_capacity(1 << 20, file);
    let mut chunk = PointChunk::default();
    let mut layout: Option<Option<usize>> = None;
    let mut values = Vec::new();
    let mut read = 0u64;
    for (number, line) in reader.lines().enumerate() {
        let line = line.map_err(|e| TilingError::io(path, e))?;
        let text = line.trim();
        if text.is_empty() || text.starts_with("//") || text.starts_with('#') {
            continue;
        }
        values.clear();
        for word in text
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|w| !w.is_empty())
        {
            values.push(word.parse::<f64>().map_err(|_| {
                TilingError::malformed(
                    path,
                    format!("line {}: `{word}` is not a number", number + 1),
                )
            })?);
        }
        if number == 0 && values.len() == 1 {
            continue;
        }
        if values.len() < 3 {
            return Err(TilingError::malformed(
                path,
                format!("line {}: fewer than 3 values", number + 1),
            ));
        }
        let colour = *layout.get_or_insert_with(|| colour_start(&values));
        chunk
            .positions
            .push(DVec3::new(values[0], values[1], values[2]));
        if let Some(c) = colour {
            let rgb = values.get(c..c + 3).ok_or_else(|| {
                TilingError::malformed(path, format!("line {}: no colour columns", number + 1))
            })?;
            let b = |v: f64| v.clamp(0.0, 255.0) as u8;
            chunk
                .colours
                .get_or_insert_with(Vec::new)
                .push([b(rgb[0]), b(rgb[1]), b(rgb[2]), 255]);
        }
        read += 1;
        if chunk.len() == CHUNK_POINTS {
            visit(&chunk)?;
            chunk.clear();
        }
    }
    if !chunk.is_empty() {
        visit(&chunk)?;
    }
    Ok(read)
}
