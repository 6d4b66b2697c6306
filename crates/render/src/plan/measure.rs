//! Cell measurement: per piece, which projected cells are drawn (four used
//! corners, not facing away), how large the largest cell edges are on
//! screen (which sets the subdivision) and the screen box and row spans.
//!
//! Input: a mip level, a node range and its projected positions
//! ([`NodeXY`]). Output: one flag byte per cell ([`crate::grid`]), one row
//! span per row of cells, and a [`CellMeasure`]. The decisions equal the
//! straightforward pass over the node array (`measure_cells_reference` in `measure_tests`,
//! kept for the tests) bit for bit.
//!
//! Cost: O(nodes), no allocation once warm: ≈ 36 instructions per node
//! on the bunny at 500², 2.6 M of a 43.6 M frame with `grid.rs`'s share
//! (4.3 M before the one-pass cells, [`cells_small`]; callgrind, 1
//! thread, instructions attributed through their inlined frames).

use crate::grid::{close_cells, push_cells_by_node, CELL_DRAW};
use crate::plan::node_xy::{NodeXY, RowStats};
use crate::plan::split::NodeRange;
use crate::prepare::mip::MipLevel;

/// Projected size of a piece's cells and its screen box.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CellMeasure {
    /// Largest |x| and |y| of the drawn cells' u edges and v edges (fixed
    /// point): `[ux, uy, vx, vy]`.
    pub(crate) edges: [i64; 4],
    pub(crate) drawable_cells: u64,
    /// Drawn cells that draw their right column / top row / both (see
    /// [`crate::raster::cell_bilinear`]).
    pub(crate) right_edges: u64,
    pub(crate) top_edges: u64,
    pub(crate) both_edges: u64,
    /// Cells left out because they face away from the eye everywhere.
    pub(crate) backfacing_cells: u64,
    pub(crate) used_nodes: u64,
    /// Pixel box of the used nodes: x0, y0, x1, y1 (inclusive).
    pub(crate) bbox: [i32; 4],
}

impl CellMeasure {
    /// Nothing measured yet (an empty box).
    pub(crate) const EMPTY: CellMeasure = CellMeasure {
        edges: [0; 4],
        drawable_cells: 0,
        right_edges: 0,
        top_edges: 0,
        both_edges: 0,
        backfacing_cells: 0,
        used_nodes: 0,
        bbox: [i32::MAX, i32::MAX, i32::MIN, i32::MIN],
    };

    /// Sub-nodes placed when every cell is cut into `nu × nv`.
    pub(crate) fn refined_nodes(&self, nu: u64, nv: u64) -> u64 {
        self.drawable_cells * nu * nv
            + nv * self.right_edges
            + nu * self.top_edges
            + self.both_edges
    }
}

