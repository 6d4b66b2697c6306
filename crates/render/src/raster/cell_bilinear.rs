//! Cell rendering by bilinear subdivision in fixed point, and the
//! node-placing path of patches that need no interpolation.
//!
//! A piece of patch is drawn as a refined grid: each drawable cell is cut
//! into `nu × nv` sub-cells, chosen per piece (fewest sub-cells, so
//! foreshortened patches are cut less across) so that every sub-cell's
//! extent `max(|u_x| + |v_x|, |u_y| + |v_y|)` (u, v its edges) is below one
//! pixel. Then every point of a cell lies within half a pixel (max norm) of
//! one of its sub-nodes, so writing each sub-node to the pixel that holds
//! it covers every pixel centre inside the cell: no holes, with no
//! per-pixel edge tests. This is recursive midpoint subdivision down to
//! sub-pixel size, evaluated non-recursively at a depth chosen in advance.
//! When `nu = nv = 1` (no magnification) only the nodes themselves are
//! placed ([`draw_nodes`]), the original work's optimized path.
//!
//! Each cell places sub-nodes `(a, b)` for `a < nu`, `b < nv`, plus its
//! last column or row when the neighbouring cell on that side is not drawn,
//! so each sub-node of a piece is placed once. A sample carries only its
//! position and depth, plus the cell and `(a, b)` so that the resolve pass
//! interpolates attributes for visible pixels only ([`crate::shade::resolve`]).
//!
//! Arithmetic: positions, depth and attributes are evaluated by forward
//! differences on `i64` values carrying 16 extra fractional bits; the
//! divisions by `nu`, `nv` and `nu · nv` are multiplications by `2^30 / n`.
//! Per sub-node: three adds and one depth test. Error: below 2^-12 pixel
//! for `n ≤ 64`.
//!
//! Rows of cells that need no clipping, in pieces cut `1 × 2`, `2 × 1`,
//! `2 × 2`, `4 × 1`, `4 × 2` or `2 × 4`, are walked sub-row by sub-row
//! instead (`walk_row`, below):
//! with powers of two the forward differences round nowhere, so the walk
//! places the same samples (only their order within the row changes).
//!
//! Based on: the spatial patch rendering of the original work (nodes placed
//! directly when a patch is not magnified, cells subdivided otherwise);
//! E. Catmull's subdivision rendering (1974) for the recursive idea.

use crate::fixed::{Node, EMPTY_NODE};
use crate::grid::{CELL_DRAW, CELL_RIGHT, CELL_TOP};
use crate::raster::band::{keep_nearer, patch_word, splat_sample, BandTarget};

/// Largest subdivision per cell side; bigger cells go to the triangle
/// rasterizer (cheaper per pixel at that size, and exact).
pub(crate) const MAX_SUBDIVISION: u32 = 64;

/// Extra fractional bits carried by the forward differences.
pub(crate) const EXT: u32 = 16;
/// Reciprocal scale.
const RECIP_BITS: u32 = 30;

/// The sub-coordinate word of sub-node `(a, b)` of cell `(ci, cj)`:
/// `ci << 24 | cj << 16 | a << 8 | b` (a grid has at most 256 cells per
/// side and `a, b <= MAX_SUBDIVISION`). Why the cell's column and row rather
/// than its number: the resolve pass then needs no division per pixel.
#[inline(always)]
pub(crate) fn sub_word(ci: usize, cj: usize, a: u32, b: u32) -> u32 {
    (ci as u32) << 24 | (cj as u32) << 16 | a << 8 | b
}

/// Places every used node of a `cols × rows` piece (the path for
/// `nu = nv = 1`). Each node is recorded as a corner of a cell it belongs to.
#[inline(always)]
pub(crate) fn draw_nodes(
    t: &mut BandTarget<'_>,
    nodes: &[Node],
    cols: usize,
    rows: usize,
    item: u32,
) {
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows);
    let mut k = 0;
    for j in 0..rows {
        let (cj, b) = if j + 1 < rows { (j, 0) } else { (j - 1, 1) };
        for i in 0..cols {
            let node = &nodes[k];
            k += 1;
            if node[0] == EMPTY_NODE {
                continue;
            }
            let py = node[1] >> 16;
            if py < y_lo || py >= y_hi {
                continue;
            }
            let (ci, a) = if i + 1 < cols { (i, 0) } else { (i - 1, 1) };
            let sub = sub_word(ci, cj, a, b);
            splat_sample(t, node[0] >> 16, py, node[2], patch_word(sub, item));
        }
    }
}

