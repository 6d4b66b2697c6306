//! The points of a cloud as a binary hierarchy of boxes cut along their Morton codes, for
//! exact nearest-point queries (the error's `node_to_cloud`).
//!
//! Input: points and their Morton codes (`morton_order.rs`), both in increasing code order.
//! Output: a [`PointHierarchy`]; [`PointHierarchy::nearest`] gives the squared distance
//! from a query to the nearest point, and that point.
//!
//! The tree: a range of points is cut where its codes' highest differing bit changes (every
//! code of the range shares the bits above it), so each node holds the points of one cell of
//! the Morton octree, never of two cells far apart; ranges of at most [`LEAF`] points are
//! leaves, and a range of equal codes is halved. A node's box is its points' own bounds.
//! (Runs of a fixed length in Morton order can straddle a jump across the model and get a
//! box as large as it: `patch_surface/tree.rs`. Cuts at the codes' bits cannot.)
//!
//! A query starts from a hint point (the answer to the previous query of a run, a node
//! step away) and its leaf: the ball around the query through the hint holds every nearer
//! point, so the search climbs from that leaf to the first ancestor whose Morton cell holds
//! the ball's box (every point with a code in the cell is in the subtree; the codes of the
//! box's corners bound the codes inside it, the code being monotone on each axis), then
//! descends nearer child first, pruning every box farther than the best so far. Without a
//! hint it descends from the root. Exact: a point inside a box is never nearer in f32 than
//! the box (rounding of differences, squares and sums is monotone, and both sum the axes
//! in the same order), so a pruned box holds no point nearer than the best: the result is
//! the minimum of `(p - q).length_squared()` over every point, as a linear scan or the
//! kd-tree gives it (tests compare both, from near and far hints).
//!
//! Why: the kd-tree over the cloud (`PointTree`, the `kiddo` crate) cost 0.8 G instructions
//! to build over a 1 M-point scan set, on one thread, and sorted the points itself; this
//! tree is one recursive pass over codes the conversion has already sorted.
//!
//! Memory: 37 bytes per node (box, children, parent, cell), at most `2n` nodes and about
//! `n / 2` on a scan, beside the caller's points and codes. Cost: build O(n) plus a binary
//! search per node; a query from a near hint climbs and descends a few levels of a small
//! subtree, without one O(depth) boxes, the depth at most 48 code bits plus the halvings
//! of equal codes.
//!
//! Based on: T. Karras, "Maximizing parallelism in the construction of BVHs, octrees, and
//! k-d trees", HPG 2012 (splits at the highest differing Morton bit); Ericson, *Real-Time
//! Collision Detection* (2005), §6.6 (closest-point traversal).

use std::ops::Range;

use glam::Vec3;

use crate::morton_order::MortonFrame;

/// Most points in a leaf.
pub(crate) const LEAF: usize = 8;

/// Marks a leaf in [`Node::second`].
const LEAF_FLAG: u32 = 1 << 31;

/// Traversal stack: one pending sibling per level, and at most 48 code bits plus 32
/// halvings of equal codes (`u32` indices) deep.
const STACK: usize = 96;

/// A box of the tree: an inner node (its left child follows it, `second` is its right
/// child) or a leaf (`first..second & !LEAF_FLAG` are its points).
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    first: u32,
    second: u32,
}

impl Node {
    /// Squared distance from `q` to the box (0 inside), summing the axes as
    /// `Vec3::length_squared` does.
    #[inline]
    fn distance_squared(&self, q: Vec3) -> f32 {
        (self.lo - q)
            .max(q - self.hi)
            .max(Vec3::ZERO)
            .length_squared()
    }
}

/// A node's Morton cell, the `shift` of its codes' shared prefix: every point whose code
/// shares the node's prefix (`code >> shift`) is one of its points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cell {
    /// The root: the whole frame.
    Whole,
    /// The prefix `code >> shift`.
    Prefix(u8),
    /// A half of a run of equal codes: no cell holds its points alone.
    Shared,
}

/// Where a query starts: a point and the leaf holding it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Hint {
    /// The point's index.
    pub(crate) point: u32,
    /// The leaf's node index.
    leaf: u32,
}

/// The tree over points in Morton order (see the module documentation).
#[derive(Debug)]
pub(crate) struct PointHierarchy<'a> {
    points: &'a [Vec3],
    codes: &'a [u64],
    frame: MortonFrame,
    /// Depth-first order, the root first.
    nodes: Vec<Node>,
    /// Each node's parent (the root's is itself).
    parents: Vec<u32>,
    /// Each node's Morton cell.
    cells: Vec<Cell>,
}

