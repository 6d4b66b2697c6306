//! Point normals by principal component analysis of each point's neighbourhood.
//!
//! Input: positions and a voxel size `v`. Output: one unit normal per point, the eigenvector
//! of the smallest eigenvalue of the covariance of the points in the 3×3×3 block of voxels
//! around the point's voxel (a neighbourhood about `3v` wide); a zero vector where that
//! neighbourhood has no plane (all points coincide or lie on a line). Normals are
//! *unoriented*: the sign is arbitrary, and the pipeline only uses them up to sign (depth
//! placement inside a pixel and grazing-angle tests).
//!
//! Method: points are binned into cubic voxels of side `v` (sorted by voxel key `x, y, z`);
//! each voxel keeps its point count and first and second moments (f64, relative to the voxel
//! grid's corner); each voxel's normal comes from the sum of the moments of its 27-voxel
//! block, and every point takes its voxel's normal. The block's voxels are found without
//! hashing: voxels in key order form columns of equal `(x, y)`, the nine neighbour columns
//! of a column are found by three cursors that only move forward over the sorted column
//! list, and within a column the voxels at `z − 1 ..= z + 1` are a short sorted run. (A hash
//! map lookup per neighbour voxel cost 27 cache misses per voxel: 0.8 s of the 1M-point run
//! against 0.3 s now.) All points of a voxel share a normal, which is what the range images
//! need (a tangent plane per pixel-sized area); a k-nearest query per point (the textbook
//! method) gives the same normals on smooth surfaces at about 20 times the cost (measured
//! 8.3 s against 0.4 s for 1M points on the loaded 2-core machine).
//!
//! The 3×3 symmetric eigenproblem is solved in f64 on the centred and rescaled covariance:
//! the smallest eigenvalue by Newton's method on the characteristic polynomial from a point
//! left of its smallest root (no trigonometry), then the eigenvector as the largest cross
//! product of two rows of `A − λI`.
//!
//! Invariants: deterministic (voxels in key order, parallel work collected in order).
//!
//! Cost: O(n) for the sort by column (`bucket_sort.rs`), then short runs; O(voxels) cursor steps, moment sums and eigen solves;
//! memory about 100 bytes per voxel.
//!
//! Based on: H. Hoppe, T. DeRose, T. Duchamp, J. McDonald, W. Stuetzle, "Surface
//! reconstruction from unorganized points", SIGGRAPH 1992 (PCA of a neighbourhood); S. A.
//! Gershgorin, "Über die Abgrenzung der Eigenwerte einer Matrix", 1931 (the start).

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::bucket_sort::column_sorted_keys;

/// Largest voxel coordinate on an axis (21 bits; coordinates beyond are clamped to the edge
/// voxels).
const KEY_MASK: u64 = (1 << 21) - 1;

/// Columns handed to one parallel task when block moments are gathered.
const COLUMNS_PER_TASK: usize = 4096;

/// Point count and moments of one voxel (or block of voxels).
#[derive(Clone, Copy, Default)]
struct Moments {
    count: f64,
    sum: DVec3,
    /// xx xy xz yy yz zz
    squares: [f64; 6],
}

impl Moments {
    fn add_point(&mut self, p: DVec3) {
        self.count += 1.0;
        self.sum += p;
        let s = &mut self.squares;
        s[0] += p.x * p.x;
        s[1] += p.x * p.y;
        s[2] += p.x * p.z;
        s[3] += p.y * p.y;
        s[4] += p.y * p.z;
        s[5] += p.z * p.z;
    }

    fn add(&mut self, other: &Moments) {
        self.count += other.count;
        self.sum += other.sum;
        for (a, b) in self.squares.iter_mut().zip(other.squares) {
            *a += b;
        }
    }

