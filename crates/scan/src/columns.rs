//! Column layouts for text clouds, as the user writes them: `x,y,z,nx,ny,nz,r,g,b`.
//!
//! Input: a comma- (or space-) separated list of column names (see
//! [`XyzColumn::from_name`]). Output: a validated [`XyzLayout`] for the text reader, or a
//! [`ScanError::ColumnSpec`] naming what is wrong.

use spatch_mesh::load::xyz::{XyzColumn, XyzLayout};

use crate::{ColumnSpecProblem, ScanError};

/// Parses a `--columns` layout such as `x,y,z,intensity,r,g,b` or `x y z skip nx ny nz`.
pub fn parse_columns(spec: &str) -> Result<XyzLayout, ScanError> {
    let fail = |problem| ScanError::ColumnSpec {
        spec: spec.to_string(),
        problem,
    };
    let mut list = Vec::new();
    for name in spec
        .split(|c: char| c == ',' || c.is_ascii_whitespace())
        .filter(|n| !n.is_empty())
    {
        let column = XyzColumn::from_name(name).ok_or_else(|| {
            fail(ColumnSpecProblem::UnknownName {
                name: name.chars().take(40).collect(),
            })
        })?;
        if column != XyzColumn::Skip && list.contains(&column) {
            return Err(fail(ColumnSpecProblem::Repeated {
                name: name.to_string(),
            }));
        }
        list.push(column);
    }
    let groups: [(&[XyzColumn], [&'static str; 3]); 3] = [
        (&[XyzColumn::X, XyzColumn::Y, XyzColumn::Z], ["x", "y", "z"]),
        (
            &[XyzColumn::Nx, XyzColumn::Ny, XyzColumn::Nz],
            ["nx", "ny", "nz"],
        ),
        (&[XyzColumn::R, XyzColumn::G, XyzColumn::B], ["r", "g", "b"]),
    ];
    for (i, (kinds, names)) in groups.iter().enumerate() {
        let present: Vec<bool> = kinds.iter().map(|k| list.contains(k)).collect();
        let required = i == 0;
        if required || present.contains(&true) {
            if let Some(missing) = present.iter().position(|&p| !p) {
                return Err(fail(ColumnSpecProblem::Incomplete {
                    missing: names[missing],
                }));
            }
        }
    }
    XyzLayout::new(list)
        .ok_or_else(|| ScanError::Bug(format!("layout `{spec}` passed the checks but was refused")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_in_order() {
        let layout = parse_columns("x,y,z,nx,ny,nz,R,G,B").unwrap();
        assert_eq!(layout.columns().len(), 9);
        assert_eq!(layout.columns()[3], XyzColumn::Nx);
        assert_eq!(layout.columns()[6], XyzColumn::R);
        let spaced = parse_columns("x y z skip skip intensity").unwrap();
        assert_eq!(spaced.columns()[5], XyzColumn::Intensity);
    }

    #[test]
    fn bad_layouts_say_why() {
        let cases = [
            ("x,y,w", "unknown column `w`"),
            ("x,y,z,x", "column `x` appears twice"),
            ("x,y", "column `z` is missing"),
            ("x,y,z,r,g", "column `b` is missing"),
            ("x,y,z,nx,nz", "column `ny` is missing"),
        ];
        for (spec, expected) in cases {
            let message = parse_columns(spec).unwrap_err().to_string();
            assert!(message.contains(expected), "{spec}: {message}");
            assert!(message.contains(spec), "{message}");
        }
    }
}
