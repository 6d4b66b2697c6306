//! Where the scanners of a scan set were, and which scan saw each point: the sight lines that
//! turn each point's estimated normal to its scanner's side.
//!
//! Input: [`Scanners`], one [`Scanner`] per scan with the run of consecutive cloud points it
//! saw (scans are merged in order, so a scan's points are one run). Output: per point, its
//! scan (`PointScans`, one byte a point for up to 256 scans, two up to 65,536), filtered and
//! sorted with the cloud, and its *sight line* (the unit vector toward its scanner) computed
//! where it is used.
//!
//! Why not a sight line stored per point: that was 12 bytes a point alive in the normals
//! stage, the memory peak of structured scan sets (115 against 98 bytes a point on 1 M
//! synthetic range-scan points). The line is one subtraction and a normalisation away from
//! the scanner's place.
//!
//! Invariants: a far scanner's line is its direction as given, for every point; a scanner at
//! a position gives `(at − p) / |at − p|`, zero at the position itself.
//!
//! Cost: O(points) bytes for the scan of each point, O(scans) for the scanners.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::CloudError;

/// Where one scan's scanner was, in the cloud's common frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scanner {
    /// Far away along this unit direction (from the points toward the scanner): a line or
    /// orthographic scanner, every point seen from the same side.
    Far(DVec3),
    /// At this world position (the cloud's `origin` plus a position): a terrestrial scanner
    /// at the centre of its spherical scan.
    At(DVec3),
}

impl Scanner {
    /// The unit direction from the point at `origin + p` toward the scanner (zero at the
    /// scanner's own position).
    pub fn sight_line(self, origin: DVec3, p: Vec3) -> Vec3 {
        match self {
            Scanner::Far(d) => d.as_vec3(),
            Scanner::At(at) => (at - (origin + p.as_dvec3())).normalize_or_zero().as_vec3(),
        }
    }
}

/// The scanners of a cloud merged from scans: see the module documentation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scanners {
    /// One entry per scan in the cloud's point order: its scanner and how many consecutive
    /// points of the cloud it saw (the first scan's points first). The counts add up to the
    /// cloud's point count.
    pub runs: Vec<(Scanner, usize)>,
}

/// Largest number of scans [`Scanners`] may hold (a two-byte scan index per point).
pub const MAX_SCANS: usize = 1 << 16;

/// The scan of every point, one or two bytes a point.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PointScans {
    /// Up to 256 scans.
    Narrow(Vec<u8>),
    /// Up to [`MAX_SCANS`] scans.
    Wide(Vec<u16>),
}

impl PointScans {
    /// The scan of each of `points` points, from the runs of `scanners`; an error when the
    /// runs do not add up to `points` or there are more than [`MAX_SCANS`] scans.
    pub(crate) fn of(scanners: &Scanners, points: usize) -> Result<PointScans, CloudError> {
        let found: usize = scanners.runs.iter().map(|r| r.1).sum();
        if found != points {
            return Err(CloudError::MismatchedAttribute {
                what: "scanner runs",
                found,
                expected: points,
            });
        }
        let runs = scanners.runs.iter().enumerate();
        if scanners.runs.len() <= 256 {
            let each = runs.flat_map(|(s, r)| std::iter::repeat_n(s as u8, r.1));
            Ok(PointScans::Narrow(each.collect()))
        } else if scanners.runs.len() <= MAX_SCANS {
            let each = runs.flat_map(|(s, r)| std::iter::repeat_n(s as u16, r.1));
            Ok(PointScans::Wide(each.collect()))
        } else {
            Err(CloudError::InvalidOption {
                option: "scanners",
                reason: "more than 65,536 scans",
            })
        }
    }

    /// The scan of point `i`.
    #[inline]
    pub(crate) fn scan(&self, i: usize) -> usize {
        match self {
            PointScans::Narrow(s) => usize::from(s[i]),
            PointScans::Wide(s) => usize::from(s[i]),
        }
    }

    /// The entries at `indices`, in their order (a filter, or a sort's permutation).
    pub(crate) fn pick(&self, indices: impl IndexedParallelIterator<Item = usize>) -> PointScans {
        match self {
            PointScans::Narrow(s) => PointScans::Narrow(indices.map(|i| s[i]).collect()),
            PointScans::Wide(s) => PointScans::Wide(indices.map(|i| s[i]).collect()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_give_each_point_its_scan() {
        let up = Scanner::Far(DVec3::Z);
        let scanners = Scanners {
            runs: vec![(up, 2), (up, 0), (up, 3)],
        };
        let scans = PointScans::of(&scanners, 5).unwrap();
        let each: Vec<usize> = (0..5).map(|i| scans.scan(i)).collect();
        assert_eq!(each, [0, 0, 2, 2, 2]);
        let picked = scans.pick([4usize, 0, 2].into_par_iter());
        assert_eq!(picked, PointScans::Narrow(vec![2, 0, 2]));
        assert!(matches!(
            PointScans::of(&scanners, 6),
            Err(CloudError::MismatchedAttribute { found: 5, .. })
        ));
        // Past 256 scans the index takes two bytes.
        let many = Scanners {
            runs: vec![(up, 1); 300],
        };
        let scans = PointScans::of(&many, 300).unwrap();
        assert!(matches!(scans, PointScans::Wide(_)));
        assert_eq!(scans.scan(299), 299);
    }

    #[test]
    fn sight_lines_point_at_the_scanner() {
        let origin = DVec3::new(100.0, 0.0, 0.0);
        let far = Scanner::Far(DVec3::new(0.0, 0.6, 0.8));
        assert_eq!(far.sight_line(origin, Vec3::ONE), Vec3::new(0.0, 0.6, 0.8));
        let at = Scanner::At(DVec3::new(100.0, 0.0, 5.0));
        let line = at.sight_line(origin, Vec3::new(0.0, 0.0, 1.0));
        assert!((line - Vec3::Z).length() < 1e-6, "{line}");
        assert_eq!(at.sight_line(origin, Vec3::new(0.0, 0.0, 5.0)), Vec3::ZERO);
    }
}
