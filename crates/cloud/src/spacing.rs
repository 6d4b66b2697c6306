//! The kd-tree over the cloud and the point spacing estimated from k nearest neighbours.
//!
//! Input: point positions. Output: a [`PointTree`] (a `kiddo` immutable kd-tree over the
//! positions, items are [`PointId`]s) and a [`SpacingEstimate`].
//!
//! The spacing `s` is the side of the square of surface each point "owns": for a surface
//! sampled with density `ρ` points per unit area, `s = 1/√ρ`. Around a sample point the
//! `k` nearest neighbours fill a disc of radius `r_k`, so `ρ ≈ k / (π r_k²)` and
//! `s ≈ r_k · √(π/k)`. With `k = 12` this gives the grid step on a regular grid (the 12th
//! neighbour of a grid point is at 2 steps: `2·√(π/12) = 1.02`) and is unbiased on uniform
//! random samples (`E[r_k²] = k/(πρ)`). The estimate is the median over up to
//! [`SPACING_SAMPLES`] points taken at a regular stride, so a few outliers or dense clumps do
//! not move it. The mean distance to the nearest other point is reported too (on random
//! samples it is about `s/2`). The neighbours come from a grid of cells
//! (`neighbour_grid.rs`), whose distances equal the kd-tree's to the bit; the kd-tree stays
//! for the other callers (coverage and error measurements).
//!
//! Clouds larger than [`SPACING_SUBSET`] points are thinned first: each point is kept with
//! probability `f = SPACING_SUBSET / n` (a seeded generator, so deterministic), the spacing
//! of the thinned cloud is measured, and scaled by `√f` (thinning a surface sample by `f`
//! divides its density by `f`). This keeps the search small (a tree over 1M points cost
//! more than the rest of the estimate) at the price of treating the thinned set as a uniform
//! sample, which slightly raises the estimate for scans on a regular grid (their 12th
//! neighbour is nearer than a random sample's).
//!
//! Invariants: deterministic (seeded thinning, fixed stride, exact neighbour distances).
//!
//! Cost: the grid's sort of `m ≤ 200,000` points; about 27 cells of points for each of
//! `s ≤ 20,000` sample queries.
//!
//! Based on: J. L. Bentley, "Multidimensional binary search trees used for associative
//! searching", CACM 18(9), 1975 (the kd-tree; the `kiddo` crate implements it).

use std::num::NonZeroUsize;

use glam::Vec3;
use kiddo::{ImmutableKdTree, SquaredEuclidean};
use rayon::prelude::*;

use crate::neighbour_grid::NeighbourGrid;
use crate::{CloudError, PointId};

/// Points sampled for the spacing estimate.
pub const SPACING_SAMPLES: usize = 20_000;

/// Largest number of points the spacing is measured on (larger clouds are thinned).
pub const SPACING_SUBSET: usize = 200_000;

/// Neighbours (excluding the point itself) whose disc gives the local density.
pub const SPACING_NEIGHBOURS: usize = 12;

/// A kd-tree over point positions.
pub struct PointTree {
    tree: ImmutableKdTree<f32, 3>,
    len: usize,
}

impl std::fmt::Debug for PointTree {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PointTree").field("len", &self.len).finish()
    }
}

impl PointTree {
    /// Builds the tree. Fails with [`CloudError::EmptyCloud`] on no points and
    /// [`CloudError::TooManyPoints`] beyond `u32` ids.
    pub fn build(positions: &[Vec3]) -> Result<PointTree, CloudError> {
        if positions.is_empty() {
            return Err(CloudError::EmptyCloud {
                dropped_non_finite: 0,
            });
        }
        let max = u32::MAX as usize - 1;
        if positions.len() > max {
            return Err(CloudError::TooManyPoints {
                points: positions.len(),
                max,
            });
        }
        let coords: Vec<[f32; 3]> = positions.iter().map(|p| p.to_array()).collect();
        let tree = ImmutableKdTree::new_from_slice(&coords).map_err(|_| CloudError::NoExtent {
            points: positions.len(),
            extent: 0.0,
        })?;
        Ok(PointTree {
            tree,
            len: positions.len(),
        })
    }

    /// Number of points in the tree.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether the tree is empty (never, once built).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The `k` nearest points to `query` as `(squared distance, id)`, nearest first, written
    /// into `out` (cleared first). Fewer when the tree holds fewer points.
    pub fn nearest_k(&self, query: Vec3, k: usize, out: &mut Vec<(f32, PointId)>) {
        out.clear();
        let Some(k) = NonZeroUsize::new(k.min(self.len)) else {
            return;
        };
        let found = self
            .tree
            .query(&query.to_array())
            .nearest_n::<SquaredEuclidean<f32>>(k)
            .execute();
        out.extend(found.iter().map(|r| (r.distance, PointId(r.item))));
    }

    /// Every point within `sqrt(radius2)` of `query` as `(squared distance, id)`, nearest
    /// first, written into `out` (cleared first).
    pub fn within(&self, query: Vec3, radius2: f32, out: &mut Vec<(f32, PointId)>) {
        out.clear();
        let found = self
            .tree
            .query(&query.to_array())
            .within::<SquaredEuclidean<f32>>(radius2)
            .execute();
        out.extend(found.iter().map(|r| (r.distance, PointId(r.item))));
    }

