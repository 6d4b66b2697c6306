//! Object File Format (ASCII `.off`, as CGAL and Geomview write it).
//!
//! Header keyword `OFF` with optional prefixes `ST` (texture coordinates, skipped), `C`
//! (vertex colours), `N` (vertex normals); counts `vertices faces edges` on the header line or
//! the next; then one vertex per line (`x y z [nx ny nz] [r g b [a]] [s t]`) and one face per
//! line (`n i0 .. in-1 [face colour]`, face colours ignored). `#` starts a comment. Binary OFF
//! is refused. Polygons are split by [`triangulate_polygon`](crate::triangulate_polygon).
//!
//! Colours given as integers are bytes; given with a decimal point they are `0..=1`.
//!
//! Cost: one pass over the text.
//!
//! Based on: the Geomview OFF file format documentation.

use std::path::Path;

use glam::{DVec3, Vec3};

use super::{read_file, LoadedMesh, MeshBuilder};
use crate::error::{Element, ElementKind, SyntaxProblem};
use crate::triangulate::PolygonTriangulator;
use crate::{LoadWarning, MeshError};

/// The header of an OFF file: which vertex fields it declares and how
/// many vertices and faces follow.
struct OffHeader {
    has_uv: bool,
    has_colour: bool,
    has_normal: bool,
    vertex_count: u64,
    face_count: u64,
    /// The line of the counts (reported when the file ends early).
    counts_line: usize,
}

/// Loads an ASCII OFF file.
pub fn load_off(path: &Path) -> Result<LoadedMesh, MeshError> {
    let bytes = read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let text = super::strip_bom(&text);
    // Meaningful lines with their 1-based numbers, comments removed.
    let mut lines = text.lines().enumerate().filter_map(|(i, l)| {
        let content = l.split('#').next().unwrap_or("").trim();
        (!content.is_empty()).then_some((i + 1, content))
    });
    let header = read_header(&mut lines, path, bytes.len() as u64)?;
    let vertices = read_vertices(&mut lines, &header, path)?;
    let mut builder = MeshBuilder::default();
    let warnings = read_faces(&mut lines, &header, &vertices.positions, &mut builder, path)?;
    builder.positions = vertices.positions;
    if header.has_normal {
        builder.vertex_normals = Some(vertices.normals);
    }
    if header.has_colour {
        builder.vertex_colours = Some(vertices.colours);
    }
    let mesh = builder.finish(path)?;
    Ok(LoadedMesh { mesh, warnings })
}

/// Reads the keyword line and the counts (on it or the next line);
/// counts the file's `budget` bytes cannot hold are refused.
fn read_header<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    path: &Path,
    budget: u64,
) -> Result<OffHeader, MeshError> {
    let (line_no, header) = lines.next().ok_or_else(|| MeshError::EmptyFile {
        path: path.to_path_buf(),
    })?;
    let mut tokens = header.split_ascii_whitespace();
    let prefix = keyword_prefix(tokens.next().unwrap_or(""))
        .ok_or_else(|| MeshError::syntax(path, line_no, SyntaxProblem::MissingOffHeader))?;
    let mut rest: Vec<&str> = tokens.collect();
    if rest.first() == Some(&"BINARY") {
        return Err(MeshError::syntax(
            path,
            line_no,
            SyntaxProblem::BinaryVariant,
        ));
    }
    let mut counts_line = line_no;
    if rest.is_empty() {
        let (n, l) = lines
            .next()
            .ok_or_else(|| MeshError::syntax(path, line_no, SyntaxProblem::BadOffCounts))?;
        counts_line = n;
        rest = l.split_ascii_whitespace().collect();
    }
    let bad_counts = || MeshError::syntax(path, counts_line, SyntaxProblem::BadOffCounts);
    let (vertex_count, face_count) = parse_counts(&rest, budget).ok_or_else(bad_counts)?;
    Ok(OffHeader {
        has_uv: prefix.contains("ST"),
        has_colour: prefix.contains('C'),
        has_normal: prefix.contains('N'),
        vertex_count,
        face_count,
        counts_line,
    })
}

/// What precedes `OFF` in the header keyword (`ST`, `C`, `N`, in any
/// mix), or `None` for a keyword that is not an OFF one or names a variant
/// without a reader here (`4OFF`, `nOFF`).
fn keyword_prefix(keyword: &str) -> Option<&str> {
    let prefix = keyword.strip_suffix("OFF")?;
    (!prefix.contains('4') && !prefix.contains('n')).then_some(prefix)
}

/// The vertex and face counts at the start of `tokens`, unless missing,
/// not numbers, or more than a file of `budget` bytes can hold (each
/// vertex needs at least 6 bytes, "0 0 0\n", each face 8): refused before
/// anything is sized by them.
fn parse_counts(tokens: &[&str], budget: u64) -> Option<(u64, u64)> {
    let count = |k: usize| tokens.get(k).and_then(|s| s.parse::<u64>().ok());
    let (vertices, faces) = (count(0)?, count(1)?);
    (vertices <= budget / 6 + 1 && faces <= budget / 8 + 1).then_some((vertices, faces))
}

/// The vertices of an OFF file: positions, and normals and colours when
/// the header declares them (empty otherwise).
struct OffVertices {
    positions: Vec<DVec3>,
    normals: Vec<Vec3>,
    colours: Vec<[u8; 4]>,
}