    /// The least-squares plane of the points: centroid, unit normal (zero when there is no
    /// unique plane) and the RMS distance of the points from it.
    fn plane(&self) -> BlockPlane {
        if self.count < 3.0 {
            return BlockPlane::default();
        }
        let m = self.sum / self.count;
        let s = self.squares.map(|v| v / self.count);
        let c = [
            s[0] - m.x * m.x,
            s[1] - m.x * m.y,
            s[2] - m.x * m.z,
            s[3] - m.y * m.y,
            s[4] - m.y * m.z,
            s[5] - m.z * m.z,
        ];
        let n = smallest_eigenvector(c);
        // nᵀ C n: the variance of the points along the normal.
        let variance = n.x * (c[0] * n.x + c[1] * n.y + c[2] * n.z)
            + n.y * (c[1] * n.x + c[3] * n.y + c[4] * n.z)
            + n.z * (c[2] * n.x + c[4] * n.y + c[5] * n.z);
        BlockPlane {
            centre: m,
            normal: n.as_vec3(),
            spread: variance.max(0.0).sqrt() as f32,
            count: self.count as u32,
        }
    }
}

/// A per-voxel value that sums over a block of voxels (moments, side counts).
trait BlockSum: Copy + Default {
    fn add_to(&mut self, other: &Self);
}

impl BlockSum for Moments {
    fn add_to(&mut self, other: &Self) {
        self.add(other);
    }
}

impl BlockSum for [u32; 2] {
    fn add_to(&mut self, other: &Self) {
        self[0] += other[0];
        self[1] += other[1];
    }
}

/// The least-squares plane of a voxel's 3×3×3 block.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct BlockPlane {
    /// Centroid of the block's points, relative to [`VoxelPlanes::origin`].
    pub(crate) centre: DVec3,
    /// Unit normal (unoriented), or zero where the block has no unique plane.
    pub(crate) normal: Vec3,
    /// RMS distance of the block's points from the plane (same unit as the positions).
    pub(crate) spread: f32,
    /// Points in the block.
    pub(crate) count: u32,
}

/// Every voxel's block plane and the voxel of every point.
pub(crate) struct VoxelPlanes {
    /// Corner of the voxel grid; plane centres are relative to it.
    pub(crate) origin: DVec3,
    /// The voxel of each point (an index into `planes`).
    pub(crate) point_voxel: Vec<u32>,
    /// One plane per voxel.
    pub(crate) planes: Vec<BlockPlane>,
    /// The voxels' layout (their moments dropped), for later sums over the same blocks;
    /// `None` for an empty cloud.
    grid: Option<VoxelColumns>,
}

impl VoxelPlanes {
    /// The plane of point `i`'s voxel block.
    pub(crate) fn of_point(&self, i: usize) -> &BlockPlane {
        &self.planes[self.point_voxel[i] as usize]
    }

    /// The planes without the voxels' layout (kept only for [`VoxelPlanes::two_sided_blocks`]:
    /// about 8 bytes a voxel).
    pub(crate) fn without_layout(mut self) -> VoxelPlanes {
        self.grid = None;
        self
    }

    /// Per voxel, whether its 3×3×3 block holds at least `min` points on each side of its
    /// plane (both sides of a part thinner than a block, which one plane would pull
    /// together), `sides[i]` telling the side of point `i` (seen from its scanner; `None`:
    /// no vote).
    pub(crate) fn two_sided_blocks(&self, sides: &[Option<bool>], min: u32) -> Vec<bool> {
        let Some(grid) = &self.grid else {
            return vec![false; self.planes.len()];
        };
        let mut counts = vec![[0u32; 2]; self.planes.len()];
        for (&v, &side) in self.point_voxel.iter().zip(sides) {
            if let Some(front) = side {
                counts[v as usize][usize::from(!front)] += 1;
            }
        }
        let mut two_sided = vec![false; self.planes.len()];
        grid.fold_all(&counts, &mut two_sided, |_, c| c[0] >= min && c[1] >= min);
        two_sided
    }
}

