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
//! The index: a flat grid of the cells by box centre (`cell_grid.rs`), the cells stored in
//! its order (a grid cell's cells are one run of `cells` and `boxes`), answers the queries:
//! the grid cells within reach of the point, then those within the best distance found. A
//! query whose neighbourhood would pass `MAX_GRID_CELLS` grid cells (a point far from the
//! surface, e.g. of a source that does not overlap the scene) searches a coarser index
//! instead, built on the first such query: the patches' boxes, nearest first, and the cells
//! of each (`patch_surface/blocks.rs`) when the blocks are patches of many cells, else a
//! bounding volume hierarchy over the cells (`patch_surface/tree.rs`); either costs a few
//! more boxes, not a scan of empty space. Every path prunes a cell whose box is
//! farther than the best distance so far (with a relative slack of [`PRUNE_SLACK`] for
//! rounding) and no other: the result is exactly the minimum of the quad distance over all
//! quads (ties go to the lower patch index), which the tests check against a linear scan.
//!
//! [`PatchSurface::nearest_all`] answers many points at once, grouped by grid cell
//! (`patch_surface/batch.rs`): the cells near a run of points of one grid cell are
//! gathered once for all of them, each point takes the quad distance of the nearest box
//! first, and only points farther from the surface than the gathered margin are searched
//! one by one. Without a grid it queries in Morton order of the points, each search
//! starting from the distance to the previous query's nearest cell. Either way the results
//! come in the caller's order and do not depend on the order, the hint or the thread count.
//!
//! Memory: the node positions of every patch (12 bytes per node; a cell's corners are read
//! from there, not copied), 8 bytes per drawable cell (its patch and corner) and 24 for its
//! box; the grid's block table (a few bytes per cell); the patches' index, when built, 4
//! bytes per cell and 24 per patch (the tree instead, for quads given alone, 16 bytes per
//! cell). The build holds 16 bytes of sort key per cell beside the cells (the grid reads the
//! boxes from the corners until the cells are in its order).
//!
//! Cost: build O(C log C) for C cells (a sort by grid cell); a query on the surface a few
//! hash look-ups, a few dozen box tests and usually one quad distance.
//!
//! Based on: Ericson, *Real-Time Collision Detection* (2005), §7.1 (uniform grids) and
//! §6.2, §6.6 (hierarchies in arrays, closest-point traversal).

use std::sync::OnceLock;

use glam::Vec3;
use rayon::prelude::*;
use spatch_format::Scene;

use crate::cell_grid::{CellGrid, CellRange};
use crate::quad_distance::{distance_to_quad, quad_beyond, Quad};
use blocks::{BlockIndex, MIN_CELLS_PER_BLOCK};
use tree::CellTree;

mod batch;
mod blocks;
mod tree;

/// Quads per leaf of the tree.
pub const LEAF_QUADS: usize = 4;

/// Relative slack on squared box distances when pruning, so that f32 rounding of a box
/// distance never prunes a quad exactly as near as the best one.
pub const PRUNE_SLACK: f32 = 1e-5;

/// The patch index of a point when there is no drawable cell at all.
pub const NO_PATCH: u32 = u32::MAX;

/// Bits of each axis in a Morton code.
const MORTON_BITS: u32 = 21;

/// Queries per parallel work item.
const QUERY_CHUNK: usize = 2048;

