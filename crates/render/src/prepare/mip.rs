//! The per-patch mip pyramid used for minification.
//!
//! Level 0 is the patch's own grid. Level `m + 1` halves level `m`: node
//! `(i, j)` is node `(2i, 2j)` of level `m` (so the surface still passes
//! through real nodes and the patch keeps its outline), with its colour the
//! 1-2-1 tent average of the filled nodes around it (so far views do not
//! alias). A side with an odd number of cells is first padded with one
//! node extrapolated from its last two (see [`padded`]), so every grid of at
//! least three nodes a side halves: 17 → 9 → 5 → 3 → 2, 16 → 9 → 5 → 3 → 2.
//! A level exists while both sides have three nodes or more and the halved
//! grid still has a drawable cell among the nodes it shares with level 0.
//!
//! Each level also records which nodes belong to a drawable cell (`used`),
//! its displacement range and its number of drawable cells.
//!
//! Cost: O(nodes) per level, 4/3 of the patch's memory for all levels.
//! Level 0 is built once per scene in [`crate::PreparedScene::new`], the
//! others the first time a frame draws them (a view draws few: the 500²
//! sphere only level 0).

use std::sync::OnceLock;

use spatch_format::EMPTY;

use crate::grid::{
    close_cells, drawn_cells, push_cells_by_node, push_weights, QuarteredCell, CELL_DRAW,
};
use crate::prepare::corner_fill::{fill_corners, fill_wanted_corners, FinerLevel};
use crate::prepare::normals::grid_slots;
use crate::prepare::quarters::{quartered_cells, quartered_corners};

/// Most levels kept per patch (including level 0).
pub(crate) const MAX_MIP_LEVELS: usize = 6;

/// One level of a patch's pyramid.
#[derive(Debug, Clone)]
pub(crate) struct MipLevel {
    pub(crate) cols: usize,
    pub(crate) rows: usize,
    /// Node spacing in level-0 nodes (`2^m`).
    pub(crate) spacing: u32,
    pub(crate) displacements: Vec<u16>,
    pub(crate) colours: Option<Vec<[u8; 4]>>,
    /// Nodes that are a corner of at least one drawable cell.
    pub(crate) used: Vec<bool>,
    /// Per node, the normal-buffer slot of its displacement differences
    /// ([`crate::prepare::normals::table_slot`]; meaningless for empty
    /// nodes), found on first use ([`Self::normal_slots`]).
    normal_slots: OnceLock<Vec<u16>>,
    /// Smallest and largest used displacement (0, 0 when none).
    pub(crate) d_range: (u16, u16),
    /// Per node, its trilinear weight along `d_range`
    /// ([`crate::grid::push_weights`]), found on first use
    /// ([`Self::weights`]).
    weights: OnceLock<Vec<f32>>,
    pub(crate) drawable_cells: u32,
    /// Per cell (row-major, `(cols - 1) × (rows - 1)`), the flags of the
    /// whole level without back-face culling: [`CELL_DRAW`] when its four
    /// corners are filled, and [`crate::grid::CELL_RIGHT`] /
    /// [`crate::grid::CELL_TOP`] when it closes
    /// its column / row. Why: which cells have four used corners does not
    /// depend on the view, so a frame only adds the back-face test (see
    /// [`crate::plan::measure::measure_cells`]).
    pub(crate) cell_flags: Vec<u8>,
    /// Closing counts of [`Self::cell_flags`]: right, top, both.
    pub(crate) closing: [u64; 3],
    /// Level 1 drawn by quarters ([`halve_quartered`]): the cells drawn by
    /// the level-0 cells they hold, not whole ([`crate::prepare::quarters`];
    /// not in [`Self::cell_flags`], their corners [`Self::used`]). Empty
    /// at the other levels.
    pub(crate) quartered: Vec<QuarteredCell>,
    /// The flags of [`Self::cells_by_node`], found on first use.
    cells_by_node: OnceLock<Vec<u8>>,
}