/// The voxels of a cloud in key order (`x`, then `y`, then `z`), grouped into columns of
/// equal `(x, y)`.
struct VoxelColumns {
    /// Bits of the `y` and `z` fields of a key.
    y_bits: u32,
    z_bits: u32,
    /// Voxel keys `x << (Y + Z) | y << Z | z` (`Y`, `Z`: the widths of the `y` and `z`
    /// fields, just wide enough for the cloud), increasing.
    keys: Vec<u64>,
    /// Moments of each voxel's points (relative to the voxel grid's corner).
    moments: Vec<Moments>,
    /// Column keys `x << Y | y` (the voxel key without `z`), increasing.
    columns: Vec<u64>,
    /// Index of each column's first voxel, plus the voxel count at the end.
    starts: Vec<u32>,
}

impl VoxelColumns {
    /// The voxels of the column at `c`.
    fn column(&self, c: usize) -> std::ops::Range<usize> {
        self.starts[c] as usize..self.starts[c + 1] as usize
    }

    /// Writes the voxel runs `(start, start, end)` of the up to nine
    /// columns next to column `c` (itself included) into `neighbours` and
    /// returns how many; `cursors` (one per `dx`) only move forward.
    #[inline]
    fn neighbour_columns(
        &self,
        c: usize,
        cursors: &mut [usize; 3],
        neighbours: &mut [(usize, usize, usize); 9],
    ) -> usize {
        let y_mask = (1u64 << self.y_bits) - 1;
        let (x, y) = (self.columns[c] >> self.y_bits, self.columns[c] & y_mask);
        let mut count = 0;
        for (cursor, dx) in cursors.iter_mut().zip([-1i64, 0, 1]) {
            let nx = x as i64 + dx;
            if nx < 0 {
                continue;
            }
            // `y + 1` is clamped so that it never carries into the `x` field.
            let low = (nx as u64) << self.y_bits | y.saturating_sub(1);
            let high = (nx as u64) << self.y_bits | (y + 1).min(y_mask);
            while *cursor < self.columns.len() && self.columns[*cursor] < low {
                *cursor += 1;
            }
            let mut n = *cursor;
            while n < self.columns.len() && self.columns[n] <= high {
                let voxels = self.column(n);
                neighbours[count] = (voxels.start, voxels.start, voxels.end);
                count += 1;
                n += 1;
            }
        }
        count
    }

    /// `finish` of each voxel's index and the sum of `values` (one per voxel) over its
    /// 3×3×3 block, for every voxel of columns `range`, written to `out` (one slot per voxel
    /// of those columns, in voxel order): the block planes of the voxels' moments, or their
    /// counts of points seen from each side.
    ///
    /// The nine neighbour columns of a column are found by three cursors (one per `dx`) that
    /// only move forward, since the neighbour keys grow with the column key; this replaces 27
    /// random hash lookups per voxel by a merge over the sorted column list. Within the
    /// neighbour columns, one cursor each follows the column's voxels up in `z` (a binary
    /// search per voxel and neighbour column was 5.5 % of a one-thread run's samples).
    fn fold_blocks<T: BlockSum, U>(
        &self,
        range: std::ops::Range<usize>,
        values: &[T],
        out: &mut [U],
        finish: impl Fn(usize, &T) -> U,
    ) {
        let mut slots = out.iter_mut();
        let (y_mask, z_mask) = ((1u64 << self.y_bits) - 1, (1u64 << self.z_bits) - 1);
        let split = |column: u64| (column >> self.y_bits, column & y_mask);
        // Start each cursor at the first neighbour column of the task's first column.
        let mut cursors = [0usize; 3];
        if let Some(&column) = self.columns.get(range.start) {
            let (x, y) = split(column);
            for (cursor, dx) in cursors.iter_mut().zip([-1i64, 0, 1]) {
                let low = ((x as i64 + dx).max(0) as u64) << self.y_bits | y.saturating_sub(1);
                *cursor = self.columns.partition_point(|&k| k < low);
            }
        }
        // Per neighbour column: its first voxel not below `z - 1`, its first voxel above
        // `z + 1` (cursors that only move forward, as the column's voxels come in increasing
        // `z`) and its end.
        let mut neighbours = [(0usize, 0usize, 0usize); 9];
        for c in range {
            let count = self.neighbour_columns(c, &mut cursors, &mut neighbours);
            for v in self.column(c) {
                let z = self.keys[v] & z_mask;
                let mut block = T::default();
                for (from, to, end) in &mut neighbours[..count] {
                    // Cut at the column's end, so the cursors' test is the bounds check
                    // (one check a step instead of two: 65 M fewer worker instructions on
                    // the covering 1 M scan set, callgrind).
                    let keys = &self.keys[..*end];
                    while *from < keys.len() && (keys[*from] & z_mask) + 1 < z {
                        *from += 1;
                    }
                    *to = (*to).max(*from);
                    while *to < keys.len() && (keys[*to] & z_mask) <= z + 1 {
                        *to += 1;
                    }
                    for m in &values[*from..*to] {
                        block.add_to(m);
                    }
                }
                if let Some(slot) = slots.next() {
                    *slot = finish(v, &block);
                }
            }
        }
    }