/// Reciprocals for dividing by `nu`, `nv` and `nu · nv`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Reciprocals {
    u: i64,
    v: i64,
    uv: i64,
}

impl Reciprocals {
    /// The reciprocals of a cut `nu × nv`.
    #[inline(always)]
    pub(crate) fn new(nu: u32, nv: u32) -> Self {
        Reciprocals {
            u: (1i64 << RECIP_BITS) / nu as i64,
            v: (1i64 << RECIP_BITS) / nv as i64,
            uv: (1i64 << RECIP_BITS) / (nu as i64 * nv as i64),
        }
    }
}

/// A piece of patch as the cell drawer reads it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BilinearPiece<'a> {
    /// Its `cols × rows` projected nodes, row by row.
    pub(crate) nodes: &'a [Node],
    /// Per cell, the flags of [`crate::plan::measure::measure_cells`].
    pub(crate) flags: &'a [u8],
    /// Per row of cells, the pixel rows its used nodes span (inclusive).
    pub(crate) spans: &'a [[i32; 2]],
    /// Nodes per row.
    pub(crate) cols: usize,
    /// Rows of nodes.
    pub(crate) rows: usize,
    /// Every used node lies in the image's columns `1..width - 1`.
    pub(crate) inside_columns: bool,
}

/// Draws the cells of a piece cut into `nu × nv`, as their flags (see
/// [`crate::plan::measure::measure_cells`]) say.
#[inline(always)]
pub(crate) fn draw_cells_bilinear(
    t: &mut BandTarget<'_>,
    piece: &BilinearPiece<'_>,
    nu: u32,
    nv: u32,
    item: u32,
) {
    // Why copies for the common small cuts: with `nu` and `nv` known to the
    // compiler the sub-node loops unroll and the reciprocals fold (the
    // bunny's pixel-sized cells are cut 1-3 per side); the samples and
    // their order are the same, so the images are identical. `3 × 1` and
    // `1 × 3` (a sixth of the bunny's pieces): 74.50 → 71.41 M
    // instructions per bunny frame (callgrind, 500²; 74.93 → 73.02 M with
    // one codegen unit); copies of the sphere's `4 × 3` and `3 × 4` cost
    // it 1.2 M more per frame.
    // Cuts of powers of two walk their unclipped rows of cells sub-row by
    // sub-row (`walk_row`: the same samples).
    match (nu, nv) {
        (1, 2) => draw_cells::<1, 2, true>(t, piece, nu, nv, item),
        (2, 1) => draw_cells::<2, 1, true>(t, piece, nu, nv, item),
        (2, 2) => draw_cells::<2, 2, true>(t, piece, nu, nv, item),
        (2, 3) => draw_cells::<2, 3, false>(t, piece, nu, nv, item),
        (3, 2) => draw_cells::<3, 2, false>(t, piece, nu, nv, item),
        (3, 3) => draw_cells::<3, 3, false>(t, piece, nu, nv, item),
        (4, 1) => draw_cells::<4, 1, true>(t, piece, nu, nv, item),
        (4, 2) => draw_cells::<4, 2, true>(t, piece, nu, nv, item),
        (2, 4) => draw_cells::<2, 4, true>(t, piece, nu, nv, item),
        (3, 1) => draw_cells::<3, 1, false>(t, piece, nu, nv, item),
        (1, 3) => draw_cells::<1, 3, false>(t, piece, nu, nv, item),
        _ => draw_cells::<0, 0, false>(t, piece, nu, nv, item),
    }
}

