//! Plain-text point clouds: `.xyz` / `.txt` and Leica-style `.pts`.
//!
//! One point per line; values separated by spaces, tabs or commas; blank lines and lines
//! starting with `#` or `//` are skipped. Every data line must have the same number of
//! columns as the first. What the column count means:
//!
//! | columns | `.xyz` / `.txt` | `.pts` |
//! |---|---|---|
//! | 3 | `x y z` | `x y z` |
//! | 4 | `x y z intensity` (intensity ignored) | `x y z intensity` |
//! | 6 | `x y z r g b` when the first line's last three values are integers, else `x y z nx ny nz` | same |
//! | 7 | `x y z r g b a` | `x y z intensity r g b` |
//! | 9 | `x y z r g b nx ny nz` | same |
//!
//! A `.pts` file may start with a line holding only the point count, which is skipped.
//! Colours are bytes (`0..=255`) unless every colour value in the file is at most 1, in which
//! case they are read as `0..=1`. Points with a NaN or infinite coordinate or normal are dropped
//! and counted ([`LoadedPointCloud::dropped_non_finite`]).
//!
//! Cost: one pass over the text; the values are held once in f64 before conversion.

use std::path::Path;

use glam::{DVec3, Vec3};

use super::{build_point_cloud, read_file, LoadedPointCloud};
use crate::error::SyntaxProblem;
use crate::MeshError;

/// Which columns hold what, decided from the first data line.
#[derive(Clone, Copy)]
struct Columns {
    colour: Option<usize>,
    alpha: bool,
    normal: Option<usize>,
}

/// Loads a text point cloud; `pts` selects the `.pts` column rules.
pub fn load_xyz(path: &Path, pts: bool) -> Result<LoadedPointCloud, MeshError> {
    let bytes = read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let err = |line: usize, problem| MeshError::Syntax {
        path: path.to_path_buf(),
        line,
        problem,
    };
    let mut width = 0usize;
    let mut columns = Columns {
        colour: None,
        alpha: false,
        normal: None,
    };
    let mut values: Vec<f64> = Vec::new();
    let mut first = true;
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') || line.starts_with("//") {
            continue;
        }
        let tokens: Vec<&str> = line
            .split(|c: char| c.is_ascii_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .collect();
        if first {
            first = false;
            if pts && tokens.len() == 1 && tokens[0].parse::<u64>().is_ok() {
                continue;
            }
            width = tokens.len();
            let integers = |range: std::ops::Range<usize>| {
                tokens[range]
                    .iter()
                    .all(|t| !t.contains(['.', 'e', 'E']) && t.parse::<i64>().is_ok())
            };
            columns = match (width, pts) {
                (3 | 4, _) => columns,
                (6, _) if integers(3..6) => Columns {
                    colour: Some(3),
                    ..columns
                },
                (6, _) => Columns {
                    normal: Some(3),
                    ..columns
                },
                (7, false) => Columns {
                    colour: Some(3),
                    alpha: true,
                    normal: None,
                },
                (7, true) => Columns {
                    colour: Some(4),
                    ..columns
                },
                (9, _) => Columns {
                    colour: Some(3),
                    alpha: false,
                    normal: Some(6),
                },
                (found, _) => {
                    return Err(err(
                        line_no,
                        SyntaxProblem::UnsupportedColumnCount { found },
                    ))
                }
            };
        }
        if tokens.len() != width {
            return Err(err(
                line_no,
                SyntaxProblem::TooFewValues {
                    expected: width,
                    found: tokens.len(),
                },
            ));
        }
        for (column, t) in tokens.iter().enumerate() {
            let v = t
                .parse::<f64>()
                .map_err(|_| err(line_no, SyntaxProblem::NotANumber { column: column + 1 }))?;
            values.push(v);
        }
    }
    if width == 0 {
        return Err(MeshError::NoPoints {
            path: path.to_path_buf(),
        });
    }
    let rows = values.chunks_exact(width);
    let positions: Vec<DVec3> = rows.clone().map(|r| DVec3::new(r[0], r[1], r[2])).collect();
    let colours = columns.colour.map(|c| {
        let channels = if columns.alpha { 4 } else { 3 };
        let unit = rows
            .clone()
            .all(|r| r[c..c + channels].iter().all(|&v| v <= 1.0));
        let scale = if unit { 255.0 } else { 1.0 };
        rows.clone()
            .map(|r| {
                let mut out = [255u8; 4];
                for k in 0..channels {
                    let v = r[c + k] * scale;
                    out[k] = if v.is_nan() {
                        0
                    } else {
                        (v.clamp(0.0, 255.0) + 0.5) as u8
                    };
                }
                out
            })
            .collect()
    });
    let normals = columns.normal.map(|n| {
        rows.clone()
            .map(|r| Vec3::new(r[n] as f32, r[n + 1] as f32, r[n + 2] as f32))
            .collect()
    });
    build_point_cloud(path, positions, colours, normals, Vec::new())
}
