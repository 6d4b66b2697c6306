//! A frame's level-1 cells drawn by quarters
//! ([`crate::prepare::quarters`]): which of a piece's are drawn (not
//! facing away), the size of their edges on screen (so the piece's cut
//! covers them too), and, for a piece drawn by its nodes alone, its nodes
//! that only those cells use.
//!
//! Cost: O(quartered cells) per level-1 piece and frame.

use crate::fixed::{Node, EMPTY_NODE};
use crate::grid::{QuarteredCell, CELL_DRAW};
use crate::plan::node_xy::NodeXY;

/// Appends to `out` the cells of `cells` (of a whole level `cols` nodes
/// wide, projected into `xy`) that do not face away (`back_sign` as for
/// [`crate::plan::measure::measure_cells`]: 0 tests nothing), and returns
/// the largest `|x|`, `|y|` of their u and v edges (position units), as
/// the measured edges of the drawn cells are.
pub(crate) fn gather_quartered(
    cells: &[QuarteredCell],
    xy: &NodeXY,
    cols: usize,
    back_sign: i64,
    out: &mut Vec<QuarteredCell>,
) -> [i64; 4] {
    let mut edges = [0i64; 4];
    for &c in cells {
        let k = c.cell as usize;
        let first = (k / (cols - 1)) * cols + k % (cols - 1);
        let at = |n: usize| (xy.xs[n] as i64, xy.ys[n] as i64);
        let (a, b, p, d) = (
            at(first),
            at(first + 1),
            at(first + cols),
            at(first + cols + 1),
        );
        if back_sign != 0 && faces_away([a, b, p, d], back_sign) {
            continue;
        }
        let span = |p: (i64, i64), q: (i64, i64)| ((q.0 - p.0).abs(), (q.1 - p.1).abs());
        let (u0, u1, v0, v1) = (span(a, b), span(p, d), span(a, p), span(b, d));
        let cell = [
            u0.0.max(u1.0),
            u0.1.max(u1.1),
            v0.0.max(v1.0),
            v0.1.max(v1.1),
        ];
        for (e, c) in edges.iter_mut().zip(cell) {
            *e = (*e).max(c);
        }
        out.push(c);
    }
    edges
}

/// True when the cell with corners `[a, b, c, d]` (`(0, 0), (1, 0), (0, 1),
/// (1, 1)`) faces away at all four corners, the test of the measured cells.
fn faces_away([a, b, c, d]: [(i64, i64); 4], back_sign: i64) -> bool {
    let edge = |p: (i64, i64), q: (i64, i64)| (q.0 - p.0, q.1 - p.1);
    let away = |u: (i64, i64), v: (i64, i64)| (u.0 * v.1 - u.1 * v.0) * back_sign > 0;
    let (u0, v0, u1, v1) = (edge(a, b), edge(a, c), edge(c, d), edge(b, d));
    away(u0, v0) && away(u0, v1) && away(u1, v0) && away(u1, v1)
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
            let around = [
                (i.wrapping_sub(1), j.wrapping_sub(1)),
                (i, j.wrapping_sub(1)),
            ];
            let around = around
                .into_iter()
                .chain([(i.wrapping_sub(1), j), (i, j)])
                .filter(|&(a, b)| a < cols - 1 && b < rows - 1);
            if !around.into_iter().any(|(a, b)| drawn(a, b)) {
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
