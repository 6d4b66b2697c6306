//! Merging posed scans into one point cloud.
//!
//! Input: scans as read ([`PosedScan`]: f64 positions in the scan's own frame, optional
//! colours and normals, a [`Pose`]). Output: one [`PointCloud`] in the common frame, its
//! positions f32 relative to the f64 centre of the merged cloud's robust bounds
//! (`spatch_mesh::robust_centre`: the bounding box's centre unless far outliers would
//! move it off the real points), and a
//! [`ScanSummary`] per scan (which points came from it).
//!
//! Invariants: points keep their scan order, scans keep their input order (so the result is
//! deterministic); normals are rotated with their scan; colours survive when any scan has them
//! (scans without get white, with a [`ScanWarning::ColoursMissing`]); normals survive only when
//! every scan has them (else [`ScanWarning::NormalsDropped`] and the pipeline estimates them).
//! A scan's [`Viewpoint`] is moved by its pose into the common frame
//! ([`ScanSummary::viewpoint`]); when no scan has normals and every scan has one
//! ([`sight_lines_of`]), each point's *sight line* (the unit vector toward the scanner that
//! saw it) follows from its scan ([`ScanSummary::sight_line`]). No vector is stored per
//! point: that was 12 bytes a point at the memory peak of structured scan sets.
//!
//! Cost: one pass over the points, O(n) f64 scratch for the world positions.

use std::ops::Range;
use std::path::PathBuf;

use glam::{DVec3, Vec3};
use spatch_mesh::PointCloud;

use crate::{Pose, ScanError, ScanWarning, Viewpoint};

/// Largest number of points a merged cloud may hold (32-bit point ids, one kept free).
pub const MAX_POINTS: usize = u32::MAX as usize - 1;

/// One scan as read from its file, before it is moved into the common frame.
#[derive(Clone, Debug, Default)]
pub struct PosedScan {
    /// The file it came from (for messages).
    pub path: PathBuf,
    /// Which scan of the file (E57 files hold several; 0 otherwise).
    pub index: usize,
    /// Finite positions in the scan's own frame.
    pub positions: Vec<DVec3>,
    /// sRGB RGBA8 colour per point.
    pub colours: Option<Vec<[u8; 4]>>,
    /// Normal per point in the scan's own frame.
    pub normals: Option<Vec<Vec3>>,
    /// Where the scanner was, in the scan's own frame, when the reader knows it (a structured
    /// scan: `viewpoint.rs`); gives each point its sight line when merged.
    pub viewpoint: Option<Viewpoint>,
    /// Scan frame to common frame.
    pub pose: Pose,
    /// Points the reader dropped because a value was NaN or infinite.
    pub dropped_non_finite: u64,
}

/// Where one scan's points ended up in the merged cloud.
#[derive(Clone, Debug, PartialEq)]
pub struct ScanSummary {
    /// The file it came from.
    pub path: PathBuf,
    /// Which scan of the file (E57 files hold several; 0 otherwise).
    pub index: usize,
    /// Its points' indices in the merged cloud.
    pub points: Range<usize>,
    /// The pose that was applied.
    pub pose: Pose,
    /// Where the scan's scanner was, in the common frame (the scan's [`Viewpoint`] moved by
    /// its pose), when the reader knew it.
    pub viewpoint: Option<Viewpoint>,
}

impl ScanSummary {
    /// The unit sight line of the point at `world` (common frame, a point of this scan):
    /// toward the scanner that saw it. `None` without a viewpoint.
    pub fn sight_line(&self, world: DVec3) -> Option<DVec3> {
        Some(self.viewpoint?.toward(world))
    }
}

/// Whether the points of `scans` have sight lines to turn their estimated normals by: no
/// scan has normals of its own and every scan has a [`Viewpoint`].
pub fn sight_lines_of(scans: &[PosedScan]) -> bool {
    !scans.is_empty()
        && scans
            .iter()
            .all(|s| s.normals.is_none() && s.viewpoint.is_some())
}

/// Moves every scan into the common frame and concatenates them; see the module docs.
pub fn merge_scans(
    scans: Vec<PosedScan>,
    warnings: &mut Vec<ScanWarning>,
) -> Result<(PointCloud, Vec<ScanSummary>), ScanError> {
    let total: usize = scans.iter().map(|s| s.positions.len()).sum();
    if total > MAX_POINTS {
        return Err(ScanError::TooManyPoints {
            count: total as u64,
        });
    }
    let mut merged = MergedPoints::for_scans(&scans, total);
    let mut summaries = Vec::with_capacity(scans.len());
    for scan in scans {
        let start = merged.world.len();
        let pose = scan.pose;
        merged.append(&scan, warnings);
        summaries.push(ScanSummary {
            path: scan.path,
            index: scan.index,
            points: start..merged.world.len(),
            pose,
            viewpoint: scan.viewpoint.map(|v| v.posed(&pose)),
        });
    }
    Ok((merged.into_cloud(), summaries))
}

/// The merged points so far, in the common frame: f64 positions, the colours when any scan
/// has them, the normals when every scan has them.
struct MergedPoints {
    world: Vec<DVec3>,
    colours: Option<Vec<[u8; 4]>>,
    normals: Option<Vec<Vec3>>,
}

impl MergedPoints {
    /// Empty columns for the `total` points of `scans`, with colours and normals as the
    /// module docs say they survive.
    fn for_scans(scans: &[PosedScan], total: usize) -> MergedPoints {
        let any_colour = scans.iter().any(|s| s.colours.is_some());
        let all_normals = scans.iter().all(|s| s.normals.is_some());
        MergedPoints {
            world: Vec::with_capacity(total),
            colours: any_colour.then(|| Vec::with_capacity(total)),
            normals: all_normals.then(|| Vec::with_capacity(total)),
        }
    }