/// Measures the projected cells of `range` of `level`, whose node
/// positions are in `xy` (see [`NodeXY`]), and appends one flag byte per
/// cell (row-major, the flags of [`crate::grid`]) to
/// `flags`, and per row of cells the pixel rows its used nodes span
/// (`[lo, hi]`, inclusive; empty rows give `lo > hi`) to `spans`.
///
/// With `back_sign` ±1 (back-face culling on: the sign of the local map's
/// determinant), a cell is left out when the screen cross product of its
/// edges has that sign at all four corners: the Jacobian determinant of a
/// bilinear cell is bilinear in `(s, t)`, so the whole drawn cell then faces
/// away from the eye (a front-facing cell of the closed surface covers the
/// same pixels). `back_sign = 0` keeps every cell with four used corners.
///
/// The same decisions as the straightforward measurement over the node
/// array (`measure_cells_reference` in `measure_tests`, kept for the
/// tests), in fewer instructions. Why (callgrind, `profile_sphere 500 1`;
/// ≈ 155 instructions per cell before): which cells have four used
/// corners, and their closing flags without back-face culling, come from
/// the level ([`MipLevel::cell_flags`]); the row boxes come from the
/// projection when it kept them ([`NodeXY::row_stats`]); on pieces
/// spanning less than 2^24 units (256 px) the back-face test, the flags,
/// the counts and the largest edges come from one flat pass over the
/// piece's cells ([`cells_small`]); wider pieces take them row by row in
/// `i32` or `i64`.
#[inline(always)]
pub(crate) fn measure_cells(
    level: &MipLevel,
    range: NodeRange,
    xy: &mut NodeXY,
    back_sign: i64,
    flags: &mut Vec<u8>,
    spans: &mut Vec<[i32; 2]>,
) -> CellMeasure {
    let (cols, rows) = range.size();
    let mut m = CellMeasure::EMPTY;
    let [x0, y0, x1, y1] = row_boxes(level, range, xy, spans, &mut m);
    // Differences of two used positions fit in `i32` when the box does
    // (always within the guard band; else the `i64` form).
    let narrow = m.used_nodes > 0
        && (x1 as i64 - x0 as i64) <= i32::MAX as i64
        && (y1 as i64 - y0 as i64) <= i32::MAX as i64;
    // And they are exact in `f32` below 2^24 units (256 pixels).
    let small = narrow && (x1 as i64 - x0 as i64) < 1 << 24 && (y1 as i64 - y0 as i64) < 1 << 24;
    let base = flags.len();
    let whole = range.i0 == 0 && range.j0 == 0 && cols == level.cols && rows == level.rows;
    if small {
        measure_small(level, range, xy, back_sign, whole, flags, &mut m);
    } else {
        mark_cells(level, range, xy, back_sign, whole, flags, &mut m);
        m.edges = largest_edges(xy, &flags[base..], cols, narrow, m.drawable_cells);
    }
    let out = &mut flags[base..];
    // Closing flags: the level's own when the piece is the whole level and
    // no cell faced away (already in `out` but for the row path's tested
    // cells).
    let [right, top, both] = if whole && m.backfacing_cells == 0 {
        if back_sign != 0 && !small {
            out.copy_from_slice(&level.cell_flags);
        }
        level.closing
    } else if m.drawable_cells == 0 {
        [0; 3]
    } else {
        close_cells(out, cols - 1, rows - 1)
    };
    (m.right_edges, m.top_edges, m.both_edges) = (right, top, both);
    m
}

/// The node rows of `range`: appends to `spans` the pixel rows each row of
/// cells spans, counts the used nodes into `m` with their pixel box, and
/// returns that box in position units (`[x0, y0, x1, y1]`; `MAX, MIN`
/// when no node is used). Each row's box and count come from the
/// projection when it kept them ([`NodeXY::row_stats`]), else from the
/// positions.
#[inline(always)]
fn row_boxes(
    level: &MipLevel,
    range: NodeRange,
    xy: &mut NodeXY,
    spans: &mut Vec<[i32; 2]>,
    m: &mut CellMeasure,
) -> [i32; 4] {
    let (cols, rows) = range.size();
    let lcols = level.cols;
    let (mut x0, mut y0, mut x1, mut y1) = (i32::MAX, i32::MAX, i32::MIN, i32::MIN);
    let first_span = spans.len();
    spans.resize(first_span + rows - 1, [i32::MAX, i32::MIN]);
    if xy.row_stats.len() != rows {
        xy.row_stats.clear();
        for j in 0..rows {
            let (xl, xh, lo, hi, n) = row_box(
                &level.used[(range.j0 + j) * lcols + range.i0..][..cols],
                &xy.xs[j * cols..][..cols],
                &xy.ys[j * cols..][..cols],
            );
            xy.row_stats.push(RowStats {
                bbox: [xl, lo, xh, hi],
                used: n as u32,
            });
        }
    }
    let stats = &xy.row_stats[..rows];
    // Why separate passes over the row boxes: no branch or index check per
    // row (callgrind, `profile_sphere 500 1`).
    for (span, pair) in spans[first_span..].iter_mut().zip(stats.windows(2)) {
        let (a, b) = (pair[0].bbox, pair[1].bbox);
        *span = [a[1].min(b[1]) >> 16, a[3].max(b[3]) >> 16];
    }
    for s in stats {
        (x0, y0) = (x0.min(s.bbox[0]), y0.min(s.bbox[1]));
        (x1, y1) = (x1.max(s.bbox[2]), y1.max(s.bbox[3]));
        m.used_nodes += s.used as u64;
    }
    if m.used_nodes > 0 {
        m.bbox = [x0 >> 16, y0 >> 16, x1 >> 16, y1 >> 16];
    }
    [x0, y0, x1, y1]
}