/// [`draw_cells_bilinear`] for cuts `NU × NV` known at compile time (0:
/// `nu × nv` at run time); `WALK`: the cut is a power of two per side and
/// unclipped rows of cells take the row walk (`walk_row`).
#[inline(always)]
pub(super) fn draw_cells<const NU: u32, const NV: u32, const WALK: bool>(
    t: &mut BandTarget<'_>,
    piece: &BilinearPiece<'_>,
    nu: u32,
    nv: u32,
    item: u32,
) {
    let nu = if NU == 0 { nu } else { NU };
    let nv = if NV == 0 { nv } else { NV };
    let r = Reciprocals::new(nu, nv);
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows);
    let (cols, nodes) = (piece.cols, piece.nodes);
    // Why flags: drawability, back faces and the closing column/row are
    // decided once per frame at plan time instead of per band (callgrind,
    // `profile_sphere 500 1`).
    let rows_of_cells = piece.flags.chunks_exact(cols - 1).zip(piece.spans);
    for (j, (row_flags, &[lo, hi])) in rows_of_cells.take(piece.rows - 1).enumerate() {
        // Skip a row of cells wholly outside the band (its span covers its
        // used nodes). Why: an item is walked by every band it touches
        // (callgrind, `profile_sphere 500 1`).
        if hi < y_lo || lo >= y_hi {
            continue;
        }
        let below = &nodes[j * cols..(j + 1) * cols];
        let above = &nodes[(j + 1) * cols..(j + 2) * cols];
        // A row of cells whose span lies a pixel inside the band, in a piece
        // inside the image's columns, has every cell inside (the same test
        // as a cell's box below): no per-cell box. Why: most rows are (bands
        // of 64 rows, cells of 1–3 px); 86.0 → 83.0 M instructions per frame
        // (callgrind, `profile_sphere 500 1`).
        let row_inside = piece.inside_columns && lo > y_lo && hi < y_hi - 1;
        let row = CellRow {
            flags: row_flags,
            below,
            above,
            j,
        };
        if WALK && row_inside {
            walk_row::<NU, NV>(t, row, nu, nv, item);
            continue;
        }
        let inside = (row_inside, piece.inside_columns);
        draw_row_cells(t, row, inside, (r, nu, nv), item);
    }
}

/// Draws the drawn cells of `row` one at a time, cut `nu × nv`
/// (reciprocals `r`): `row_inside`, every cell lies in the band; else
/// each is tested ([`cell_in_band`]; `inside_columns` as in
/// [`BilinearPiece`]) and clipped when it crosses the band's edges.
#[inline(always)]
fn draw_row_cells(
    t: &mut BandTarget<'_>,
    row: CellRow<'_>,
    (row_inside, inside_columns): (bool, bool),
    (r, nu, nv): (Reciprocals, u32, u32),
    item: u32,
) {
    let CellRow {
        flags,
        below,
        above,
        j,
    } = row;
    let cells = flags.iter().zip(below.windows(2)).zip(above.windows(2));
    for (i, ((&f, b), a)) in cells.enumerate() {
        if f & CELL_DRAW == 0 {
            continue;
        }
        let c = [&b[0], &b[1], &a[0], &a[1]];
        let right = (f & CELL_RIGHT != 0) as u32;
        let top = (f & CELL_TOP != 0) as u32;
        let (cut, word) = ([nu, right, nv, top], patch_word(sub_word(i, j, 0, 0), item));
        if row_inside {
            draw_cell::<false>(t, c, r, cut, word);
            continue;
        }
        let Some(inside) = cell_in_band(t, c, inside_columns) else {
            continue;
        };
        if inside {
            draw_cell::<false>(t, c, r, cut, word);
        } else {
            draw_cell::<true>(t, c, r, cut, word);
        }
    }
}

/// Forward-difference set-up of one channel: start, row step, column step
/// and its change per row.
#[inline(always)]
pub(crate) fn setup(c00: i32, c10: i32, c01: i32, c11: i32, r: Reciprocals) -> [i64; 4] {
    let shift = RECIP_BITS - EXT;
    let (a, b, c, d) = (c00 as i64, c10 as i64, c01 as i64, c11 as i64);
    [
        a << EXT,
        ((c - a) * r.v) >> shift,
        ((b - a) * r.u) >> shift,
        ((d - b - c + a) * r.uv) >> shift,
    ]
}