    /// [`VoxelColumns::fold_blocks`] over every column, in parallel tasks of
    /// [`COLUMNS_PER_TASK`] columns, written in place (`out`: one slot per voxel).
    fn fold_all<T: BlockSum + Sync, U: Send>(
        &self,
        values: &[T],
        out: &mut [U],
        finish: impl Fn(usize, &T) -> U + Sync,
    ) {
        let mut slices = Vec::new();
        let mut rest = out;
        for start in (0..self.columns.len()).step_by(COLUMNS_PER_TASK) {
            let range = start..(start + COLUMNS_PER_TASK).min(self.columns.len());
            let voxels = (self.starts[range.end] - self.starts[range.start]) as usize;
            let (slice, tail) = rest.split_at_mut(voxels);
            slices.push((range, slice));
            rest = tail;
        }
        slices
            .into_par_iter()
            .for_each(|(range, slice)| self.fold_blocks(range, values, slice, &finish));
    }
}

/// PCA normals of every point over 3×3×3 blocks of voxels of side `voxel` (see the module
/// documentation).
pub fn estimate_normals(positions: &[Vec3], voxel: f32) -> Vec<Vec3> {
    let planes = estimate_planes(positions, voxel);
    planes
        .point_voxel
        .par_iter()
        .map(|&v| planes.planes[v as usize].normal)
        .collect()
}

/// The least-squares plane of every point's 3×3×3 voxel block (voxels of side `voxel`): what
/// [`estimate_normals`] takes the normals from, with the planes' centres and spreads.
pub(crate) fn estimate_planes(positions: &[Vec3], voxel: f32) -> VoxelPlanes {
    if positions.is_empty() || !(voxel.is_finite() && voxel > 0.0) {
        return VoxelPlanes {
            origin: DVec3::ZERO,
            point_voxel: vec![0; positions.len()],
            planes: vec![BlockPlane::default()],
            grid: None,
        };
    }
    let (lo, hi) = positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let scale = VoxelScale {
        lo,
        inv: 1.0 / f64::from(voxel),
    };
    // Key fields just wide enough for the cloud.
    let bits = scale
        .coordinates(hi)
        .map(|c| (u64::BITS - c.leading_zeros()).max(1));
    let (y_bits, z_bits) = (bits[1], bits[2]);
    let order = column_sorted_keys(positions, |p| scale.coordinates(p), (y_bits, z_bits));
    let (mut grid, runs) = group_voxels(&order, y_bits, z_bits);
    let point_voxel = voxel_of_points(&order, &runs, positions.len());
    let origin = lo.as_dvec3();
    grid.moments = voxel_moments(order, runs, positions, origin);
    let planes = block_planes(&mut grid);
    VoxelPlanes {
        origin,
        point_voxel,
        planes,
        grid: Some(grid),
    }
}

/// The voxel grid of [`estimate_planes`]: its lowest corner and the inverse voxel side.
struct VoxelScale {
    /// The lowest corner of the points.
    lo: Vec3,
    /// One over the voxel side.
    inv: f64,
}