    /// Appends the points of `scan`, moved by its pose; a scan without the colours others
    /// have gets white, and normals that others lack are dropped (each with its warning).
    fn append(&mut self, scan: &PosedScan, warnings: &mut Vec<ScanWarning>) {
        let pose = scan.pose;
        let world = &mut self.world;
        if pose.is_identity() {
            world.extend_from_slice(&scan.positions);
        } else {
            world.extend(scan.positions.iter().map(|&p| pose.apply_point(p)));
        }
        if let Some(out) = self.colours.as_mut() {
            match &scan.colours {
                Some(c) => out.extend_from_slice(c),
                None => {
                    warnings.push(ScanWarning::ColoursMissing {
                        path: scan.path.clone(),
                    });
                    out.resize(world.len(), [255; 4]);
                }
            }
        }
        match (self.normals.as_mut(), &scan.normals) {
            (Some(out), Some(n)) => {
                out.extend(n.iter().map(|&v| pose.apply_vector(v.as_dvec3()).as_vec3()))
            }
            (None, Some(_)) => warnings.push(ScanWarning::NormalsDropped {
                path: scan.path.clone(),
            }),
            _ => {}
        }
    }

    /// The merged cloud: positions f32 relative to the robust centre of the world positions.
    fn into_cloud(self) -> PointCloud {
        let world = self.world;
        let origin = spatch_mesh::robust_centre(world.len(), |k| world[k]);
        PointCloud {
            origin,
            positions: world.iter().map(|&p| (p - origin).as_vec3()).collect(),
            colours: self.colours,
            normals: self.normals,
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::*;

    fn scan(points: &[[f64; 3]], pose: Pose) -> PosedScan {
        PosedScan {
            path: PathBuf::from("s.xyz"),
            positions: points.iter().map(|&p| DVec3::from(p)).collect(),
            pose,
            ..PosedScan::default()
        }
    }

    #[test]
    fn poses_apply_and_origin_is_the_centre() {
        let turn = Pose::new(
            DQuat::from_rotation_z(std::f64::consts::PI),
            DVec3::new(10.0, 0.0, 0.0),
        )
        .unwrap();
        let mut warnings = Vec::new();
        let (cloud, summaries) = merge_scans(
            vec![
                scan(&[[1.0, 0.0, 0.0]], Pose::IDENTITY),
                scan(&[[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]], turn),
            ],
            &mut warnings,
        )
        .unwrap();
        assert_eq!(cloud.len(), 3);
        assert_eq!(summaries[1].points, 1..3);
        let xs: Vec<f64> = (0..3).map(|i| cloud.world_position(i).x).collect();
        assert!(
            (xs[1] - 9.0).abs() < 1e-6 && (xs[2] - 8.0).abs() < 1e-6,
            "{xs:?}"
        );
        assert!((cloud.origin.x - 5.0).abs() < 1e-12);
        assert!(warnings.is_empty());
    }

    #[test]
    fn viewpoints_become_sight_lines_turned_by_the_pose() {
        // A scanner far up +z of its scan, turned over by a half turn about x; a scanner at
        // the origin of a scan moved to x = 10.
        let mut a = scan(
            &[[0.0, 0.0, 1.0]],
            Pose::new(DQuat::from_rotation_x(std::f64::consts::PI), DVec3::ZERO).unwrap(),
        );
        a.viewpoint = Some(Viewpoint::Direction(DVec3::Z));
        let mut b = scan(
            &[[0.0, 3.0, 0.0]],
            Pose::new(DQuat::IDENTITY, DVec3::new(10.0, 0.0, 0.0)).unwrap(),
        );
        b.viewpoint = Some(Viewpoint::Position(DVec3::ZERO));
        assert!(sight_lines_of(&[a.clone(), b.clone()]));
        let (cloud, summaries) = merge_scans(vec![a.clone(), b], &mut Vec::new()).unwrap();
        // No vector stored per point: each point's line comes from its scan's viewpoint.
        assert!(cloud.normals.is_none());
        let line = |k: usize| summaries[k].sight_line(cloud.world_position(k)).unwrap();
        assert!((line(0) - -DVec3::Z).length() < 1e-6, "{}", line(0));
        assert!((line(1) - -DVec3::Y).length() < 1e-6, "{}", line(1));
        assert_eq!(
            summaries[1].viewpoint,
            Some(Viewpoint::Position(DVec3::new(10.0, 0.0, 0.0)))
        );
        // A scan without a viewpoint: no sight lines for any.
        let plain = scan(&[[1.0; 3]], Pose::IDENTITY);
        assert!(!sight_lines_of(&[a.clone(), plain.clone()]));
        let (cloud, summaries) = merge_scans(vec![a, plain], &mut Vec::new()).unwrap();
        assert!(cloud.normals.is_none());
        assert_eq!(summaries[1].sight_line(DVec3::ZERO), None);
    }

    #[test]
    fn missing_colours_are_white_and_partial_normals_dropped() {
        let mut a = scan(&[[0.0; 3]], Pose::IDENTITY);
        a.colours = Some(vec![[10, 20, 30, 255]]);
        let mut b = scan(&[[1.0; 3]], Pose::IDENTITY);
        b.normals = Some(vec![Vec3::Z]);
        let mut warnings = Vec::new();
        let (cloud, _) = merge_scans(vec![a, b], &mut warnings).unwrap();
        assert_eq!(
            cloud.colours,
            Some(vec![[10, 20, 30, 255], [255, 255, 255, 255]])
        );
        assert!(cloud.normals.is_none());
        assert_eq!(warnings.len(), 2, "{warnings:?}");
    }
}