/// [`measure_cells`] for a piece spanning under 2^24 units: appends its
/// cells' drawn bits to `flags` (the level's flags when it is the whole
/// level and no cell faces away) and puts the drawn and back-facing counts
/// and the largest edges into `m`, from one pass of [`cells_small`].
#[inline(always)]
fn measure_small(
    level: &MipLevel,
    range: NodeRange,
    xy: &mut NodeXY,
    back_sign: i64,
    whole: bool,
    flags: &mut Vec<u8>,
    m: &mut CellMeasure,
) {
    let (cols, rows) = range.size();
    let (ccols, crows) = (cols - 1, rows - 1);
    let NodeXY {
        xs,
        ys,
        cells,
        drawn,
        ..
    } = xy;
    let cells: &[u8] = if whole {
        level.cells_by_node()
    } else {
        let lccols = level.cols - 1;
        let first = range.j0 * lccols + range.i0;
        cells.clear();
        push_cells_by_node(
            (0..crows).map(|j| &level.cell_flags[first + j * lccols..][..ccols]),
            cells,
        );
        cells
    };
    // The last node of the last row starts no cell.
    drawn.clear();
    drawn.resize(crows * cols - 1, 0);
    let (edges, n_drawn, n_back) = match back_sign {
        1 => cells_small::<1>(xs, ys, cols, cells, drawn),
        -1 => cells_small::<-1>(xs, ys, cols, cells, drawn),
        _ => cells_small::<0>(xs, ys, cols, cells, drawn),
    };
    (m.edges, m.drawable_cells, m.backfacing_cells) = (edges.map(|e| e as i64), n_drawn, n_back);
    if whole && n_back == 0 {
        flags.extend_from_slice(&level.cell_flags);
    } else {
        for j in 0..crows {
            flags.extend_from_slice(&drawn[j * cols..][..ccols]);
        }
    }
}

/// The row path of [`measure_cells`] (a piece spanning 2^24 units or
/// more): appends the flag byte of every cell of `range` to `flags` and
/// counts the drawable cells and those facing away into `m` (`back_sign`
/// as for [`measure_cells`]; `whole`: the piece is the whole level).
#[inline(always)]
fn mark_cells(
    level: &MipLevel,
    range: NodeRange,
    xy: &NodeXY,
    back_sign: i64,
    whole: bool,
    flags: &mut Vec<u8>,
    m: &mut CellMeasure,
) {
    let (cols, rows) = range.size();
    let (ccols, crows) = (cols - 1, rows - 1);
    let lccols = level.cols - 1;
    let base = flags.len();
    if whole && back_sign == 0 {
        // No back-face test on the whole level: the level's flags as they are.
        flags.extend_from_slice(&level.cell_flags);
        m.drawable_cells = level.drawable_cells as u64;
        return;
    }
    flags.resize(base + ccols * crows, 0);
    let out = &mut flags[base..];
    for (cj, row) in out.chunks_exact_mut(ccols).enumerate() {
        let mask = &level.cell_flags[(range.j0 + cj) * lccols + range.i0..][..ccols];
        let (lo, hi) = (cj * cols, (cj + 1) * cols);
        let (xl, yl) = (&xy.xs[lo..lo + cols], &xy.ys[lo..lo + cols]);
        let (xh, yh) = (&xy.xs[hi..hi + cols], &xy.ys[hi..hi + cols]);
        let (drawn, back) = match back_sign {
            1 => mark_row::<1>(xl, yl, xh, yh, mask, row),
            -1 => mark_row::<-1>(xl, yl, xh, yh, mask, row),
            _ => mark_row::<0>(xl, yl, xh, yh, mask, row),
        };
        m.drawable_cells += drawn;
        m.backfacing_cells += back;
    }
}

