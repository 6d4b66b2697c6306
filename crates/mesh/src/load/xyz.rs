//! Plain-text point clouds: `.xyz` / `.txt` and Leica-style `.pts`.
//!
//! One point per line; values separated by spaces, tabs or commas; blank lines and lines
//! starting with `#` are skipped. What each column holds comes from, in this order:
//!
//! 1. the caller's layout ([`load_xyz_columns`], `spatch from-cloud --columns x,y,z,...`);
//! 2. a header line before the first point: CloudCompare's `//X Y Z R G B Nx Ny Nz`, or a line
//!    of names alone such as `x y z intensity` (names as in [`XyzColumn::from_name`]; unknown
//!    names, such as scalar fields, are skipped);
//! 3. the number of values on the first point line:
//!
//! | columns | `.xyz` / `.txt` | `.pts` |
//! |---|---|---|
//! | 3 | `x y z` | `x y z` |
//! | 4 | `x y z intensity` | `x y z intensity` |
//! | 6 | `x y z r g b` when the first line's last three values are integers, else `x y z nx ny nz` | same |
//! | 7 | `x y z r g b a` | `x y z intensity r g b` |
//! | 9 | `x y z nx ny nz r g b` when values 4-6 are a unit vector or values 7-9 are integers (and 4-6 are not), else `x y z r g b nx ny nz` | same |
//!
//! A `.pts` file may start with a line holding only the point count, which is skipped. Other
//! lines starting with `//` are comments. Every point line must have as many values as the
//! layout has columns.
//!
//! Colours are bytes (`0..=255`) unless every colour value in the file is at most 1, in which
//! case they are read as `0..=1`. A file with intensity but no colour gets the intensity as a
//! grey level, scaled so that the file's lowest intensity is black and its highest white.
//! Points with a NaN or infinite coordinate or normal are dropped and counted
//! ([`LoadedPointCloud::dropped_non_finite`]).
//!
//! Cost: one pass over the text; the values are held once in f64 before conversion.

use std::path::Path;

use glam::{DVec3, Vec3};

use super::{build_point_cloud, read_file, LoadedPointCloud};
use crate::error::SyntaxProblem;
use crate::MeshError;

/// What one column of a text point cloud holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum XyzColumn {
    /// Position x.
    X,
    /// Position y.
    Y,
    /// Position z.
    Z,
    /// Normal x.
    Nx,
    /// Normal y.
    Ny,
    /// Normal z.
    Nz,
    /// Red (`0..=255`, or `0..=1` when every colour value of the file is at most 1).
    R,
    /// Green.
    G,
    /// Blue.
    B,
    /// Alpha (opacity).
    A,
    /// Intensity (any range; the grey level when the file has no colour).
    Intensity,
    /// A column to ignore.
    Skip,
}

impl XyzColumn {
    /// The column a name stands for, case-insensitively: `x`, `y`, `z`, `nx`, `ny`, `nz`,
    /// `r`/`red`, `g`/`green`, `b`/`blue`, `a`/`alpha`, `i`/`intensity`, `skip`/`_`. CloudCompare's
    /// float colour names `rf`, `gf`, `bf` count as colours. `None` for anything else.
    pub fn from_name(name: &str) -> Option<XyzColumn> {
        Some(match name.to_ascii_lowercase().as_str() {
            "x" => XyzColumn::X,
            "y" => XyzColumn::Y,
            "z" => XyzColumn::Z,
            "nx" => XyzColumn::Nx,
            "ny" => XyzColumn::Ny,
            "nz" => XyzColumn::Nz,
            "r" | "red" | "rf" => XyzColumn::R,
            "g" | "green" | "gf" => XyzColumn::G,
            "b" | "blue" | "bf" => XyzColumn::B,
            "a" | "alpha" => XyzColumn::A,
            "i" | "intensity" => XyzColumn::Intensity,
            "skip" | "_" => XyzColumn::Skip,
            _ => return None,
        })
    }
}

/// A validated column layout for [`load_xyz_columns`].
///
/// # Guarantees
///
/// Names x, y and z exactly once each; every other kind at most once (`Skip` may repeat).
#[derive(Clone, Debug, PartialEq)]
pub struct XyzLayout {
    list: Vec<XyzColumn>,
    columns: Columns,
}

impl XyzLayout {
    /// A layout from its columns in line order; `None` unless x, y and z are each named once
    /// and no other kind but [`XyzColumn::Skip`] is repeated.
    pub fn new(list: Vec<XyzColumn>) -> Option<XyzLayout> {
        let repeated = list
            .iter()
            .enumerate()
            .any(|(i, &c)| c != XyzColumn::Skip && list[..i].contains(&c));
        if repeated {
            return None;
        }
        let columns = Columns::from_list(&list)?;
        Some(XyzLayout { list, columns })
    }

