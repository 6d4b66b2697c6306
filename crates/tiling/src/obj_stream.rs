//! Streamed OBJ geometry: `v` lines (positions) and `f` lines (polygons), one line at a
//! time.
//!
//! Face corners are `v`, `v/vt`, `v//vn` or `v/vt/vn`; only the vertex index is used, 1-based
//! or negative (relative to the vertices read so far), as OBJ defines them. A file that
//! names materials (`mtllib`, `usemtl`) or texture coordinates (`vt`) is not plain geometry:
//! [`obj_is_plain`] says so, and its tiles are read by the whole-mesh loader instead.

use std::io::{BufRead, BufReader};
use std::path::Path;

use glam::DVec3;

use crate::TilingError;

/// A visitor of polygons (0-based vertex indices).
pub(crate) type PolygonVisit<'a> = dyn FnMut(&[u32]) -> Result<(), TilingError> + 'a;

/// What one pass over an OBJ file hands out.
pub(crate) struct ObjVisitor<'a> {
    /// Each vertex position, in file order.
    pub vertex: &'a mut dyn FnMut(DVec3) -> Result<(), TilingError>,
    /// Each polygon as 0-based vertex indices, or `None` to skip faces.
    pub polygon: Option<&'a mut PolygonVisit<'a>>,
}

/// Whether `path` holds geometry only (no `mtllib`, `usemtl` or `vt` line).
pub(crate) fn obj_is_plain(path: &Path) -> Result<bool, TilingError> {
    let mut plain = true;
    each_line(path, &mut |line| {
        if line.starts_with(b"mtllib") || line.starts_with(b"usemtl") || line.starts_with(b"vt ") {
            plain = false;
        }
        Ok(())
    })?;
    Ok(plain)
}

/// Streams `path`'s vertices and (when asked) polygons; returns the vertex count.
pub(crate) fn stream_obj(path: &Path, visitor: &mut ObjVisitor<'_>) -> Result<u64, TilingError> {
    let (mut vertices, mut lines, mut polygon) = (0u64, 0u64, Vec::new());
    each_line(path, &mut |line| {
        lines += 1;
        if let Some(rest) = line.strip_prefix(b"v ") {
            (visitor.vertex)(parse_vertex(path, lines, rest)?)?;
            vertices += 1;
        } else if let (Some(rest), Some(visit)) = (line.strip_prefix(b"f "), &mut visitor.polygon) {
            polygon.clear();
            for corner in rest.split(|b| b.is_ascii_whitespace()) {
                if !corner.is_empty() {
                    polygon.push(corner_index(path, lines, corner, vertices)?);
                }
            }
            visit(&polygon)?;
        }
        Ok(())
    })?;
    Ok(vertices)
}

/// Calls `visit` with every line of `path` (without its line break).
fn each_line(
    path: &Path,
    visit: &mut dyn FnMut(&[u8]) -> Result<(), TilingError>,
) -> Result<(), TilingError> {
    let file = std::fs::File::open(path).map_err(|e| TilingError::io(path, e))?;
    let mut reader = BufReader::with_capacity(1 << 20, file);
    let mut line = Vec::new();
    loop {
        line.clear();
        if reader
            .read_until(b'\n', &mut line)
            .map_err(|e| TilingError::io(path, e))?
            == 0
        {
            return Ok(());
        }
        let trimmed = line.trim_ascii();
        visit(trimmed)?;
    }
}

/// The position of a `v` line (its first three numbers).
fn parse_vertex(path: &Path, line: u64, rest: &[u8]) -> Result<DVec3, TilingError> {
    let bad = || TilingError::malformed(path, format!("line {line}: a bad vertex"));
    let text = std::str::from_utf8(rest).map_err(|_| bad())?;
    let mut words = text.split_ascii_whitespace().map(str::parse::<f64>);
    let mut next = || words.next().and_then(Result::ok).ok_or_else(bad);
    Ok(DVec3::new(next()?, next()?, next()?))
}

/// The 0-based vertex index of a face corner, given the vertices read so far.
fn corner_index(path: &Path, line: u64, corner: &[u8], seen: u64) -> Result<u32, TilingError> {
    let bad = || TilingError::malformed(path, format!("line {line}: a bad face corner"));
    let first = corner.split(|&b| b == b'/').next().unwrap_or(corner);
    let text = std::str::from_utf8(first).map_err(|_| bad())?;
    let i: i64 = text.parse().map_err(|_| bad())?;
    let index = match i {
        1.. => i - 1,
        ..=-1 => seen as i64 + i,
        0 => return Err(bad()),
    };
    u32::try_from(index).map_err(|_| bad())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_take_the_vertex_index_in_every_form() {
        let p = Path::new("x.obj");
        assert_eq!(corner_index(p, 1, b"3", 5).unwrap(), 2);
        assert_eq!(corner_index(p, 1, b"3/1", 5).unwrap(), 2);
        assert_eq!(corner_index(p, 1, b"3//7", 5).unwrap(), 2);
        assert_eq!(corner_index(p, 1, b"-1/2/3", 5).unwrap(), 4);
        assert!(corner_index(p, 1, b"0", 5).is_err());
        assert!(corner_index(p, 1, b"-6", 5).is_err());
        assert!(corner_index(p, 1, b"x", 5).is_err());
    }
}
