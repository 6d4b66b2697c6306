//! The grid vocabulary every stage shares: the per-cell flags of a piece
//! (drawn, closes its right column, closes its top row), which cells of a
//! grid of displacement codes have four filled corners, how a piece's
//! flags close its last column and row, the cell flags laid out along the
//! node rows, and the weight of each node within a displacement range.
//!
//! Each drawn cell places its sub-nodes `(a, b)` for `a < nu`, `b < nv`,
//! plus its last column or row when the neighbouring cell on that side is
//! not drawn ([`close_cells`]), so each sub-node of a piece is placed once.
//! These do not depend on the view: a mip level computes them once per
//! scene ([`crate::prepare::mip`]) and a frame only adds its back-face
//! test ([`crate::plan::measure`]).
//!
//! Cost: one pass over the cells (or nodes), in byte or word lanes.

use spatch_format::EMPTY;

use crate::fixed::{Node, EMPTY_NODE};

/// Cell flag: the cell is drawn (its four corners are used and, with
/// back-face culling, it does not face away everywhere).
pub(crate) const CELL_DRAW: u8 = 1;
/// Cell flag: the cell also places its last column of sub-nodes (its right
/// neighbour is not drawn).
pub(crate) const CELL_RIGHT: u8 = 2;
/// Cell flag: the cell also places its last row of sub-nodes.
pub(crate) const CELL_TOP: u8 = 4;
/// Cell flag: the cell's side along its first node row (toward cell
/// `(i, j − 1)`) is an outline of the surface
/// ([`crate::plan::open_sides`]); set only on magnified pieces.
pub(crate) const CELL_OPEN_BOTTOM: u8 = 8;
/// Cell flag: the side toward cell `(i + 1, j)` is an outline.
pub(crate) const CELL_OPEN_RIGHT: u8 = 16;
/// Cell flag: the side toward cell `(i, j + 1)` is an outline.
pub(crate) const CELL_OPEN_TOP: u8 = 32;
/// Cell flag: the side toward cell `(i − 1, j)` is an outline.
pub(crate) const CELL_OPEN_LEFT: u8 = 64;
/// Cell flag: the cell is drawn by pixel-centre coverage
/// ([`crate::raster::cell_exact`]); set on every drawn cell of a piece
/// that asks for exact outlines ([`crate::plan::piece`]).
pub(crate) const CELL_EXACT: u8 = 128;
/// A cell drawn by the finer cells (quarters) it holds, not whole: level
/// 1's cells along a patch's outline ([`crate::prepare::quarters`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct QuarteredCell {
    /// The cell's index in its level, row by row.
    pub(crate) cell: u32,
    /// Bit `a + 2 b` set when quarter `(a, b)` (`a` along the row) holds a
    /// drawable finer cell; never 0.
    pub(crate) quarters: u8,
}

/// Every open-side flag.
pub(crate) const CELL_OPEN: u8 =
    CELL_OPEN_BOTTOM | CELL_OPEN_RIGHT | CELL_OPEN_TOP | CELL_OPEN_LEFT;

/// True when the four corners of the cell whose (0, 0) node is `k` are used.
#[inline]
pub(crate) fn cell_drawable(nodes: &[Node], k: usize, cols: usize) -> bool {
    nodes[k][0] != EMPTY_NODE
        && nodes[k + 1][0] != EMPTY_NODE
        && nodes[k + cols][0] != EMPTY_NODE
        && nodes[k + cols + 1][0] != EMPTY_NODE
}