/// The largest projected edge components `[ux, uy, vx, vy]` (position
/// units) of the drawn cells `out` of a piece of `cols` nodes per row,
/// `drawable` of them drawn, row by row (`narrow`: its positions' box fits
/// `i32`).
#[inline(always)]
fn largest_edges(xy: &NodeXY, out: &[u8], cols: usize, narrow: bool, drawable: u64) -> [i64; 4] {
    // No cell drawn: no edge, nothing to close (such a piece is dropped).
    if drawable == 0 {
        return [0; 4];
    }
    let mut edges = [0u64; 4];
    for (cj, row) in out.chunks_exact(cols - 1).enumerate() {
        let (lo, hi) = (cj * cols, (cj + 1) * cols);
        let (xl, yl) = (&xy.xs[lo..lo + cols], &xy.ys[lo..lo + cols]);
        let (xh, yh) = (&xy.xs[hi..hi + cols], &xy.ys[hi..hi + cols]);
        let e = if narrow {
            row_edges_narrow(xl, yl, xh, yh, row)
        } else {
            row_edges_wide(xl, yl, xh, yh, row)
        };
        for (a, b) in edges.iter_mut().zip(e) {
            *a = (*a).max(b);
        }
    }
    edges.map(|e| e as i64)
}

/// The used positions of one node row: smallest and largest x, smallest
/// and largest y (`MAX, MIN` when none) and the used count.
#[inline(always)]
fn row_box(used: &[bool], xs: &[i32], ys: &[i32]) -> (i32, i32, i32, i32, usize) {
    let n = used.iter().filter(|&&u| u).count();
    if n == xs.len() {
        // Why a plain pass for full rows: it runs in vector lanes
        // (callgrind, `profile_sphere 500 1`).
        let ((xl, xh), (lo, hi)) = (min_max(xs), min_max(ys));
        return (xl, xh, lo, hi, n);
    }
    let (mut lo, mut hi, mut xl, mut xh) = (i32::MAX, i32::MIN, i32::MAX, i32::MIN);
    for ((&u, &x), &y) in used.iter().zip(xs).zip(ys) {
        if u {
            (xl, xh, lo, hi) = (xl.min(x), xh.max(x), lo.min(y), hi.max(y));
        }
    }
    (xl, xh, lo, hi, n)
}

/// The smallest and largest values of a non-empty slice. Why through
/// `f64` (exact for every `i32`): `minpd` and `maxpd` are single
/// instructions where `i32` lanes need four without SSE4.1 (callgrind,
/// `profile_sphere 500 1`: ≈ 350 → ≈ 150 instructions per row of 17).
#[inline(always)]
fn min_max(v: &[i32]) -> (i32, i32) {
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            let x = x as f64;
            (lo.min(x), hi.max(x))
        });
    (lo as i32, hi as i32)
}

