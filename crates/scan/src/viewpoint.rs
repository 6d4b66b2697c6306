//! Where a structured scan's scanner was, and the sight line from each point toward it.
//!
//! A scan that comes as a range grid (a PLY `range_grid` element, an E57 scan with row and
//! column indices) was taken from one place: every point was seen from the scanner's side
//! of the surface. The reader records that place in the scan's own frame
//! ([`Viewpoint`]); after the scan's pose, [`merge_scans`](crate::merge_scans) turns it into
//! one unit *sight line* per point (from the point toward the scanner), which
//! `spatch-cloud` uses to give each point's estimated normal its sign
//! (`CloudOptions::sight_lines`).
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
//! Cost: none here; one vector a point when merged.

use glam::DVec3;

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
}