/// Marks which drawn cells of a `ccols × crows` flag array close their
/// right column ([`CELL_RIGHT`]: the next cell of the row is not drawn)
/// and their top row ([`CELL_TOP`]: the cell above is not drawn). Returns
/// the counts of right, top and both.
#[inline(always)]
pub(crate) fn close_cells(cell_flags: &mut [u8], ccols: usize, crows: usize) -> [u64; 3] {
    let mut counts = [0u64; 3];
    // Why byte arithmetic on row slices: no branch or bounds check per cell
    // (callgrind, `profile_sphere 500 1`: ~4 M instructions per frame
    // before).
    for j in 0..crows {
        let (head, tail) = cell_flags.split_at_mut((j + 1) * ccols);
        let row = &mut head[j * ccols..];
        let above: &[u8] = if j + 1 < crows { &tail[..ccols] } else { &[] };
        // The next cell's and the upper cell's drawn bits, 0 past the end.
        let mut next = [0u8; 64];
        let mut over = [0u8; 64];
        if ccols <= next.len() {
            next[..ccols - 1].copy_from_slice(&row[1..]);
            if !above.is_empty() {
                over[..ccols].copy_from_slice(above);
            }
            let (next, over) = (&next[..ccols], &over[..ccols]);
            // Byte counters (at most 64 cells a row): the loop stays in
            // byte lanes.
            let (mut right_n, mut top_n, mut both_n) = (0u8, 0u8, 0u8);
            for ((f, &n), &o) in row.iter_mut().zip(next).zip(over) {
                let drawn = *f & CELL_DRAW;
                let (right, top) = (drawn & !n, drawn & !o);
                *f |= (right * CELL_RIGHT) | (top * CELL_TOP);
                right_n += right;
                top_n += top;
                both_n += right & top;
            }
            counts[0] += right_n as u64;
            counts[1] += top_n as u64;
            counts[2] += both_n as u64;
            continue;
        }
        for i in 0..ccols {
            let drawn = row[i] & CELL_DRAW;
            let next = row.get(i + 1).map_or(0, |f| f & CELL_DRAW);
            let over = above.get(i).map_or(0, |f| f & CELL_DRAW);
            let (right, top) = (drawn & !next, drawn & !over);
            row[i] |= (right * CELL_RIGHT) | (top * CELL_TOP);
            counts[0] += right as u64;
            counts[1] += top as u64;
            counts[2] += (right & top) as u64;
        }
    }
    counts
}

/// Appends to `out` the cell flags `rows` (each row `ccols` cells) laid
/// out along the node rows: per node, [`CELL_DRAW`] when the cell whose
/// (0, 0) node it is has that bit, and 0 for the last node of each row
/// (no cell). Why: the measurement takes a piece's cells in one flat pass
/// over its nodes ([`crate::plan::measure`]).
#[inline(always)]
pub(crate) fn push_cells_by_node<'a>(rows: impl Iterator<Item = &'a [u8]>, out: &mut Vec<u8>) {
    for row in rows {
        out.extend(row.iter().map(|&f| f & CELL_DRAW));
        out.push(0);
    }
}

/// Appends the trilinear weights of displacements `disp` along the range
/// `d` (`(dk - d.0) / (d.1 - d.0)`, 0 when the range is flat; meaningless
/// for empty nodes) to `out`, in the operations of the `Vec3` form. Why a
/// pass of its own: it converts in vector lanes.
#[inline(always)]
pub(crate) fn push_weights(disp: &[u16], d: (u16, u16), out: &mut Vec<f32>) {
    let inv_d = if d.1 > d.0 {
        1.0 / (d.1 - d.0) as f32
    } else {
        0.0
    };
    out.extend(disp.iter().map(|&dk| dk.wrapping_sub(d.0) as f32 * inv_d));
}

