//! Reading scan inputs: one or more files, each a cloud or a scan set, into one cloud.
//!
//! [`load_scans`] expands every input (a `.conf` pose file into its scans), reads the scans
//! in parallel (one reader per file, chosen by extension), applies each scan's pose and merges
//! them in input order ([`merge_scans`](crate::merge_scans)).
//!
//! | extension | reader | poses |
//! |---|---|---|
//! | `.conf` | [`read_conf`](crate::read_conf), then each listed scan | one per `bmesh` line |
//! | `.ply` | `spatch_mesh::load_point_cloud` | identity |
//! | `.xyz`, `.txt`, `.pts` | `spatch_mesh::load::xyz` (with [`ScanOptions::columns`]) | identity |
//! | `.las`, `.laz` | [`read_las`](crate::read_las) | identity |
//! | `.e57` | [`read_e57`](crate::read_e57) | each scan's own pose (then the `.conf`'s, if any) |
//!
//! Cost: the readers' (all files are held in memory at once as f64 positions before merging).

use std::path::{Path, PathBuf};

use glam::DVec3;
use rayon::prelude::*;
use spatch_mesh::load::xyz::{load_xyz_columns, XyzLayout};
use spatch_mesh::{load_point_cloud, LoadedPointCloud, PointCloud};

use crate::e57::read_e57_scans;
use crate::set_viewpoints::read_ply_scan_header;
use crate::{
    merge_scans, read_conf, read_las, sight_lines_of, Pose, PosedScan, ScanError, ScanSummary,
    ScanWarning, Viewpoint,
};

/// How to read the inputs.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct ScanOptions {
    /// What each column of the text inputs (`.xyz`, `.txt`, `.pts`) holds, overriding their
    /// header line and the column-count rules (see [`parse_columns`](crate::parse_columns)).
    /// Default: none (header or count rules).
    pub columns: Option<XyzLayout>,
    /// Ignore that a scan is structured (a PLY `range_grid`, E57 row and column indices).
    /// Default `false`: such a scan without normals of its own gets its scanner's
    /// [`Viewpoint`](crate::Viewpoint), and when every scan has one the points have sight
    /// lines ([`LoadedScans::sight_lines`]).
    pub ignore_range_grids: bool,
}

/// The merged cloud of every input and what happened on the way.
#[derive(Clone, Debug)]
pub struct LoadedScans {
    /// All points in the common frame.
    pub cloud: PointCloud,
    /// One entry per scan, in input order.
    pub scans: Vec<ScanSummary>,
    /// The `camera` pose of the first `.conf` that has one (a suggested viewpoint).
    pub camera: Option<Pose>,
    /// Points dropped because a coordinate or normal was NaN or infinite.
    pub dropped_non_finite: u64,
    /// Whether every point has a sight line (the unit vector toward the scanner that saw
    /// it, `viewpoint.rs`): every scan has a [`ScanSummary::viewpoint`] and none has normals
    /// of its own. The lines are not stored per point ([`LoadedScans::sight_line`]).
    pub sight_lines: bool,
    /// What the readers worked around.
    pub warnings: Vec<ScanWarning>,
}

impl LoadedScans {
    /// The sight line of point `i` of the cloud (unit, toward its scanner, common frame), when
    /// its scan has a viewpoint. A binary search over the scans; for a pass over every point,
    /// walk [`LoadedScans::scans`] instead.
    pub fn sight_line(&self, i: usize) -> Option<glam::DVec3> {
        let scan = self.scans.partition_point(|s| s.points.end <= i);
        self.scans
            .get(scan)?
            .sight_line(self.cloud.world_position(i))
    }
}

/// A file to read and the pose to apply to all its scans.
struct Job {
    path: PathBuf,
    pose: Pose,
}