impl MipLevel {
    /// The level over `displacements` (and `colours`); `range`, when
    /// known, is its used nodes' displacement range ([`Self::d_range`]).
    #[inline(always)]
    fn new(
        [cols, rows]: [usize; 2],
        spacing: u32,
        (displacements, colours): (Vec<u16>, Option<Vec<[u8; 4]>>),
        range: Option<(u16, u16)>,
    ) -> Self {
        let drawn = drawn_cells(&displacements, cols, rows);
        Self::with_drawn_cells(
            [cols, rows],
            spacing,
            (displacements, colours),
            OnceLock::new(),
            (drawn, range, Vec::new()),
        )
    }

    /// Leaves out the cells `trimmed` marks (row-major per cell; see
    /// [`crate::prepare::overlap`]), keeping the level's nodes.
    pub(crate) fn trim_cells(&mut self, trimmed: &[bool]) {
        let drawn: Vec<u8> = self
            .cell_flags
            .iter()
            .zip(trimmed)
            .map(|(&f, &t)| f & CELL_DRAW & !(t as u8))
            .collect();
        *self = Self::with_drawn_cells(
            [self.cols, self.rows],
            self.spacing,
            (std::mem::take(&mut self.displacements), self.colours.take()),
            std::mem::take(&mut self.normal_slots),
            (drawn, None, std::mem::take(&mut self.quartered)),
        );
    }

    /// A level drawing the cells whose flag in `drawn` is [`CELL_DRAW`]
    /// (each with four filled corners; the others 0), which becomes its
    /// [`Self::cell_flags`], and the cells `quartered` by quarters; `range`
    /// as in [`Self::new`].
    #[inline(always)]
    fn with_drawn_cells(
        [cols, rows]: [usize; 2],
        spacing: u32,
        (displacements, colours): (Vec<u16>, Option<Vec<[u8; 4]>>),
        normal_slots: OnceLock<Vec<u16>>,
        (mut cell_flags, range, quartered): (Vec<u8>, Option<(u16, u16)>, Vec<QuarteredCell>),
    ) -> Self {
        let (ccols, crows) = (cols - 1, rows - 1);
        cell_flags.truncate(ccols * crows);
        let drawn = &cell_flags[..];
        let drawable_cells = drawn.iter().map(|&d| u32::from(d)).sum::<u32>();
        let mut used = corners_of_drawn(drawn, [cols, rows]);
        if !quartered.is_empty() {
            let corners = quartered_corners(&quartered, [cols, rows]);
            used.iter_mut().zip(corners).for_each(|(u, c)| *u |= c);
        }
        let (lo, hi) = range.unwrap_or_else(|| used_range(&displacements, &used));
        let d_range = if lo > hi { (0, 0) } else { (lo, hi) };
        let closing = close_cells(&mut cell_flags, ccols, crows);
        Self {
            cols,
            rows,
            spacing,
            displacements,
            colours,
            used,
            normal_slots,
            d_range,
            weights: OnceLock::new(),
            drawable_cells,
            cell_flags,
            closing,
            quartered,
            cells_by_node: OnceLock::new(),
        }
    }

    /// Per node, the normal-buffer slot of its displacement differences,
    /// found the first time a Phong frame draws the level. Why on first
    /// use: only Phong frames read them, and only for the levels a view
    /// draws (a quarter of the bunny's patches face away at the default
    /// view); finding them for every level 0 was 23.5 M of a one-frame
    /// bunny render's 233 M instructions (callgrind, `spatch render
    /// bunny.spatch -o out.png --threads 1`).
    pub(crate) fn normal_slots(&self) -> &[u16] {
        self.normal_slots
            .get_or_init(|| grid_slots(&self.displacements, self.cols, self.rows, EMPTY))
    }

    /// Per node, its trilinear weight along [`Self::d_range`]: a piece of
    /// whole rows at the level's range reads them instead of converting
    /// every frame. Why on first use: a level below the one a patch is
    /// drawn at (the bunny's level 0 under its level 1 at 500²) is only
    /// read to build the next level: finding its weights anyway cost a
    /// one-image bunny render 311 page faults (`perf stat`, 2 threads).
    pub(crate) fn weights(&self) -> &[f32] {
        self.weights.get_or_init(|| {
            let mut weights = Vec::with_capacity(self.displacements.len());
            push_weights(&self.displacements, self.d_range, &mut weights);
            weights
        })
    }

