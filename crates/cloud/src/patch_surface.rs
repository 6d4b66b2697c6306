//! The patch surface of a scene as a spatial index: the exact nearest point of any drawable
//! cell to a query point, for the error measures both ways (cloud and mesh sources).
//!
//! Input: a [`Scene`] and a shift into the caller's coordinates. Output: a [`PatchSurface`]
//! answering "how far is the patch surface from `p`, and which patch is nearest" for one
//! point ([`PatchSurface::nearest`]) or many in parallel ([`PatchSurface::nearest_all`]).
//!
//! The surface: every drawable cell (four filled corners) as the bilinear quad through its
//! nodes, the surface the renderer draws (`quad_distance` gives the distance to one quad and
//! its accuracy).
//!
//! The index: a bounding volume hierarchy over the quads, complete and implicit (node `k` has
//! children `2k + 1` and `2k + 2`; the leaf count is a power of two and the leaves share the
//! cells evenly, [`LEAF_QUADS`] / 2 to [`LEAF_QUADS`] each), so the nodes are 24-byte boxes
//! with no child pointers. The cells are ordered by recursive median splits: the cells of a
//! node are split at the median of the longest axis of their centres into its two halves
//! (a kd-tree order), so every subtree is a compact group of cells. Morton order was tried
//! first and dropped: a run of consecutive Morton codes can jump across the model, and on a
//! converted sphere some 8-cell nodes spanned the whole of it, so most queries entered them
//! (29.6 s instead of 1.9 s for 1 M points). The build is the splits (parallel over halves)
//! and one bottom-up pass of box unions. A query descends nearer child first and prunes
//! every box farther than the best distance so far (with a relative slack of
//! [`PRUNE_SLACK`] for rounding), and every quad whose own box is: the result is exactly the
//! minimum of the quad distance over all quads (ties go to the lower patch index), which the
//! tests check against a linear scan.
//! A point far from every patch (a source that does not overlap the scene) costs a few more
//! boxes, not a scan of empty space.
//!
//! In front of the tree, a flat grid of the cells by centre (`cell_grid.rs`) answers most
//! queries: the grid cells within reach of the point, then those within the best distance
//! found; the tree is descended only when that neighbourhood would pass
//! `MAX_GRID_CELLS` grid cells (points far from the surface). The result is the same
//! either way.
//!
//! [`PatchSurface::nearest_all`] queries in Morton order of the query points (so consecutive
//! queries walk the same nodes and quads, which stay in cache), each search starting from
//! the distance to the previous query's nearest cell (so boxes farther than that are pruned
//! from the root down), and returns the results in the caller's order; the per-point results
//! do not depend on the order, the hint or the thread count.
//!
//! Memory: the node positions of every patch (12 bytes per node; a cell's corners are read
//! from there, not copied), 8 bytes per drawable cell (its patch and corner) and at most
//! 12 bytes per cell of tree nodes (24 bytes per node, two nodes per leaf of four cells,
//! padded to a power of two): about 32 bytes per cell, where copying each quad would take 52.
//!
//! Cost: build O(C log C) for C cells (a linear selection per level); a query about O(log C) box tests and a few
//! quad distances for points near the surface.
//!
//! Based on: Bentley, *Multidimensional binary search trees used for associative searching*
//! (CACM 1975) for the median splits; Ericson, *Real-Time Collision Detection* (2005), §6.2
//! and §6.6 (hierarchies in arrays, closest-point traversal).

use glam::Vec3;
use rayon::prelude::*;
use spatch_format::Scene;

use crate::cell_grid::{CellGrid, CellRange};
use crate::quad_distance::{distance_to_quad, Quad};

/// Quads per leaf of the tree.
pub const LEAF_QUADS: usize = 4;

/// Relative slack on squared box distances when pruning, so that f32 rounding of a box
/// distance never prunes a quad exactly as near as the best one.
pub const PRUNE_SLACK: f32 = 1e-5;

/// The patch index of a point when there is no drawable cell at all.
pub const NO_PATCH: u32 = u32::MAX;

/// Bits of each axis in a Morton code.
const MORTON_BITS: u32 = 21;

/// Cells below which a split of the build runs on one thread.
const SEQUENTIAL_SPLIT: usize = 1 << 14;

/// Queries per parallel work item.
const QUERY_CHUNK: usize = 2048;

/// Most grid cells a query reads around its own before it searches the tree instead.
const MAX_GRID_CELLS: f64 = 64.0;

