//! A flat, sparse uniform grid over boxes (the cells of a [`crate::PatchSurface`]): which
//! boxes have their centre near a point, in a few hash look-ups instead of a tree descent.
//!
//! Input: one axis-aligned box per item (item `k` is `boxes[k]`). Output: a [`CellGrid`]
//! and an order of the items, grouped by grid cell with the extras last, which the caller
//! stores its items in (so the items of a grid cell are one run of its arrays). The grid
//! lists, for any query point `p` and radius `r`, the grid cells holding every item whose
//! box could hold a point within `r` of `p` on each axis ([`CellGrid::cells_within`]), and
//! visits the runs of items (positions in that order) of such a range of cells, less a
//! range already visited ([`CellGrid::visit`]).
//!
//! Each item sits in exactly one grid cell, the one holding its box centre. Its box then
//! lies within `reach` (the largest half-extent of any gridded box, per axis) of that cell,
//! so every box reaching within `r` of `p` has its centre in the cells overlapping
//! `p ± (r + reach)`: those are the cells visited. The cell side is [`GRID_SCALE`] times the
//! median half-extent; boxes more than [`BIG_BOX`] times the median (a few stretched cells)
//! would inflate `reach` for every query, so they are kept aside in a short list visited by
//! every query ([`CellGrid::extras`]; the limit on them doubles until at most
//! [`MAX_EXTRAS`] are left). Coordinates are reduced to grid cells in f64 with a margin, so
//! rounding never drops a box that qualifies.
//!
//! [`CellGrid::visit_near`] skips a cell whose boxes all lie beyond a gap from a box of
//! queries: each cell keeps the largest half-extent of its own boxes, so a cell far from the
//! queries is passed over whole, where the range around them (widened by the largest
//! half-extent of all boxes) would read each of its boxes (half the error measurement's
//! gathers on a scan set went to boxes of such cells).
//!
//! Storage: none per item (the caller keeps its items in the grid's order); the grid cells
//! in blocks of 4³, each non-empty block a run of 65 item offsets and 65 half-extents
//! (520 bytes); an
//! open-addressing hash table (linear probing) from a block's packed coordinates to its
//! run, 16 bytes a slot, at most half full. Blocks keep the cells a query reads in one or
//! two cache lines: hashing every cell alone cost a cache miss per cell read.
//!
//! Cost: build O(n log n) (a parallel sort of the items by grid cell); a query visits the
//! `(1 + 2(r + reach)/side)³` cells around it at most, each one hash probe.
//!
//! Based on: Ericson, *Real-Time Collision Detection* (2005), §7.1 (uniform grids, hashed
//! storage, objects inserted by their centre with the neighbourhood widened by their extent).

use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Grid cell side over the median box half-extent (largest axis). Two median boxes span a
/// cell: a query on the surface reads a handful of cells of a few boxes each.
pub(crate) const GRID_SCALE: f64 = 4.0;

/// Boxes whose half-extent exceeds this many median half-extents (on some axis) start out
/// outside the grid, in the extras list.
pub(crate) const BIG_BOX: f64 = 2.0;

/// Most boxes kept outside the grid: past that the [`BIG_BOX`] limit doubles.
pub(crate) const MAX_EXTRAS: usize = 64;

/// Bits of each axis of a packed cell coordinate (so at most 2²¹ cells an axis).
const AXIS_BITS: u32 = 21;

/// Margin in grid cells added to both ends of a query's cell range against rounding.
const ROUNDING_MARGIN: f64 = 1e-6;

/// Bits of each axis of a cell's position within its block: blocks of 4³ grid cells are
/// hashed, so the cells a query reads around it usually share one block and a cache line
/// or two of `starts` (one hash slot per cell cost a cache miss for every cell read).
const BLOCK_BITS: u32 = 2;

/// Grid cells per block.
const BLOCK_CELLS: usize = 1 << (3 * BLOCK_BITS);

/// Marks an unused hash slot (no packed coordinate reaches it: each axis is below 2²¹).
const EMPTY_KEY: u64 = u64::MAX;

/// One hash slot: a block's packed coordinates and where its [`BLOCK_CELLS`] + 1 run starts
/// begin in `starts`.
#[derive(Clone, Copy, Debug)]
struct Slot {
    key: u64,
    base: u32,
}