impl VoxelScale {
    /// The voxel coordinates of `p` (a point not below `lo`), clamped to [`KEY_MASK`].
    #[inline] // Once per point, inside the parallel key loop of `column_sorted_keys`.
    fn coordinates(&self, p: Vec3) -> [u64; 3] {
        let max_index = KEY_MASK as f64;
        // `p ≥ lo`, so the scaled offsets are ≥ 0 and truncation is the floor (inline, where
        // `floor` is a libm call).
        let d = (p - self.lo).as_dvec3() * self.inv;
        // Through `u32` (the values are below 2²¹): Rust's saturating `f64 as u64` has no
        // single x86-64 instruction and took 83 M instructions of the two plane fits.
        [d.x, d.y, d.z].map(|v| u64::from(v.min(max_index) as u32))
    }
}

/// The voxels of the key-sorted points `order` (runs of equal keys) grouped into columns
/// (runs of equal `(x, y)`), without their moments yet; and the first index in `order` of
/// each voxel's run, plus the point count at the end.
fn group_voxels(order: &[(u64, u32)], y_bits: u32, z_bits: u32) -> (VoxelColumns, Vec<usize>) {
    let mut runs: Vec<usize> = Vec::new();
    let mut grid = VoxelColumns {
        y_bits,
        z_bits,
        keys: Vec::new(),
        moments: Vec::new(),
        columns: Vec::new(),
        starts: Vec::new(),
    };
    for (j, &(k, _)) in order.iter().enumerate() {
        if grid.keys.last() != Some(&k) {
            if grid.columns.last() != Some(&(k >> z_bits)) {
                grid.columns.push(k >> z_bits);
                grid.starts.push(grid.keys.len() as u32);
            }
            grid.keys.push(k);
            runs.push(j);
        }
    }
    grid.starts.push(grid.keys.len() as u32);
    runs.push(order.len());
    (grid, runs)
}

/// The voxel of each of the `points` points, from the voxels' `runs` of the sorted `order`.
fn voxel_of_points(order: &[(u64, u32)], runs: &[usize], points: usize) -> Vec<u32> {
    let mut point_voxel = vec![0u32; points];
    for (v, run) in runs.windows(2).enumerate() {
        for &(_, i) in &order[run[0]..run[1]] {
            point_voxel[i as usize] = v as u32;
        }
    }
    point_voxel
}

/// Each voxel's moments, relative to `origin` (the grid corner) to keep them small, in
/// parallel from its run of the sorted points: its points in index order, so the sums are
/// those of one pass over the points (0.08 G of sequential instructions on the evenly spread
/// 1 M scan set before). The points' indices alone (4 bytes a point, not the pairs' 16) live
/// beside the moments, so this stays under the moments and planes of [`block_planes`], the
/// stage's peak.
fn voxel_moments(
    order: Vec<(u64, u32)>,
    runs: Vec<usize>,
    positions: &[Vec3],
    origin: DVec3,
) -> Vec<Moments> {
    let members: Vec<u32> = order.par_iter().map(|&(_, i)| i).collect();
    drop(order);
    let moments = runs
        .par_windows(2)
        .map(|run| {
            let mut moments = Moments::default();
            for &i in &members[run[0]..run[1]] {
                moments.add_point(positions[i as usize].as_dvec3() - origin);
            }
            moments
        })
        .collect();
    drop((members, runs));
    moments
}

/// The plane of every voxel's block, from the voxels' moments (taken from `grid` and
/// dropped).
fn block_planes(grid: &mut VoxelColumns) -> Vec<BlockPlane> {
    // Written in place, one slice of voxels per task: collecting the tasks' planes would hold
    // them twice at the peak of this stage.
    let mut planes = vec![BlockPlane::default(); grid.keys.len()];
    let moments = std::mem::take(&mut grid.moments);
    grid.fold_all(&moments, &mut planes, |_, m| m.plane());
    drop(moments);
    planes
}