/// Traversal stack: each level leaves at most one sibling pending, and the tree has at most
/// 31 levels (leaves of four quads with `u32` quad indices), so 64 entries never overflow.
const STACK: usize = 64;

/// An axis-aligned box of the tree.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Vec3,
    hi: Vec3,
}

impl Node {
    /// The box of nothing: infinitely far from every point.
    const EMPTY: Node = Node {
        lo: Vec3::INFINITY,
        hi: Vec3::NEG_INFINITY,
    };

    fn of_quad(q: &Quad) -> Node {
        Node {
            lo: q[0].min(q[1]).min(q[2]).min(q[3]),
            hi: q[0].max(q[1]).max(q[2]).max(q[3]),
        }
    }

    fn union(self, other: Node) -> Node {
        Node {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }

    /// Squared distance from `p` to the box (0 inside).
    #[inline]
    fn distance_squared(&self, p: Vec3) -> f32 {
        (self.lo - p)
            .max(p - self.hi)
            .max(Vec3::ZERO)
            .length_squared()
    }
}

/// One drawable cell: the block (a patch, or one quad given alone) and the grid index of its
/// corner `p00` in that block.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Cell {
    block: u32,
    node: u32,
}

/// A grid of node positions: where its nodes start in the position array, its row stride
/// and the patch its cells belong to.
#[derive(Clone, Copy, Debug)]
struct Block {
    start: usize,
    stride: usize,
    owner: u32,
}

/// The drawable cells of a scene as bilinear quads, indexed for nearest-point queries (see
/// the module docs).
#[derive(Debug)]
pub struct PatchSurface {
    /// Every node position of every block (an empty node keeps an unused position: no drawable cell touches it).
    positions: Vec<Vec3>,
    blocks: Vec<Block>,
    /// Cells in Morton order of their centres.
    cells: Vec<Cell>,
    /// The implicit tree in heap order: `2 * leaves - 1` boxes.
    nodes: Vec<Node>,
    /// Leaf count, a power of two.
    leaves: usize,
    /// Bounds of all cells (the frame of the Morton codes).
    bounds: Node,
    /// The cells (indices into `cells`) in a flat grid by their centres, the first place a
    /// query looks; `None` when the cells have no extent.
    grid: Option<CellGrid>,
}

