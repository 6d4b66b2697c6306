//! Many nearest-cell queries at once, grouped by the cells of the flat grid.
//!
//! Input: a [`PatchSurface`] with its grid and the query points. Output: for every point the
//! distance to the patch surface and the nearest patch, exactly as [`PatchSurface::nearest`]
//! gives them, in the caller's order ([`PatchSurface::nearest_all`]).
//!
//! Method: the points are sorted by the grid cell holding them (block by block, the order in
//! which the grid stores its cells), and each run of points of one grid cell `G` is answered
//! together:
//! 1. Once per run, every drawable cell whose box lies within `m` = [`COVER`] grid sides of
//!    `G` on every axis is gathered from the grid cells around `G` (and the grid's extras):
//!    its corners, its box as columns, its patch. On a surface that is a few dozen cells,
//!    read once for the ten or so points of the run instead of once a point through the
//!    hash table and three indirections.
//! 2. Per point `p`: the squared distance from `p` to every gathered box in one pass (the
//!    compiler vectorizes it), the quad distance of the nearest box, then of every other box
//!    as near as the best distance so far (with [`PRUNE_SLACK`], as the search prunes) that
//!    `quad_beyond` does not rule out (a lower bound on the quad's distance from its
//!    linearisation, a few dozen instructions against about a thousand for the distance).
//!    A point on the surface lies in its own cell's box, so it usually costs one quad
//!    distance.
//! 3. Exactness: a cell at most `b` from `p` has its box within `b` of `p` on every axis,
//!    so within `b` of `G`. When the best distance found is at most `m`, every cell that
//!    could be as near was gathered, and the result is that of the search (the minimum
//!    over all cells, ties to the lower patch). Otherwise (a point more than `m` off the
//!    surface, over a hole, outside the grid) the point goes through
//!    [`PatchSurface::search`], which starts from the best cell found here.
//!
//! Cost: a sort of the points; per run, the grid cells around `G` (a hash look-up each)
//! and the gathered cells; per point, one box per gathered cell and the quad distances of
//! the boxes that reach the best distance.

use glam::Vec3;
use rayon::prelude::*;

use super::{
    near_enough, scatter_to_input_order, Best, Node, PatchSurface, MAX_GRID_CELLS, NO_PATCH,
    QUERY_CHUNK,
};
use crate::cell_grid::CellGrid;
use crate::quad_distance::{distance_to_quad, quad_beyond};
use crate::PRUNE_SLACK;

/// Margin around a run's points, in grid sides, within which its cells are gathered: a
/// point whose best distance is within it needs no further search.
const COVER: f64 = 0.25;

/// Relative widening of the gather radius, far above the f32 rounding of a gap.
const GATHER_SLACK: f64 = 1e-4;

/// Most grid cells any run's gather reads (see [`gather_budget`]).
const MAX_GATHER_CELLS: f64 = 1024.0;

/// Sort key of points outside the grid (answered one by one).
const OUTSIDE: u64 = u64::MAX;

/// The cells gathered for one run, as columns (reused from run to run).
#[derive(Default)]
struct Gathered {
    lo: [Vec<f32>; 3],
    hi: [Vec<f32>; 3],
    /// Positions of the cells in the surface's order.
    cells: Vec<usize>,
    /// Squared distances from the current point to each box.
    d2: Vec<f32>,
}

impl Gathered {
    fn clear(&mut self) {
        for a in 0..3 {
            self.lo[a].clear();
            self.hi[a].clear();
        }
        self.cells.clear();
    }

    fn push(&mut self, b: &Node, k: usize) {
        for a in 0..3 {
            self.lo[a].push(b.lo[a]);
            self.hi[a].push(b.hi[a]);
        }
        self.cells.push(k);
    }

    /// Fills `d2` with the squared distance from `p` to every box.
    fn box_distances(&mut self, p: Vec3) {
        let n = self.cells.len();
        self.d2.clear();
        self.d2.resize(n, 0.0);
        for a in 0..3 {
            let (lo, hi, x) = (&self.lo[a][..n], &self.hi[a][..n], p[a]);
            for ((d2, &l), &h) in self.d2.iter_mut().zip(lo).zip(hi) {
                // Written with comparisons so that it compiles to packed max instructions.
                let below = l - x;
                let above = x - h;
                let gap = if below > above { below } else { above };
                let gap = if gap > 0.0 { gap } else { 0.0 };
                *d2 += gap * gap;
            }
        }
    }