/// Moves the forward differences of x, y and depth (each from [`setup`])
/// up one row of sub-nodes: the row's start by the row step, the column
/// step by its change per row.
#[inline(always)]
pub(crate) fn next_row(start: &mut [i64; 3], step: &mut [i64; 3], channels: [[i64; 4]; 3]) {
    for (k, s) in channels.iter().enumerate() {
        start[k] += s[1];
        step[k] += s[3];
    }
}

/// Places the sub-nodes of one cell, `[nu, right, nv, top]` of `cut`: `nu`
/// (plus one when `right` is 1) per row, `nv` rows (plus one when `top` is
/// 1); `CLIP = false` when the caller has checked that the cell lies inside
/// the band and the image; `word0` is the [`patch_word`] of sub-node
/// `(0, 0)`. Why: the unclipped variant drops the per-row band test and
/// the per-sample bounds compares (callgrind, `profile_sphere 500 1`: see
/// docs/performance-log.md).
#[inline(always)]
pub(crate) fn draw_cell<const CLIP: bool>(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    r: Reciprocals,
    [nu, right, nv, top]: [u32; 4],
    word0: u64,
) {
    let (mut start, mut step, channels) = cell_differences::<CLIP>(t, c, r);
    let (y_lo, y_hi) = (t.y0 as i64, (t.y0 + t.rows) as i64);
    let rows = Row {
        nu,
        right,
        band: [y_lo, y_hi],
    };
    // `nv` rows, then the closing one when `top` is 1 (the `break` says so
    // to the compiler). Why a row drawer of its own rather than the loop
    // body inline: 77.29 → 75.79 M instructions per bunny frame (callgrind,
    // 500²); as a closure it was not inlined (89.3 M).
    for b in 0..nv + top {
        if b == nv && top == 0 {
            break;
        }
        rows.draw::<CLIP>(t, start, step, word0 + b as u64);
        next_row(&mut start, &mut step, channels);
    }
}

/// The forward differences ([`setup`]) of x, y and depth over the cell
/// with corners `c` for a band `t`: the first sub-node, the column step
/// and the channels for [`next_row`]. Unclipped (`CLIP = false`), y is
/// kept relative to the band's first row (an exact shift of whole
/// pixels), so a sample's row needs no subtraction.
#[inline(always)]
fn cell_differences<const CLIP: bool>(
    t: &BandTarget<'_>,
    c: [&Node; 4],
    r: Reciprocals,
) -> ([i64; 3], [i64; 3], [[i64; 4]; 3]) {
    let s = |ch: usize| setup(c[0][ch], c[1][ch], c[2][ch], c[3][ch], r);
    let (sx, sy, sz) = (s(0), s(1), s(2));
    let y_origin = if CLIP { 0 } else { (t.y0 as i64) << (16 + EXT) };
    let start = [sx[0], sy[0] - y_origin, sz[0]];
    (start, [sx[2], sy[2], sz[2]], [sx, sy, sz])
}

/// Places, for each row `b` of sub-nodes `0..=nv` of one cell cut
/// `nu × nv` (`r` their reciprocals), the run of sub-nodes `a0..=a1` that
/// `run(b)` names (none when `None`), each sample pushed back by `z_bias`:
/// the cells drawn by quarters ([`crate::raster::cell_quarters`]). `CLIP`
/// and `word0` as for [`draw_cell`].
#[inline(always)]
pub(crate) fn draw_cell_runs<const CLIP: bool>(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    ([_, nv], r, z_bias): ([u32; 2], Reciprocals, i64),
    word0: u64,
    run: impl Fn(u32) -> Option<(u32, u32)>,
) {
    let (mut start, mut step, channels) = cell_differences::<CLIP>(t, c, r);
    start[2] += z_bias << EXT;
    let (y_lo, y_hi) = (t.y0 as i64, (t.y0 + t.rows) as i64);
    for b in 0..=nv {
        if let Some((a0, a1)) = run(b) {
            let v = [0, 1, 2].map(|k| start[k] + a0 as i64 * step[k]);
            let row = Row {
                nu: a1 - a0 + 1,
                right: 0,
                band: [y_lo, y_hi],
            };
            row.draw::<CLIP>(t, v, step, word0 + ((a0 << 8) + b) as u64);
        }
        next_row(&mut start, &mut step, channels);
    }
}

