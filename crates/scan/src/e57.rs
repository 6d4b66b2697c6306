//! ASTM E57 scanner files, through the `e57` crate: every point cloud ("scan") of the file
//! with its own pose.
//!
//! Input: an `.e57` file. Output: one [`PosedScan`] per point cloud of the file, in file
//! order, its positions in the scan's local frame and its [`Pose`] from the scan's `pose`
//! element (E57 defines it as the rigid transform from the scan's local frame to the file's
//! frame, `p' = q p q⁻¹ + t`; missing means identity). Spherical-only scans are converted
//! to Cartesian by the reader. Points without a valid Cartesian position (the scanner saw no
//! return, only a direction) are dropped and counted with the non-finite ones.
//!
//! Colours come normalised to `0..=1` by the reader (from the scan's colour limits) and are
//! rounded to bytes. Scans without colour but with intensity give the intensity as grey (also
//! normalised by the reader) with a [`ScanWarning::IntensityAsGrey`].
//!
//! A structured scan (its points carry row and column indices) was taken from its frame's
//! origin: [`load_scans`](crate::load_scans) gives it that [`Viewpoint`], so each point gets
//! its sight line (`viewpoint.rs`).
//!
//! Cost: one pass over each scan's points; the reader holds one packet at a time.

use std::path::Path;

use glam::{DQuat, DVec3};

use crate::{Pose, PosedScan, ScanError, ScanWarning, Viewpoint};

/// Reads every scan of an E57 file; see the module docs. (Without viewpoints:
/// [`load_scans`](crate::load_scans) adds them.)
pub fn read_e57(path: &Path) -> Result<(Vec<PosedScan>, Vec<ScanWarning>), ScanError> {
    read_e57_scans(path, false)
}

/// [`read_e57`], and with `grids` every structured scan (row and column indices in its
/// points' records) gets its scanner's [`Viewpoint`]: the origin of its own frame.
pub(crate) fn read_e57_scans(
    path: &Path,
    grids: bool,
) -> Result<(Vec<PosedScan>, Vec<ScanWarning>), ScanError> {
    let file = std::fs::File::open(path).map_err(|source| ScanError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let refuse = |source| ScanError::E57 {
        path: path.to_path_buf(),
        source: Box::new(source),
    };
    let mut reader = e57::E57Reader::new(std::io::BufReader::new(file)).map_err(refuse)?;
    let mut scans = Vec::new();
    let mut warnings = Vec::new();
    for (index, pc) in reader.pointclouds().into_iter().enumerate() {
        let pose = scan_pose(path, &pc)?;
        let has_colour = pc.has_color();
        let grey = !has_colour && pc.has_intensity();
        let mut points = reader.pointcloud_simple(&pc).map_err(refuse)?;
        points.apply_pose(false);
        points.intensity_to_color(false);
        let mut scan = PosedScan {
            path: path.to_path_buf(),
            index,
            pose,
            colours: (has_colour || grey).then(Vec::new),
            viewpoint: (grids && pc.has_row_column()).then_some(Viewpoint::Position(DVec3::ZERO)),
            ..PosedScan::default()
        };
        for point in points {
            let point = point.map_err(refuse)?;
            let Some(p) = finite_position(&point) else {
                scan.dropped_non_finite += 1;
                continue;
            };
            scan.positions.push(p);
            if let Some(colours) = scan.colours.as_mut() {
                colours.push(point_colour(&point, grey));
            }
        }
        if grey {
            warnings.push(ScanWarning::IntensityAsGrey {
                path: path.to_path_buf(),
            });
        }
        scans.push(scan);
    }
    if scans.iter().all(|s| s.positions.is_empty()) {
        return Err(ScanError::NoPoints {
            path: path.to_path_buf(),
        });
    }
    Ok((scans, warnings))
}

/// The scan's pose as a [`Pose`]; a non-finite or zero quaternion is the file's fault.
pub(crate) fn scan_pose(path: &Path, pc: &e57::PointCloud) -> Result<Pose, ScanError> {
    let Some(t) = &pc.transform else {
        return Ok(Pose::IDENTITY);
    };
    let q = &t.rotation;
    let rotation = DQuat::from_xyzw(q.x, q.y, q.z, q.w);
    let translation = DVec3::new(t.translation.x, t.translation.y, t.translation.z);
    Pose::new(rotation, translation).map_err(|problem| ScanError::BadScanPose {
        path: path.to_path_buf(),
        scan: pc.name.clone().unwrap_or_default(),
        problem,
    })
}

/// A point's Cartesian position, or `None` when the scanner marked it invalid or a
/// coordinate is not finite (such points are dropped and counted).
pub(crate) fn finite_position(point: &e57::Point) -> Option<DVec3> {
    let e57::CartesianCoordinate::Valid { x, y, z } = point.cartesian else {
        return None;
    };
    let p = DVec3::new(x, y, z);
    p.is_finite().then_some(p)
}

/// A point's colour (or grey from intensity) as RGBA8; invalid values are black.
pub(crate) fn point_colour(point: &e57::Point, grey: bool) -> [u8; 4] {
    let byte = |v: f32| unit_byte(f64::from(v));
    if grey {
        let g = point.intensity.map_or(0, byte);
        return [g, g, g, 255];
    }
    match &point.color {
        Some(c) => [byte(c.red), byte(c.green), byte(c.blue), 255],
        None => [0, 0, 0, 255],
    }
}

/// A `0..=1` value (clamped; NaN is 0) as a byte.
fn unit_byte(v: f64) -> u8 {
    if v.is_nan() {
        0
    } else {
        (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
    }
}