    /// The nearest gathered cell to `p` (nearest box first, then every box as near as the
    /// best), or `None` when nothing was gathered.
    fn nearest(&mut self, surface: &PatchSurface, p: Vec3) -> Option<Best> {
        if self.cells.is_empty() {
            return None;
        }
        self.box_distances(p);
        let first = self
            .d2
            .iter()
            .enumerate()
            .fold(0, |m, (k, &d)| if d < self.d2[m] { k } else { m });
        let at = self.cells[first];
        let mut best = Best {
            distance: distance_to_quad(p, &surface.quad(surface.cells[at])),
            owner: surface.owner(at),
            cell: at,
        };
        for (k, &d2) in self.d2.iter().enumerate() {
            if k == first || !near_enough(d2, best.distance) {
                continue;
            }
            let at = self.cells[k];
            let quad = surface.quad(surface.cells[at]);
            if quad_beyond(p, &quad, best.distance) {
                continue;
            }
            let d = distance_to_quad(p, &quad);
            let o = surface.owner(at);
            if d < best.distance || (d == best.distance && o < best.owner) {
                best = Best {
                    distance: d,
                    owner: o,
                    cell: at,
                };
            }
        }
        Some(best)
    }
}

/// One run of points answered together: the points of one grid cell.
struct Run<'a> {
    /// The surface's grid.
    grid: &'a CellGrid,
    /// The run's `(grid key, point index)` entries.
    entries: &'a [(u64, u32)],
    /// Every query point (the entries index it).
    points: &'a [Vec3],
    /// Bounds `(lo, hi)` of the run's points.
    bounds: (Vec3, Vec3),
}

impl Run<'_> {
    /// The point of the run's entry `at`.
    #[inline]
    fn point(&self, at: usize) -> Vec3 {
        self.points[self.entries[at].1 as usize]
    }
}

/// Most grid cells the gather of a run of `points` points may read: what their searches one
/// by one could read ([`MAX_GRID_CELLS`] each), up to [`MAX_GATHER_CELLS`]. A grid whose
/// largest boxes are long (steep cells of a scan set: `reach` over a grid side) needs more
/// than [`MAX_GRID_CELLS`] cells around a run; searching its points one by one instead
/// made the error measurement 3 times slower per point there than on a clean cloud.
fn gather_budget(points: usize) -> f64 {
    (MAX_GRID_CELLS * points as f64).min(MAX_GATHER_CELLS)
}

/// Whether a best distance `d` is within a gather margin `cover`: every cell as near as `d`
/// (with the pruning slack) was then gathered.
#[inline]
fn within(d: f32, cover: f64) -> bool {
    f64::from(d) * (1.0 + 2.0 * f64::from(PRUNE_SLACK)) <= cover
}

/// Largest per-axis gap between box `b` and the box `lo..=hi` (0 when they overlap), in f32:
/// each difference is within half an ulp of the exact one (callers allow for it).
#[inline]
fn axis_gap(b: &Node, lo: Vec3, hi: Vec3) -> f32 {
    (lo - b.hi).max(b.lo - hi).max(Vec3::ZERO).max_element()
}

impl PatchSurface {
    /// [`PatchSurface::nearest`] for every point, in parallel, in the order given (see the
    /// module docs of `batch.rs`); the results do not depend on the thread count.
    pub fn nearest_all(&self, points: &[Vec3]) -> (Vec<f32>, Vec<u32>) {
        self.nearest_all_placed(points, None)
    }

    /// [`PatchSurface::nearest_all`] with the answer for `points[k]` at position
    /// `place[k]` (one pass puts the answers in the caller's order instead of two), or at
    /// `k` without `place`. `place` must be a permutation of the points' indices.
    pub(crate) fn nearest_all_placed(
        &self,
        points: &[Vec3],
        place: Option<&[u32]>,
    ) -> (Vec<f32>, Vec<u32>) {
        let Some(grid) = &self.grid else {
            return self.nearest_all_in_morton_order(points, place);
        };
        let mut order: Vec<(u64, u32)> = points
            .par_iter()
            .enumerate()
            .map(|(k, &p)| (grid.key_at(p).unwrap_or(OUTSIDE), k as u32))
            .collect();
        order.par_sort_unstable();
        // A run cut between two work items is gathered twice: the results are the same.
        let found: Vec<(f32, u32)> = order
            .par_chunks(QUERY_CHUNK)
            .flat_map_iter(|chunk| {
                let mut out = Vec::with_capacity(chunk.len());
                let mut gathered = Gathered::default();
                for run in chunk.chunk_by(|a, b| a.0 == b.0) {
                    self.answer_run(grid, run, points, &mut gathered, &mut out);
                }
                out
            })
            .collect();
        scatter_to_input_order(&order, &found, place)
    }