/// What every row of sub-nodes of one cell shares (see [`draw_cell`]).
#[derive(Clone, Copy)]
struct Row {
    nu: u32,
    right: u32,
    band: [i64; 2],
}

impl Row {
    /// Places one row of sub-nodes starting at `v` with column step
    /// `step`, the first sample's [`patch_word`] `row_word`.
    #[inline(always)]
    fn draw<const CLIP: bool>(
        self,
        t: &mut BandTarget<'_>,
        mut v: [i64; 3],
        step: [i64; 3],
        row_word: u64,
    ) {
        let Row {
            nu,
            right,
            band: [y_lo, y_hi],
        } = self;
        let xy_shift = 16 + EXT;
        // The word of sample (a, b) is `row_word + a << 8` (the sub-word is
        // its low half): kept as a running sum so the loop carries no index.
        let mut word = row_word;
        if CLIP {
            let a_end = nu + right;
            // Skip rows wholly outside the band.
            let y_first = v[1] >> xy_shift;
            let y_last = (v[1] + step[1] * (a_end as i64 - 1)) >> xy_shift;
            if !(y_first.max(y_last) < y_lo || y_first.min(y_last) >= y_hi) {
                for _ in 0..a_end {
                    let (px, py) = ((v[0] >> xy_shift) as i32, (v[1] >> xy_shift) as i32);
                    splat_sample(t, px, py, (v[2] >> EXT) as i32, word);
                    word += 1 << 8;
                    v[0] += step[0];
                    v[1] += step[1];
                    v[2] += step[2];
                }
            }
        } else {
            // `nu` samples, then the closing one: a loop of a constant
            // count when `nu` is (see `draw_cells_bilinear`).
            for _ in 0..nu {
                place_inside(t, v, word);
                word += 1 << 8;
                v[0] += step[0];
                v[1] += step[1];
                v[2] += step[2];
            }
            if right != 0 {
                place_inside(t, v, word);
            }
        }
    }
}

/// Where the cell with corners `c` lies against the band of `t`: `None`
/// when wholly outside the band's rows, else whether its corners lie a
/// pixel inside the band and the image, so that no sample needs clipping
/// (samples are convex combinations of the corners, up to 2^-12 px).
/// `inside_columns`: the piece is known to lie inside the image's columns.
/// Why min/max rather than per-corner tests: one pass of branch-free
/// compares decides both the band test and the unclipped path (callgrind,
/// `profile_sphere 500 1`); most cells are inside (see the "why" in
/// `draw_cell`).
#[inline(always)]
pub(crate) fn cell_in_band(
    t: &BandTarget<'_>,
    c: [&Node; 4],
    inside_columns: bool,
) -> Option<bool> {
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows);
    let y_min = c[0][1].min(c[1][1]).min(c[2][1]).min(c[3][1]) >> 16;
    let y_max = c[0][1].max(c[1][1]).max(c[2][1]).max(c[3][1]) >> 16;
    if y_max < y_lo || y_min >= y_hi {
        return None;
    }
    let inside_columns = inside_columns || {
        let x_min = c[0][0].min(c[1][0]).min(c[2][0]).min(c[3][0]) >> 16;
        let x_max = c[0][0].max(c[1][0]).max(c[2][0]).max(c[3][0]) >> 16;
        x_min > 0 && x_max < t.width - 1
    };
    Some(y_min > y_lo && y_max < y_hi - 1 && inside_columns)
}

