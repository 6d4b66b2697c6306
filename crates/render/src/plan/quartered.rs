//! A frame's level-1 cells drawn by quarters
//! ([`crate::prepare::quarters`]): which of a piece's are drawn (not
//! facing away), the size of their edges on screen (so the piece's cut
//! covers them too), and, for a piece drawn by its nodes alone, its nodes
//! that only those cells use.
//!
//! Cost: O(quartered cells) per level-1 piece and frame.

use crate::fixed::{Node, EMPTY_NODE};
use crate::grid::{QuarteredCell, CELL_DRAW};
use crate::plan::measure::{mark_row, row_edges_wide};
use crate::plan::node_xy::NodeXY;

/// [`mark_row`] for one back-face sign.
type MarkRow = fn(&[i32], &[i32], &[i32], &[i32], &[u8], &mut [u8]) -> (u64, u64);

/// Appends to `out` the cells of `cells` (of a whole level `cols` nodes
/// wide, projected into `xy`) that do not face away (`back_sign` as for
/// [`crate::plan::measure::measure_cells`]: 0 tests nothing), and returns
/// the largest `|x|`, `|y|` of their u and v edges (position units): each
/// cell as a row of one cell for the measured cells' own tests
/// ([`mark_row`], [`row_edges_wide`]).
pub(crate) fn gather_quartered(
    cells: &[QuarteredCell],
    xy: &NodeXY,
    cols: usize,
    back_sign: i64,
    out: &mut Vec<QuarteredCell>,
) -> [i64; 4] {
    let mark: MarkRow = match back_sign {
        1 => mark_row::<1>,
        -1 => mark_row::<-1>,
        _ => mark_row::<0>,
    };
    let mut edges = [0u64; 4];
    for &c in cells {
        let k = c.cell as usize;
        let first = (k / (cols - 1)) * cols + k % (cols - 1);
        let (low, high) = (first..first + 2, first + cols..first + cols + 2);
        let (xl, yl) = (&xy.xs[low.clone()], &xy.ys[low]);
        let (xh, yh) = (&xy.xs[high.clone()], &xy.ys[high]);
        let mut flag = [0u8];
        mark(xl, yl, xh, yh, &[CELL_DRAW], &mut flag);
        if flag[0] == 0 {
            continue;
        }
        let cell = row_edges_wide(xl, yl, xh, yh, &flag);
        for (e, c) in edges.iter_mut().zip(cell) {
            *e = (*e).max(c);
        }
        out.push(c);
    }
    edges.map(|e| e as i64)
}

/// Empties the nodes of a `cols`-wide whole-level piece (`nodes`, its
/// cells' frame flags `flags`) that are corners of `cells` and of no
/// drawn cell: a piece drawn by its nodes alone places every node it
/// holds, and those lie past the patch's data.
pub(crate) fn drop_quartered_corners(
    cells: &[QuarteredCell],
    flags: &[u8],
    cols: usize,
    nodes: &mut [Node],
) {
    let rows = nodes.len() / cols;
    let drawn = |i: usize, j: usize| flags[j * (cols - 1) + i] & CELL_DRAW != 0;
    for c in cells {
        let k = c.cell as usize;
        let (ci, cj) = (k % (cols - 1), k / (cols - 1));
        for (i, j) in [(ci, cj), (ci + 1, cj), (ci, cj + 1), (ci + 1, cj + 1)] {
            // The (up to) four cells around node (i, j).
            let (left, below) = (i.wrapping_sub(1), j.wrapping_sub(1));
            let around = [(left, below), (i, below), (left, j), (i, j)];
            let inside = |a: usize, b: usize| a < cols - 1 && b < rows - 1;
            if !around.iter().any(|&(a, b)| inside(a, b) && drawn(a, b)) {
                nodes[j * cols + i][0] = EMPTY_NODE;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xy_of(points: &[(i32, i32)]) -> NodeXY {
        NodeXY {
            xs: points.iter().map(|p| p.0).collect(),
            ys: points.iter().map(|p| p.1).collect(),
            ..Default::default()
        }
    }

    #[test]
    fn cells_facing_away_are_left_out_and_edges_measured() {
        // 3 × 2 nodes: cell 0 counter-clockwise on screen, cell 1 folded
        // over (clockwise).
        let one = 1 << 16;
        let xy = xy_of(&[
            (0, 0),
            (2 * one, 0),
            (one, 0),
            (0, 3 * one),
            (2 * one, 3 * one),
            (one, 3 * one),
        ]);
        let cells = [
            QuarteredCell {
                cell: 0,
                quarters: 1,
            },
            QuarteredCell {
                cell: 1,
                quarters: 2,
            },
        ];
        let mut out = Vec::new();
        let edges = gather_quartered(&cells, &xy, 3, 0, &mut out);
        assert_eq!(out.len(), 2);
        assert_eq!(edges, [2 * one as i64, 0, 0, 3 * one as i64]);
        out.clear();
        gather_quartered(&cells, &xy, 3, -1, &mut out);
        assert_eq!(out, vec![cells[0]]);
        out.clear();
        gather_quartered(&cells, &xy, 3, 1, &mut out);
        assert_eq!(out, vec![cells[1]]);
    }

    #[test]
    fn only_corners_of_no_drawn_cell_are_emptied() {
        // 3 × 2 nodes, cell 0 drawn, cell 1 quartered.
        let mut nodes = vec![[1, 1, 1, 0]; 6];
        let cells = [QuarteredCell {
            cell: 1,
            quarters: 1,
        }];
        drop_quartered_corners(&cells, &[CELL_DRAW, 0], 3, &mut nodes);
        let empty: Vec<bool> = nodes.iter().map(|n| n[0] == EMPTY_NODE).collect();
        assert_eq!(empty, [false, false, true, false, false, true]);
    }
}