impl<'a> PointHierarchy<'a> {
    /// The tree over `points`, whose Morton codes in `frame` are `codes`, in increasing
    /// order; `None` when there is no point or more than `u32` indices hold. Panics if the
    /// lengths differ.
    pub(crate) fn build(
        points: &'a [Vec3],
        codes: &'a [u64],
        frame: MortonFrame,
    ) -> Option<PointHierarchy<'a>> {
        assert_eq!(points.len(), codes.len(), "one code per point");
        if points.is_empty() || points.len() >= LEAF_FLAG as usize {
            return None;
        }
        let mut tree = PointHierarchy {
            points,
            codes,
            frame,
            nodes: Vec::with_capacity(4 * points.len() / LEAF + 1),
            parents: Vec::with_capacity(4 * points.len() / LEAF + 1),
            cells: Vec::with_capacity(4 * points.len() / LEAF + 1),
        };
        tree.build_range(0..points.len(), 0, Cell::Whole);
        Some(tree)
    }

    /// Appends the subtree of the points `range` (depth first), child of `parent` with the
    /// Morton cell `cell`.
    fn build_range(&mut self, range: Range<usize>, parent: u32, cell: Cell) {
        let at = self.nodes.len();
        self.parents.push(parent);
        self.cells.push(cell);
        if range.len() <= LEAF {
            let (lo, hi) = self.points[range.clone()]
                .iter()
                .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
                    (lo.min(p), hi.max(p))
                });
            self.nodes.push(Node {
                lo,
                hi,
                first: range.start as u32,
                second: range.end as u32 | LEAF_FLAG,
            });
            return;
        }
        self.nodes.push(Node {
            lo: Vec3::INFINITY,
            hi: Vec3::NEG_INFINITY,
            first: range.start as u32,
            second: 0,
        });
        let (mid, cell) = split(self.codes, range.clone());
        self.build_range(range.start..mid, at as u32, cell);
        let right = self.nodes.len();
        self.build_range(mid..range.end, at as u32, cell);
        let (l, r) = (self.nodes[at + 1], self.nodes[right]);
        let node = &mut self.nodes[at];
        (node.lo, node.hi, node.second) = (l.lo.min(r.lo), l.hi.max(r.hi), right as u32);
    }

    /// The squared distance from `q` to the nearest point, and where that point is (for the
    /// next query's `hint`). Without a hint the search starts at the root; with one, at the
    /// smallest ancestor of the hint's leaf whose Morton cell holds the box around `q` of
    /// half-side the hint's distance (widened against rounding), which holds every point as
    /// near as the hint: the nearer the hint, the fewer boxes are read.
    pub(crate) fn nearest(&self, q: Vec3, hint: Option<Hint>) -> (f32, Hint) {
        let Some(hint) = hint else {
            let start = Hint { point: 0, leaf: 0 };
            return self.descend(q, 0, (f32::INFINITY, start));
        };
        let d2 = (self.points[hint.point as usize] - q).length_squared();
        let r = d2.sqrt() * (1.0 + 1e-5) + q.abs().max_element() * 1e-6 + f32::MIN_POSITIVE;
        let (lo, hi) = (self.frame.code(q - r), self.frame.code(q + r));
        let mut at = hint.leaf;
        while !self.cell_holds(at, lo, hi) {
            at = self.parents[at as usize];
        }
        self.descend(q, at, (d2, hint))
    }

    /// Whether node `at`'s Morton cell holds every code between `lo` and `hi` (the codes of
    /// a box's corners).
    #[inline]
    fn cell_holds(&self, at: u32, lo: u64, hi: u64) -> bool {
        match self.cells[at as usize] {
            Cell::Whole => true,
            Cell::Shared => false,
            Cell::Prefix(shift) => {
                let code = self.codes[self.nodes[at as usize].first as usize] >> shift;
                lo >> shift == code && hi >> shift == code
            }
        }
    }

    /// The nearest point to `q` in the subtree at `start`, or `best` when none is nearer:
    /// nearer child first, every box farther than the best pruned.
    fn descend(&self, q: Vec3, start: u32, mut best: (f32, Hint)) -> (f32, Hint) {
        let mut stack = [(0u32, 0.0f32); STACK];
        stack[0] = (start, self.nodes[start as usize].distance_squared(q));
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (at, d2) = stack[top];
            if d2 > best.0 {
                continue;
            }
            let node = &self.nodes[at as usize];
            if node.second & LEAF_FLAG != 0 {
                for k in node.first..node.second & !LEAF_FLAG {
                    let d = (self.points[k as usize] - q).length_squared();
                    if d < best.0 {
                        best = (d, Hint { point: k, leaf: at });
                    }
                }
                continue;
            }
            let (left, right) = (at + 1, node.second);
            let dl = self.nodes[left as usize].distance_squared(q);
            let dr = self.nodes[right as usize].distance_squared(q);
            // The farther child goes below the nearer one.
            let (near, far) = if dl <= dr {
                ((left, dl), (right, dr))
            } else {
                ((right, dr), (left, dl))
            };
            for entry in [far, near] {
                if entry.1 <= best.0 {
                    stack[top] = entry;
                    top += 1;
                }
            }
        }
        best
    }
}