/// The grid (see the module docs).
#[derive(Debug)]
pub(crate) struct CellGrid {
    /// Centre of grid cell (0, 0, 0)'s lower corner.
    origin: DVec3,
    /// Cell side.
    side: f64,
    /// Cells per axis (each at most 2²¹).
    dims: [i64; 3],
    /// Largest half-extent of a gridded box, per axis.
    reach: DVec3,
    /// Per non-empty block, where each of its cells' items start in the grid's order of
    /// the items (and where the block's end): cell `l` of the block at `base` holds
    /// `starts[base + l]..starts[base + l + 1]`.
    starts: Vec<u32>,
    /// Per entry of `starts`, the largest half-extent (any axis, rounded up) of the boxes of
    /// that cell (0 for an empty cell and the blocks' end entries): a cell's boxes lie
    /// within it of the cell, which lets [`CellGrid::visit_near`] skip a cell whole.
    reaches: Vec<f32>,
    /// Open-addressing table of the non-empty blocks.
    slots: Vec<Slot>,
    /// Positions of the items kept out of the grid (the end of the order), visited by
    /// every query.
    extras: std::ops::Range<usize>,
}

/// Half-extent and centre of a box, in f64 (exact for f32 corners).
fn centre_and_half(lo: Vec3, hi: Vec3) -> (DVec3, DVec3) {
    let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
    ((lo + hi) * 0.5, (hi - lo) * 0.5)
}

/// The order to store the items in: the gridded items of `keyed` in its order, then the
/// `extras`.
fn stored_order(keyed: Vec<(u64, u32)>, extras: Vec<u32>) -> Vec<u32> {
    let mut order: Vec<u32> = Vec::with_capacity(keyed.len() + extras.len());
    order.par_extend(keyed.par_iter().map(|&(_, k)| k));
    drop(keyed);
    order.extend(extras);
    order
}

impl CellGrid {
    /// Grids `boxes` (`(lo, hi)` per item) and gives the order to store the items in: the
    /// item at each position, grouped by grid cell, the extras last. `None` when there are
    /// none or all are points or not finite (the caller then searches otherwise).
    pub(crate) fn build(
        len: usize,
        box_of: impl Fn(usize) -> (Vec3, Vec3) + Sync,
    ) -> Option<(CellGrid, Vec<u32>)> {
        if len == 0 || len >= u32::MAX as usize {
            return None;
        }
        let half_of = |k: usize| {
            let (lo, hi) = box_of(k);
            centre_and_half(lo, hi)
        };
        let median = Self::median_half(len, &half_of)?;
        let (extras, limit) = Self::split_extras(len, &half_of, median);
        // Exactly the boxes `split_extras` did not set aside (a NaN extent among them).
        let in_grid = |k: usize| {
            let half = half_of(k).1.max_element();
            half.partial_cmp(&limit) != Some(std::cmp::Ordering::Greater)
        };
        let (lo, hi, reach) = Self::gridded_bounds(len, &half_of, &in_grid)?;
        let mut grid = Self::sized(lo, hi, reach, median);
        let keyed = grid.sorted_keys(len, &half_of, &in_grid);
        grid.fill(&keyed);
        grid.reaches = grid.cell_reaches(&keyed, &half_of);
        grid.extras = keyed.len()..keyed.len() + extras.len();
        let order = stored_order(keyed, extras);
        Some((grid, order))
    }

    /// The median over the boxes of their largest half-extent; `None` unless it is
    /// positive and finite.
    fn median_half(len: usize, half_of: &(impl Fn(usize) -> (DVec3, DVec3) + Sync)) -> Option<f64> {
        let mut halves: Vec<f64> = (0..len)
            .into_par_iter()
            .map(|k| half_of(k).1.max_element())
            .collect();
        let mid = halves.len() / 2;
        let median = *halves.select_nth_unstable_by(mid, f64::total_cmp).1;
        drop(halves);
        if !(median > 0.0 && median.is_finite()) {
            return None;
        }
        Some(median)
    }

    /// The lowest and highest centre and the largest half-extent (per axis) of the gridded
    /// boxes; `None` when the centres' bounds are not finite.
    fn gridded_bounds(
        len: usize,
        half_of: &(impl Fn(usize) -> (DVec3, DVec3) + Sync),
        in_grid: &(impl Fn(usize) -> bool + Sync),
    ) -> Option<(DVec3, DVec3, DVec3)> {
        let (lo, hi, reach) = (0..len)
            .into_par_iter()
            .filter(|&k| in_grid(k))
            .map(|k| {
                let (c, h) = half_of(k);
                (c, c, h)
            })
            .reduce(
                || (DVec3::INFINITY, DVec3::NEG_INFINITY, DVec3::ZERO),
                |a, b| (a.0.min(b.0), a.1.max(b.1), a.2.max(b.2)),
            );
        if !lo.is_finite() || !hi.is_finite() {
            return None;
        }
        Some((lo, hi, reach))
    }