impl PatchSurface {
    /// Indexes the drawable cells of `scene`, each node moved by `shift` (scene-relative
    /// positions plus `shift` are the caller's coordinates); `None` when no cell is drawable.
    pub fn new(scene: &Scene, shift: Vec3) -> Option<PatchSurface> {
        let patches = scene.patches();
        let mut start = 0;
        let blocks: Vec<Block> = patches
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let block = Block {
                    start,
                    stride: usize::from(p.grid().cols()),
                    owner: k as u32,
                };
                start += usize::from(p.grid().cols()) * usize::from(p.grid().rows());
                block
            })
            .collect();
        let mut positions = vec![Vec3::ZERO; start];
        let mut slices = Vec::with_capacity(patches.len());
        let mut rest = positions.as_mut_slice();
        for p in patches {
            let (mine, others) =
                rest.split_at_mut(usize::from(p.grid().cols()) * usize::from(p.grid().rows()));
            slices.push(mine);
            rest = others;
        }
        slices
            .into_par_iter()
            .zip(patches.par_iter())
            .for_each(|(slice, patch)| {
                let cols = usize::from(patch.grid().cols());
                for (k, out) in slice.iter_mut().enumerate() {
                    if let Some(q) = patch.node_position(k % cols, k / cols) {
                        *out = q + shift;
                    }
                }
            });
        let cells: Vec<Cell> = patches
            .par_iter()
            .enumerate()
            .flat_map_iter(|(k, patch)| {
                let (cols, rows) = (
                    usize::from(patch.grid().cols()),
                    usize::from(patch.grid().rows()),
                );
                (0..rows - 1).flat_map(move |j| {
                    (0..cols - 1).filter_map(move |i| {
                        patch.cell_is_drawable(i, j).then_some(Cell {
                            block: k as u32,
                            node: (j * cols + i) as u32,
                        })
                    })
                })
            })
            .collect();
        PatchSurface::index(positions, blocks, cells)
    }

    /// Indexes `quads` (corners `[p00, p10, p01, p11]`), `owners[k]` being the patch of
    /// `quads[k]`; `None` when there is none. Panics if the two lengths differ.
    pub fn from_quads(quads: &[Quad], owners: &[u32]) -> Option<PatchSurface> {
        assert_eq!(quads.len(), owners.len(), "one owner per quad");
        let positions: Vec<Vec3> = quads.iter().flatten().copied().collect();
        let blocks = owners
            .iter()
            .enumerate()
            .map(|(k, &owner)| Block {
                start: 4 * k,
                stride: 2,
                owner,
            })
            .collect();
        let cells = (0..quads.len() as u32)
            .map(|block| Cell { block, node: 0 })
            .collect();
        PatchSurface::index(positions, blocks, cells)
    }

    /// Sorts `cells` and builds the tree over them.
    fn index(positions: Vec<Vec3>, blocks: Vec<Block>, cells: Vec<Cell>) -> Option<PatchSurface> {
        if cells.is_empty() {
            return None;
        }
        let mut surface = PatchSurface {
            positions,
            blocks,
            cells: Vec::new(),
            nodes: Vec::new(),
            leaves: 0,
            bounds: Node::EMPTY,
            grid: None,
        };
        surface.bounds = cells
            .par_iter()
            .map(|&c| Node::of_quad(&surface.quad(c)))
            .reduce(|| Node::EMPTY, Node::union);
        let mut items: Vec<(Vec3, Cell)> = cells
            .par_iter()
            .map(|&c| (quad_centre(&surface.quad(c)), c))
            .collect();
        drop(cells);
        let n = items.len();
        surface.leaves = n.div_ceil(LEAF_QUADS).next_power_of_two();
        let leaves = surface.leaves;
        split_in_halves(&mut items, 0, leaves, &|l| leaf_start(l, n, leaves));
        surface.cells = items.par_iter().map(|&(_, c)| c).collect();
        drop(items);
        let mut nodes = vec![Node::EMPTY; 2 * leaves - 1];
        nodes[leaves - 1..]
            .par_iter_mut()
            .enumerate()
            .for_each(|(l, node)| {
                let cells = &surface.cells[leaf_start(l, n, leaves)..leaf_start(l + 1, n, leaves)];
                *node = cells
                    .iter()
                    .map(|&c| Node::of_quad(&surface.quad(c)))
                    .fold(Node::EMPTY, Node::union);
            });
        // Level of `width` nodes: indices width - 1 .. 2 * width - 1; children of node k are
        // 2k + 1 and 2k + 2, on the level below.
        let mut width = surface.leaves / 2;
        while width >= 1 {
            let (upper, lower) = nodes.split_at_mut(2 * width - 1);
            upper[width - 1..]
                .par_iter_mut()
                .enumerate()
                .for_each(|(i, node)| *node = lower[2 * i].union(lower[2 * i + 1]));
            width /= 2;
        }
        surface.nodes = nodes;
        let boxes: Vec<(Vec3, Vec3)> = surface
            .cells
            .par_iter()
            .map(|&c| {
                let b = Node::of_quad(&surface.quad(c));
                (b.lo, b.hi)
            })
            .collect();
        surface.grid = CellGrid::build(&boxes);
        Some(surface)
    }

    /// The corners of `cell`.
    #[inline]
    fn quad(&self, cell: Cell) -> Quad {
        let block = self.blocks[cell.block as usize];
        let k = block.start + cell.node as usize;
        let p = &self.positions;
        [p[k], p[k + 1], p[k + block.stride], p[k + block.stride + 1]]
    }

    /// Number of drawable cells indexed.
    pub fn cell_count(&self) -> usize {
        self.cells.len()
    }

    /// Bounds `(min, max)` of the indexed cells (caller's coordinates).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.bounds.lo, self.bounds.hi)
    }

    /// Distance from `p` to the nearest point of the patch surface and the patch that point
    /// belongs to (the lower patch index on a tie).
    pub fn nearest(&self, p: Vec3) -> (f32, u32) {
        let (d, owner, _) = self.search(p, None);
        (d, owner)
    }

    /// [`PatchSurface::nearest`], and the nearest cell. The search starts from the distance
    /// to `hint` (the previous query's cell, usually as near as the best) and the cells of
    /// the query's own grid cell, then reads the grid cells around it that can hold a nearer
    /// cell; when that neighbourhood is too wide (a point far from the surface) it descends
    /// the tree instead, pruning every box farther than the best so far. The result is the
    /// same with any hint and either way.
    fn search(&self, p: Vec3, hint: Option<Cell>) -> (f32, u32, Cell) {
        let mut best = match hint {
            Some(c) => Best {
                distance: distance_to_quad(p, &self.quad(c)),
                owner: self.blocks[c.block as usize].owner,
                cell: c,
            },
            None => Best {
                distance: f32::INFINITY,
                owner: NO_PATCH,
                cell: self.cells[0],
            },
        };
        if let Some(grid) = &self.grid {
            // First the cells that can hold a cell containing `p` (its own one, for a point on
            // the surface), then those that can hold one nearer than the best found.
            let first = grid.cells_within(p, 0.0);
            if first.count() <= MAX_GRID_CELLS {
                self.consider_all(p, grid.extras(), &mut best);
                grid.visit(&first, &CellRange::EMPTY, |items| {
                    self.consider_all(p, items, &mut best)
                });
                let r = f64::from(best.distance) * (1.0 + f64::from(PRUNE_SLACK));
                let rest = grid.cells_within(p, r);
                if rest.count() <= MAX_GRID_CELLS {
                    grid.visit(&rest, &first, |items| {
                        self.consider_all(p, items, &mut best)
                    });
                    return (best.distance, best.owner, best.cell);
                }
            }
        }
        self.descend(p, &mut best);
        (best.distance, best.owner, best.cell)
    }

    /// [`PatchSurface::consider`] for the cells `items` (indices into `cells`).
    #[inline]
    fn consider_all(&self, p: Vec3, items: &[u32], best: &mut Best) {
        for &k in items {
            self.consider(p, self.cells[k as usize], best);
        }
    }

    /// Takes `cell` as `best` when it is nearer to `p` (or as near, of a lower patch); its
    /// box is tested first.
    #[inline]
    fn consider(&self, p: Vec3, cell: Cell, best: &mut Best) {
        let quad = self.quad(cell);
        if !near_enough(Node::of_quad(&quad).distance_squared(p), best.distance) {
            return;
        }
        let d = distance_to_quad(p, &quad);
        let o = self.blocks[cell.block as usize].owner;
        if d < best.distance || (d == best.distance && o < best.owner) {
            *best = Best {
                distance: d,
                owner: o,
                cell,
            };
        }
    }

    /// Improves `best` by a descent of the tree, nearer child first, pruning every box
    /// farther than the best so far.
    fn descend(&self, p: Vec3, best: &mut Best) {
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
                    self.consider(p, cell, best);
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

    /// [`PatchSurface::nearest`] for every point, in parallel, in the order given (see the
    /// module docs for the query order).
    pub fn nearest_all(&self, points: &[Vec3]) -> (Vec<f32>, Vec<u32>) {
        let mut order: Vec<(u64, u32)> = points
            .par_iter()
            .enumerate()
            .map(|(k, &p)| (morton(p, &self.bounds), k as u32))
            .collect();
        order.par_sort_unstable();
        let found: Vec<(f32, u32)> = order
            .par_chunks(QUERY_CHUNK)
            .flat_map_iter(|chunk| {
                let mut hint = None;
                chunk.iter().map(move |&(_, k)| {
                    let (d, owner, cell) = self.search(points[k as usize], hint);
                    hint = Some(cell);
                    (d, owner)
                })
            })
            .collect();
        let mut distances = vec![0.0f32; points.len()];
        let mut owners = vec![NO_PATCH; points.len()];
        for (&(_, k), &(d, o)) in order.iter().zip(&found) {
            distances[k as usize] = d;
            owners[k as usize] = o;
        }
        (distances, owners)
    }
}

