//! Normal cones of blocks of consecutive points: which blocks no point of a view can be
//! drawn from, so the range images skip them.
//!
//! Input: unit normals (zero where unknown) in the pipeline's spatial (Morton) order.
//! Output: per block of [`CONE_BLOCK`] consecutive points, a centre `c` (the mean normal)
//! and a radius `r = max |n − c|` over the block's normals; and, per view, the runs of
//! blocks that may hold a drawn point.
//!
//! Method: for every normal `n` of a block and unit view direction `d`,
//! `n · d = c · d + (n − c) · d ≤ c · d + r` (Cauchy–Schwarz), and likewise
//! `|n · d| ≤ |c · d| + r`. A range image draws a point only when `n · d` (oriented normals)
//! or `|n · d|` (unoriented) reaches [`MIN_POINT_COSINE`]; a block whose bound stays below it
//! by [`CONE_MARGIN`] (far more than the rounding of either side) holds no drawn point and is
//! skipped in both passes of the z-buffer. A block with an unknown (zero) normal is never
//! skipped: such points are drawn in every view. Skipping only drops points the projection
//! would mark as not drawn, so the images are exactly the same.
//!
//! Cost: one pass over the normals (in parallel), 16 bytes per block (0.125 bytes a point);
//! per view, one dot product per block. With oriented normals (scan sets) about half of
//! each view's points face away from it, most of them in whole blocks, since neighbours in
//! Morton order lie on the same patch of surface.

use std::ops::Range;

use glam::Vec3;
use rayon::prelude::*;

use crate::range_image::MIN_POINT_COSINE;

/// Consecutive points in one cone: small enough that a block's normals stay close on
/// curved surfaces, large enough that the projection loop runs over long slices.
pub(crate) const CONE_BLOCK: usize = 32;

/// How far (in cosine) a block's bound must stay below [`MIN_POINT_COSINE`] to be skipped:
/// the bound and the projection's `n · d` each round by under `1e-6`.
const CONE_MARGIN: f32 = 1e-4;

/// The normal cones of the blocks of a point list (see the module documentation).
#[derive(Clone, Debug, Default)]
pub(crate) struct NormalCones {
    /// Mean normal of each block.
    centre: Vec<Vec3>,
    /// Largest distance of a block's normals from its centre; infinite when the block has
    /// an unknown normal.
    radius: Vec<f32>,
}

impl NormalCones {
    /// The cones of `normals`, [`CONE_BLOCK`] points at a time.
    pub(crate) fn new(normals: &[Vec3]) -> NormalCones {
        let (centre, radius) = normals.par_chunks(CONE_BLOCK).map(block_cone).unzip();
        NormalCones { centre, radius }
    }

    /// The point ranges of the blocks that may hold a point drawn in the view along
    /// `direction` (`oriented`: normals face their scanner), consecutive blocks merged, in
    /// order; `points` is the number of points.
    pub(crate) fn drawn_runs(
        &self,
        direction: Vec3,
        oriented: bool,
        points: usize,
    ) -> Vec<Range<usize>> {
        let mut runs: Vec<Range<usize>> = Vec::new();
        for (b, (&c, &r)) in self.centre.iter().zip(&self.radius).enumerate() {
            let along = c.dot(direction);
            let reach = if oriented { along } else { along.abs() } + r;
            if reach < MIN_POINT_COSINE - CONE_MARGIN {
                continue;
            }
            let block = b * CONE_BLOCK..((b + 1) * CONE_BLOCK).min(points);
            match runs.last_mut() {
                Some(last) if last.end == block.start => last.end = block.end,
                _ => runs.push(block),
            }
        }
        runs
    }
}

/// The centre and radius of one block's normals.
fn block_cone(normals: &[Vec3]) -> (Vec3, f32) {
    if normals.contains(&Vec3::ZERO) {
        return (Vec3::ZERO, f32::INFINITY);
    }
    let centre = normals.iter().sum::<Vec3>() / normals.len() as f32;
    let radius = normals
        .iter()
        .map(|&n| n.distance(centre))
        .fold(0.0, f32::max);
    (centre, radius)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_block_is_skipped_only_when_every_normal_faces_away() {
        // Block 0 faces −z, block 1 +z, block 2 −z but for one normal facing +z.
        let mut normals = vec![-Vec3::Z; 3 * CONE_BLOCK];
        normals[CONE_BLOCK..2 * CONE_BLOCK].fill(Vec3::Z);
        normals[2 * CONE_BLOCK + 5] = Vec3::Z;
        let cones = NormalCones::new(&normals);
        let runs = cones.drawn_runs(Vec3::Z, true, normals.len());
        assert_eq!(runs, vec![CONE_BLOCK..3 * CONE_BLOCK]);
        // Unoriented, every block is seen from +z.
        assert_eq!(
            cones.drawn_runs(Vec3::Z, false, normals.len()),
            vec![0..3 * CONE_BLOCK]
        );
        // Seen edge-on, no normal reaches the cosine, but the cone of the mixed block is
        // too wide to tell.
        assert_eq!(
            cones.drawn_runs(Vec3::X, false, normals.len()),
            vec![2 * CONE_BLOCK..3 * CONE_BLOCK]
        );
    }

    #[test]
    fn unknown_normals_keep_their_block_and_the_last_block_is_short() {
        let mut normals = vec![-Vec3::Z; CONE_BLOCK + 7];
        normals[CONE_BLOCK + 3] = Vec3::ZERO;
        let runs = NormalCones::new(&normals).drawn_runs(Vec3::Z, true, normals.len());
        assert_eq!(runs, vec![CONE_BLOCK..CONE_BLOCK + 7]);
    }

    #[test]
    fn the_bound_holds_for_spread_normals() {
        // Normals spread over a cone around a tilted axis: every normal the projection
        // would draw lies in a run.
        let axis = Vec3::new(0.3, -0.5, 0.8).normalize();
        let normals: Vec<Vec3> = (0..40 * CONE_BLOCK)
            .map(|k| {
                let t = k as f32 * 0.37;
                (axis + 0.6 * Vec3::new(t.cos(), t.sin(), (t * 1.7).sin())).normalize()
            })
            .collect();
        let cones = NormalCones::new(&normals);
        for view in crate::directions::view_directions(40) {
            let d = view.direction;
            for oriented in [false, true] {
                let runs = cones.drawn_runs(d, oriented, normals.len());
                for (i, n) in normals.iter().enumerate() {
                    let cosine = if oriented { n.dot(d) } else { n.dot(d).abs() };
                    if cosine >= MIN_POINT_COSINE {
                        assert!(runs.iter().any(|r| r.contains(&i)), "point {i} dropped");
                    }
                }
            }
        }
    }
}