/// The unit eigenvector of the smallest eigenvalue of the symmetric matrix
/// `[[a0, a1, a2], [a1, a3, a4], [a2, a4, a5]]`, or zero when it is not unique.
///
/// The smallest eigenvalue is the smallest root of the characteristic polynomial, found by
/// Newton's method from a point left of it (`smallest_root`); the eigenvector is the
/// largest cross product of two rows of `A − λI`. (The trigonometric closed form cost 536
/// instructions a call, half of them `acos` and two `cos`; this one about 360.)
pub fn smallest_eigenvector(a: [f64; 6]) -> DVec3 {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return DVec3::ZERO;
    }
    let inv = 1.0 / scale;
    let [a00, a01, a02, a11, a12, a22] = a.map(|v| v * inv);
    let Some(smallest) = smallest_root([a00, a01, a02, a11, a12, a22]) else {
        return DVec3::ZERO;
    };
    let rows = [
        DVec3::new(a00 - smallest, a01, a02),
        DVec3::new(a01, a11 - smallest, a12),
        DVec3::new(a02, a12, a22 - smallest),
    ];
    // The longest cross product, the last of equals.
    let mut best = rows[0].cross(rows[1]);
    for cross in [rows[0].cross(rows[2]), rows[1].cross(rows[2])] {
        if cross.length_squared() >= best.length_squared() {
            best = cross;
        }
    }
    best.try_normalize().unwrap_or(DVec3::ZERO)
}

