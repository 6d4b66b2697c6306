//! One surface from overlapping scans: every point is moved onto the least-squares plane of
//! its voxel block before the range images are drawn.
//!
//! Input: positions, the block planes of `normals.rs` (voxels of `normal_voxel · s`, blocks
//! of 3×3×3 voxels, about 20–40 points on a surface) and limits in spacings. Output: the
//! positions moved in place and how many points moved.
//!
//! Why: registered scans of one surface are offset from each other by a fraction of the
//! spacing (registration error, scanner noise). Each range image averages whichever scans
//! fall in a pixel, so two views reconstruct two slightly different surfaces; where their
//! patches overlap they z-fight, and the shading of the noisy depth shows as dark specks.
//! Moving every point onto its block's plane collapses the offset layers into one surface
//! before any view sees them, so every view reconstructs the same one.
//!
//! A point is left where it is when its block has no unique plane, too few points, a spread
//! (RMS distance from the plane) above `max_spread` (the block straddles a crease, a corner
//! or both sides of a thin part, where a plane is no consensus), or when the point lies
//! farther than `max_move` from the plane (another layer or an outlier).
//!
//! Invariants: deterministic (a pure per-point map); a point moves along its block's normal
//! only, by at most `max_move`.
//!
//! Cost: one O(n) parallel pass, in place.
//!
//! Based on: the projection step of moving least squares (M. Alexa et al., "Point set
//! surfaces", IEEE Visualization 2001), with a single plane per voxel block instead of a
//! weighted fit per point.

use glam::Vec3;
use rayon::prelude::*;

use crate::normals::VoxelPlanes;
use crate::CloudOptions;

/// Fewest points in a block for its plane to move points.
pub const CONSENSUS_MIN_POINTS: u32 = 8;

/// Fewest points seen from each side of a block's plane for the block to hold both sides of
/// a thin part (when the points' scanners are known): its points are left out of the scan
/// alignment.
pub const TWO_SIDED_MIN_POINTS: u32 = 4;

/// Limits of the consensus projection, in the positions' unit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConsensusLimits {
    /// Largest RMS distance of a block's points from its plane.
    pub(crate) max_spread: f32,
    /// Largest distance a point moves.
    pub(crate) max_move: f32,
}

impl ConsensusLimits {
    /// The limits for points of spacing `spacing` ([`CloudOptions::CONSENSUS_MAX_SPREAD`] and
    /// [`CloudOptions::CONSENSUS_MAX_MOVE`] spacings).
    pub(crate) fn at_spacing(spacing: f32) -> ConsensusLimits {
        ConsensusLimits {
            max_spread: CloudOptions::CONSENSUS_MAX_SPREAD * spacing,
            max_move: CloudOptions::CONSENSUS_MAX_MOVE * spacing,
        }
    }
}

/// Moves `positions` onto their block planes in place, and gives how many moved (see the
/// module docs). In place: a moved copy beside the sorted positions was the memory peak of
/// scan sets (12 bytes a point, plus 16 while it was collected).
pub(crate) fn project_to_consensus(
    positions: &mut [Vec3],
    planes: &VoxelPlanes,
    limits: ConsensusLimits,
) -> usize {
    positions
        .par_iter_mut()
        .enumerate()
        .map(|(i, p)| {
            let plane = planes.of_point(i);
            if plane.count < CONSENSUS_MIN_POINTS
                || plane.normal == Vec3::ZERO
                || plane.spread > limits.max_spread
            {
                return 0;
            }
            let n = plane.normal.as_dvec3();
            let d = (p.as_dvec3() - planes.origin - plane.centre).dot(n);
            if d.abs() > f64::from(limits.max_move) {
                return 0;
            }
            *p = (p.as_dvec3() - d * n).as_vec3();
            1
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normals::estimate_planes;

    /// Two copies of a grid on the plane z = 0, offset by ±0.2 spacings along z: both land on
    /// one plane.
    #[test]
    fn offset_layers_of_one_plane_collapse_onto_it() {
        let mut points = Vec::new();
        for layer in [-0.2f32, 0.2] {
            for k in 0..1600 {
                let (x, y) = ((k % 40) as f32, (k / 40) as f32);
                points.push(Vec3::new(x + 0.5 * layer, y, layer));
            }
        }
        let planes = estimate_planes(&points, 1.5);
        let limits = ConsensusLimits {
            max_spread: 1.0,
            max_move: 2.0,
        };
        let mut moved = points.clone();
        let count = project_to_consensus(&mut moved, &planes, limits);
        assert_eq!(count, points.len());
        // Away from the grid's border, where the shifted layers' extents differ.
        let interior = |p: &Vec3| (3.0..36.0).contains(&p.x) && (3.0..36.0).contains(&p.y);
        for p in moved.iter().filter(|p| interior(p)) {
            assert!(p.z.abs() < 0.02, "{p}");
        }
    }

    /// Both sides of a sheet thinner than a block: the plane's spread (1) exceeds the limit
    /// (0.5), the sides are not merged.
    #[test]
    fn both_sides_of_a_thin_sheet_stay_apart() {
        let mut points = Vec::new();
        for side in [-1.0f32, 1.0] {
            for k in 0..1600 {
                points.push(Vec3::new((k % 40) as f32, (k / 40) as f32, side));
            }
        }
        let planes = estimate_planes(&points, 1.5);
        let limits = ConsensusLimits {
            max_spread: 0.5,
            max_move: 2.0,
        };
        let mut moved = points.clone();
        project_to_consensus(&mut moved, &planes, limits);
        // (At the sheet's corners a block is narrower than thick and may slide points
        // sideways; no point leaves its side.)
        for (p, q) in points.iter().zip(&moved) {
            assert_eq!(p.z, q.z, "{p} moved to {q}");
        }
    }
}