    /// The columns in line order.
    pub fn columns(&self) -> &[XyzColumn] {
        &self.list
    }
}

/// Where each kind of value sits on a line (column indices), decided once per file.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Columns {
    width: usize,
    position: [usize; 3],
    colour: Option<[usize; 3]>,
    alpha: Option<usize>,
    normal: Option<[usize; 3]>,
    intensity: Option<usize>,
}

impl Columns {
    /// The layout a list of columns describes; `None` unless x, y and z are all named (groups
    /// named in part, such as `r g` without `b`, are ignored).
    fn from_list(list: &[XyzColumn]) -> Option<Columns> {
        let find = |kind: XyzColumn| list.iter().position(|&c| c == kind);
        let triple = |a, b, c| Some([find(a)?, find(b)?, find(c)?]);
        Some(Columns {
            width: list.len(),
            position: triple(XyzColumn::X, XyzColumn::Y, XyzColumn::Z)?,
            colour: triple(XyzColumn::R, XyzColumn::G, XyzColumn::B),
            alpha: find(XyzColumn::A),
            normal: triple(XyzColumn::Nx, XyzColumn::Ny, XyzColumn::Nz),
            intensity: find(XyzColumn::Intensity),
        })
    }

    /// The layout a first point line implies by its value count (the module table).
    fn from_first_line(tokens: &[&str], pts: bool) -> Option<Columns> {
        use XyzColumn::*;
        let integers = |range: std::ops::Range<usize>| {
            tokens[range]
                .iter()
                .all(|t| !t.contains(['.', 'e', 'E']) && t.parse::<i64>().is_ok())
        };
        let unit = |range: std::ops::Range<usize>| {
            let v: Vec<f64> = tokens[range]
                .iter()
                .filter_map(|t| t.parse().ok())
                .collect();
            v.len() == 3 && ((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() - 1.0).abs() < 0.02
        };
        let list: &[XyzColumn] = match (tokens.len(), pts) {
            (3, _) => &[X, Y, Z],
            (4, _) => &[X, Y, Z, Intensity],
            (6, _) if integers(3..6) => &[X, Y, Z, R, G, B],
            (6, _) => &[X, Y, Z, Nx, Ny, Nz],
            (7, false) => &[X, Y, Z, R, G, B, A],
            (7, true) => &[X, Y, Z, Intensity, R, G, B],
            (9, _) => {
                let normals_first =
                    (integers(6..9) && !integers(3..6)) || (unit(3..6) && !unit(6..9));
                if normals_first {
                    &[X, Y, Z, Nx, Ny, Nz, R, G, B]
                } else {
                    &[X, Y, Z, R, G, B, Nx, Ny, Nz]
                }
            }
            _ => return None,
        };
        Columns::from_list(list)
    }
}

/// Loads a text point cloud with the layout rules of the module docs; `pts` selects the
/// `.pts` rules.
pub fn load_xyz(path: &Path, pts: bool) -> Result<LoadedPointCloud, MeshError> {
    load_xyz_columns(path, pts, None)
}

/// Loads a text point cloud; `layout`, when given, says what each column holds (every point
/// line must then have exactly that many values, and header lines are skipped).
pub fn load_xyz_columns(
    path: &Path,
    pts: bool,
    layout: Option<&XyzLayout>,
) -> Result<LoadedPointCloud, MeshError> {
    let bytes = read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let err = |line: usize, problem| MeshError::syntax(path, line, problem);
    let mut layout: Option<Columns> = layout.map(|l| l.columns);
    let mut header: Option<Columns> = None;
    let mut seen_line = false;
    let mut values: Vec<f64> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let first_line = !seen_line;
        seen_line = true;
        if let Some(names) = line.strip_prefix("//") {
            if first_line && layout.is_none() {
                header = header_columns(names);
            }
            continue;
        }
        let tokens = split_tokens(line);
        let Some(columns) = layout else {
            if first_line && skips_first_line(line, &tokens, pts, &mut header) {
                continue;
            }
            let chosen = first_layout(header, &tokens, pts).map_err(|p| err(line_no, p))?;
            layout = Some(chosen);
            push_values(&tokens, chosen.width, &mut values).map_err(|p| err(line_no, p))?;
            continue;
        };
        push_values(&tokens, columns.width, &mut values).map_err(|p| err(line_no, p))?;
    }
    let Some(columns) = layout.filter(|_| !values.is_empty()) else {
        return Err(MeshError::NoPoints {
            path: path.to_path_buf(),
        });
    };
    build_from_rows(path, &values, &columns)
}

