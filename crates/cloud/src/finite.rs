//! The `filter` stage: the cloud without its non-finite points, and the bounds of what is
//! left, or why it cannot be converted.
//!
//! Input: a borrowed or owned cloud and, when its scanners are known, the scan of each point.
//! Output: the finite points (the same cloud, borrowed, when every point is finite), how many
//! were dropped, the kept points' scans, and the bounds.
//!
//! Invariants: the kept points keep their order; a point's scan stays with it.
//!
//! Cost: one pass over the points; a copy only when a point is dropped.

use std::borrow::Cow;

use rayon::prelude::*;
use spatch_mesh::{Aabb, PointCloud};

use crate::scanners::PointScans;
use crate::CloudError;

/// The bounds of the finite cloud, or why it cannot be converted (too few points, no
/// extent).
pub(crate) fn check_extent(cloud: &PointCloud, dropped: u64) -> Result<Aabb, CloudError> {
    let n = cloud.len();
    if n == 0 {
        return Err(CloudError::EmptyCloud {
            dropped_non_finite: dropped,
        });
    }
    if n < 3 {
        return Err(CloudError::TooFewPoints {
            found: n,
            needed: 3,
        });
    }
    let bounds = cloud.bounds();
    if bounds.diagonal().is_nan() || bounds.diagonal() <= 0.0 {
        return Err(CloudError::NoExtent {
            points: n,
            extent: 0.0,
        });
    }
    Ok(bounds)
}

/// A cloud, how many points were dropped, and the points' scans (when known).
pub(crate) type FiniteCloud<'a> = (Cow<'a, PointCloud>, u64, Option<PointScans>);

/// The cloud without its non-finite points (borrowed when there are none), how many were
/// dropped, and the kept points' `scans`.
pub(crate) fn keep_finite(
    cloud: Cow<'_, PointCloud>,
    scans: Option<PointScans>,
) -> Result<FiniteCloud<'_>, CloudError> {
    let n = cloud.len();
    if let Some(c) = &cloud.colours {
        if c.len() != n {
            return Err(CloudError::MismatchedAttribute {
                what: "colours",
                found: c.len(),
                expected: n,
            });
        }
    }
    if let Some(normals) = &cloud.normals {
        if normals.len() != n {
            return Err(CloudError::MismatchedAttribute {
                what: "normals",
                found: normals.len(),
                expected: n,
            });
        }
    }
    let is_finite = |i: usize| {
        cloud.positions[i].is_finite()
            && cloud
                .normals
                .as_ref()
                .is_none_or(|normals| normals[i].is_finite())
    };
    if (0..n).all(is_finite) {
        return Ok((cloud, 0, scans));
    }
    let keep: Vec<usize> = (0..n).filter(|&i| is_finite(i)).collect();
    let scans = scans.map(|s| s.pick(keep.par_iter().copied()));
    let filtered = PointCloud {
        origin: cloud.origin,
        positions: keep.iter().map(|&i| cloud.positions[i]).collect(),
        colours: cloud
            .colours
            .as_ref()
            .map(|c| keep.iter().map(|&i| c[i]).collect()),
        normals: cloud
            .normals
            .as_ref()
            .map(|v| keep.iter().map(|&i| v[i]).collect()),
    };
    Ok((Cow::Owned(filtered), (n - keep.len()) as u64, scans))
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, Vec3};

    use super::*;
    use crate::{Scanner, Scanners};

    #[test]
    fn dropped_points_take_their_scans_with_them() {
        let cloud = PointCloud {
            origin: DVec3::ZERO,
            positions: vec![Vec3::ZERO, Vec3::NAN, Vec3::X, Vec3::Y, Vec3::ONE],
            colours: None,
            normals: None,
        };
        let up = Scanner::Far(DVec3::Z);
        let scanners = Scanners {
            runs: vec![(up, 2), (up, 2), (up, 1)],
        };
        let scans = PointScans::of(&scanners, cloud.len()).unwrap();
        let (kept, dropped, scans) = keep_finite(Cow::Borrowed(&cloud), Some(scans)).unwrap();
        assert_eq!((kept.len(), dropped), (4, 1));
        let scans = scans.unwrap();
        let each: Vec<usize> = (0..4).map(|i| scans.scan(i)).collect();
        assert_eq!(each, [0, 1, 1, 2]);
        let bounds = check_extent(&kept, dropped).unwrap();
        assert_eq!(bounds.max, Vec3::ONE);
    }
}