/// Most grid cells a query reads around its own before it searches the tree instead.
const MAX_GRID_CELLS: f64 = 64.0;

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
    /// The cells, grouped by grid cell (the grid's order; as given without a grid).
    cells: Vec<Cell>,
    /// The box of each cell, in the same order.
    boxes: Vec<Node>,
    /// Bounds of all cells (the frame of the Morton codes).
    bounds: Node,
    /// The flat grid of the cells by their centres, the first place a query looks; `None`
    /// when the cells have no extent.
    grid: Option<CellGrid>,
    /// The tree over the cells, built by the first query that needs it (surfaces of few
    /// cells per block).
    tree: OnceLock<CellTree>,
    /// The blocks' boxes and cells, built by the first query that needs it (surfaces of
    /// patches: see `blocks.rs`).
    block_index: OnceLock<BlockIndex>,
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

    /// Orders `cells` by grid cell and keeps their boxes (the tree waits for a query).
    fn index(positions: Vec<Vec3>, blocks: Vec<Block>, cells: Vec<Cell>) -> Option<PatchSurface> {
        if cells.is_empty() {
            return None;
        }
        let mut surface = PatchSurface {
            positions,
            blocks,
            cells,
            boxes: Vec::new(),
            bounds: Node::EMPTY,
            grid: None,
            tree: OnceLock::new(),
            block_index: OnceLock::new(),
        };
        // The grid reads each cell's box from its corners, so no box array is held beside
        // its sort keys; the boxes are stored once the cells are in the grid's order.
        let box_of = |k: usize| {
            let b = Node::of_quad(&surface.quad(surface.cells[k]));
            (b.lo, b.hi)
        };
        if let Some((grid, order)) = CellGrid::build(surface.cells.len(), box_of) {
            let cells = &surface.cells;
            let sorted: Vec<Cell> = order.par_iter().map(|&k| cells[k as usize]).collect();
            drop(order);
            surface.cells = sorted;
            surface.grid = Some(grid);
        }
        surface.boxes = surface
            .cells
            .par_iter()
            .map(|&c| Node::of_quad(&surface.quad(c)))
            .collect();
        surface.bounds = surface
            .boxes
            .par_iter()
            .copied()
            .reduce(|| Node::EMPTY, Node::union);
        Some(surface)
    }

    /// The tree over the cells (built on first use).
    fn tree(&self) -> &CellTree {
        self.tree.get_or_init(|| CellTree::build(&self.boxes))
    }

    /// Whether searches beyond the grid go through the patches' boxes (`blocks.rs`): the
    /// blocks are patches of many cells.
    fn searches_blocks(&self) -> bool {
        self.blocks.len() * MIN_CELLS_PER_BLOCK <= self.cells.len()
    }

    /// Most grid cells a query reads before it searches beyond the grid: [`MAX_GRID_CELLS`],
    /// or as many as there are patches when that search tests and sorts every patch's box
    /// (a grid cell read costs about one box test). Why: on a dense scene the largest cells
    /// can widen most queries' neighbourhoods past 64 grid cells, and each such query then
    /// sorted all the patches' boxes (a bunny subdivided to 1.1 M triangles, 24,425 patches:
    /// 803 s to measure its conversion's error, 64 % of it in those sorts; 27 s now).
    fn grid_cell_limit(&self) -> f64 {
        if self.searches_blocks() {
            MAX_GRID_CELLS.max(self.blocks.len() as f64)
        } else {
            MAX_GRID_CELLS
        }
    }

    /// Improves `best` for `p` over every cell: through the patches' boxes when the blocks
    /// are patches of many cells (`blocks.rs`), else through the tree over the cells.
    fn search_everywhere(&self, p: Vec3, best: &mut Best) {
        if self.searches_blocks() {
            let index = self.block_index.get_or_init(|| {
                BlockIndex::build(self.blocks.len(), &self.boxes, |k| {
                    self.cells[k].block as usize
                })
            });
            index.descend(self, p, best);
        } else {
            self.tree().descend(self, p, best);
        }
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

    /// [`PatchSurface::nearest`], and the nearest cell (its position in `cells`). The search
    /// starts from the distance to `hint` (a cell found near `p`, usually as near as the
    /// best) and the cells of the query's own grid cell, then reads the grid cells around
    /// it that can hold a nearer cell; when that neighbourhood is too wide (a point far from
    /// the surface) it searches every cell through the patches' boxes or the tree instead,
    /// pruning every box farther than the best so far. The result is the same with any hint
    /// and either way.
    fn search(&self, p: Vec3, hint: Option<usize>) -> (f32, u32, usize) {
        let mut best = match hint {
            Some(k) => Best {
                distance: distance_to_quad(p, &self.quad(self.cells[k])),
                owner: self.owner(k),
                cell: k,
            },
            None => Best {
                distance: f32::INFINITY,
                owner: NO_PATCH,
                cell: 0,
            },
        };
        if let Some(grid) = &self.grid {
            // First the cells that can hold a cell containing `p` (its own one, for a point on
            // the surface), then those that can hold one nearer than the best found.
            let limit = self.grid_cell_limit();
            let first = grid.cells_within(p, 0.0);
            if first.count() <= limit {
                self.consider_all(p, grid.extras(), &mut best);
                grid.visit(&first, &CellRange::EMPTY, |items| {
                    self.consider_all(p, items, &mut best)
                });
                let r = f64::from(best.distance) * (1.0 + f64::from(PRUNE_SLACK));
                let rest = grid.cells_within(p, r);
                if rest.count() <= limit {
                    grid.visit(&rest, &first, |items| {
                        self.consider_all(p, items, &mut best)
                    });
                    return (best.distance, best.owner, best.cell);
                }
            }
        }
        self.search_everywhere(p, &mut best);
        (best.distance, best.owner, best.cell)
    }

    /// The patch of the cell at position `k`.
    #[inline]
    fn owner(&self, k: usize) -> u32 {
        self.blocks[self.cells[k].block as usize].owner
    }

    /// [`PatchSurface::consider`] for the cells at positions `items`.
    #[inline]
    fn consider_all(&self, p: Vec3, items: std::ops::Range<usize>, best: &mut Best) {
        for k in items {
            self.consider(p, k, best);
        }
    }

    /// Takes the cell at position `k` as `best` when it is nearer to `p` (or as near, of a
    /// lower patch); its box is tested first.
    #[inline]
    fn consider(&self, p: Vec3, k: usize, best: &mut Best) {
        if k == best.cell && best.owner != NO_PATCH
            || !near_enough(self.boxes[k].distance_squared(p), best.distance)
        {
            return;
        }
        let quad = self.quad(self.cells[k]);
        if quad_beyond(p, &quad, best.distance) {
            return;
        }
        let d = distance_to_quad(p, &quad);
        let o = self.owner(k);
        if d < best.distance || (d == best.distance && o < best.owner) {
            *best = Best {
                distance: d,
                owner: o,
                cell: k,
            };
        }
    }

    /// [`PatchSurface::nearest`] for every point, in parallel, in the order given, for a
    /// surface without a grid (see the module docs for the query order).
    fn nearest_all_in_morton_order(
        &self,
        points: &[Vec3],
        place: Option<&[u32]>,
    ) -> (Vec<f32>, Vec<u32>) {
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
        scatter_to_input_order(&order, &found, place)
    }
}