/// The tokens of a line (values or column names): split at ASCII whitespace and commas.
fn split_tokens(line: &str) -> Vec<&str> {
    line.split(|c: char| c.is_ascii_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
        .collect()
}

/// Whether the first line of a file read without a given layout holds no points: a Leica
/// point count (when `pts`), or a header of column names (then kept in `header`).
fn skips_first_line(line: &str, tokens: &[&str], pts: bool, header: &mut Option<Columns>) -> bool {
    if pts && tokens.len() == 1 && tokens[0].parse::<u64>().is_ok() {
        return true;
    }
    if let Some(named) = header_columns(line) {
        *header = Some(named);
        return true;
    }
    false
}

/// The layout of a file read without a given one, from its first point line's `tokens`:
/// the `header`'s when it had one, else guessed from the number of values.
fn first_layout(
    header: Option<Columns>,
    tokens: &[&str],
    pts: bool,
) -> Result<Columns, SyntaxProblem> {
    match header {
        Some(named) => Ok(named),
        None => {
            Columns::from_first_line(tokens, pts).ok_or(SyntaxProblem::UnsupportedColumnCount {
                found: tokens.len(),
            })
        }
    }
}

/// A header line's layout: every token a name (no numbers), with x, y and z among them.
fn header_columns(line: &str) -> Option<Columns> {
    let names = split_tokens(line);
    if names.is_empty() || names.iter().any(|n| n.parse::<f64>().is_ok()) {
        return None;
    }
    let list: Vec<XyzColumn> = names
        .iter()
        .map(|n| XyzColumn::from_name(n).unwrap_or(XyzColumn::Skip))
        .collect();
    Columns::from_list(&list)
}

/// Parses one point line's values onto `values`, checking its width.
fn push_values(tokens: &[&str], width: usize, values: &mut Vec<f64>) -> Result<(), SyntaxProblem> {
    if tokens.len() != width {
        return Err(SyntaxProblem::TooFewValues {
            expected: width,
            found: tokens.len(),
        });
    }
    for (column, t) in tokens.iter().enumerate() {
        let v = t
            .parse::<f64>()
            .map_err(|_| SyntaxProblem::NotANumber { column: column + 1 })?;
        values.push(v);
    }
    Ok(())
}

/// The cloud from rows of `columns.width` values.
fn build_from_rows(
    path: &Path,
    values: &[f64],
    columns: &Columns,
) -> Result<LoadedPointCloud, MeshError> {
    let rows = values.chunks_exact(columns.width);
    let [px, py, pz] = columns.position;
    let positions: Vec<DVec3> = rows
        .clone()
        .map(|r| DVec3::new(r[px], r[py], r[pz]))
        .collect();
    let colours = match (columns.colour, columns.intensity) {
        (Some(rgb), _) => Some(colours_from_rows(rows.clone(), rgb, columns.alpha)),
        (None, Some(i)) => grey_from_rows(rows.clone(), i),
        (None, None) => None,
    };
    let normals = columns.normal.map(|[nx, ny, nz]| {
        rows.clone()
            .map(|r| Vec3::new(r[nx] as f32, r[ny] as f32, r[nz] as f32))
            .collect()
    });
    build_point_cloud(path, positions, colours, normals, Vec::new())
}

/// RGB(A) per row; `0..=1` values when every colour value is at most 1, else bytes.
fn colours_from_rows<'a>(
    rows: impl Iterator<Item = &'a [f64]> + Clone,
    rgb: [usize; 3],
    alpha: Option<usize>,
) -> Vec<[u8; 4]> {
    let channels: Vec<usize> = rgb.iter().copied().chain(alpha).collect();
    let unit = rows.clone().all(|r| channels.iter().all(|&c| r[c] <= 1.0));
    let scale = if unit { 255.0 } else { 1.0 };
    rows.map(|r| {
        let mut out = [255u8; 4];
        for (k, &c) in channels.iter().enumerate() {
            out[k] = byte_of(r[c] * scale);
        }
        out
    })
    .collect()
}

/// Intensity as grey, the file's lowest black and highest white; `None` when every finite
/// intensity is equal (nothing to show).
fn grey_from_rows<'a>(
    rows: impl Iterator<Item = &'a [f64]> + Clone,
    column: usize,
) -> Option<Vec<[u8; 4]>> {
    let finite = rows.clone().map(|r| r[column]).filter(|v| v.is_finite());
    let lo = finite.clone().fold(f64::INFINITY, f64::min);
    let hi = finite.fold(f64::NEG_INFINITY, f64::max);
    // NaN-free here (only finite values fold in), so `<=` is the plain negation of `>`.
    if hi <= lo {
        return None;
    }
    let scale = 255.0 / (hi - lo);
    Some(
        rows.map(|r| {
            let g = byte_of((r[column] - lo) * scale);
            [g, g, g, 255]
        })
        .collect(),
    )
}

/// A `0..=255` value (clamped, NaN as 0) rounded to a byte.
fn byte_of(v: f64) -> u8 {
    if v.is_nan() {
        0
    } else {
        (v.clamp(0.0, 255.0) + 0.5) as u8
    }
}
