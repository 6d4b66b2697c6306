//! The bounding volume hierarchy of a [`PatchSurface`], for the queries its grid does not
//! answer well (points far from every cell) and for surfaces without a grid.
//!
//! Complete and implicit (node `k` has children `2k + 1` and `2k + 2`; the leaf count is a
//! power of two and the leaves share the cells evenly, [`LEAF_QUADS`] / 2 to [`LEAF_QUADS`]
//! each), so the nodes are 24-byte boxes with no child pointers. The cells are ordered by
//! recursive median splits: the cells of a node are split at the median of the longest axis
//! of their box centres into its two halves (a kd-tree order), so every subtree is a compact
//! group of cells. Morton order was tried first and dropped: a run of consecutive Morton
//! codes can jump across the model, and on a converted sphere some 8-cell nodes spanned the
//! whole of it, so most queries entered them (29.6 s instead of 1.9 s for 1 M points). The
//! build is the splits (parallel over halves) and one bottom-up pass of box unions. A query
//! descends nearer child first and prunes every box farther than the best distance so far
//! (with a relative slack of [`PRUNE_SLACK`] for rounding), and every cell whose own box is.
//!
//! Memory: 4 bytes per cell (its position in the surface's cell order) and at most 12 bytes
//! per cell of tree nodes (24 bytes per node, two nodes per leaf of four cells, padded to a
//! power of two). The surface builds it on the first query that needs it.
//!
//! Cost: build O(C log C) for C cells (a linear selection per level); a query about
//! O(log C) box tests.
//!
//! Based on: Bentley, *Multidimensional binary search trees used for associative searching*
//! (CACM 1975) for the median splits; Ericson, *Real-Time Collision Detection* (2005), §6.2
//! and §6.6 (hierarchies in arrays, closest-point traversal).

use glam::Vec3;
use rayon::prelude::*;

use super::{near_enough, Best, Node, PatchSurface, LEAF_QUADS};
#[cfg(doc)]
use crate::PRUNE_SLACK;

/// Cells below which a split of the build runs on one thread.
const SEQUENTIAL_SPLIT: usize = 1 << 14;

/// Traversal stack: each level leaves at most one sibling pending, and the tree has at most
/// 31 levels (leaves of four quads with `u32` quad indices), so 64 entries never overflow.
const STACK: usize = 64;

/// The tree (see the module docs).
#[derive(Debug)]
pub(super) struct CellTree {
    /// Positions of the cells (in the surface's order), leaf by leaf.
    cells: Vec<u32>,
    /// The implicit tree in heap order: `2 * leaves - 1` boxes.
    nodes: Vec<Node>,
    /// Leaf count, a power of two.
    leaves: usize,
}

impl CellTree {
    /// The tree over cells whose boxes are `boxes` (not empty).
    pub(super) fn build(boxes: &[Node]) -> CellTree {
        let n = boxes.len();
        let mut items: Vec<(Vec3, u32)> = boxes
            .par_iter()
            .enumerate()
            .map(|(k, b)| ((b.lo + b.hi) * 0.5, k as u32))
            .collect();
        let leaves = n.div_ceil(LEAF_QUADS).next_power_of_two();
        split_in_halves(&mut items, 0, leaves, &|l| leaf_start(l, n, leaves));
        let cells: Vec<u32> = items.par_iter().map(|&(_, k)| k).collect();
        drop(items);
        let mut nodes = vec![Node::EMPTY; 2 * leaves - 1];
        nodes[leaves - 1..]
            .par_iter_mut()
            .enumerate()
            .for_each(|(l, node)| {
                *node = cells[leaf_start(l, n, leaves)..leaf_start(l + 1, n, leaves)]
                    .iter()
                    .map(|&k| boxes[k as usize])
                    .fold(Node::EMPTY, Node::union);
            });
        // Level of `width` nodes: indices width - 1 .. 2 * width - 1; children of node k are
        // 2k + 1 and 2k + 2, on the level below.
        let mut width = leaves / 2;
        while width >= 1 {
            let (upper, lower) = nodes.split_at_mut(2 * width - 1);
            upper[width - 1..]
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, node)| *node = lower[2 * i].union(lower[2 * i + 1]));
            width /= 2;
        }
        CellTree {
            cells,
            nodes,
            leaves,
        }
    }

    /// Improves `best` by a descent of the tree, nearer child first, pruning every box
    /// farther than the best so far.
    pub(super) fn descend(&self, surface: &PatchSurface, p: Vec3, best: &mut Best) {
        let mut stack = [(0u32, 0.0f32); STACK];
        stack[0] = (0, self.nodes[0].distance_squared(p));
        let mut top = 1;
        let first_leaf = self.leaves - 1;
        while top > 0 {
            top -= 1;
            let (k, d2) = stack[top];
            if !near_enough(d2, best.distance) {
                continue;
            }
            let k = k as usize;
            if k >= first_leaf {
                let (n, l) = (self.cells.len(), k - first_leaf);
                let range = leaf_start(l, n, self.leaves)..leaf_start(l + 1, n, self.leaves);
                for &cell in &self.cells[range] {
                    surface.consider(p, cell as usize, best);
                }
                continue;
            }
            let (a, b) = (2 * k + 1, 2 * k + 2);
            let (da, db) = (
                self.nodes[a].distance_squared(p),
                self.nodes[b].distance_squared(p),
            );
            let (near, far) = if da <= db {
                ((a, da), (b, db))
            } else {
                ((b, db), (a, da))
            };
            // The nearer child is popped first.
            for (node, d2) in [far, near] {
                if near_enough(d2, best.distance) {
                    stack[top] = (node as u32, d2);
                    top += 1;
                }
            }
        }
    }
}

/// The first cell of leaf `l` of `leaves` over `n` cells (the last leaf ends at `n`): the
/// leaves share the cells evenly, so each holds `LEAF_QUADS / 2` to `LEAF_QUADS` of them.
#[inline]
fn leaf_start(l: usize, n: usize, leaves: usize) -> usize {
    (l as u128 * n as u128 / leaves as u128) as usize
}

/// Orders `items` (the cells of leaves `l0..l1`, by centre) so that each half of the leaves
/// gets the cells on one side of the median of the longest axis of their centres, and
/// recursively within each half: every subtree of the implicit tree then holds a compact
/// group of cells. Parallel over halves; the order does not depend on the thread count.
fn split_in_halves(
    items: &mut [(Vec3, u32)],
    l0: usize,
    l1: usize,
    start_of: &(impl Fn(usize) -> usize + Sync),
) {
    if l1 - l0 < 2 || items.len() < 2 {
        return;
    }
    let lm = (l0 + l1) / 2;
    let mid = start_of(lm) - start_of(l0);
    let (lo, hi) = items
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), c| {
            (lo.min(c.0), hi.max(c.0))
        });
    let extent = hi - lo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    if mid < items.len() {
        items.select_nth_unstable_by(mid, |a, b| {
            a.0[axis].total_cmp(&b.0[axis]).then_with(|| a.1.cmp(&b.1))
        });
    }
    let (left, right) = items.split_at_mut(mid.min(items.len()));
    if left.len() + right.len() > SEQUENTIAL_SPLIT {
        rayon::join(
            || split_in_halves(left, l0, lm, start_of),
            || split_in_halves(right, lm, l1, start_of),
        );
    } else {
        split_in_halves(left, l0, lm, start_of);
        split_in_halves(right, lm, l1, start_of);
    }
}