/// Per cell of a `cols × rows` grid of displacement codes (row-major,
/// `(cols - 1) × (rows - 1)`), true when its four corners are filled. Why
/// one flat pass over the grid (every node with the three after it along
/// the row and across, the nodes closing a row dropped after): the test
/// runs in byte lanes over the whole grid; a row at a time (15–17 cells on
/// a scan) left it to the loops' scalar remainders (3.6 M of a one-frame
/// bunny render's 187 M instructions; callgrind, `spatch render
/// bunny.spatch -o out.png --threads 1`). Why the four codes' largest
/// compared with [`EMPTY`] (the largest code), and the closing nodes
/// dropped in place: a vector of filled flags and one of the flat pass's
/// cells, each allocated, filled and freed per level, were 1 M of that
/// render (callgrind, the same command).
#[inline(always)]
pub(crate) fn drawn_cells(displacements: &[u16], cols: usize, rows: usize) -> Vec<u8> {
    let (ccols, crows) = (cols - 1, rows - 1);
    if ccols * crows == 0 {
        return Vec::new();
    }
    // Node k with node k + 1, k + cols and k + cols + 1 (the last node of
    // the last row of cells has no k + cols + 1: it closes its row).
    let (m, d) = (crows * cols - 1, displacements);
    let quads = d[..m].iter().zip(&d[1..=m]);
    let quads = quads
        .zip(&d[cols..cols + m])
        .zip(&d[cols + 1..cols + 1 + m]);
    let largest = |(((&a, &b), &c), &e): (((&u16, &u16), &u16), &u16)| a.max(b).max(c.max(e));
    let mut drawn: Vec<u8> = quads
        .map(|q| u8::from(largest(q) != EMPTY) * CELL_DRAW)
        .collect();
    for j in 1..crows {
        drawn.copy_within(j * cols..j * cols + ccols, j * ccols);
    }
    drawn.truncate(ccols * crows);
    drawn
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    #[test]
    fn drawn_cells_are_the_cells_with_four_filled_corners() {
        // Grids of 2–20 nodes a side, single cell rows and columns
        // included, empty nodes from none to most.
        let mut rng = crate::test_rng::XorShift(0xd4a3_ce11);
        for case in 0..400 {
            let (cols, rows) = (2 + rng.below(19) as usize, 2 + rng.below(19) as usize);
            let holes = [0, 10, 50, 90][case % 4];
            let d = rng.holed_grid(cols * rows, holes, 0, u32::from(EMPTY));
            let filled = |i: usize, j: usize| d[j * cols + i] != EMPTY;
            let expected: Vec<u8> = (0..rows - 1)
                .flat_map(|j| (0..cols - 1).map(move |i| (i, j)))
                .map(|(i, j)| {
                    let four = filled(i, j) && filled(i + 1, j);
                    u8::from(four && filled(i, j + 1) && filled(i + 1, j + 1)) * CELL_DRAW
                })
                .collect();
            assert_eq!(drawn_cells(&d, cols, rows), expected, "{cols} x {rows}");
        }
    }

    /// `push_cells_by_node` puts cell `(i, j)`'s drawn bit at node
    /// `(i, j)` and 0 at the last node of each row.
    #[test]
    fn cells_by_node_follow_the_node_rows() {
        let mut rng = XorShift(4242);
        let mut out = Vec::new();
        for _ in 0..300 {
            let cols = 2 + rng.below64(18) as usize;
            let rows = 2 + rng.below64(18) as usize;
            let (ccols, crows) = (cols - 1, rows - 1);
            let flags: Vec<u8> = (0..ccols * crows)
                .map(|_| [0, CELL_DRAW, CELL_DRAW | CELL_RIGHT][rng.below64(3) as usize])
                .collect();
            out.clear();
            push_cells_by_node(flags.chunks_exact(ccols), &mut out);
            assert_eq!(out.len(), crows * cols);
            for j in 0..crows {
                for i in 0..cols {
                    let want = if i < ccols {
                        flags[j * ccols + i] & CELL_DRAW
                    } else {
                        0
                    };
                    assert_eq!(out[j * cols + i], want, "{i}, {j}");
                }
            }
        }
    }

    /// `close_cells` marks exactly the drawn cells whose right or upper
    /// neighbour is not drawn (or missing), on narrow and wide rows.
    #[test]
    fn closing_flags_follow_the_neighbours() {
        let mut rng = XorShift(777);
        for case in 0..200 {
            let ccols = 1 + rng.below64(if case % 4 == 0 { 100 } else { 20 }) as usize;
            let crows = 1 + rng.below64(12) as usize;
            let drawn: Vec<bool> = (0..ccols * crows).map(|_| rng.below64(4) != 0).collect();
            let mut flags: Vec<u8> = drawn.iter().map(|&d| d as u8 * CELL_DRAW).collect();
            let counts = close_cells(&mut flags, ccols, crows);
            let mut expected = [0u64; 3];
            for j in 0..crows {
                for i in 0..ccols {
                    let k = j * ccols + i;
                    let right = drawn[k] && (i + 1 == ccols || !drawn[k + 1]);
                    let top = drawn[k] && (j + 1 == crows || !drawn[k + ccols]);
                    let want = (drawn[k] as u8 * CELL_DRAW)
                        | (right as u8 * CELL_RIGHT)
                        | (top as u8 * CELL_TOP);
                    assert_eq!(flags[k], want, "case {case} cell ({i}, {j})");
                    expected[0] += right as u64;
                    expected[1] += top as u64;
                    expected[2] += (right && top) as u64;
                }
            }
            assert_eq!(counts, expected);
        }
    }
}
