//! The scanners of an input without reading its points: each scan's posed [`Viewpoint`]
//! from headers alone (a PLY header's `range_grid` element, an E57 scan's row and column
//! indices), for runs that stream the points (tiled conversions, `spatch_tiling`).
//!
//! Input: one input path (a `.conf` scan set, an `.e57` file, or any single cloud file) and
//! [`ScanOptions`]. Output: one entry per scan, in the order the scans are streamed and
//! merged ([`load_scans`](crate::load_scans)'s order): its posed viewpoint, or `None` when
//! it has none or has normals of its own (every entry `Some` exactly when
//! [`load_scans`](crate::load_scans) gives the merged cloud sight lines,
//! [`LoadedScans::sight_lines`](crate::LoadedScans::sight_lines)).
//!
//! Cost: one read of each PLY header (up to `end_header`) and of each E57 file's XML
//! section; no point is read.

use std::io::{BufRead, BufReader};
use std::path::Path;

use glam::DVec3;

use crate::e57::scan_pose;
use crate::load::{extension, is_scan_set};
use crate::{read_conf, Pose, ScanError, ScanOptions, Viewpoint};

/// What a PLY header says about a scan.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct PlyScanHeader {
    /// It declares a `range_grid` element: a raw range scan in its scanner's frame, the
    /// scanner far along +z (`viewpoint.rs`).
    pub(crate) range_grid: bool,
    /// Its vertices have normals (an `nx` property).
    pub(crate) normals: bool,
}

/// Longest PLY header read (a header this long is not a scan's).
const MAX_HEADER: u64 = 64 * 1024;

/// Reads the header of the PLY file at `path`, line by line up to `end_header`.
pub(crate) fn read_ply_scan_header(path: &Path) -> Result<PlyScanHeader, ScanError> {
    use std::io::Read;
    let io = |source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let mut reader = BufReader::new(file.take(MAX_HEADER));
    let mut header = PlyScanHeader::default();
    let mut line = Vec::new();
    while reader.read_until(b'\n', &mut line).map_err(io)? > 0 {
        let text = String::from_utf8_lossy(&line);
        let words: Vec<&str> = text.split_ascii_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            ["element", "range_grid", ..] => header.range_grid = true,
            ["property", .., "nx"] => header.normals = true,
            _ => {}
        }
        line.clear();
    }
    Ok(header)
}

/// The posed viewpoint of every scan of `input` (see the module documentation).
///
/// Errors: [`ScanError::Io`], [`ScanError::E57`], the `.conf` reader's errors,
/// [`ScanError::NestedScanSet`].
pub fn scan_viewpoints(
    input: &Path,
    options: &ScanOptions,
) -> Result<Vec<Option<Viewpoint>>, ScanError> {
    let mut found = Vec::new();
    if is_scan_set(input) {
        for entry in read_conf(input)?.scans {
            if is_scan_set(&entry.path) {
                return Err(ScanError::NestedScanSet {
                    path: input.to_path_buf(),
                    nested: entry.path,
                });
            }
            file_viewpoints(&entry.path, &entry.pose, options, &mut found)?;
        }
    } else {
        file_viewpoints(input, &Pose::IDENTITY, options, &mut found)?;
    }
    Ok(found)
}

/// Appends the posed viewpoint of each scan of the file at `path` (by its own pose, then
/// by `pose`).
fn file_viewpoints(
    path: &Path,
    pose: &Pose,
    options: &ScanOptions,
    found: &mut Vec<Option<Viewpoint>>,
) -> Result<(), ScanError> {
    let grids = !options.ignore_range_grids;
    match extension(path).as_deref() {
        Some("e57") => e57_viewpoints(path, pose, grids, found)?,
        Some("ply") if grids => {
            let header = read_ply_scan_header(path)?;
            let seen = header.range_grid && !header.normals;
            found.push(seen.then(|| Viewpoint::Direction(DVec3::Z).posed(pose)));
        }
        _ => found.push(None),
    }
    Ok(())
}

/// The viewpoints of an E57 file's scans: the origin of each structured scan's frame.
fn e57_viewpoints(
    path: &Path,
    pose: &Pose,
    grids: bool,
    found: &mut Vec<Option<Viewpoint>>,
) -> Result<(), ScanError> {
    let file = std::fs::File::open(path).map_err(|source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let reader = e57::E57Reader::new(BufReader::new(file)).map_err(|source| ScanError::E57 {
        path: path.to_path_buf(),
        source: Box::new(source),
    })?;
    for pc in reader.pointclouds() {
        let total = pose.after(&scan_pose(path, &pc)?);
        let seen = grids && pc.has_row_column();
        found.push(seen.then(|| Viewpoint::Position(DVec3::ZERO).posed(&total)));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("spatch-scan-vp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn headers_give_range_grids_and_normals() {
        let grid = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                    property float z\nelement range_grid 1\nproperty list uchar int vertex_indices\n\
                    end_header\n0 0 0\n1 0\n";
        let path = write("grid.ply", grid);
        let header = read_ply_scan_header(&path).unwrap();
        assert_eq!(
            header,
            PlyScanHeader {
                range_grid: true,
                normals: false
            }
        );
        let options = ScanOptions::default();
        let turned =
            Pose::new(glam::DQuat::from_rotation_x(std::f64::consts::PI), DVec3::X).unwrap();
        let conf = write(
            "set.conf",
            "bmesh grid.ply 0 0 0 0 0 0 1\nbmesh grid.ply 1 0 0 1 0 0 0\n",
        );
        let found = scan_viewpoints(&conf, &options).unwrap();
        assert_eq!(found.len(), 2);
        assert_eq!(found[0], Some(Viewpoint::Direction(DVec3::Z)));
        let Some(Viewpoint::Direction(d)) = found[1] else {
            panic!("{:?}", found[1])
        };
        assert!((d - turned.apply_vector(DVec3::Z)).length() < 1e-12, "{d}");

        // Normals of its own, or no grid: no viewpoints for the set.
        let normals = grid.replace(
            "property float z\n",
            "property float z\nproperty float nx\n",
        );
        write("normals.ply", &normals);
        let mixed = write(
            "mixed.conf",
            "bmesh grid.ply 0 0 0 0 0 0 1\nbmesh normals.ply 0 0 0 0 0 0 1\n",
        );
        let mixed = scan_viewpoints(&mixed, &options).unwrap();
        assert_eq!(mixed, [Some(Viewpoint::Direction(DVec3::Z)), None]);
        let plain = write(
            "plain.ply",
            &grid.replace(
                "element range_grid 1\nproperty list uchar int vertex_indices\n",
                "",
            ),
        );
        assert_eq!(scan_viewpoints(&plain, &options).unwrap(), [None]);
        let mut off = options.clone();
        off.ignore_range_grids = true;
        assert_eq!(scan_viewpoints(&conf, &off).unwrap(), [None, None]);
    }
}