    /// An empty grid over the centres `lo..=hi`: cells [`GRID_SCALE`] medians wide, or
    /// wider where the span would need more than 2²¹ − 1 cells an axis.
    fn sized(lo: DVec3, hi: DVec3, reach: DVec3, median: f64) -> CellGrid {
        let max_cells = f64::from((1u32 << AXIS_BITS) - 1);
        let side = (GRID_SCALE * median).max((hi - lo).max_element() / (max_cells - 1.0));
        let span = ((hi - lo) / side).floor() + DVec3::ONE;
        let dims = [span.x as i64, span.y as i64, span.z as i64];
        CellGrid {
            origin: lo,
            side,
            dims,
            reach,
            starts: Vec::new(),
            reaches: Vec::new(),
            slots: Vec::new(),
            extras: 0..0,
        }
    }

    /// The gridded items, each with the key of the cell holding its box centre, sorted by
    /// key (then item).
    fn sorted_keys(
        &self,
        len: usize,
        half_of: &(impl Fn(usize) -> (DVec3, DVec3) + Sync),
        in_grid: &(impl Fn(usize) -> bool + Sync),
    ) -> Vec<(u64, u32)> {
        let mut keyed: Vec<(u64, u32)> = (0..len)
            .into_par_iter()
            .filter(|&k| in_grid(k))
            .map(|k| {
                let c = half_of(k).0;
                (self.key_of(self.cell_of(c)), k as u32)
            })
            .collect();
        keyed.par_sort_unstable();
        keyed
    }

    /// The boxes kept out of the grid and the half-extent limit of the rest: the limit
    /// starts at [`BIG_BOX`] medians and doubles while more than [`MAX_EXTRAS`] exceed it.
    fn split_extras(
        len: usize,
        half_of: &(impl Fn(usize) -> (DVec3, DVec3) + Sync),
        median: f64,
    ) -> (Vec<u32>, f64) {
        let mut limit = BIG_BOX * median;
        loop {
            let extras: Vec<u32> = (0..len as u32)
                .into_par_iter()
                // A non-finite box compares false and stays in the grid's bounds check.
                .filter(|&k| half_of(k as usize).1.max_element() > limit)
                .collect();
            if extras.len() <= MAX_EXTRAS {
                return (extras, limit);
            }
            limit *= 2.0;
        }
    }

    /// Per entry of `starts`, the largest half-extent of the boxes of its cell (the items at
    /// its positions of `keyed`), rounded up to f32.
    fn cell_reaches(
        &self,
        keyed: &[(u64, u32)],
        half_of: &(impl Fn(usize) -> (DVec3, DVec3) + Sync),
    ) -> Vec<f32> {
        let starts = &self.starts;
        (0..starts.len())
            .into_par_iter()
            .map(|at| {
                // The last entry of a block is its end, not a cell.
                if (at + 1) % (BLOCK_CELLS + 1) == 0 {
                    return 0.0;
                }
                let half = keyed[starts[at] as usize..starts[at + 1] as usize]
                    .iter()
                    .map(|&(_, k)| half_of(k as usize).1.max_element())
                    .fold(0.0f64, f64::max);
                let rounded = half as f32;
                if f64::from(rounded) < half {
                    rounded.next_up()
                } else {
                    rounded
                }
            })
            .collect()
    }

    /// Groups the sorted `(key, item)` pairs by block and cell and builds the hash table of
    /// the blocks.
    fn fill(&mut self, keyed: &[(u64, u32)]) {
        let block_of = |key: u64| key >> (3 * BLOCK_BITS);
        let blocks = keyed
            .windows(2)
            .filter(|w| block_of(w[0].0) != block_of(w[1].0))
            .count()
            + 1;
        let size = (2 * blocks).next_power_of_two();
        self.slots = vec![
            Slot {
                key: EMPTY_KEY,
                base: 0,
            };
            size
        ];
        self.starts = Vec::with_capacity(blocks * (BLOCK_CELLS + 1));
        let mut start = 0;
        while start < keyed.len() {
            let block = block_of(keyed[start].0);
            let run = &keyed[start..];
            let end = start + run.partition_point(|&(k, _)| block_of(k) == block);
            let mut at = self.hash(block);
            while self.slots[at].key != EMPTY_KEY {
                at = (at + 1) & (size - 1);
            }
            self.slots[at] = Slot {
                key: block,
                base: self.starts.len() as u32,
            };
            let local = |k: u64| (k & (BLOCK_CELLS as u64 - 1)) as usize;
            for l in 0..=BLOCK_CELLS {
                let first = keyed[start..end].partition_point(|&(k, _)| local(k) < l);
                self.starts.push((start + first) as u32);
            }
            start = end;
        }
    }