/// The nearest cell found so far, its distance and patch.
#[derive(Clone, Copy, Debug)]
struct Best {
    distance: f32,
    owner: u32,
    cell: Cell,
}

/// Whether a box at squared distance `d2` may hold a cell as near as `best` (with the
/// relative slack [`PRUNE_SLACK`] for rounding).
#[inline]
fn near_enough(d2: f32, best: f32) -> bool {
    d2 < f32::INFINITY && d2 <= best * best * (1.0 + PRUNE_SLACK)
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
    items: &mut [(Vec3, Cell)],
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

fn quad_centre(q: &Quad) -> Vec3 {
    (q[0] + q[1] + q[2] + q[3]) * 0.25
}

/// The Morton code of `p` in the frame of `bounds` (points outside are clamped to it).
fn morton(p: Vec3, bounds: &Node) -> u64 {
    let scale = ((1u32 << MORTON_BITS) - 1) as f32;
    let extent = (bounds.hi - bounds.lo).max(Vec3::splat(f32::MIN_POSITIVE));
    let unit = ((p - bounds.lo) / extent).clamp(Vec3::ZERO, Vec3::ONE) * scale;
    // `as` saturates, and a NaN becomes 0.
    spread(unit.x as u32) | (spread(unit.y as u32) << 1) | (spread(unit.z as u32) << 2)
}

/// The low 21 bits of `v`, two zero bits inserted after each.
fn spread(v: u32) -> u64 {
    let mut x = u64::from(v) & 0x1f_ffff;
    x = (x | (x << 32)) & 0x1f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x1f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use spatch_mesh::SplitMix64;

    /// A wavy sheet of `n × n` cells, in patches of `per` cells a side, with a gap.
    fn sheet(n: usize, per: usize) -> (Vec<Quad>, Vec<u32>) {
        let h = |x: f32, y: f32| (x * 3.0).sin() * 0.1 + y * y * 0.2;
        let step = 1.0 / n as f32;
        let at = |i: usize, j: usize| {
            let (x, y) = (i as f32 * step, j as f32 * step);
            Vec3::new(x, y, h(x, y))
        };
        let (mut quads, mut owners) = (Vec::new(), Vec::new());
        for j in 0..n {
            for i in 0..n {
                if (n / 3..n / 2).contains(&i) && (n / 3..n / 2).contains(&j) {
                    continue;
                }
                quads.push([at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]);
                owners.push(((j / per) * n.div_ceil(per) + i / per) as u32);
            }
        }
        (quads, owners)
    }

    fn linear_scan(p: Vec3, quads: &[Quad], owners: &[u32]) -> (f32, u32) {
        let (mut best, mut owner) = (f32::INFINITY, NO_PATCH);
        for (q, &o) in quads.iter().zip(owners) {
            let d = distance_to_quad(p, q);
            if d < best || (d == best && o < owner) {
                (best, owner) = (d, o);
            }
        }
        (best, owner)
    }

    #[test]
    fn morton_interleaves_bits() {
        assert_eq!(spread(0b1011), 0b001_000_001_001);
        let b = Node {
            lo: Vec3::ZERO,
            hi: Vec3::ONE,
        };
        assert_eq!(morton(Vec3::ZERO, &b), 0);
        assert_eq!(morton(Vec3::ONE, &b), (1u64 << 63) - 1);
        assert_eq!(morton(Vec3::splat(-5.0), &b), 0);
    }

    #[test]
    fn nearest_equals_a_linear_scan() {
        let (quads, owners) = sheet(40, 7);
        let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
        assert_eq!(surface.cell_count(), quads.len());
        let mut rng = SplitMix64::new(3);
        let mut r = |lo: f32, hi: f32| lo + (hi - lo) * rng.next_f64() as f32;
        // Near the sheet, in the gap, off its rim, and far away.
        let points: Vec<Vec3> = (0..3000)
            .map(|k| {
                let spread = [0.01, 0.2, 3.0, 1e4][k % 4];
                Vec3::new(
                    r(-spread, 1.0 + spread),
                    r(-spread, 1.0 + spread),
                    r(-spread, spread),
                )
            })
            .collect();
        let (all_d, all_o) = surface.nearest_all(&points);
        for (k, &p) in points.iter().enumerate() {
            let expected = linear_scan(p, &quads, &owners);
            assert_eq!(surface.nearest(p), expected, "{p}");
            assert_eq!((all_d[k], all_o[k]), expected, "{p}");
        }
    }

    /// Random twisted quads of sizes spread over three decades, a few of them long slivers
    /// (the grid's extras), in a unit cube.
    fn quad_soup(n: usize, seed: u64) -> (Vec<Quad>, Vec<u32>) {
        let mut rng = SplitMix64::new(seed);
        let mut r = move || rng.next_f64() as f32;
        let (mut quads, mut owners) = (Vec::new(), Vec::new());
        for k in 0..n {
            let size = 10f32.powf(-3.0 + 2.0 * r()) * if k % 50 == 0 { 40.0 } else { 1.0 };
            let o = Vec3::new(r(), r(), r());
            let (u, v) = (
                Vec3::new(r(), r(), r()) - 0.5,
                Vec3::new(r(), r(), r()) - 0.5,
            );
            let twist = (Vec3::new(r(), r(), r()) - 0.5) * 0.3;
            let (u, v) = (u * size, v * size);
            quads.push([o, o + u, o + v, o + u + v + twist * size]);
            owners.push((k % 17) as u32);
        }
        (quads, owners)
    }

    #[test]
    fn random_quad_soups_match_a_linear_scan() {
        for seed in 0..4 {
            let (quads, owners) = quad_soup(3000, seed);
            let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
            assert!(surface.grid.is_some());
            let mut rng = SplitMix64::new(100 + seed);
            let mut r = move || rng.next_f64() as f32;
            let points: Vec<Vec3> = (0..4000)
                .map(|k| match k % 3 {
                    // On a quad, near one, anywhere in the cube and around it.
                    0 => {
                        let q = &quads[(r() * quads.len() as f32) as usize % quads.len()];
                        crate::quad_distance::bilinear(q, r(), r())
                    }
                    1 => {
                        let q = &quads[(r() * quads.len() as f32) as usize % quads.len()];
                        q[0] + (Vec3::new(r(), r(), r()) - 0.5) * 0.01
                    }
                    _ => Vec3::new(r(), r(), r()) * 3.0 - 1.0,
                })
                .collect();
            let (all_d, all_o) = surface.nearest_all(&points);
            for (k, &p) in points.iter().enumerate() {
                let expected = linear_scan(p, &quads, &owners);
                assert_eq!(surface.nearest(p), expected, "seed {seed}: {p}");
                assert_eq!((all_d[k], all_o[k]), expected, "seed {seed}: {p}");
            }
        }
    }

    #[test]
    fn results_do_not_depend_on_the_thread_count() {
        let (quads, owners) = sheet(30, 5);
        let surface = PatchSurface::from_quads(&quads, &owners).unwrap();
        let points: Vec<Vec3> = (0..5000)
            .map(|k| Vec3::new((k % 71) as f32 / 70.0, (k / 71) as f32 / 70.0, 0.05))
            .collect();
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| surface.nearest_all(&points));
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap()
            .install(|| surface.nearest_all(&points));
        assert_eq!(one, two);
    }

    /// Two tilted, overlapping patches with empty nodes, in a scene far from the origin.
    fn small_scene() -> Scene {
        use spatch_format::{ColourChannel, Frame, GridSize, Patch, EMPTY};
        let patch = |origin: Vec3, ax: Vec3, ay: Vec3, seed: u64| {
            let mut rng = SplitMix64::new(seed);
            let d: Vec<u16> = (0..81)
                .map(|k| {
                    if k % 13 == 5 {
                        EMPTY
                    } else {
                        (rng.next_u64() % 40) as u16
                    }
                })
                .collect();
            let az = ax.cross(ay).normalize() * 0.01;
            Patch::new(
                Frame::new(origin, ax, ay, az).unwrap(),
                GridSize::new(9, 9).unwrap(),
                d,
                None,
            )
            .unwrap()
        };
        let patches = vec![
            patch(Vec3::ZERO, Vec3::X * 0.1, Vec3::Y * 0.1, 1),
            patch(
                Vec3::new(0.5, 0.2, 0.1),
                Vec3::new(0.06, 0.08, 0.0),
                Vec3::new(0.0, 0.0, 0.1),
                2,
            ),
        ];
        Scene::new(glam::DVec3::splat(1e5), ColourChannel::None, patches).unwrap()
    }

    #[test]
    fn scene_cells_match_a_brute_force_over_drawable_cells() {
        let scene = small_scene();
        let shift = Vec3::new(1.0, -2.0, 0.5);
        let (mut quads, mut owners) = (Vec::new(), Vec::new());
        for (k, patch) in scene.patches().iter().enumerate() {
            for j in 0..8 {
                for i in 0..8 {
                    if patch.cell_is_drawable(i, j) {
                        let at = |a, b| patch.node_position(a, b).unwrap() + shift;
                        quads.push([at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]);
                        owners.push(k as u32);
                    }
                }
            }
        }
        let surface = PatchSurface::new(&scene, shift).unwrap();
        assert_eq!(surface.cell_count(), quads.len());
        let mut rng = SplitMix64::new(9);
        for _ in 0..2000 {
            let mut r = || rng.next_f64() as f32 * 1.4 - 0.2;
            let p = Vec3::new(r(), r(), r() * 0.5) + shift;
            assert_eq!(surface.nearest(p), linear_scan(p, &quads, &owners), "{p}");
        }
    }

    #[test]
    fn no_quads_no_surface() {
        assert!(PatchSurface::from_quads(&[], &[]).is_none());
    }
}