/// Writes the sample at `v` (forward-difference units, `y` relative to
/// the band) known to lie inside the band and the image.
#[inline(always)]
fn place_inside(t: &mut BandTarget<'_>, v: [i64; 3], word: u64) {
    let xy_shift = 16 + EXT;
    let row = (v[1] >> xy_shift) as usize;
    let idx = row * t.width as usize + (v[0] >> xy_shift) as usize;
    debug_assert!((v[0] >> xy_shift) < t.width as i64 && row < t.rows as usize);
    let z = (v[2] >> EXT) as i32;
    // The slice index still checks: a broken caller panics, never writes
    // elsewhere.
    keep_nearer(&mut t.px[idx], z, word);
}

// The row walk of the bilinear cell drawer: a whole row of cells placed
// sub-row by sub-row, for cuts `nu × nv` that are powers of two, in rows
// of cells that lie a pixel inside the band and the image (no clipping).
//
// Row of cells `j` lies between node rows `j` and `j + 1`. For sub-row
// `b` (`0..nv`, plus the closing row `nv` for cells whose `CELL_TOP` is
// set), the point `E_i(b) = lerp(node(i, j), node(i, j + 1), b / nv)` of
// node column `i` is computed once: it is cell `i`'s sub-node `(0, b)`,
// and cell `i - 1`'s closing sub-node `(nu, b)` when its `CELL_RIGHT` is
// set. Cell `i`'s sub-nodes `(a, b)`, `a < nu`, follow from `E_i(b)` by
// `a` steps of `(E_{i+1}(b) - E_i(b)) / nu`. Undrawn cells place nothing.
//
// Exactness: with `nu = 2^lu`, `nv = 2^lv` the per-cell forward
// differences (`setup`, `next_row` above) divide by
// exact reciprocals, so they round nowhere; both kernels then compute the
// same exact integers (`E_i(b)` is the per-cell row start, the step the
// per-cell column step `Cu + b·D`, since `lu + lv <= 16`). The samples are
// the same bit for bit; only their order within a row of cells changes
// (sub-row major instead of cell major), which matters only for two
// samples of one piece with equal depth in one pixel. Cuts with another
// factor (3, 5, …) round differently per cell and stay with the per-cell
// kernel, as do rows that need clipping.
//
// Why: a sub-row keeps two edge points live (the per-cell kernel twelve
// corner values) and shares each with the neighbouring cell; 76.59 →
// 74.48 M instructions per bunny frame (callgrind, 500², see
// docs/algorithms/render.md: the samples, not the set-up, are most of a
// pixel-sized cell's cost, so the gain is small).

/// One row of cells as the row walk reads it.
#[derive(Clone, Copy)]
struct CellRow<'a> {
    /// The flags of its `cols - 1` cells.
    flags: &'a [u8],
    /// Its lower row of nodes (`cols`).
    below: &'a [Node],
    /// Its upper row of nodes (`cols`).
    above: &'a [Node],
    /// Its index in the piece.
    j: usize,
}

/// Whether a cut `nu × nv` can be walked by rows (both powers of two).
#[inline(always)]
fn walkable(nu: u32, nv: u32) -> bool {
    nu.is_power_of_two() && nv.is_power_of_two()
}

/// Places every sub-node of the drawn cells of `row`, cut `nu × nv`
/// (powers of two: [`walkable`]; `NU`, `NV` the same when known at compile
/// time, else 0). The caller has checked that every node of the row lies a
/// pixel inside the band and the image.
#[inline(always)]
fn walk_row<const NU: u32, const NV: u32>(
    t: &mut BandTarget<'_>,
    row: CellRow<'_>,
    nu: u32,
    nv: u32,
    item: u32,
) {
    let nu = if NU == 0 { nu } else { NU };
    let nv = if NV == 0 { nv } else { NV };
    debug_assert!(walkable(nu, nv) && nu <= 64 && nv <= 64);
    let cut = [nu, nu.trailing_zeros(), nv, nv.trailing_zeros()];
    // y relative to the band's first row (an exact shift of whole pixels),
    // as `draw_cell` keeps it unclipped.
    let y_origin = (t.y0 as i64) << (16 + EXT);
    let pass = |t: &mut BandTarget<'_>, b: u32| sub_row::<NU>(t, row, b, cut, y_origin, item);
    // Why the sub-rows spelled out for `nv <= 4`: with `b` a constant the
    // edge points need no multiply (`b = 0`, `b = nv`: a shift; `2b = nv`:
    // an add and a shift, the same integer; else a constant factor).
    let tops = match NV {
        1 => pass(t, 0),
        2 => pass(t, 0) | pass(t, 1),
        4 => pass(t, 0) | pass(t, 1) | pass(t, 2) | pass(t, 3),
        _ => (0..nv).fold(0, |tops, b| tops | pass(t, b)),
    };
    if tops & CELL_TOP != 0 {
        pass(t, nv);
    }
}