    /// The nearest point to `query` as `(squared distance, id)`.
    pub fn nearest(&self, query: Vec3) -> (f32, PointId) {
        let r = self
            .tree
            .query(&query.to_array())
            .nearest_one::<SquaredEuclidean<f32>>()
            .execute();
        (r.distance, PointId(r.item))
    }
}

/// The spacing of a cloud (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpacingEstimate {
    /// `s = 1/√ρ`, the median over the samples (model units).
    pub spacing: f32,
    /// Mean distance from a sample to its nearest other point (model units).
    pub mean_nearest: f32,
    /// Points sampled.
    pub samples: usize,
}

/// Estimates the spacing of `positions` (see the module documentation).
///
/// Fails with [`CloudError::TooFewPoints`] below 3 points and [`CloudError::NoExtent`] when
/// the estimate is zero (more than half of the points are duplicates of their neighbours).
pub fn estimate_spacing(positions: &[Vec3]) -> Result<SpacingEstimate, CloudError> {
    if positions.len() > SPACING_SUBSET {
        let keep = SPACING_SUBSET as f64 / positions.len() as f64;
        let mut rng = spatch_mesh::SplitMix64::new(0x5EED_5BAC);
        let thinned: Vec<Vec3> = positions
            .iter()
            .copied()
            .filter(|_| rng.next_f64() < keep)
            .collect();
        let scale = (thinned.len() as f64 / positions.len() as f64).sqrt() as f32;
        let estimate = estimate_spacing_of(&thinned)?;
        return Ok(SpacingEstimate {
            spacing: estimate.spacing * scale,
            mean_nearest: estimate.mean_nearest * scale,
            samples: estimate.samples,
        });
    }
    estimate_spacing_of(positions)
}

/// The spacing of `positions`, unthinned. The neighbours come from a grid of cells
/// (`neighbour_grid.rs`), whose distances are the kd-tree's to the bit; building the kd-tree
/// was sequential and cost more than the queries.
fn estimate_spacing_of(positions: &[Vec3]) -> Result<SpacingEstimate, CloudError> {
    if positions.is_empty() {
        return Err(CloudError::EmptyCloud {
            dropped_non_finite: 0,
        });
    }
    let n = positions.len();
    if n < 3 {
        return Err(CloudError::TooFewPoints {
            found: n,
            needed: 3,
        });
    }
    if n > u32::MAX as usize - 1 {
        return Err(CloudError::TooManyPoints {
            points: n,
            max: u32::MAX as usize - 1,
        });
    }
    let k = SPACING_NEIGHBOURS.min(n - 1);
    let grid = NeighbourGrid::new(positions, k + 1);
    let scale = (std::f32::consts::PI / k as f32).sqrt();
    let stride = n.div_ceil(SPACING_SAMPLES).max(1);
    // Per sample: (spacing from the k-th neighbour, nearest other point); the queries are
    // independent and collected in order, so the sums below do not depend on the threads.
    let found: Vec<(f32, f32)> = positions
        .par_iter()
        .step_by(stride)
        .map_init(
            || Vec::with_capacity(k + 1),
            |neighbours, p| {
                grid.nearest_k(*p, k + 1, neighbours);
                // The first result is the point itself (distance 0) or a duplicate of it.
                let kth = neighbours.last().map_or(0.0, |d: &f32| d.sqrt());
                (kth * scale, neighbours.get(1).map_or(0.0, |d| d.sqrt()))
            },
        )
        .collect();
    let mut local: Vec<f32> = found.iter().map(|f| f.0).collect();
    let nearest_sum: f64 = found.iter().map(|f| f64::from(f.1)).sum();
    let samples = local.len();
    let mid = samples / 2;
    let (_, median, _) = local.select_nth_unstable_by(mid, f32::total_cmp);
    let spacing = *median;
    if !(spacing.is_finite() && spacing > 0.0) {
        let extent = spatch_mesh::Aabb::from_points(positions.iter().copied())
            .size()
            .max_element();
        return Err(CloudError::NoExtent { points: n, extent });
    }
    Ok(SpacingEstimate {
        spacing,
        mean_nearest: (nearest_sum / samples as f64) as f32,
        samples,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacing_of_a_regular_grid_is_its_step() {
        let step = 0.25f32;
        let positions: Vec<Vec3> = (0..100 * 100)
            .map(|k| Vec3::new((k % 100) as f32 * step, (k / 100) as f32 * step, 3.0))
            .collect();
        let estimate = estimate_spacing(&positions).unwrap();
        assert!((estimate.spacing / step - 1.0).abs() < 0.05, "{estimate:?}");
        assert!(
            (estimate.mean_nearest / step - 1.0).abs() < 1e-4,
            "{estimate:?}"
        );
    }

    #[test]
    fn nearest_queries_agree_with_brute_force() {
        let positions: Vec<Vec3> = (0..500)
            .map(|k| {
                let t = k as f32;
                Vec3::new((t * 0.37).sin(), (t * 0.71).cos(), (t * 0.13).sin())
            })
            .collect();
        let tree = PointTree::build(&positions).unwrap();
        let q = Vec3::new(0.1, -0.2, 0.3);
        let brute = positions
            .iter()
            .map(|p| p.distance_squared(q))
            .fold(f32::INFINITY, f32::min);
        assert_eq!(tree.nearest(q).0, brute);
        let mut out = Vec::new();
        tree.nearest_k(q, 5, &mut out);
        assert_eq!(out.len(), 5);
        assert_eq!(out[0].0, brute);
        assert!(out.windows(2).all(|w| w[0].0 <= w[1].0));
    }
}
