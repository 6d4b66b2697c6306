//! The patches of a [`PatchSurface`] as a two-level index for the few points far from every
//! cell: each patch's box, and its cells listed together.
//!
//! Input: the surface's cells (in the grid's order) with their boxes. Output: a
//! [`BlockIndex`]: per block (a patch), the union of its cells' boxes and the positions of
//! its cells. A query ([`BlockIndex::descend`]) measures its distance to every block's box,
//! visits the blocks nearest box first and, within a block, considers every cell (its own
//! box first), until the next block's box is farther than the best distance so far (with
//! the search's relative slack, [`crate::PRUNE_SLACK`]). Every cell it skips has its box,
//! which holds the cell, farther than the best: the result is the exact minimum, as the
//! grid's and the tree's searches give it.
//!
//! Why: a scene has a few thousand patches over hundreds of thousands of cells, so the
//! patches are a ready-made hierarchy. The bounding volume hierarchy of every cell
//! (`tree.rs`) cost 0.60 G instructions to build on a 1 M-point scan set for the 204
//! points (of 990,618) that needed it; this index is one counting pass over the cells.
//!
//! Cost: build O(C + B) for C cells in B blocks; a query O(B log B) box tests and sorts,
//! plus the cells of the blocks within reach. It is used when blocks hold at least
//! [`MIN_CELLS_PER_BLOCK`] cells on average (scenes of patches); a soup of single quads
//! keeps the tree.

use glam::Vec3;

use super::{near_enough, Best, Node, PatchSurface};

/// Mean cells per block from which the block index replaces the tree for far points.
pub(super) const MIN_CELLS_PER_BLOCK: usize = 16;

/// Per block, the union of its cells' boxes and its cells (see the module docs).
#[derive(Debug)]
pub(super) struct BlockIndex {
    /// The box of each block's cells (empty for a block without a drawable cell).
    boxes: Vec<Node>,
    /// Where each block's cells start in `cells` (one more entry than blocks).
    starts: Vec<u32>,
    /// Positions of the cells in the surface's order, block by block.
    cells: Vec<u32>,
}

impl BlockIndex {
    /// The index of `blocks` blocks over cells whose block is `block_of(k)` and box
    /// `boxes[k]`, for every position `k`.
    pub(super) fn build(blocks: usize, boxes: &[Node], block_of: impl Fn(usize) -> usize) -> Self {
        let mut starts = vec![0u32; blocks + 1];
        let mut block_boxes = vec![Node::EMPTY; blocks];
        for (k, b) in boxes.iter().enumerate() {
            let block = block_of(k);
            starts[block + 1] += 1;
            block_boxes[block] = block_boxes[block].union(*b);
        }
        for b in 0..blocks {
            starts[b + 1] += starts[b];
        }
        let mut next = starts.clone();
        let mut cells = vec![0u32; boxes.len()];
        for k in 0..boxes.len() {
            let slot = &mut next[block_of(k)];
            cells[*slot as usize] = k as u32;
            *slot += 1;
        }
        BlockIndex {
            boxes: block_boxes,
            starts,
            cells,
        }
    }

    /// Improves `best` for `p` over every cell of the surface: blocks nearest box first,
    /// stopping at the first block farther than the best so far.
    pub(super) fn descend(&self, surface: &PatchSurface, p: Vec3, best: &mut Best) {
        let mut reach: Vec<(f32, u32)> = self
            .boxes
            .iter()
            .enumerate()
            .filter_map(|(b, node)| {
                let d2 = node.distance_squared(p);
                near_enough(d2, best.distance).then_some((d2, b as u32))
            })
            .collect();
        reach.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (d2, b) in reach {
            if !near_enough(d2, best.distance) {
                break;
            }
            let b = b as usize;
            for &k in &self.cells[self.starts[b] as usize..self.starts[b + 1] as usize] {
                surface.consider(p, k as usize, best);
            }
        }
    }
}
