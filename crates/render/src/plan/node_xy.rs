//! The screen positions of the last projected piece and the scratch that
//! its projection ([`crate::plan::project`]) and its cell measurement
//! ([`crate::plan::measure`]) reuse from piece to piece.
//!
//! Invariant: after a projection, `xs` and `ys` hold the used nodes'
//! fixed-point positions row after row (0 for unused nodes), and
//! `row_stats` is either empty or holds every node row's box and count.
//! Cost: no allocation once warm.

use glam::Vec4;

use crate::plan::lanes::truncate_lanes;

/// The fixed-point screen positions of the last projected piece, one row
/// of nodes after another (`x` in `xs`, `y` in `ys`, 0 for unused nodes):
/// the same values as the nodes' first two words, laid out for
/// [`measure_cells`](crate::plan::measure::measure_cells). Why: the measurement reads them a row pair at a time
/// in plain `i32` lanes instead of striding over the nodes (36 bytes each
/// when measured, 16 since; callgrind, `profile_sphere 500 1`).
#[derive(Debug, Default)]
pub(crate) struct NodeXY {
    pub(crate) xs: Vec<i32>,
    pub(crate) ys: Vec<i32>,
    /// Scratch of the trilinear projection: per node the displacement
    /// weight and the used flag, per row its lanes.
    pub(crate) ws: Vec<f32>,
    pub(crate) used: Vec<bool>,
    pub(crate) rows: Vec<RowLanes>,
    /// Scratch of [`measure_cells`](crate::plan::measure::measure_cells):
    /// a part of a level's cell flags laid out along the node rows
    /// ([`crate::grid::push_cells_by_node`]), and per cell (at its (0, 0)
    /// node) whether it is drawn.
    pub(crate) cells: Vec<u8>,
    pub(crate) drawn: Vec<u8>,
    /// Per node row, its used positions' box and count, when the
    /// projection found them (the trilinear one within range; else empty,
    /// and [`measure_cells`](crate::plan::measure::measure_cells) scans the positions).
    pub(crate) row_stats: Vec<RowStats>,
}

impl NodeXY {
    /// Clears and sizes both arrays for `len` nodes (all 0), and forgets
    /// the row boxes of the previous piece.
    #[inline(always)]
    pub(crate) fn reset(&mut self, len: usize) {
        self.row_stats.clear();
        self.xs.clear();
        self.xs.resize(len, 0);
        self.ys.clear();
        self.ys.resize(len, 0);
    }
}

/// One node row's used positions: the box `[x_lo, y_lo, x_hi, y_hi]`
/// (empty: `[MAX, MAX, MIN, MIN]`) and the used count.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowStats {
    pub(crate) bbox: [i32; 4],
    pub(crate) used: u32,
}

impl RowStats {
    /// A row without used nodes.
    pub(crate) const EMPTY: RowStats = RowStats {
        bbox: [i32::MAX, i32::MAX, i32::MIN, i32::MIN],
        used: 0,
    };

    /// From the row's smallest and largest scaled lanes (see
    /// [`crate::plan::lanes::scaled_lanes`]) over `count` used nodes.
    #[inline(always)]
    pub(crate) fn of(lo: Vec4, hi: Vec4, count: u32) -> Self {
        if count == 0 {
            return Self::EMPTY;
        }
        let (lo, hi) = (truncate_lanes(lo), truncate_lanes(hi));
        Self {
            bbox: [lo[0], lo[1], hi[0], hi[1]],
            used: count,
        }
    }
}

/// One row of trilinear nodes in lanes `x, y, depth, 0`: the bottom and
/// top points of its first node and their steps per node.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowLanes {
    pub(crate) bottom: Vec4,
    pub(crate) top: Vec4,
    pub(crate) db: Vec4,
    pub(crate) dt: Vec4,
}
