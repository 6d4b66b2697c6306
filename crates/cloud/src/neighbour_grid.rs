//! Exact distances to the k nearest points, on a uniform grid of cubic cells: what the
//! spacing estimate asks of a few thousand sample points.
//!
//! Input: positions (any order) and, per query, a point and `k`. Output: the squared
//! distances to the `k` nearest positions, nearest first, exactly the values a kd-tree gives
//! (each computed as `(dx² + dy²) + dz²` in f32, as `kiddo`'s squared Euclidean metric sums
//! them), so the spacing does not change with the search structure.
//!
//! Method: the points are sorted by cell (a counting sort over the cells' `(x, y)` columns,
//! `bucket_sort.rs`); a query visits the cube of cells within one cell of its own, then
//! within two, and so on, and stops once the `k`-th distance found is within the distance
//! from the query to the cube's faces (less a margin for the rounding of the cells' bounds),
//! or the cube covers the grid; beyond [`MAX_RADIUS`] (an isolated point) it takes every
//! point. The cell side is 1.5 times the median distance to the `k`-th nearest point,
//! measured by brute force on a small subset ([`cell_side`]), so the first 27 cells usually
//! hold the answer. (The kd-tree over the 200,000 thinned points it replaces was built
//! sequentially: 0.15 G of the evenly spread 1 M scan set's 0.99 G sequential instructions.)
//!
//! Invariants: the distances do not depend on the cell side, only the time does; at most
//! 2²¹ cells a side.
//!
//! Cost: 64 × 4,096 distances for the cell side; one sort of the points (parallel keys, a
//! sequential counting pass), 12 bytes a point and 12 a non-empty cell; per query, a binary
//! search per column of cells visited and one distance per point in the visited cells.
//!
//! Based on: J. L. Bentley, B. W. Weide, A. C. Yao, "Optimal expected-time algorithms for
//! closest point problems", ACM TOMS 6(4), 1980 (cell techniques).

use glam::Vec3;
use rayon::prelude::*;

use crate::bucket_sort::column_sorted_keys;

/// Bits of a cell coordinate (cells per side at most `2^CELL_BITS`).
const CELL_BITS: u32 = 21;

/// Points sorted by their cubic cell, for k-nearest queries (see the module documentation).
pub(crate) struct NeighbourGrid {
    /// Corner of the grid.
    lo: Vec3,
    /// Cell side.
    cell: f32,
    /// Cells per side on each axis.
    dims: [i64; 3],
    /// Bits of the `y` and `z` fields of a key.
    y_bits: u32,
    z_bits: u32,
    /// Keys `x << (Y + Z) | y << Z | z` of the non-empty cells (`Y`, `Z`: the widths of the
    /// `y` and `z` fields, just wide enough for the grid), increasing.
    keys: Vec<u64>,
    /// Index in `points` of each non-empty cell's first point, plus the point count.
    starts: Vec<u32>,
    /// The points, by cell.
    points: Vec<Vec3>,
    /// Absolute slack in the stopping test, for the rounding of points near cell faces.
    margin: f32,
}