/// Reads every input (see the module docs) and merges them into one cloud.
pub fn load_scans(inputs: &[PathBuf], options: &ScanOptions) -> Result<LoadedScans, ScanError> {
    if inputs.is_empty() {
        return Err(ScanError::NoInputs);
    }
    let mut jobs = Vec::new();
    let mut camera = None;
    for input in inputs {
        if is_scan_set(input) {
            let set = read_conf(input)?;
            camera = camera.or(set.camera);
            for entry in set.scans {
                if is_scan_set(&entry.path) {
                    return Err(ScanError::NestedScanSet {
                        path: input.clone(),
                        nested: entry.path,
                    });
                }
                jobs.push(Job {
                    path: entry.path,
                    pose: entry.pose,
                });
            }
        } else {
            jobs.push(Job {
                path: input.clone(),
                pose: Pose::IDENTITY,
            });
        }
    }
    let read: Vec<(Vec<PosedScan>, Vec<ScanWarning>)> = jobs
        .par_iter()
        .map(|job| read_scan_file(&job.path, job.pose, options))
        .collect::<Result<_, _>>()?;
    let mut warnings = Vec::new();
    let mut scans = Vec::new();
    for (file_scans, file_warnings) in read {
        warnings.extend(file_warnings);
        scans.extend(file_scans);
    }
    let dropped_non_finite = scans.iter().map(|s| s.dropped_non_finite).sum();
    let sight_lines = sight_lines_of(&scans);
    let (cloud, scans) = merge_scans(scans, &mut warnings)?;
    Ok(LoadedScans {
        cloud,
        scans,
        camera,
        dropped_non_finite,
        sight_lines,
        warnings,
    })
}

/// Whether `path` names a scan-set (pose) file.
pub fn is_scan_set(path: &Path) -> bool {
    extension(path).as_deref() == Some("conf")
}

/// The lower-case extension of `path`.
pub(crate) fn extension(path: &Path) -> Option<String> {
    Some(path.extension()?.to_str()?.to_ascii_lowercase())
}

/// Reads the scans of one file, each posed by `pose` after any pose the file holds.
fn read_scan_file(
    path: &Path,
    pose: Pose,
    options: &ScanOptions,
) -> Result<(Vec<PosedScan>, Vec<ScanWarning>), ScanError> {
    let columns = options.columns.as_ref();
    let grids = !options.ignore_range_grids;
    let (mut scans, warnings) = match extension(path).as_deref() {
        Some("ply") => {
            let (mut scans, warnings) = from_mesh_loader(path, load_point_cloud(path)?);
            // The header is read once more for its `range_grid` (the mesh loader skips it),
            // only when it can matter.
            let unnormalled = scans.iter().any(|s| s.normals.is_none());
            if grids && unnormalled && read_ply_scan_header(path)?.range_grid {
                for scan in scans.iter_mut().filter(|s| s.normals.is_none()) {
                    scan.viewpoint = Some(Viewpoint::Direction(DVec3::Z));
                }
            }
            (scans, warnings)
        }
        Some(ext @ ("xyz" | "txt" | "pts")) => {
            from_mesh_loader(path, load_xyz_columns(path, ext == "pts", columns)?)
        }
        Some("las" | "laz") => {
            let (scan, warnings) = read_las(path)?;
            (vec![scan], warnings)
        }
        Some("e57") => read_e57_scans(path, grids)?,
        _ => {
            return Err(ScanError::UnsupportedFormat {
                path: path.to_path_buf(),
            })
        }
    };
    for scan in &mut scans {
        scan.pose = pose.after(&scan.pose);
    }
    Ok((scans, warnings))
}

/// A cloud from the mesh crate's readers as one scan with its warnings.
fn from_mesh_loader(path: &Path, loaded: LoadedPointCloud) -> (Vec<PosedScan>, Vec<ScanWarning>) {
    let warnings = loaded
        .warnings
        .into_iter()
        .map(|warning| ScanWarning::Load {
            path: path.to_path_buf(),
            warning,
        })
        .collect();
    let scan = posed_from_cloud(path, loaded.cloud, loaded.dropped_non_finite);
    (vec![scan], warnings)
}

/// A loaded cloud as an unposed scan (its f32 positions back to f64 world coordinates).
fn posed_from_cloud(path: &Path, cloud: PointCloud, dropped: u64) -> PosedScan {
    let origin: DVec3 = cloud.origin;
    PosedScan {
        path: path.to_path_buf(),
        index: 0,
        positions: cloud
            .positions
            .iter()
            .map(|p| origin + p.as_dvec3())
            .collect(),
        colours: cloud.colours,
        normals: cloud.normals,
        viewpoint: None,
        pose: Pose::IDENTITY,
        dropped_non_finite: dropped,
    }
}