    /// [`Self::cell_flags`]' drawn bits laid out along the node rows
    /// ([`crate::grid::push_cells_by_node`]; `(rows - 1) × cols` bytes), so
    /// a frame measuring the whole level need not lay them out. Why on
    /// first use: as for [`Self::weights`] (the level under a drawn coarse
    /// level never needs them).
    pub(crate) fn cells_by_node(&self) -> &[u8] {
        self.cells_by_node.get_or_init(|| {
            let mut out = Vec::with_capacity((self.rows - 1) * self.cols);
            push_cells_by_node(self.cell_flags.chunks_exact(self.cols - 1), &mut out);
            out
        })
    }

    /// The level as the halving into the level above reads it.
    pub(crate) fn as_finer(&self) -> FinerLevel<'_> {
        FinerLevel {
            cols: self.cols,
            rows: self.rows,
            displacements: &self.displacements,
            cell_flags: &self.cell_flags,
            spacing: self.spacing,
        }
    }

    /// True when every cell of the level is drawn.
    pub(crate) fn draws_every_cell(&self) -> bool {
        self.drawable_cells as usize == self.cell_flags.len()
    }

    /// True when cell `(i, j)` is drawn: its four corners are filled and it
    /// was not trimmed away ([`crate::prepare::overlap`]).
    pub(crate) fn cell_is_drawable(&self, i: usize, j: usize) -> bool {
        self.cell_flags[j * (self.cols - 1) + i] & CELL_DRAW != 0
    }
}

/// Per node of a `cols × rows` grid, whether it is a corner of a cell
/// flagged in `drawn` (one flag per cell, 0: not drawn).
#[inline(always)]
fn corners_of_drawn(drawn: &[u8], [cols, rows]: [usize; 2]) -> Vec<bool> {
    let ccols = cols - 1;
    // A node is used when a drawn cell of the row of cells below or
    // above it has it as a corner. Why by rows of nodes: four indexed
    // stores per drawn cell were a third of this function (callgrind,
    // `profile_sphere 500 1 1 trimmed`).
    let mut used = vec![false; cols * rows];
    // On the stack for grids up to 64 nodes a row.
    let (mut stack, mut heap) = ([false; 64], Vec::new());
    let corner: &mut [bool] = if cols <= 64 {
        &mut stack[..cols]
    } else {
        heap.resize(cols, false);
        &mut heap
    };
    for (j, row) in drawn.chunks_exact(ccols).enumerate() {
        // Nodes of this row of cells that are a corner of a drawn cell.
        corner[0] = row[0] != 0;
        corner[ccols] = row[ccols - 1] != 0;
        for (c, pair) in corner[1..ccols].iter_mut().zip(row.windows(2)) {
            *c = pair[0] | pair[1] != 0;
        }
        let (below, above) = used[j * cols..(j + 2) * cols].split_at_mut(cols);
        for ((b, a), &c) in below.iter_mut().zip(above.iter_mut()).zip(corner.iter()) {
            *b |= c;
            *a |= c;
        }
    }
    used
}

/// The smallest and largest of `displacements` where `used` (`(u16::MAX,
/// 0)` when none). Why eight lanes of extremes, merged at the end: a fold
/// into one pair ran one node at a time (3.7 M of a one-frame bunny
/// render's 187 M instructions; callgrind).
#[inline(always)]
fn used_range(displacements: &[u16], used: &[bool]) -> (u16, u16) {
    let (mut lo, mut hi) = ([u16::MAX; 8], [0u16; 8]);
    let nodes = displacements.chunks_exact(8).zip(used.chunks_exact(8));
    for (d, u) in nodes {
        for l in 0..8 {
            let (a, b) = if u[l] { (d[l], d[l]) } else { (u16::MAX, 0) };
            lo[l] = lo[l].min(a);
            hi[l] = hi[l].max(b);
        }
    }
    let whole = displacements.len() / 8 * 8;
    for (&d, &u) in displacements[whole..].iter().zip(&used[whole..]) {
        let (a, b) = if u { (d, d) } else { (u16::MAX, 0) };
        lo[0] = lo[0].min(a);
        hi[0] = hi[0].max(b);
    }
    (
        lo.into_iter().min().unwrap_or(u16::MAX),
        hi.into_iter().max().unwrap_or(0),
    )
}