impl NeighbourGrid {
    /// The grid of `positions` (non-empty, finite), with cells of about the distance to the
    /// `k`-th nearest point ([`cell_side`]).
    pub(crate) fn new(positions: &[Vec3], k: usize) -> NeighbourGrid {
        let (lo, hi) = positions.iter().fold(
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        // Never more than 2^CELL_BITS cells a side, never a zero cell.
        let finest = (hi - lo).max_element() / (1u32 << (CELL_BITS - 1)) as f32;
        let cell = cell_side(positions, k).max(finest).max(f32::MIN_POSITIVE);
        let inv = 1.0 / cell;
        let max = ((1u64 << CELL_BITS) - 1) as f32;
        let coordinates = |p: Vec3| ((p - lo) * inv).min(Vec3::splat(max)).as_uvec3();
        let top = coordinates(hi);
        let dims = [top.x, top.y, top.z].map(|c| i64::from(c) + 1);
        let [_, y_bits, z_bits] =
            [top.x, top.y, top.z].map(|c| (u32::BITS - c.leading_zeros()).max(1));
        let cell_of = |p: Vec3| {
            let c = coordinates(p);
            [c.x, c.y, c.z].map(u64::from)
        };
        let pairs = column_sorted_keys(positions, cell_of, (y_bits, z_bits));
        let mut keys = Vec::new();
        let mut starts = Vec::new();
        for (j, &(k, _)) in pairs.iter().enumerate() {
            if keys.last() != Some(&k) {
                keys.push(k);
                starts.push(j as u32);
            }
        }
        starts.push(pairs.len() as u32);
        let points = pairs.iter().map(|&(_, i)| positions[i as usize]).collect();
        let extent = lo.abs().max(hi.abs()).max_element();
        NeighbourGrid {
            lo,
            cell,
            dims,
            y_bits,
            z_bits,
            keys,
            starts,
            points,
            margin: 1e-3 * cell + 1e-5 * extent,
        }
    }

    /// The squared distances from `query` to its `k` nearest points (the query itself
    /// included when it is one of them), nearest first, written into `out` (cleared first);
    /// fewer when the grid holds fewer points.
    pub(crate) fn nearest_k(&self, query: Vec3, k: usize, out: &mut Vec<f32>) {
        out.clear();
        if k == 0 {
            return;
        }
        let centre = ((query - self.lo) / self.cell).floor();
        let centre = [centre.x, centre.y, centre.z].map(|c| c as i64);
        for radius in 1..=MAX_RADIUS {
            out.clear();
            self.visit_cube(query, centre, radius, k, out);
            let covers =
                (0..3).all(|a| centre[a] - radius <= 0 && centre[a] + radius >= self.dims[a] - 1);
            if covers || (out.len() == k && out[k - 1] <= self.reach(query, centre, radius)) {
                return;
            }
        }
        // An isolated point: every point, once.
        out.clear();
        for p in &self.points {
            offer(squared_distance(*p, query), k, out);
        }
    }

    /// The squared distance below which no point outside the cube of cells within `radius`
    /// of `centre` can be (zero when the margin covers it).
    fn reach(&self, query: Vec3, centre: [i64; 3], radius: i64) -> f32 {
        let q = (query - self.lo).to_array();
        let gap = (0..3)
            .map(|a| {
                let below = q[a] - (centre[a] - radius) as f32 * self.cell;
                let above = (centre[a] + radius + 1) as f32 * self.cell - q[a];
                below.min(above)
            })
            .fold(f32::INFINITY, f32::min);
        let gap = (gap - self.margin).max(0.0);
        gap * gap
    }

    /// Offers every point of the cells within Chebyshev distance `radius` of `centre` to the
    /// `k` nearest kept in `out`: one binary search per column of cells, whose cells in the
    /// `z` range are consecutive keys.
    fn visit_cube(&self, query: Vec3, centre: [i64; 3], radius: i64, k: usize, out: &mut Vec<f32>) {
        let range =
            |a: usize| (centre[a] - radius).max(0)..=(centre[a] + radius).min(self.dims[a] - 1);
        let (z_low, z_high) = (*range(2).start() as u64, *range(2).end() as u64);
        for x in range(0) {
            for y in range(1) {
                let column =
                    ((x as u64) << (self.y_bits + self.z_bits)) | ((y as u64) << self.z_bits);
                let (low, high) = (column | z_low, column | z_high);
                let first = self.keys.partition_point(|&key| key < low);
                for (cell, _) in self.keys[first..]
                    .iter()
                    .enumerate()
                    .take_while(|(_, &key)| key <= high)
                {
                    let cell = first + cell;
                    let points =
                        &self.points[self.starts[cell] as usize..self.starts[cell + 1] as usize];
                    for p in points {
                        offer(squared_distance(*p, query), k, out);
                    }
                }
            }
        }
    }
}

/// Cube radii (in cells) searched before a query falls back to every point (an isolated
/// point, or cells far too small for the cloud).
const MAX_RADIUS: i64 = 4;

/// Cell side per median `k`-th distance: most queries then end at the first cube (27 cells),
/// whose faces are at least one cell from the query.
const CELL_PER_DISTANCE: f32 = 1.5;

/// Sample points whose neighbours set the cell side, and the subset they search.
const SIDE_QUERIES: usize = 64;
const SIDE_SUBSET: usize = 4096;

/// A cell side of about the distance from a point to its `k`-th nearest: the median of that
/// distance for [`SIDE_QUERIES`] points within a subset of [`SIDE_SUBSET`] points (both at a
/// regular stride, by brute force), scaled by `√(subset / n)` as on a surface (thinning a
/// surface sample by `f` stretches its distances by `1/√f`). Only the time of the queries
/// depends on it.
fn cell_side(positions: &[Vec3], k: usize) -> f32 {
    let subset: Vec<Vec3> = positions
        .iter()
        .step_by(positions.len().div_ceil(SIDE_SUBSET).max(1))
        .copied()
        .collect();
    let k = k.min(subset.len());
    if k == 0 {
        return 0.0;
    }
    let mut distances: Vec<f32> = subset
        .par_iter()
        .step_by(subset.len().div_ceil(SIDE_QUERIES).max(1))
        .map(|&q| {
            let mut nearest = Vec::with_capacity(k);
            for p in &subset {
                offer(squared_distance(*p, q), k, &mut nearest);
            }
            nearest[k - 1]
        })
        .collect();
    let middle = distances.len() / 2;
    let (_, median, _) = distances.select_nth_unstable_by(middle, f32::total_cmp);
    CELL_PER_DISTANCE * median.sqrt() * (subset.len() as f32 / positions.len() as f32).sqrt()
}

/// `(dx² + dy²) + dz²` in f32: the sum in kiddo's order, so the distances are the kd-tree's
/// to the bit.
fn squared_distance(p: Vec3, q: Vec3) -> f32 {
    let d = p - q;
    (d.x * d.x + d.y * d.y) + d.z * d.z
}

/// Keeps `d2` among the `k` smallest of `out` (increasing).
fn offer(d2: f32, k: usize, out: &mut Vec<f32>) {
    if out.len() == k && d2 >= out[k - 1] {
        return;
    }
    let at = out.partition_point(|&v| v <= d2);
    if out.len() == k {
        out.pop();
    }
    out.insert(at, d2);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::PointTree;

    #[test]
    fn distances_equal_the_kd_tree_s_on_a_surface_a_line_and_a_blob() {
        let mut rng = spatch_mesh::SplitMix64::new(7);
        let mut next = || rng.next_f64() as f32;
        let sheet: Vec<Vec3> = (0..5000)
            .map(|_| Vec3::new(next() * 3.0 + 10.0, next(), 0.01 * next()))
            .collect();
        let line: Vec<Vec3> = (0..800)
            .map(|i| Vec3::new(i as f32 * 0.25, 0.0, 0.0))
            .collect();
        let blob: Vec<Vec3> = (0..3000)
            .map(|_| Vec3::new(next(), next(), next()) * 1e-3)
            .collect();
        let mut duplicates = vec![Vec3::ONE; 20];
        duplicates.push(Vec3::new(1.0, 1.0, 2.0));
        for cloud in [sheet, line, blob, duplicates] {
            let grid = NeighbourGrid::new(&cloud, 13);
            let tree = PointTree::build(&cloud).unwrap();
            let (mut found, mut expected) = (Vec::new(), Vec::new());
            for (i, &p) in cloud.iter().enumerate().step_by(7) {
                for k in [1, 2, 13, 40] {
                    grid.nearest_k(p, k, &mut found);
                    tree.nearest_k(p, k, &mut expected);
                    let expected: Vec<f32> = expected.iter().map(|r| r.0).collect();
                    assert_eq!(found, expected, "point {i}, k {k}");
                }
            }
            // A query away from every point.
            let far = Vec3::splat(-5.0);
            grid.nearest_k(far, 3, &mut found);
            tree.nearest_k(far, 3, &mut expected);
            assert_eq!(found, expected.iter().map(|r| r.0).collect::<Vec<_>>());
        }
    }
}
