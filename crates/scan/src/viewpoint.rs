//! Where a structured scan's scanner was, and the sight line from each point toward it.
//!
//! A scan that comes as a range grid (a PLY `range_grid` element, an E57 scan with row and
//! column indices) was taken from one place: every point was seen from the scanner's side
//! of the surface. The reader records that place in the scan's own frame
//! ([`Viewpoint`]); [`merge_scans`](crate::merge_scans) moves it by the scan's pose into the
//! common frame ([`ScanSummary::viewpoint`](crate::ScanSummary::viewpoint)), and each
//! point's unit *sight line* (from the point toward its scanner,
//! [`LoadedScans::sight_line`](crate::LoadedScans::sight_line)) follows from the point's
//! scan. `spatch-cloud` uses it to give each point's estimated normal its sign
//! (`CloudOptions::scanners`), computing it where it is needed rather than storing a vector
//! per point (12 bytes a point at the memory peak of scan sets; the scan of a point is one
//! byte or two).
//!
//! Where the scanner is:
//! - Stanford raw range scans (PLY with `range_grid`): far along the scan's own +z axis
//!   (the scanner looks down −z). Worked out from the data: of the points of `bun000`
//!   (whose frame is that of the reconstruction `bun_zipper`) that have reconstruction
//!   surface both above and below them (2 mm bins of `x, y`, layers over 1 cm apart),
//!   36,442 lie on the upper (+z) layer and none on the lower one. The grid agrees: its
//!   columns step along +x (0.5 mm) and its rows along +y, so the image is the scan's `x y`
//!   plane seen along z.
//! - E57 structured scans: at the scan's origin (E57's local frame is the scanner's).
//!
//! Why sight lines and not normals from the grid: normals from grid neighbours (rows and
//! columns two cells either side, depth jumps skipped, oriented toward the scanner) were
//! measured on the ten bunny scans (`bun.conf`) as normals (specks 0.52 %, 0.42 % with the
//! signs used) and as the sign of the PCA normals (0.33 %); the sight line alone as that
//! sign gave 0.30 % (docs/algorithms/cloud.md, "Range grids"). A grid normal is a plane
//! over 5 × 5 noisy samples of one scan; the PCA plane pools every scan.
//!
//! Cost: none here; one viewpoint a scan.

use glam::DVec3;

use crate::Pose;

/// Where a scan's scanner was, in the scan's own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Viewpoint {
    /// Far away along this direction (a line or orthographic scanner: every point is seen
    /// from the same side).
    Direction(DVec3),
    /// At this position (a terrestrial scanner at the centre of its spherical scan).
    Position(DVec3),
}

impl Viewpoint {
    /// The unit direction from `p` (in the scan's frame) toward the scanner; zero when `p`
    /// is the scanner's position.
    pub fn toward(self, p: DVec3) -> DVec3 {
        match self {
            Viewpoint::Direction(d) => d.normalize_or_zero(),
            Viewpoint::Position(o) => (o - p).normalize_or_zero(),
        }
    }

    /// The viewpoint moved by `pose` (a scan's frame into the common frame): a direction
    /// is made unit, then turned; a position is moved.
    pub fn posed(self, pose: &Pose) -> Viewpoint {
        match self {
            Viewpoint::Direction(d) => {
                Viewpoint::Direction(pose.apply_vector(d.normalize_or_zero()))
            }
            Viewpoint::Position(o) => Viewpoint::Position(pose.apply_point(o)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sight_lines_point_at_the_scanner() {
        let far = Viewpoint::Direction(DVec3::new(0.0, 0.0, 2.0));
        assert_eq!(far.toward(DVec3::new(5.0, -3.0, 1.0)), DVec3::Z);
        let near = Viewpoint::Position(DVec3::new(1.0, 0.0, 0.0));
        assert_eq!(near.toward(DVec3::new(1.0, 0.0, -4.0)), DVec3::Z);
        assert_eq!(near.toward(DVec3::new(1.0, 0.0, 0.0)), DVec3::ZERO);
    }

    #[test]
    fn posed_viewpoints_turn_and_move_with_their_scan() {
        let quarter = glam::DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
        let pose = Pose::new(quarter, DVec3::new(10.0, 0.0, 0.0)).unwrap();
        // A direction is made unit and turned, not moved: +x turns to +y.
        let Viewpoint::Direction(d) = Viewpoint::Direction(DVec3::new(3.0, 0.0, 0.0)).posed(&pose)
        else {
            panic!("a direction stays a direction");
        };
        assert!((d - DVec3::Y).length() < 1e-12, "{d}");
        // A position is turned and moved: (1, 0, 0) to (10, 1, 0).
        let Viewpoint::Position(o) = Viewpoint::Position(DVec3::X).posed(&pose) else {
            panic!("a position stays a position");
        };
        assert!((o - DVec3::new(10.0, 1.0, 0.0)).length() < 1e-12, "{o}");
        // Each point's sight line in the common frame is its scan-frame line turned.
        let p = DVec3::new(1.0, 0.0, -4.0);
        let turned = pose.apply_vector(Viewpoint::Position(DVec3::X).toward(p));
        let posed = Viewpoint::Position(DVec3::X)
            .posed(&pose)
            .toward(pose.apply_point(p));
        assert!((turned - posed).length() < 1e-12);
    }
}