/// Places sub-row `b` of the drawn cells of `row` (`cut`: `[nu, lu, nv,
/// lv]`, `nu = 2^lu`, `nv = 2^lv`; `b = nv`: the closing row of the cells
/// whose `CELL_TOP` is set) and returns the flags of its cells or-ed.
#[inline(always)]
fn sub_row<const NU: u32>(
    t: &mut BandTarget<'_>,
    row: CellRow<'_>,
    b: u32,
    [nu, lu, nv, lv]: [u32; 4],
    y_origin: i64,
    item: u32,
) -> u8 {
    // `E(b)` of one node column; the same integers as the per-cell
    // kernel's row start after `b` rows (see the module header).
    let lerp = |lo: &Node, hi: &Node| {
        let e = |ch: usize| {
            let (l, h) = (lo[ch] as i64, hi[ch] as i64);
            if b == 0 {
                l << EXT
            } else if b == nv {
                h << EXT
            } else if 2 * b == nv {
                (l + h) << (EXT - 1)
            } else {
                (l << EXT) + b as i64 * ((h - l) << (EXT - lv))
            }
        };
        [e(0), e(1) - y_origin, e(2)]
    };
    let cell = |t: &mut BandTarget<'_>, f: u8, ends: [[i64; 3]; 2], word: u64| {
        if f & CELL_DRAW != 0 && (b < nv || f & CELL_TOP != 0) {
            place_span::<NU>(t, ends, [nu, lu], f & CELL_RIGHT != 0, word);
        }
    };
    let mut left = lerp(&row.below[0], &row.above[0]);
    let mut word = patch_word(sub_word(0, row.j, 0, b), item);
    let mut tops = 0;
    // Two cells a turn, the edge points taking turns as left and right.
    // Why: no copy of the right edge into the left one per cell.
    let (flags, below, above) = (row.flags, &row.below[1..], &row.above[1..]);
    let pairs = flags.chunks_exact(2).zip(below.chunks_exact(2));
    for ((f, lo), hi) in pairs.zip(above.chunks_exact(2)) {
        let mid = lerp(&lo[0], &hi[0]);
        cell(t, f[0], [left, mid], word);
        left = lerp(&lo[1], &hi[1]);
        cell(t, f[1], [mid, left], word + (1 << 24));
        tops |= f[0] | f[1];
        word += 2 << 24;
    }
    if flags.len() % 2 == 1 {
        let k = flags.len() - 1;
        let f = flags[k];
        cell(t, f, [left, lerp(&below[k], &above[k])], word);
        tops |= f;
    }
    tops
}

/// Places one cell's sub-nodes `(a, b)` of one sub-row, from its left edge
/// point to its right one (`ends`), `a < nu` (`[nu, lu]` with
/// `nu = 2^lu`), plus `a = nu` when `closing`; `word` is `(0, b)`'s
/// [`patch_word`].
#[inline(always)]
fn place_span<const NU: u32>(
    t: &mut BandTarget<'_>,
    [left, right]: [[i64; 3]; 2],
    [nu, lu]: [u32; 2],
    closing: bool,
    word: u64,
) {
    let nu = if NU == 0 { nu } else { NU };
    // Exact: the difference is a multiple of `nu` (see the module header).
    let step = [0, 1, 2].map(|k| (right[k] - left[k]) >> lu);
    let (mut v, mut word) = (left, word);
    for _ in 0..nu {
        place_inside(t, v, word);
        word += 1 << 8;
        v = [v[0] + step[0], v[1] + step[1], v[2] + step[2]];
    }
    if closing {
        place_inside(t, right, word);
    }
}