/// One pass over the cells of a piece of `cols` nodes per row whose used
/// positions differ by less than 2^24 units: cell `k` (its (0, 0) node
/// `k`, for `k` below `drawn.len()` = `(rows - 1) · cols - 1`) is a
/// candidate when `cells[k]` has [`CELL_DRAW`] (four used corners; 0 for
/// the last node of a row, see [`push_cells_by_node`]), and is drawn
/// (`drawn[k]` = [`CELL_DRAW`], else 0) unless the cross products of its
/// edges have sign `BACK` at all four corners, as [`mark_row`] decides
/// (`BACK` 0: no test). Returns the largest `|x|` and `|y|` of the drawn
/// cells' u and v edges (`[ux, uy, vx, vy]`), the drawn count and the
/// count facing away.
///
/// The products are below 2^48 and their difference below 2^49, exact in
/// `f64`, so the signs are those of the `i64` form; cells that are not
/// candidates (unused corners at 0) are masked out whatever their
/// positions give. Why one pass: the back-face test, the flags, the edge
/// masks and the masked edges were four passes over the piece (and a
/// fifth marking the rows), each with its own loop set-up on pieces of a
/// few dozen nodes (callgrind, bunny 500²).
#[inline(always)]
fn cells_small<const BACK: i64>(
    xs: &[i32],
    ys: &[i32],
    cols: usize,
    cells: &[u8],
    drawn: &mut [u8],
) -> ([u32; 4], u64, u64) {
    let m = drawn.len();
    let cells = &cells[..m];
    let (xa, xb) = (&xs[..m], &xs[1..m + 1]);
    let (xc, xd) = (&xs[cols..cols + m], &xs[cols + 1..cols + 1 + m]);
    let (ya, yb) = (&ys[..m], &ys[1..m + 1]);
    let (yc, yd) = (&ys[cols..cols + m], &ys[cols + 1..cols + 1 + m]);
    let sign = BACK as f64;
    let mut e = [0u32; 4];
    let (mut n_drawn, mut n_back) = (0u32, 0u32);
    for k in 0..m {
        let d = |p: i32, q: i32| q.wrapping_sub(p);
        let (u0, v0) = (
            (d(xa[k], xb[k]), d(ya[k], yb[k])),
            (d(xa[k], xc[k]), d(ya[k], yc[k])),
        );
        let (u1, v1) = (
            (d(xc[k], xd[k]), d(yc[k], yd[k])),
            (d(xb[k], xd[k]), d(yb[k], yd[k])),
        );
        let candidate = cells[k] & CELL_DRAW;
        let away = if BACK == 0 {
            0
        } else {
            let faces = |u: (i32, i32), v: (i32, i32)| {
                let (ux, uy, vx, vy) = (u.0 as f64, u.1 as f64, v.0 as f64, v.1 as f64);
                (ux * vy - uy * vx) * sign > 0.0
            };
            (faces(u0, v0) & faces(u0, v1) & faces(u1, v0) & faces(u1, v1)) as u8
        };
        let f = candidate & !away;
        drawn[k] = f;
        n_drawn += f as u32;
        n_back += (candidate & away) as u32;
        let keep = 0u32.wrapping_sub(f as u32);
        let larger = |a: i32, b: i32| a.unsigned_abs().max(b.unsigned_abs()) & keep;
        e[0] = e[0].max(larger(u0.0, u1.0));
        e[1] = e[1].max(larger(u0.1, u1.1));
        e[2] = e[2].max(larger(v0.0, v1.0));
        e[3] = e[3].max(larger(v0.1, v1.1));
    }
    (e, n_drawn as u64, n_back as u64)
}