/// Where `range` (more than one point) is cut, and its halves' cell: at the first code
/// whose highest bit that differs across the range is set (each half then shares the codes'
/// bits down to that one), or in the middle when every code is equal.
fn split(codes: &[u64], range: Range<usize>) -> (usize, Cell) {
    let (a, b) = (codes[range.start], codes[range.end - 1]);
    if a == b {
        return ((range.start + range.end) / 2, Cell::Shared);
    }
    let bit = 63 - (a ^ b).leading_zeros();
    let mid = range.start + codes[range].partition_point(|&c| (c >> bit) & 1 == 0);
    (mid, Cell::Prefix(bit as u8))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::morton_order::{morton_order, MortonFrame};
    use crate::spacing::PointTree;
    use spatch_mesh::{Aabb, SplitMix64};

    /// A wavy sheet, a far cluster and duplicates, in Morton order with their codes.
    fn cloud(n: usize) -> (Vec<Vec3>, Vec<u64>, MortonFrame) {
        let mut rng = SplitMix64::new(11);
        let mut r = || rng.next_f64() as f32;
        let mut points: Vec<Vec3> = (0..n)
            .map(|k| match k % 10 {
                0 => Vec3::new(50.0 + r(), r(), r()),
                1 => Vec3::splat(0.25),
                _ => {
                    let (x, y) = (r(), r());
                    Vec3::new(x, y, (x * 7.0).sin() * 0.05)
                }
            })
            .collect();
        let bounds = Aabb::from_points(points.iter().copied());
        let order = morton_order(&points, &bounds);
        points = order.iter().map(|&(_, k)| points[k as usize]).collect();
        let frame = MortonFrame::new(&bounds);
        let codes = points.iter().map(|&p| frame.code(p)).collect();
        (points, codes, frame)
    }

    #[test]
    fn nearest_equals_a_linear_scan_and_the_kd_tree() {
        let (points, codes, frame) = cloud(20_000);
        let tree = PointHierarchy::build(&points, &codes, frame).unwrap();
        let kd = PointTree::build(&points).unwrap();
        let mut rng = SplitMix64::new(5);
        let mut hint = None;
        for k in 0..2000 {
            let spread = [0.01f32, 0.3, 60.0][k % 3];
            let q = Vec3::new(
                rng.next_f64() as f32 * (1.0 + spread),
                rng.next_f64() as f32,
                (rng.next_f64() as f32 - 0.5) * spread,
            );
            let (d2, at) = tree.nearest(q, hint);
            let linear = points
                .iter()
                .map(|&p| (p - q).length_squared())
                .fold(f32::INFINITY, f32::min);
            assert_eq!(d2, linear, "{q}");
            assert_eq!((points[at.point as usize] - q).length_squared(), d2);
            assert_eq!(d2, kd.nearest(q).0, "{q}");
            // No hint, or the answer for another point, gives the same distance.
            assert_eq!(tree.nearest(q, None).0, d2);
            let other = points[k * 7919 % points.len()];
            let far_hint = tree.nearest(other, None).1;
            assert_eq!(tree.nearest(q, Some(far_hint)).0, d2);
            hint = Some(at);
        }
    }

    #[test]
    fn leaves_bound_their_points_and_never_straddle_a_jump() {
        let (points, codes, frame) = cloud(5000);
        let tree = PointHierarchy::build(&points, &codes, frame).unwrap();
        let mut leaves = 0;
        for node in &tree.nodes {
            if node.second & LEAF_FLAG == 0 {
                continue;
            }
            let range = node.first as usize..(node.second & !LEAF_FLAG) as usize;
            assert!(!range.is_empty() && range.len() <= LEAF);
            for p in &points[range.clone()] {
                assert!(p.cmpge(node.lo).all() && p.cmple(node.hi).all());
            }
            leaves += range.len();
        }
        assert_eq!(leaves, points.len());
        // Morton order passes several times between the sheet (x ≤ 1) and the far cluster
        // (x ≥ 50); runs of LEAF points would straddle those jumps, no leaf does.
        for node in tree.nodes.iter().filter(|n| n.second & LEAF_FLAG != 0) {
            assert!(node.hi.x < 2.0 || node.lo.x >= 50.0, "{node:?}");
        }
        let jumps = points
            .windows(2)
            .filter(|w| (w[0].x < 2.0) != (w[1].x < 2.0))
            .count();
        assert!(jumps >= 3, "{jumps}");
        assert!(PointHierarchy::build(&[], &[], frame).is_none());
    }
}
