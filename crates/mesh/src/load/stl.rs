//! STL reader (binary and ASCII), as CAD tools and slicers write it.
//!
//! Binary: an 80-byte header, a little-endian `u32` triangle count, then 50 bytes per triangle
//! (normal, three vertices as `f32`, a 2-byte attribute). ASCII: `solid name`, then per
//! triangle `facet normal nx ny nz` / `outer loop` / `vertex x y z` (three or more) /
//! `endloop` / `endfacet`, closed by `endsolid`; several solids may follow each other.
//!
//! Which is which: a file whose length is exactly `84 + 50 * count` is binary, even when its
//! header starts with `solid` (many exporters write that); otherwise a file starting with
//! `solid` is ASCII, and anything else is a binary file whose length does not match its count
//! ([`MeshError::StlLength`]).
//!
//! STL shares no vertices: every triangle gets three new ones, welded later by
//! [`prepare_mesh`](crate::prepare_mesh) (bit-identical positions). Facet normals are not
//! read (the winding gives the normal; exporters often write zeros). Attribute bytes (a few
//! tools store a colour there, with conflicting conventions) are ignored. A loop of more than
//! three vertices is split by [`triangulate_polygon`](crate::triangulate_polygon) and counted in
//! [`LoadWarning::PolygonsTriangulated`](crate::LoadWarning::PolygonsTriangulated).
//!
//! Cost: one pass; memory O(triangles). The triangle count of a binary file is checked
//! against the file length before anything is sized by it.
//!
//! Based on: 3D Systems, *StereoLithography Interface Specification* (1989, 1995 revision).

use std::path::Path;

use glam::DVec3;

use super::{read_file, LoadedMesh, MeshBuilder};
use crate::error::{Element, SyntaxProblem};
use crate::triangulate::PolygonTriangulator;
use crate::MeshError;

/// Bytes before the first binary triangle: the header and the count.
const BINARY_HEADER_BYTES: usize = 84;
/// Bytes of one binary triangle record.
const BINARY_TRIANGLE_BYTES: usize = 50;

/// Loads a binary or ASCII STL file.
pub fn load_stl(path: &Path) -> Result<LoadedMesh, MeshError> {
    let bytes = read_file(path)?;
    if let Some(count) = binary_count(&bytes) {
        return read_binary(path, &bytes, count);
    }
    if starts_with_solid(&bytes) {
        return read_ascii(path, &bytes);
    }
    let declared = bytes
        .get(80..84)
        .map_or(0, |c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]));
    Err(MeshError::StlLength {
        path: path.to_path_buf(),
        declared: u64::from(declared),
        length: bytes.len() as u64,
    })
}

/// The triangle count of a binary STL whose length matches it exactly.
fn binary_count(bytes: &[u8]) -> Option<usize> {
    let c = bytes.get(80..BINARY_HEADER_BYTES)?;
    let count = u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as usize;
    let expected = count
        .checked_mul(BINARY_TRIANGLE_BYTES)?
        .checked_add(BINARY_HEADER_BYTES)?;
    (expected == bytes.len()).then_some(count)
}

/// Whether the file opens with the ASCII keyword `solid` (after an optional byte-order mark
/// and whitespace).
fn starts_with_solid(bytes: &[u8]) -> bool {
    let bytes = bytes.strip_prefix(b"\xef\xbb\xbf").unwrap_or(bytes);
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    bytes[start..]
        .get(..5)
        .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
}

fn read_binary(path: &Path, bytes: &[u8], count: usize) -> Result<LoadedMesh, MeshError> {
    let mut builder = MeshBuilder::default();
    builder.positions.reserve(count * 3);
    builder.triangles.reserve(count);
    let records = bytes[BINARY_HEADER_BYTES..].chunks_exact(BINARY_TRIANGLE_BYTES);
    for record in records {
        for corner in 0..3 {
            let at = 12 + corner * 12;
            let value = |k: usize| {
                let b = &record[at + 4 * k..at + 4 * k + 4];
                f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            };
            push_vertex(path, &mut builder, DVec3::new(value(0), value(1), value(2)))?;
        }
        let first = builder.positions.len() as u32 - 3;
        builder.triangles.push([first, first + 1, first + 2]);
    }
    let mesh = builder.finish(path)?;
    Ok(LoadedMesh {
        mesh,
        warnings: Vec::new(),
    })
}

/// Appends a vertex, refusing a non-finite one with its index.
fn push_vertex(path: &Path, builder: &mut MeshBuilder, p: DVec3) -> Result<(), MeshError> {
    if !p.is_finite() {
        return Err(MeshError::NonFinite {
            path: path.to_path_buf(),
            element: Element::Vertex(builder.positions.len() as u64),
        });
    }
    builder.positions.push(p);
    Ok(())
}

/// One whitespace-separated word of an ASCII STL, with its 1-based line.
struct Word<'a> {
    text: &'a str,
    line: usize,
}

/// The words of an ASCII STL in order.
fn words(text: &str) -> impl Iterator<Item = Word<'_>> {
    text.lines().enumerate().flat_map(|(i, l)| {
        l.split_ascii_whitespace()
            .map(move |text| Word { text, line: i + 1 })
    })
}

fn read_ascii(path: &Path, bytes: &[u8]) -> Result<LoadedMesh, MeshError> {
    let text = String::from_utf8_lossy(bytes);
    let text = super::strip_bom(&text);
    let err = |line: usize, problem| MeshError::syntax(path, line, problem);
    let mut builder = MeshBuilder::default();
    let mut triangulator = PolygonTriangulator::default();
    let mut loop_start: Option<usize> = None;
    let mut last_line = 1;
    let mut it = words(text);
    while let Some(word) = it.next() {
        last_line = word.line;
        let keyword = word.text.to_ascii_lowercase();
        match keyword.as_str() {
            "outer" => loop_start = Some(builder.positions.len()),
            "vertex" => {
                if loop_start.is_none() {
                    return Err(err(word.line, SyntaxProblem::StlVertexOutsideLoop));
                }
                let mut v = [0.0f64; 3];
                for (k, slot) in v.iter_mut().enumerate() {
                    let w = it.next().ok_or_else(|| {
                        err(
                            word.line,
                            SyntaxProblem::TooFewValues {
                                expected: 3,
                                found: k,
                            },
                        )
                    })?;
                    *slot = w
                        .text
                        .parse()
                        .map_err(|_| err(w.line, SyntaxProblem::NotANumber { column: k + 2 }))?;
                }
                push_vertex(path, &mut builder, DVec3::from_array(v))?;
            }
            "endloop" => {
                let start = loop_start
                    .take()
                    .ok_or_else(|| err(word.line, SyntaxProblem::StlVertexOutsideLoop))?;
                let len = builder.positions.len() - start;
                if len < 3 {
                    return Err(err(word.line, SyntaxProblem::FaceTooSmall { len }));
                }
                let polygon: Vec<u32> = (start as u32..(start + len) as u32).collect();
                triangulator.push(&builder.positions, &polygon, &mut builder.triangles);
            }
            // Everything else (solid names, facet normals, end keywords) carries nothing
            // this reader needs.
            _ => {}
        }
    }
    if loop_start.is_some() {
        return Err(err(last_line, SyntaxProblem::StlUnclosedLoop));
    }
    let mesh = builder.finish(path)?;
    let warnings = triangulator.warnings().collect();
    Ok(LoadedMesh { mesh, warnings })
}