/// Draw flags of one row of cells between node rows `(xl, yl)` and
/// `(xh, yh)`: the level's `mask` minus the cells facing away (`BACK`: the
/// back-face sign, 0 for no test). Returns the drawn and back-facing
/// counts.
#[inline(always)]
pub(crate) fn mark_row<const BACK: i64>(
    xl: &[i32],
    yl: &[i32],
    xh: &[i32],
    yh: &[i32],
    mask: &[u8],
    row: &mut [u8],
) -> (u64, u64) {
    let n = row.len();
    let (mut drawn, mut back) = (0, 0);
    let (xl, yl, xh, yh, mask) = (
        &xl[..n + 1],
        &yl[..n + 1],
        &xh[..n + 1],
        &yh[..n + 1],
        &mask[..n],
    );
    // The left corners of a cell are the right corners of the previous
    // one. Why carried: four loads per cell instead of eight, and the test
    // stops at the first corner that does not face away (most cells: the
    // first; callgrind, `profile_sphere 500 1`).
    let (mut a, mut c) = ((xl[0] as i64, yl[0] as i64), (xh[0] as i64, yh[0] as i64));
    for i in 0..n {
        let mut f = mask[i] & CELL_DRAW;
        let b = (xl[i + 1] as i64, yl[i + 1] as i64);
        let d = (xh[i + 1] as i64, yh[i + 1] as i64);
        if BACK != 0 && f != 0 {
            let edge = |p: (i64, i64), q: (i64, i64)| (q.0 - p.0, q.1 - p.1);
            let away = |u: (i64, i64), v: (i64, i64)| (u.0 * v.1 - u.1 * v.0) * BACK > 0;
            let (u0, v0) = (edge(a, b), edge(a, c));
            if away(u0, v0) {
                let (u1, v1) = (edge(c, d), edge(b, d));
                if away(u0, v1) && away(u1, v0) && away(u1, v1) {
                    f = 0;
                    back += 1;
                }
            }
        }
        (a, c) = (b, d);
        row[i] = f;
        drawn += f as u64;
    }
    (drawn, back)
}

/// Largest `|x|` and `|y|` of the u and v edges of the drawn cells of one
/// row (`[ux, uy, vx, vy]`), for positions whose differences fit in `i32`.
/// Why branch-free masking: the loop runs in vector lanes.
#[inline(always)]
pub(crate) fn row_edges_narrow(
    xl: &[i32],
    yl: &[i32],
    xh: &[i32],
    yh: &[i32],
    row: &[u8],
) -> [u64; 4] {
    let n = row.len();
    let (xl0, xl1, yl0, yl1) = (&xl[..n], &xl[1..n + 1], &yl[..n], &yl[1..n + 1]);
    let (xh0, xh1, yh0, yh1) = (&xh[..n], &xh[1..n + 1], &yh[..n], &yh[1..n + 1]);
    let mut e = [0u32; 4];
    for i in 0..n {
        let keep = 0u32.wrapping_sub((row[i] & CELL_DRAW) as u32);
        let d = |a: i32, b: i32| b.wrapping_sub(a).unsigned_abs() & keep;
        e[0] = e[0].max(d(xl0[i], xl1[i]).max(d(xh0[i], xh1[i])));
        e[1] = e[1].max(d(yl0[i], yl1[i]).max(d(yh0[i], yh1[i])));
        e[2] = e[2].max(d(xl0[i], xh0[i]).max(d(xl1[i], xh1[i])));
        e[3] = e[3].max(d(yl0[i], yh0[i]).max(d(yl1[i], yh1[i])));
    }
    e.map(u64::from)
}

/// [`row_edges_narrow`] in `i64`, for any positions.
pub(crate) fn row_edges_wide(
    xl: &[i32],
    yl: &[i32],
    xh: &[i32],
    yh: &[i32],
    row: &[u8],
) -> [u64; 4] {
    let mut e = [0u64; 4];
    let d = |a: i32, b: i32| (b as i64 - a as i64).unsigned_abs();
    for (i, &f) in row.iter().enumerate() {
        if f & CELL_DRAW == 0 {
            continue;
        }
        e[0] = e[0].max(d(xl[i], xl[i + 1])).max(d(xh[i], xh[i + 1]));
        e[1] = e[1].max(d(yl[i], yl[i + 1])).max(d(yh[i], yh[i + 1]));
        e[2] = e[2].max(d(xl[i], xh[i])).max(d(xl[i + 1], xh[i + 1]));
        e[3] = e[3].max(d(yl[i], yh[i])).max(d(yl[i + 1], yh[i + 1]));
    }
    e
}