/// True when the four corners of the cell whose first corner is node `k`
/// of `displacements` are filled; `di` and `dj` are the steps to the next
/// corner along the row and across rows.
#[inline(always)]
fn corners_filled(displacements: &[u16], k: usize, di: usize, dj: usize) -> bool {
    let filled = |k: usize| displacements[k] != EMPTY;
    filled(k) && filled(k + di) && filled(k + dj) && filled(k + di + dj)
}

/// Level 0 of `patch`'s pyramid, or `None` when the patch has no drawable
/// cell.
#[cfg(test)]
pub(crate) fn base_level(patch: &spatch_format::Patch) -> Option<MipLevel> {
    let grid = patch.grid();
    let base = level_zero(
        [grid.cols() as usize, grid.rows() as usize],
        (
            patch.displacements().to_vec(),
            patch.colours().map(<[_]>::to_vec),
        ),
        None,
    );
    (base.drawable_cells > 0).then_some(base)
}

/// Level 0 of a pyramid over a `cols × rows` grid of `displacements` (and
/// `colours`); `range`, when known, the displacement range of its used
/// nodes (the normal cone finds it, [`crate::prepare::cone::ConeScan`]).
#[inline(always)]
pub(crate) fn level_zero(
    size: [usize; 2],
    nodes: (Vec<u16>, Option<Vec<[u8; 4]>>),
    range: Option<(u16, u16)>,
) -> MipLevel {
    MipLevel::new(size, 1, nodes, range)
}

/// How many levels the pyramid over the level-0 nodes `base` (`cols × rows`) has above it (up to
/// [`MAX_MIP_LEVELS`] in all): levels halve while both sides have three
/// nodes or more ([`halved_side`]) and the halved grid has a drawable cell
/// whose four corners are level-0 nodes (level `m`'s node `(i, j)` is level
/// 0's `(2^m i, 2^m j)` up to level 0's last node; nodes past it are
/// padding). Counted from level 0's nodes without building the levels, so
/// that they can be built on first use; a counted level always halves and
/// has a drawable cell.
pub(crate) fn coarse_level_count(base: &[u16], [base_cols, base_rows]: [usize; 2]) -> usize {
    let (mut cols, mut rows, mut step) = (base_cols, base_rows, 1);
    let mut count = 0;
    while count + 1 < MAX_MIP_LEVELS {
        let (Some(c), Some(r)) = (halved_side(cols), halved_side(rows)) else {
            break;
        };
        (cols, rows, step) = (c, r, step * 2);
        // This level's nodes that are level 0's, and their distances in
        // level 0 along a row and across rows.
        let real_cols = (base_cols - 1) / step + 1;
        let real_rows = (base_rows - 1) / step + 1;
        let (di, dj) = (step, step * base_cols);
        let drawable = (0..real_rows.saturating_sub(1)).any(|j| {
            (0..real_cols.saturating_sub(1)).any(|i| corners_filled(base, j * dj + i * di, di, dj))
        });
        if !drawable {
            break;
        }
        count += 1;
    }
    count
}

/// Nodes on a side of `n` nodes after halving (an odd number of cells is
/// padded by one node first), or `None` below three nodes.
pub(crate) fn halved_side(n: usize) -> Option<usize> {
    (n >= 3).then_some(n.div_ceil(2) + usize::from(n.is_multiple_of(2)))
}

/// Builds the whole pyramid of `patch` (level 0 first); empty when the
/// patch has no drawable cell. A prepared patch builds its levels above 0
/// on first use instead ([`crate::prepare::patch::PreparedPatch::level`]).
#[cfg(test)]
pub(crate) fn build_mip_pyramid(patch: &spatch_format::Patch) -> Vec<MipLevel> {
    let Some(base) = base_level(patch) else {
        return Vec::new();
    };
    let count = coarse_level_count(&base.displacements, [base.cols, base.rows]);
    let mut levels = vec![base];
    for _ in 0..count {
        let next = halve_level(levels.last().expect("at least level 0"));
        levels.push(next.expect("a counted level halves"));
    }
    levels
}