/// The smallest eigenvalue of the symmetric matrix of [`smallest_eigenvector`] (entries of
/// magnitude at most 1), or `None` when it is not separated from the middle one (no unique
/// eigenvector) or all three are equal.
///
/// The eigenvalues are the roots of `f(λ) = λ³ − c₂λ² + c₁λ − c₀` (trace, sum of the
/// principal 2×2 minors, determinant), all real. Left of the smallest root `f` is negative,
/// rising and concave (its inflection point is the roots' mean), so Newton's steps from a
/// point there stay left of the root and increase to it. The start is 0 when that point is
/// left of the root (`f(0) ≤ 0`, `f′(0) > 0`, `f″(0) < 0`: the covariances of the pipeline,
/// where it is 1–3 steps from a small root) and otherwise Gershgorin's lower bound. The other
/// two roots then solve the deflated quadratic.
fn smallest_root([a00, a01, a02, a11, a12, a22]: [f64; 6]) -> Option<f64> {
    let c2 = a00 + a11 + a22;
    let c1 = a00 * a11 + a00 * a22 + a11 * a22 - a01 * a01 - a02 * a02 - a12 * a12;
    let c0 = a00 * (a11 * a22 - a12 * a12) - a01 * (a01 * a22 - a12 * a02)
        + a02 * (a01 * a12 - a11 * a02);
    // A multiple of the identity (the eigenvalues' spread is zero): no unique eigenvector.
    let q = c2 / 3.0;
    let spread = (a00 - q).powi(2)
        + (a11 - q).powi(2)
        + (a22 - q).powi(2)
        + 2.0 * (a01 * a01 + a02 * a02 + a12 * a12);
    if spread < 6e-24 {
        return None;
    }
    let f = |x: f64| ((x - c2) * x + c1) * x - c0;
    let slope = |x: f64| (3.0 * x - 2.0 * c2) * x + c1;
    let mut x = if -c0 <= 0.0 && c1 > 0.0 && c2 > 0.0 {
        0.0
    } else {
        (a00 - a01.abs() - a02.abs())
            .min(a11 - a01.abs() - a12.abs())
            .min(a22 - a02.abs() - a12.abs())
    };
    // Convergence is quadratic at a simple root; a double root (no unique eigenvector, which
    // the gap test below refuses) converges linearly, hence the cap.
    for _ in 0..64 {
        let (value, d) = (f(x), slope(x));
        if !(value < 0.0 && d > 0.0) {
            break;
        }
        let next = x - value / d;
        if next.partial_cmp(&x) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        x = next;
    }
    let sum = c2 - x;
    let product = c1 - x * sum;
    let root = (sum * sum - 4.0 * product).max(0.0).sqrt();
    let (middle, largest) = (0.5 * (sum - root), 0.5 * (sum + root));
    // The smallest eigenvalue must be separated from the middle one for a unique normal.
    // (A double root is found to about half the digits, so the margin is 1e-6, as the
    // trigonometric form this replaced needed near `acos(±1)`.)
    if middle - x < 1e-6 * (largest - x) {
        return None;
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn eigenvector_of_a_rotated_diagonal_matrix() {
        let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        let m = glam::DMat3::from_quat(q)
            * glam::DMat3::from_diagonal(DVec3::new(3.0, 2.0, 0.01))
            * glam::DMat3::from_quat(q).transpose();
        let a = [
            m.x_axis.x, m.y_axis.x, m.z_axis.x, m.y_axis.y, m.z_axis.y, m.z_axis.z,
        ];
        let v = smallest_eigenvector(a);
        let expected = q * DVec3::Z;
        assert!(v.dot(expected).abs() > 1.0 - 1e-9, "{v} vs {expected}");
    }

    #[test]
    fn eigenvector_of_random_symmetric_matrices_has_the_smallest_rayleigh_quotient() {
        let mut rng = spatch_mesh::SplitMix64::new(19);
        let mut next = || 2.0 * rng.next_f64() - 1.0;
        for _ in 0..2000 {
            // Indefinite matrices too: Gershgorin's start, not 0.
            let a = [next(), next(), next(), next(), next(), next()];
            let m = glam::DMat3::from_cols_array(&[
                a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5],
            ]);
            let v = smallest_eigenvector(a);
            assert!((v.length() - 1.0).abs() < 1e-12, "{a:?} gave {v}");
            let lambda = v.dot(m * v);
            assert!(
                (m * v - lambda * v).length() < 1e-9,
                "{a:?}: not an eigenvector"
            );
            for _ in 0..20 {
                let u = DVec3::new(next(), next(), next()).normalize();
                assert!(lambda <= u.dot(m * u) + 1e-12, "{a:?}: not the smallest");
            }
        }
        // Two equal smallest eigenvalues, or all three: no unique eigenvector.
        assert_eq!(
            smallest_eigenvector([1.0, 0.0, 0.0, 1.0, 0.0, 3.0]),
            DVec3::ZERO
        );
        assert_eq!(
            smallest_eigenvector([2.0, 0.0, 0.0, 2.0, 0.0, 2.0]),
            DVec3::ZERO
        );
        let v = smallest_eigenvector([4.0, 0.0, 0.0, 1.0, 0.0, 3.0]);
        assert_eq!(v.abs(), DVec3::Y);
    }

    #[test]
    fn voxel_normals_of_a_sphere_are_radial() {
        let n = 20_000;
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        let points: Vec<Vec3> = (0..n)
            .map(|k| {
                let z = 1.0 - (2.0 * k as f64 + 1.0) / n as f64;
                let r = (1.0 - z * z).sqrt();
                let phi = golden * k as f64;
                Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32)
            })
            .collect();
        let spacing = (4.0 * std::f32::consts::PI / n as f32).sqrt();
        let normals = estimate_normals(&points, 1.5 * spacing);
        for (p, nrm) in points.iter().zip(&normals) {
            assert!(nrm.dot(*p).abs() > 0.99, "{p} has normal {nrm}");
        }
    }

    #[test]
    fn moments_give_the_plane_normal_of_a_tilted_grid_and_none_for_degenerate_inputs() {
        let plane_normal = |points: &[Vec3]| {
            let mut m = Moments::default();
            for p in points {
                m.add_point(p.as_dvec3());
            }
            m.plane().normal
        };
        let n = Vec3::new(1.0, 2.0, 3.0).normalize();
        let u = n.any_orthonormal_vector();
        let w = n.cross(u);
        let pts: Vec<Vec3> = (0..16)
            .map(|k| u * (k % 4) as f32 + w * (k / 4) as f32 + Vec3::splat(5.0))
            .collect();
        assert!(plane_normal(&pts).dot(n).abs() > 0.9999);
        let line: Vec<Vec3> = (0..5).map(|k| Vec3::X * k as f32).collect();
        assert_eq!(plane_normal(&line), Vec3::ZERO);
        assert_eq!(plane_normal(&[Vec3::ONE; 6]), Vec3::ZERO);
    }
}