/// The vertex lines.
fn read_vertices<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    header: &OffHeader,
    path: &Path,
) -> Result<OffVertices, MeshError> {
    let vertex_count = header.vertex_count;
    let mut positions = Vec::with_capacity(vertex_count as usize);
    let mut normals = Vec::new();
    let mut colours = Vec::new();
    let needed = 3 + if header.has_normal { 3 } else { 0 } + if header.has_colour { 3 } else { 0 };
    for v in 0..vertex_count {
        let (n, l) = lines.next().ok_or_else(|| {
            let expected = ElementKind::Vertices;
            let problem = SyntaxProblem::UnexpectedEnd {
                expected,
                read: v,
                declared: vertex_count,
            };
            MeshError::syntax(path, header.counts_line, problem)
        })?;
        let values = parse_line(l, n, path)?;
        if values.len() < needed {
            let found = values.len();
            let problem = SyntaxProblem::TooFewValues {
                expected: needed,
                found,
            };
            return Err(MeshError::syntax(path, n, problem));
        }
        let non_finite = |element| MeshError::NonFinite {
            path: path.to_path_buf(),
            element,
        };
        let p = DVec3::new(values[0].0, values[1].0, values[2].0);
        if !p.is_finite() {
            return Err(non_finite(Element::Vertex(v)));
        }
        positions.push(p);
        let mut at = 3;
        if header.has_normal {
            let nrm = Vec3::new(values[3].0 as f32, values[4].0 as f32, values[5].0 as f32);
            if !nrm.is_finite() {
                return Err(non_finite(Element::Normal(v)));
            }
            normals.push(nrm);
            at = 6;
        }
        if header.has_colour {
            colours.push(vertex_colour(&values[at..], header.has_uv));
        }
    }
    Ok(OffVertices {
        positions,
        normals,
        colours,
    })
}

/// A vertex's colour from the values after its position and normal:
/// `r g b [a] [s t]`. With texture coordinates present, 5 remaining values
/// mean rgb + st and 6 mean rgba + st. Integers are bytes, values written
/// with a decimal point `0..=1`.
fn vertex_colour(values: &[(f64, bool)], has_uv: bool) -> [u8; 4] {
    let remaining = values.len();
    let channels = if has_uv {
        remaining.saturating_sub(2)
    } else {
        remaining
    }
    .clamp(3, 4);
    let slice = &values[..channels.min(remaining)];
    let unit = slice.iter().any(|(_, decimal)| *decimal);
    let byte = |x: f64| {
        let x = if unit { x * 255.0 } else { x };
        if x.is_nan() {
            0
        } else {
            (x.clamp(0.0, 255.0) + 0.5) as u8
        }
    };
    let mut c = [255u8; 4];
    for (k, (x, _)) in slice.iter().enumerate() {
        c[k] = byte(*x);
    }
    c
}

/// The face lines, triangulated into `builder`; the triangulation's
/// warnings.
fn read_faces<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a str)>,
    header: &OffHeader,
    positions: &[DVec3],
    builder: &mut MeshBuilder,
    path: &Path,
) -> Result<Vec<LoadWarning>, MeshError> {
    let mut triangulator = PolygonTriangulator::default();
    for f in 0..header.face_count {
        let (n, l) = lines.next().ok_or_else(|| {
            let problem = SyntaxProblem::UnexpectedEnd {
                expected: ElementKind::Triangles,
                read: f,
                declared: header.face_count,
            };
            MeshError::syntax(path, header.counts_line, problem)
        })?;
        let polygon = face_polygon(l, n, f, header.vertex_count, path)?;
        triangulator.push(positions, &polygon, &mut builder.triangles);
    }
    Ok(triangulator.warnings().collect())
}

/// The vertex indices of face `f`, line `line` (`n i0 .. in-1`, the rest
/// ignored), each checked against `vertex_count`.
fn face_polygon(
    line: &str,
    n: usize,
    f: u64,
    vertex_count: u64,
    path: &Path,
) -> Result<Vec<u32>, MeshError> {
    let mut tokens = line.split_ascii_whitespace();
    let len: usize = tokens
        .next()
        .and_then(|t| t.parse().ok())
        .ok_or_else(|| MeshError::syntax(path, n, SyntaxProblem::NotANumber { column: 1 }))?;
    if len < 3 {
        return Err(MeshError::syntax(
            path,
            n,
            SyntaxProblem::FaceTooSmall { len },
        ));
    }
    let mut polygon = Vec::with_capacity(len.min(64));
    for column in 0..len {
        let too_few = SyntaxProblem::TooFewValues {
            expected: len + 1,
            found: column + 1,
        };
        let index: i64 = tokens
            .next()
            .ok_or_else(|| MeshError::syntax(path, n, too_few))?
            .parse()
            .map_err(|_| {
                MeshError::syntax(path, n, SyntaxProblem::NotANumber { column: column + 2 })
            })?;
        if index < 0 || index as u64 >= vertex_count {
            return Err(MeshError::IndexOutOfRange {
                path: path.to_path_buf(),
                face: f,
                index,
                vertex_count,
            });
        }
        polygon.push(index as u32);
    }
    Ok(polygon)
}

/// Parses a line of numbers; each value comes with whether it was written with a decimal
/// point or exponent (to tell `0..=1` colours from byte colours).
fn parse_line(line: &str, line_no: usize, path: &Path) -> Result<Vec<(f64, bool)>, MeshError> {
    line.split_ascii_whitespace()
        .enumerate()
        .map(|(column, t)| {
            t.parse::<f64>()
                .map(|v| (v, t.contains(['.', 'e', 'E'])))
                .map_err(|_| {
                    MeshError::syntax(
                        path,
                        line_no,
                        SyntaxProblem::NotANumber { column: column + 1 },
                    )
                })
        })
        .collect()
}