/// Level `m + 1` from level `m` (padded first where a side has an odd
/// number of cells, see [`padded`]), or `None` when a side has fewer than
/// three nodes.
pub(crate) fn halve_level(level: &MipLevel) -> Option<MipLevel> {
    halve(level.as_finer(), level.colours.as_deref())
}

/// The level above `finer` (with per-node `colours`), as
/// [`halve_level`] builds it; `finer.cell_flags` need only mark its drawn
/// cells ([`crate::grid::drawn_cells`]). Why apart: level 1 is built
/// straight from a patch's nodes when level 0 itself is not drawn
/// ([`crate::prepare::patch::PreparedPatch::level`]).
pub(crate) fn halve(finer: FinerLevel<'_>, colours: Option<&[[u8; 4]]>) -> Option<MipLevel> {
    halve_with(finer, colours, false)
}

/// [`halve`] for level 0 (`finer`), with the cells that hold some but not
/// all of their level-0 cells drawn by quarters instead
/// ([`crate::prepare::quarters`]): their corners filled, listed in
/// [`MipLevel::quartered`] and not in its cell flags, those corners used.
/// A level of its own beside level 1
/// ([`crate::prepare::patch::QUARTERED_ONE`]): filling more corners
/// changes the normals of the outline's nodes and the level's box, so
/// level 1 drawn within the mip limit keeps its images.
pub(crate) fn halve_quartered(
    finer: FinerLevel<'_>,
    colours: Option<&[[u8; 4]]>,
) -> Option<MipLevel> {
    halve_with(finer, colours, true)
}

/// [`halve`], with cells by quarters when `quarters` (level 0 only).
fn halve_with(
    finer: FinerLevel<'_>,
    colours: Option<&[[u8; 4]]>,
    quarters: bool,
) -> Option<MipLevel> {
    let (hc, hr) = (halved_side(finer.cols)?, halved_side(finer.rows)?);
    let grid = padded(&finer, colours);
    let cols = grid.cols;
    let mut displacements = Vec::with_capacity(hc * hr);
    for j in 0..hr {
        for i in 0..hc {
            displacements.push(grid.displacements[2 * j * cols + 2 * i]);
        }
    }
    fill_corners(finer, [hc, hr], &mut displacements);
    let mut drawn = drawn_cells(&displacements, hc, hr);
    let quartered = if quarters && finer.spacing == 1 {
        quartered_level_one(finer, [hc, hr], &mut displacements, &mut drawn)
    } else {
        Vec::new()
    };
    let colours = grid.colours.as_ref().map(|src| {
        let mut out = Vec::with_capacity(hc * hr);
        for j in 0..hr {
            for i in 0..hc {
                out.push(tent_average(&grid, src, 2 * i, 2 * j));
            }
        }
        out
    });
    Some(MipLevel::with_drawn_cells(
        [hc, hr],
        finer.spacing * 2,
        (displacements, colours),
        OnceLock::new(),
        (drawn, None, quartered),
    ))
}

/// The cells of level 1 (`size` nodes, halved from `finer`, its corners
/// filled for the cells drawn whole, `drawn`) to draw by quarters
/// ([`crate::prepare::quarters`]), their empty corners filled in `d`.
fn quartered_level_one(
    finer: FinerLevel<'_>,
    size: [usize; 2],
    d: &mut [u16],
    drawn: &mut [u8],
) -> Vec<QuarteredCell> {
    let mut cells = quartered_cells(finer, size, drawn);
    fill_wanted_corners(finer, size, d, &quartered_corners(&cells, size));
    let cols = size[0];
    let filled = |k: usize| d[k] != EMPTY;
    cells.retain(|c| {
        let k = c.cell as usize;
        let first = (k / (cols - 1)) * cols + k % (cols - 1);
        filled(first) && filled(first + 1) && filled(first + cols) && filled(first + cols + 1)
    });
    cells
}

/// A level's nodes, as [`halve_level`] reads them.
struct NodeGrid {
    cols: usize,
    rows: usize,
    displacements: Vec<u16>,
    colours: Option<Vec<[u8; 4]>>,
}