    /// The grid cell holding `p` (possibly outside `0..dims`).
    #[inline]
    fn cell_of(&self, p: DVec3) -> [i64; 3] {
        let t = ((p - self.origin) / self.side).floor();
        [t.x as i64, t.y as i64, t.z as i64]
    }

    /// Packed coordinates of an in-range cell: its block's coordinates, then its position
    /// in the block (so a sort by key groups each block's cells).
    #[inline]
    fn key_of(&self, c: [i64; 3]) -> u64 {
        let c = [0, 1, 2].map(|a| c[a].clamp(0, self.dims[a] - 1) as u64);
        let low = (1u64 << BLOCK_BITS) - 1;
        let block_bits = AXIS_BITS - BLOCK_BITS;
        let block = (c[0] >> BLOCK_BITS)
            | ((c[1] >> BLOCK_BITS) << block_bits)
            | ((c[2] >> BLOCK_BITS) << (2 * block_bits));
        let local =
            (c[0] & low) | ((c[1] & low) << BLOCK_BITS) | ((c[2] & low) << (2 * BLOCK_BITS));
        (block << (3 * BLOCK_BITS)) | local
    }

    /// The home slot of `key`: the SplitMix64 finalizer, whose every output bit depends on
    /// every input bit (a plain multiplicative hash clustered the regular keys of a flat
    /// sheet: 7.7 probes per hit instead of 1.46, test `hash_probes_stay_short_on_a_flat_sheet`).
    #[inline]
    fn hash(&self, key: u64) -> usize {
        let mut x = key;
        x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        x ^= x >> 31;
        x as usize & (self.slots.len() - 1)
    }

    /// The positions of the items of grid cell `c` (empty outside the grid or when none is
    /// there).
    #[cfg(test)]
    fn items(&self, c: [i64; 3]) -> std::ops::Range<usize> {
        if (0..3).any(|a| c[a] < 0 || c[a] >= self.dims[a]) {
            return 0..0;
        }
        let local = (self.key_of(c) & (BLOCK_CELLS as u64 - 1)) as usize;
        let corner = c.map(|v| v & !((1i64 << BLOCK_BITS) - 1));
        self.block_base(corner).map_or(0..0, |base| {
            self.starts[base + local] as usize..self.starts[base + local + 1] as usize
        })
    }

    /// The sort key of the grid cell holding `p` (block by block, as the items are stored),
    /// or `None` when `p` lies outside the grid (or is not finite).
    pub(crate) fn key_at(&self, p: Vec3) -> Option<u64> {
        let c = self.cell_of(p.as_dvec3());
        (p.is_finite() && (0..3).all(|a| (0..self.dims[a]).contains(&c[a]))).then(|| self.key_of(c))
    }

    /// The grid cell side.
    pub(crate) fn side(&self) -> f64 {
        self.side
    }

    /// The positions of the items kept out of the grid (every query must visit them
    /// itself).
    pub(crate) fn extras(&self) -> std::ops::Range<usize> {
        self.extras.clone()
    }

    /// The grid cells that may hold a gridded box reaching within `r` of `p` on every axis
    /// (those whose centre lies within `r + reach`), clipped to the grid.
    pub(crate) fn cells_within(&self, p: Vec3, r: f64) -> CellRange {
        let p = p.as_dvec3();
        self.cells_near(p, p, r)
    }

    /// The grid cells that may hold a gridded box reaching within `r` of the box
    /// `lo..=hi` on every axis, clipped to the grid.
    pub(crate) fn cells_near(&self, lo: DVec3, hi: DVec3, r: f64) -> CellRange {
        let widen = self.reach + DVec3::splat(r);
        let lo = (lo - widen - self.origin) / self.side - DVec3::splat(ROUNDING_MARGIN);
        let hi = (hi + widen - self.origin) / self.side + DVec3::splat(ROUNDING_MARGIN);
        // `max`/`min` also take a NaN bound to the whole grid.
        let axis = |a: usize| {
            let from = (lo[a].floor().max(-1.0) as i64).max(0);
            let to = (hi[a].floor().min(self.dims[a] as f64) as i64).min(self.dims[a] - 1);
            (from, to)
        };
        CellRange {
            lo: [axis(0).0, axis(1).0, axis(2).0],
            hi: [axis(0).1, axis(1).1, axis(2).1],
        }
    }

