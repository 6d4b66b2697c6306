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
//! Cost: O(nodes), no allocation once warm: ≈ 27 instructions per node on
//! the sphere at 500² (callgrind, `profile_sphere 500 1`).

use crate::grid::{close_cells, drawn_edge_masks, CELL_DRAW};
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
/// array (`measure_cells_reference` in `measure_tests`, kept for the tests), in fewer
/// instructions. Why (callgrind, `profile_sphere 500 1`; ≈ 155
/// instructions per cell before): which cells have four used corners, and
/// their closing flags without back-face culling, come from the level
/// ([`MipLevel::cell_flags`]); the row boxes come from the projection when
/// it kept them ([`NodeXY::row_stats`]); on pieces spanning less than
/// 2^24 units (256 px) the back-face test runs in `f64` lanes
/// ([`away_cells_small`]) and the largest edges in flat `f32` passes over
/// the whole piece ([`piece_edges_small`], [`piece_edges_masked_small`]);
/// wider pieces take them row by row in `i32` or `i64`.
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
    mark_cells(level, range, xy, back_sign, (small, whole), flags, &mut m);
    let out = &mut flags[base..];
    // The level's own edge masks serve when its flags are the piece's (a
    // whole level, no back-face test).
    let own_masks = whole && back_sign == 0;
    let drawable = m.drawable_cells;
    m.edges = largest_edges(
        level,
        xy,
        out,
        (cols, rows),
        (small, narrow, own_masks),
        drawable,
    );
    // Closing flags: the level's own when the piece is the whole level and
    // no cell faced away (already in `out` when no cell was tested).
    let [right, top, both] = if whole && m.backfacing_cells == 0 {
        if back_sign != 0 {
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

/// Appends the flag byte of every cell of `range` to `flags` and counts
/// the drawable cells and those facing away into `m` (`back_sign` as for
/// [`measure_cells`]; `small`: the piece spans under 2^24 units, `whole`:
/// it is the whole level).
#[inline(always)]
fn mark_cells(
    level: &MipLevel,
    range: NodeRange,
    xy: &mut NodeXY,
    back_sign: i64,
    (small, whole): (bool, bool),
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
    if small && back_sign != 0 {
        // Which cells face away, for the whole piece in `f64` lanes.
        // Why: the `i64` test per cell cost ≈ 40 instructions (2.7 M
        // per 500² sphere frame; callgrind, `profile_sphere 500 1`).
        xy.away.clear();
        xy.away.resize(crows * cols - 1, 0);
        if back_sign > 0 {
            away_cells_small::<1>(&xy.xs, &xy.ys, cols, &mut xy.away);
        } else {
            away_cells_small::<-1>(&xy.xs, &xy.ys, cols, &mut xy.away);
        }
    }
    for (cj, row) in out.chunks_exact_mut(ccols).enumerate() {
        let mask = &level.cell_flags[(range.j0 + cj) * lccols + range.i0..][..ccols];
        if small && back_sign != 0 {
            let away = &xy.away[cj * cols..][..ccols];
            let (mut drawn, mut back) = (0u32, 0u32);
            for ((f, &mask), &away) in row.iter_mut().zip(mask).zip(away) {
                let candidate = mask & CELL_DRAW;
                *f = candidate & !away;
                drawn += *f as u32;
                back += (candidate & away) as u32;
            }
            m.drawable_cells += drawn as u64;
            m.backfacing_cells += back as u64;
            continue;
        }
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
/// units) of the drawn cells `out` of a piece of `cols × rows` nodes of
/// `level`, `drawable` of them drawn (`small`, `narrow`: the piece's span
/// fits 2^24 units, `i32`; `own_masks`: the level's edge masks are the
/// piece's).
#[inline(always)]
fn largest_edges(
    level: &MipLevel,
    xy: &mut NodeXY,
    out: &[u8],
    (cols, rows): (usize, usize),
    (small, narrow, own_masks): (bool, bool, bool),
    drawable: u64,
) -> [i64; 4] {
    let ccols = cols - 1;
    let mut edges = [0u64; 4];
    let all_drawn = drawable as usize == ccols * (rows - 1);
    if small && all_drawn {
        // Every cell drawn: every edge of the piece, in flat passes. Why:
        // rows of 17 nodes left a set-up and a remainder per row and per
        // edge component (callgrind, `profile_sphere 500 1`).
        if (xy.wrap.len(), xy.wrap_cols) != (cols * rows, cols) {
            xy.wrap_cols = cols;
            xy.wrap.clear();
            xy.wrap
                .extend((0..cols * rows).map(|k| -((k % cols != cols - 1) as i32)));
        }
        edges = piece_edges_small(&xy.xs, &xy.ys, cols, &xy.wrap);
    } else if small && drawable > 0 {
        // Some cells not drawn: the same passes, each edge masked by
        // whether a drawn cell has it. Why: as above, for the pieces the
        // back-face test cut (callgrind, `profile_sphere 500 1`).
        // The level's own masks when its flags are the piece's (a whole
        // level with trimmed cells, no cell facing away). Why: building
        // them per frame cost ≈ 2 M instructions on the trimmed sphere
        // (callgrind, `profile_sphere 500 1 1 trimmed`).
        // (The level's masks are asked for only then: they are built on
        // first use.)
        let own = if own_masks { level.edge_masks() } else { None };
        let (um, vm) = match own {
            Some(masks) => masks,
            None => {
                drawn_edge_masks(out, cols, rows, &mut xy.umask, &mut xy.vmask);
                (&xy.umask[..], &xy.vmask[..])
            }
        };
        edges = piece_edges_masked_small(&xy.xs, &xy.ys, cols, um, vm);
    }
    for (cj, row) in out.chunks_exact(ccols).enumerate() {
        // Done by the flat passes, or no cell drawn (no edge, nothing to
        // close: such a piece is dropped).
        if small || drawable == 0 {
            break;
        }
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

/// Largest `|x|` and `|y|` of every u and v edge (`[ux, uy, vx, vy]`) of
/// a piece of `cols` nodes per row whose cells are all drawn and whose
/// positions differ by less than 2^24 (exact in `f32`; `maxps` and `andps`
/// are single instructions where `u32` lanes need several without
/// SSE4.1). `wrap[k]` is 0 for the last node of a row (no u edge), else
/// all ones.
#[inline(always)]
pub(crate) fn piece_edges_small(xs: &[i32], ys: &[i32], cols: usize, wrap: &[i32]) -> [u64; 4] {
    let n = xs.len();
    let m = n - cols;
    let d = |a: i32, b: i32| (b.wrapping_sub(a) as f32).abs();
    let du = |a: i32, b: i32, w: i32| (b.wrapping_sub(a) & w) as f32;
    // Rows 0..rows - 1: their u edges and the v edges above them.
    let (x0, x1, xv) = (&xs[..m], &xs[1..m + 1], &xs[cols..cols + m]);
    let (y0, y1, yv) = (&ys[..m], &ys[1..m + 1], &ys[cols..cols + m]);
    let w = &wrap[..m];
    let mut e = [0f32; 4];
    for k in 0..m {
        e[0] = e[0].max(du(x0[k], x1[k], w[k]).abs());
        e[1] = e[1].max(du(y0[k], y1[k], w[k]).abs());
        e[2] = e[2].max(d(x0[k], xv[k]));
        e[3] = e[3].max(d(y0[k], yv[k]));
    }
    // The last row's u edges.
    let (x0, x1, y0, y1) = (&xs[m..n - 1], &xs[m + 1..], &ys[m..n - 1], &ys[m + 1..]);
    for k in 0..cols - 1 {
        e[0] = e[0].max(d(x0[k], x1[k]));
        e[1] = e[1].max(d(y0[k], y1[k]));
    }
    e.map(|v| v as u64)
}

/// [`piece_edges_small`] for a piece whose cells are not all drawn:
/// `um[k]` (`vm[k]`) is all ones when node `k`'s u (v) edge belongs to a
/// drawn cell, else 0.
#[inline(always)]
pub(crate) fn piece_edges_masked_small(
    xs: &[i32],
    ys: &[i32],
    cols: usize,
    um: &[i32],
    vm: &[i32],
) -> [u64; 4] {
    let n = xs.len();
    let m = n - cols;
    let d = |a: i32, b: i32, w: i32| ((b.wrapping_sub(a) & w) as f32).abs();
    let mut e = [0f32; 4];
    let (x0, x1, y0, y1, um) = (&xs[..n - 1], &xs[1..], &ys[..n - 1], &ys[1..], &um[..n - 1]);
    for k in 0..n - 1 {
        e[0] = e[0].max(d(x0[k], x1[k], um[k]));
        e[1] = e[1].max(d(y0[k], y1[k], um[k]));
    }
    let (x0, xv, y0, yv, vm) = (&xs[..m], &xs[cols..], &ys[..m], &ys[cols..], &vm[..m]);
    for k in 0..m {
        e[2] = e[2].max(d(x0[k], xv[k], vm[k]));
        e[3] = e[3].max(d(y0[k], yv[k], vm[k]));
    }
    e.map(|v| v as u64)
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

/// For every cell of a piece of `cols` nodes per row (its (0, 0) node at
/// `k`; `away[k]` for `k` below `(rows - 1) · cols - 1`, the last node of
/// a row giving a meaningless value), 1 when the cross products of its
/// edges have sign `BACK` at all four corners (it faces away), as
/// [`mark_row`] decides. For positions whose differences are below 2^24:
/// the products are then below 2^48 and their difference below 2^49, exact
/// in `f64`, so the signs are those of the `i64` form.
#[inline(always)]
fn away_cells_small<const BACK: i64>(xs: &[i32], ys: &[i32], cols: usize, away: &mut [u8]) {
    let m = away.len();
    let (xa, xb) = (&xs[..m], &xs[1..m + 1]);
    let (xc, xd) = (&xs[cols..cols + m], &xs[cols + 1..cols + 1 + m]);
    let (ya, yb) = (&ys[..m], &ys[1..m + 1]);
    let (yc, yd) = (&ys[cols..cols + m], &ys[cols + 1..cols + 1 + m]);
    let sign = BACK as f64;
    for k in 0..m {
        let d = |p: i32, q: i32| q.wrapping_sub(p) as f64;
        let (u0, v0) = (
            (d(xa[k], xb[k]), d(ya[k], yb[k])),
            (d(xa[k], xc[k]), d(ya[k], yc[k])),
        );
        let (u1, v1) = (
            (d(xc[k], xd[k]), d(yc[k], yd[k])),
            (d(xb[k], xd[k]), d(yb[k], yd[k])),
        );
        let faces = |u: (f64, f64), v: (f64, f64)| (u.0 * v.1 - u.1 * v.0) * sign > 0.0;
        away[k] = (faces(u0, v0) & faces(u0, v1) & faces(u1, v0) & faces(u1, v1)) as u8;
    }
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
