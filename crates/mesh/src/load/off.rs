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

/// Loads an ASCII OFF file.
pub fn load_off(path: &Path) -> Result<LoadedMesh, MeshError> {
    let bytes = read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let text = super::strip_bom(&text);
    let err = |line: usize, problem| MeshError::Syntax {
        path: path.to_path_buf(),
        line,
        problem,
    };
    // Meaningful lines with their 1-based numbers, comments removed.
    let mut lines = text.lines().enumerate().filter_map(|(i, l)| {
        let content = l.split('#').next().unwrap_or("").trim();
        (!content.is_empty()).then_some((i + 1, content))
    });

    let (line_no, header) = lines.next().ok_or_else(|| MeshError::EmptyFile {
        path: path.to_path_buf(),
    })?;
    let mut tokens = header.split_ascii_whitespace();
    let keyword = tokens.next().unwrap_or("");
    let Some(prefix) = keyword.strip_suffix("OFF") else {
        return Err(err(line_no, SyntaxProblem::MissingOffHeader));
    };
    let has_uv = prefix.contains("ST");
    let has_colour = prefix.contains('C');
    let has_normal = prefix.contains('N');
    if prefix.contains('4') || prefix.contains('n') {
        return Err(err(line_no, SyntaxProblem::MissingOffHeader));
    }
    let mut rest: Vec<&str> = tokens.collect();
    if rest.first() == Some(&"BINARY") {
        return Err(err(line_no, SyntaxProblem::BinaryVariant));
    }
    let mut counts_line = line_no;
    if rest.is_empty() {
        let (n, l) = lines
            .next()
            .ok_or_else(|| err(line_no, SyntaxProblem::BadOffCounts))?;
        counts_line = n;
        rest = l.split_ascii_whitespace().collect();
    }
    let parse_count = |s: Option<&&str>| s.and_then(|s| s.parse::<u64>().ok());
    let (Some(vertex_count), Some(face_count)) =
        (parse_count(rest.first()), parse_count(rest.get(1)))
    else {
        return Err(err(counts_line, SyntaxProblem::BadOffCounts));
    };
    // Each vertex needs at least 6 bytes ("0 0 0\n"); refuse counts the file cannot hold
    // before sizing anything by them.
    let budget = bytes.len() as u64;
    if vertex_count > budget / 6 + 1 || face_count > budget / 8 + 1 {
        return Err(err(counts_line, SyntaxProblem::BadOffCounts));
    }

    let mut positions = Vec::with_capacity(vertex_count as usize);
    let mut normals = Vec::new();
    let mut colours = Vec::new();
    for v in 0..vertex_count {
        let (n, l) = lines.next().ok_or_else(|| {
            err(
                counts_line,
                SyntaxProblem::UnexpectedEnd {
                    expected: ElementKind::Vertices,
                    read: v,
                    declared: vertex_count,
                },
            )
        })?;
        let values = parse_line(l, n, path)?;
        let needed = 3 + if has_normal { 3 } else { 0 } + if has_colour { 3 } else { 0 };
        if values.len() < needed {
            return Err(err(
                n,
                SyntaxProblem::TooFewValues {
                    expected: needed,
                    found: values.len(),
                },
            ));
        }
        let p = DVec3::new(values[0].0, values[1].0, values[2].0);
        if !p.is_finite() {
            return Err(MeshError::NonFinite {
                path: path.to_path_buf(),
                element: Element::Vertex(v),
            });
        }
        positions.push(p);
        let mut at = 3;
        if has_normal {
            let nrm = Vec3::new(values[3].0 as f32, values[4].0 as f32, values[5].0 as f32);
            if !nrm.is_finite() {
                return Err(MeshError::NonFinite {
                    path: path.to_path_buf(),
                    element: Element::Normal(v),
                });
            }
            normals.push(nrm);
            at = 6;
        }
        if has_colour {
            // r g b [a] [s t]: with texture coordinates present, 5 remaining values mean
            // rgb + st and 6 mean rgba + st.
            let remaining = values.len() - at;
            let channels = if has_uv {
                remaining.saturating_sub(2)
            } else {
                remaining
            }
            .clamp(3, 4);
            let slice = &values[at..at + channels.min(remaining)];
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
            colours.push(c);
        }
    }

    let mut builder = MeshBuilder::default();
    let mut triangulator = PolygonTriangulator::default();
    for f in 0..face_count {
        let (n, l) = lines.next().ok_or_else(|| {
            err(
                counts_line,
                SyntaxProblem::UnexpectedEnd {
                    expected: ElementKind::Triangles,
                    read: f,
                    declared: face_count,
                },
            )
        })?;
        let mut tokens = l.split_ascii_whitespace();
        let len: usize = tokens
            .next()
            .and_then(|t| t.parse().ok())
            .ok_or_else(|| err(n, SyntaxProblem::NotANumber { column: 1 }))?;
        if len < 3 {
            return Err(err(n, SyntaxProblem::FaceTooSmall { len }));
        }
        let mut polygon = Vec::with_capacity(len.min(64));
        for column in 0..len {
            let index: i64 = tokens
                .next()
                .ok_or_else(|| {
                    err(
                        n,
                        SyntaxProblem::TooFewValues {
                            expected: len + 1,
                            found: column + 1,
                        },
                    )
                })?
                .parse()
                .map_err(|_| err(n, SyntaxProblem::NotANumber { column: column + 2 }))?;
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
        triangulator.push(&positions, &polygon, &mut builder.triangles);
    }

    let warnings: Vec<LoadWarning> = triangulator.warnings().collect();
    builder.positions = positions;
    if has_normal {
        builder.vertex_normals = Some(normals);
    }
    if has_colour {
        builder.vertex_colours = Some(colours);
    }
    let mesh = builder.finish(path)?;
    Ok(LoadedMesh { mesh, warnings })
}

/// Parses a line of numbers; each value comes with whether it was written with a decimal
/// point or exponent (to tell `0..=1` colours from byte colours).
fn parse_line(line: &str, line_no: usize, path: &Path) -> Result<Vec<(f64, bool)>, MeshError> {
    line.split_ascii_whitespace()
        .enumerate()
        .map(|(column, t)| {
            t.parse::<f64>()
                .map(|v| (v, t.contains(['.', 'e', 'E'])))
                .map_err(|_| MeshError::Syntax {
                    path: path.to_path_buf(),
                    line: line_no,
                    problem: SyntaxProblem::NotANumber { column: column + 1 },
                })
        })
        .collect()
}