    /// Calls `visit` with the item positions of every grid cell of `range` outside `skip`
    /// (one hash look-up per block of the range).
    pub(crate) fn visit(
        &self,
        range: &CellRange,
        skip: &CellRange,
        visit: impl FnMut(std::ops::Range<usize>),
    ) {
        self.visit_cells(range, skip, |_, _| true, visit);
    }

    /// [`CellGrid::visit`] of the cells of `range` that may hold a box within `gap` of the box
    /// `lo..=hi` on every axis: a cell whose own boxes all lie farther (by its largest
    /// half-extent, `reaches`) is skipped without reading them.
    pub(crate) fn visit_near(
        &self,
        range: &CellRange,
        (lo, hi): (DVec3, DVec3),
        gap: f64,
        visit: impl FnMut(std::ops::Range<usize>),
    ) {
        let margin = ROUNDING_MARGIN * self.side;
        let near = |at: usize, c: [i64; 3]| {
            let cell_lo =
                self.origin + DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) * self.side;
            let widen = f64::from(self.reaches[at]) + margin;
            let (from, to) = (cell_lo - widen, cell_lo + DVec3::splat(self.side + widen));
            (lo - to).max(from - hi).max_element() <= gap
        };
        self.visit_cells(range, &CellRange::EMPTY, near, visit);
    }

    /// Calls `visit` with the item positions of every grid cell of `range` outside `skip`
    /// that `keep` (given the cell's entry in `starts` and its coordinates) keeps.
    fn visit_cells(
        &self,
        range: &CellRange,
        skip: &CellRange,
        keep: impl Fn(usize, [i64; 3]) -> bool,
        mut visit: impl FnMut(std::ops::Range<usize>),
    ) {
        let side = 1i64 << BLOCK_BITS;
        let blocks = |a: usize| (range.lo[a] >> BLOCK_BITS)..=(range.hi[a] >> BLOCK_BITS);
        for bz in blocks(2) {
            for by in blocks(1) {
                for bx in blocks(0) {
                    let corner = [bx * side, by * side, bz * side];
                    let Some(base) = self.block_base(corner) else {
                        continue;
                    };
                    let axis = |a: usize| {
                        range.lo[a].max(corner[a])..=range.hi[a].min(corner[a] + side - 1)
                    };
                    for z in axis(2) {
                        for y in axis(1) {
                            for x in axis(0) {
                                if skip.contains([x, y, z]) {
                                    continue;
                                }
                                let l = (x - corner[0])
                                    | ((y - corner[1]) << BLOCK_BITS)
                                    | ((z - corner[2]) << (2 * BLOCK_BITS));
                                let at = base + l as usize;
                                let items = self.starts[at] as usize..self.starts[at + 1] as usize;
                                if !items.is_empty() && keep(at, [x, y, z]) {
                                    visit(items);
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// Where the run starts of the block whose first grid cell is `corner` begin in
    /// `starts`, or `None` when the block is empty.
    #[inline]
    fn block_base(&self, corner: [i64; 3]) -> Option<usize> {
        let block = self.key_of(corner) >> (3 * BLOCK_BITS);
        let mask = self.slots.len() - 1;
        let mut at = self.hash(block);
        loop {
            let slot = self.slots[at];
            if slot.key == block {
                return Some(slot.base as usize);
            }
            if slot.key == EMPTY_KEY {
                return None;
            }
            at = (at + 1) & mask;
        }
    }
}

/// A box of grid cells, `lo..=hi` on each axis (empty when some `hi < lo`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct CellRange {
    lo: [i64; 3],
    hi: [i64; 3],
}

impl CellRange {
    /// The range of no cell.
    pub(crate) const EMPTY: CellRange = CellRange {
        lo: [0; 3],
        hi: [-1; 3],
    };

    /// Number of cells (as f64: a range over a whole grid may exceed `i64`).
    pub(crate) fn count(&self) -> f64 {
        (0..3)
            .map(|a| (self.hi[a] - self.lo[a] + 1).max(0) as f64)
            .product()
    }

    fn contains(&self, c: [i64; 3]) -> bool {
        (0..3).all(|a| (self.lo[a]..=self.hi[a]).contains(&c[a]))
    }
}

#[cfg(test)]
mod tests;