    /// Answers the points of `run` (one grid cell's key and the points' indices), pushing
    /// `(distance, patch)` per point onto `out`.
    fn answer_run(
        &self,
        grid: &CellGrid,
        run: &[(u64, u32)],
        points: &[Vec3],
        gathered: &mut Gathered,
        out: &mut Vec<(f32, u32)>,
    ) {
        let bounds = run
            .iter()
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &(_, k)| {
                let p = points[k as usize];
                (lo.min(p), hi.max(p))
            });
        let run = Run {
            grid,
            entries: run,
            points,
            bounds,
        };
        let cover = COVER * grid.side();
        if run.entries[0].0 == OUTSIDE || !self.gather(&run, cover, gathered) {
            self.search_each(run.entries.iter().map(|&(_, k)| k), points, out);
            return;
        }
        let first = out.len();
        let mut far = Vec::new();
        for (at, &(_, k)) in run.entries.iter().enumerate() {
            let best = gathered.nearest(self, points[k as usize]);
            match best {
                Some(b) if within(b.distance, cover) => out.push((b.distance, b.owner)),
                _ => {
                    far.push((at, best));
                    out.push((f32::INFINITY, NO_PATCH));
                }
            }
        }
        if !far.is_empty() {
            self.answer_far(&run, &far, gathered, &mut out[first..]);
        }
    }

    /// Answers the points of `run` at positions `far` (each with the best cell the first
    /// gather found, if any) into `answers` (the run's slice of the output): from a second
    /// gather wide enough for the farthest of them when one is (points off a noisy or
    /// misregistered scan set, a fraction of a grid side from the surface), one search each
    /// otherwise.
    fn answer_far(
        &self,
        run: &Run<'_>,
        far: &[(usize, Option<Best>)],
        gathered: &mut Gathered,
        answers: &mut [(f32, u32)],
    ) {
        let reach = far
            .iter()
            .map(|(_, b)| b.map_or(f32::INFINITY, |b| b.distance))
            .fold(0.0f32, f32::max);
        let cover = f64::from(reach) * (1.0 + 4.0 * f64::from(PRUNE_SLACK));
        if reach.is_finite() && self.gather(run, cover, gathered) {
            for &(at, _) in far {
                let p = run.point(at);
                let b = gathered.nearest(self, p);
                answers[at] = match b {
                    Some(b) if within(b.distance, cover) => (b.distance, b.owner),
                    _ => {
                        let (d, owner, _) = self.search(p, b.map(|b| b.cell));
                        (d, owner)
                    }
                };
            }
            return;
        }
        for &(at, best) in far {
            let (d, owner, _) = self.search(run.point(at), best.map(|b| b.cell));
            answers[at] = (d, owner);
        }
    }

    /// Gathers every cell whose box lies within `cover` of the bounds of `run` on every
    /// axis into `gathered`; `false` (nothing gathered) when that reads more grid cells
    /// than the run's [`gather_budget`].
    fn gather(&self, run: &Run<'_>, cover: f64, gathered: &mut Gathered) -> bool {
        let (grid, (lo, hi)) = (run.grid, run.bounds);
        let range = grid.cells_near(lo.as_dvec3(), hi.as_dvec3(), cover);
        if range.count() > gather_budget(run.entries.len()) {
            return false;
        }
        // The gather tests gaps in f32 against a radius widened by more than their rounding.
        let gap = (cover * (1.0 + GATHER_SLACK)) as f32;
        gathered.clear();
        let mut take = |items: std::ops::Range<usize>| {
            for k in items {
                let b = &self.boxes[k];
                if axis_gap(b, lo, hi) <= gap {
                    gathered.push(b, k);
                }
            }
        };
        take(grid.extras());
        // Cells whose boxes all lie beyond the f32 test's radius (with room for its
        // rounding) are skipped whole.
        let bounds = (lo.as_dvec3(), hi.as_dvec3());
        grid.visit_near(&range, bounds, cover * (1.0 + 2.0 * GATHER_SLACK), take);
        true
    }

    /// Searches the points `indices` one by one, each from the previous one's cell.
    fn search_each(
        &self,
        indices: impl Iterator<Item = u32>,
        points: &[Vec3],
        out: &mut Vec<(f32, u32)>,
    ) {
        let mut hint = None;
        for k in indices {
            let (d, owner, cell) = self.search(points[k as usize], hint);
            hint = Some(cell);
            out.push((d, owner));
        }
    }
}