/// `level`'s nodes with one column (row) appended when its rows (columns)
/// have an odd number of cells, so that every other node lands on both
/// ends. A padding node continues its row (column) linearly from the last
/// two nodes (clamped to the codes' range), or repeats the last node when
/// the one before it is empty; its colour repeats the last node's. Why
/// extrapolate rather than keep a shorter last cell: every level keeps one
/// uniform spacing, which the projection, the cell code and the normals
/// assume. It costs up to one cell of the level past the patch's outline
/// (where neighbouring patches overlap it on a closed surface).
fn padded(level: &FinerLevel<'_>, colours: Option<&[[u8; 4]]>) -> NodeGrid {
    let mut grid = NodeGrid {
        cols: level.cols,
        rows: level.rows,
        displacements: level.displacements.to_vec(),
        colours: colours.map(<[_]>::to_vec),
    };
    if grid.cols.is_multiple_of(2) {
        pad_columns(&mut grid);
    }
    if grid.rows.is_multiple_of(2) {
        pad_rows(&mut grid);
    }
    grid
}

/// Appends one extrapolated node to every row of `grid`.
fn pad_columns(grid: &mut NodeGrid) {
    let (cols, rows) = (grid.cols, grid.rows);
    let mut d = Vec::with_capacity((cols + 1) * rows);
    let mut colours = grid
        .colours
        .as_ref()
        .map(|_| Vec::with_capacity((cols + 1) * rows));
    for j in 0..rows {
        let row = &grid.displacements[j * cols..(j + 1) * cols];
        d.extend_from_slice(row);
        d.push(extrapolate(row[cols - 2], row[cols - 1]));
        if let (Some(out), Some(src)) = (colours.as_mut(), grid.colours.as_ref()) {
            let row = &src[j * cols..(j + 1) * cols];
            out.extend_from_slice(row);
            out.push(row[cols - 1]);
        }
    }
    (grid.cols, grid.displacements, grid.colours) = (cols + 1, d, colours);
}

/// Appends one extrapolated row to `grid`.
fn pad_rows(grid: &mut NodeGrid) {
    let (cols, rows) = (grid.cols, grid.rows);
    let (before, last) = ((rows - 2) * cols, (rows - 1) * cols);
    for i in 0..cols {
        let v = extrapolate(grid.displacements[before + i], grid.displacements[last + i]);
        grid.displacements.push(v);
    }
    if let Some(c) = grid.colours.as_mut() {
        c.extend_from_within(last..last + cols);
    }
    grid.rows = rows + 1;
}

/// The node after `a, b` on a line through them (clamped to the codes'
/// range), `b` when `a` is empty, empty when `b` is.
fn extrapolate(a: u16, b: u16) -> u16 {
    match (a, b) {
        (_, EMPTY) => EMPTY,
        (EMPTY, b) => b,
        (a, b) => (2 * b as i32 - a as i32).clamp(0, EMPTY as i32 - 1) as u16,
    }
}

/// 1-2-1 tent average of the filled colours around node `(ci, cj)` (an
/// empty node takes its filled neighbours', for the filled corners of
/// `corner_fill.rs`).
fn tent_average(level: &NodeGrid, colours: &[[u8; 4]], ci: usize, cj: usize) -> [u8; 4] {
    let mut sum = [0u32; 4];
    let mut weight = 0u32;
    for dj in -1i32..=1 {
        for di in -1i32..=1 {
            let (i, j) = (ci as i32 + di, cj as i32 + dj);
            if i < 0 || j < 0 || i >= level.cols as i32 || j >= level.rows as i32 {
                continue;
            }
            let k = j as usize * level.cols + i as usize;
            if level.displacements[k] == EMPTY {
                continue;
            }
            let w = (2 - di.unsigned_abs()) * (2 - dj.unsigned_abs());
            for (s, c) in sum.iter_mut().zip(colours[k]) {
                *s += w * c as u32;
            }
            weight += w;
        }
    }
    if weight == 0 {
        return [0; 4];
    }
    sum.map(|s| ((s + weight / 2) / weight) as u8)
}