/// The answers `found` (one `(distance, patch)` per entry of `order`, whose second field is
/// the point's index) put where `place` puts each point's answer (the point's own index, or
/// the caller's: see [`PatchSurface::nearest_all_placed`]), as `(distances, patches)`.
fn scatter_to_input_order(
    order: &[(u64, u32)],
    found: &[(f32, u32)],
    place: Option<&[u32]>,
) -> (Vec<f32>, Vec<u32>) {
    let count = order.len();
    let mut distances = vec![0.0f32; count];
    let mut owners = vec![NO_PATCH; count];
    for (&(_, k), &(d, o)) in order.iter().zip(found) {
        let at = place.map_or(k, |place| place[k as usize]) as usize;
        distances[at] = d;
        owners[at] = o;
    }
    (distances, owners)
}

/// The nearest cell found so far (its position in `cells`), its distance and patch.
#[derive(Clone, Copy, Debug)]
struct Best {
    distance: f32,
    owner: u32,
    cell: usize,
}

/// Whether a box at squared distance `d2` may hold a cell as near as `best` (with the
/// relative slack [`PRUNE_SLACK`] for rounding).
#[inline]
fn near_enough(d2: f32, best: f32) -> bool {
    d2 < f32::INFINITY && d2 <= best * best * (1.0 + PRUNE_SLACK)
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
mod tests;
