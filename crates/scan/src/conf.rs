//! Stanford scan-set pose files (`.conf`), as shipped with the Stanford 3D Scanning
//! Repository's range scans (`bun.conf` beside `bun000.ply` ...).
//!
//! Input: the text of the file. Output: a [`ScanSetFile`]: one [`ScanEntry`] per
//! `bmesh FILE tx ty tz qx qy qz qw` (or `mesh ...`) line, with the file resolved relative to
//! the `.conf`'s folder and its [`Pose`], and the viewing pose of the `camera` line when there
//! is one (a viewpoint, not a scan).
//!
//! The pose convention (established from the bunny scans, see `docs/algorithms/scan.md`):
//! the quaternion `q` is written `x y z w` (scalar last), and a scan's point `p` goes into the
//! common frame as `p' = q⁻¹ p q + t`: the conjugate rotation, then the translation. (Applying
//! `q` itself, or translating before rotating, leaves the bunny's scans millimetres apart.) Blank lines and lines starting with `#` are skipped;
//! any other keyword is refused with its line number.
//!
//! Cost: one pass over the text.

use std::path::{Path, PathBuf};

use glam::{DQuat, DVec3};

use crate::error::ConfProblem;
use crate::{Pose, ScanError};

/// One scan of a pose file: the file and the pose that takes it into the common frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanEntry {
    /// The scan file, resolved relative to the pose file's folder.
    pub path: PathBuf,
    /// Scan coordinates to the common frame.
    pub pose: Pose,
}

/// What a Stanford `.conf` file lists.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanSetFile {
    /// The scans, in file order.
    pub scans: Vec<ScanEntry>,
    /// The `camera` line's pose (a suggested viewpoint), when present.
    pub camera: Option<Pose>,
}

/// Reads and parses a `.conf` file.
pub fn read_conf(path: &Path) -> Result<ScanSetFile, ScanError> {
    let bytes = std::fs::read(path).map_err(|source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let text = String::from_utf8_lossy(&bytes);
    parse_conf(path, &text)
}

/// Parses the text of a `.conf` file; `path` resolves the scan files and names the file in
/// errors.
pub fn parse_conf(path: &Path, text: &str) -> Result<ScanSetFile, ScanError> {
    let folder = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut scans = Vec::new();
    let mut camera = None;
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let err = |problem| ScanError::Conf {
            path: path.to_path_buf(),
            line: i + 1,
            problem,
        };
        let mut tokens = line.split_ascii_whitespace();
        let keyword = tokens.next().unwrap_or_default();
        match keyword {
            "camera" => {
                let values: Vec<&str> = tokens.collect();
                camera = Some(parse_pose(&values).map_err(err)?);
            }
            "bmesh" | "mesh" => {
                let file = tokens.next().ok_or_else(|| err(ConfProblem::MissingFile))?;
                let values: Vec<&str> = tokens.collect();
                let pose = parse_pose(&values).map_err(err)?;
                scans.push(ScanEntry {
                    path: folder.join(file),
                    pose,
                });
            }
            other => {
                return Err(err(ConfProblem::UnknownKeyword {
                    keyword: other.chars().take(40).collect(),
                }))
            }
        }
    }
    if scans.is_empty() {
        return Err(ScanError::NoScans {
            path: path.to_path_buf(),
        });
    }
    Ok(ScanSetFile { scans, camera })
}

/// `tx ty tz qx qy qz qw` into a pose.
fn parse_pose(values: &[&str]) -> Result<Pose, ConfProblem> {
    if values.len() != 7 {
        return Err(ConfProblem::PoseValues {
            found: values.len(),
        });
    }
    let mut v = [0.0f64; 7];
    for (k, token) in values.iter().enumerate() {
        v[k] = token
            .parse()
            .map_err(|_| ConfProblem::NotANumber { value: k + 1 })?;
    }
    let translation = DVec3::new(v[0], v[1], v[2]);
    // The file writes the quaternion of the inverse rotation (equivalently: the rotation
    // matrix transposed, as OpenGL's column-major matrices read row-major); see the module docs.
    let rotation = DQuat::from_xyzw(v[3], v[4], v[5], v[6]).conjugate();
    Pose::new(rotation, translation).map_err(ConfProblem::BadPose)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_scans_and_camera() {
        let text = "camera 0 0 1 0 0 0 1\n\n# a comment\nbmesh a.ply 1 2 3 0 0 0 1\nmesh sub/b.ply 0 0 0 0 0 1 0\n";
        let set = parse_conf(Path::new("/data/x.conf"), text).unwrap();
        assert_eq!(set.scans.len(), 2);
        assert_eq!(set.scans[0].path, PathBuf::from("/data/a.ply"));
        assert_eq!(set.scans[1].path, PathBuf::from("/data/sub/b.ply"));
        assert_eq!(set.scans[0].pose.translation(), DVec3::new(1.0, 2.0, 3.0));
        // (0 0 1 0) is a half turn about z (its own inverse): x goes to -x.
        let p = set.scans[1].pose.apply_point(DVec3::X);
        assert!((p + DVec3::X).length() < 1e-12, "{p}");
        assert!(set.camera.is_some());
    }

    #[test]
    fn the_written_quaternion_is_inverted() {
        // (0 0 s c) with s = sin 45°, c = cos 45° is a quarter turn about +z; the scan's
        // points turn the other way: x goes to -y.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let text = format!("bmesh a.ply 0 0 1 0 0 {h} {h}\n");
        let set = parse_conf(Path::new("x.conf"), &text).unwrap();
        let p = set.scans[0].pose.apply_point(DVec3::X);
        assert!((p - DVec3::new(0.0, -1.0, 1.0)).length() < 1e-12, "{p}");
    }

    #[test]
    fn malformed_lines_name_the_line() {
        let cases = [
            ("bmesh a.ply 1 2 3\n", "line 1: expected 7 pose values"),
            (
                "\nbmesh a.ply 1 2 x 0 0 0 1\n",
                "line 2: pose value 3 is not a number",
            ),
            ("bmesh\n", "line 1: the scan file name is missing"),
            (
                "bmesh a.ply 0 0 0 0 0 0 0\n",
                "line 1: the pose's quaternion",
            ),
            (
                "scan a.ply 0 0 0 0 0 0 1\n",
                "line 1: unknown keyword `scan`",
            ),
            ("camera 0 0 0 0 0 0 1\n", "lists no scans"),
        ];
        for (text, expected) in cases {
            let message = parse_conf(Path::new("s.conf"), text)
                .unwrap_err()
                .to_string();
            assert!(message.starts_with("s.conf: "), "{message}");
            assert!(message.contains(expected), "{text:?}: {message}");
        }
    }
}
