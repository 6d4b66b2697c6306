//! Level-1 cells drawn by quarters: the outline of a patch kept at level 1.
//!
//! A level-1 cell spans four level-0 cells, its quarters. Where a patch's
//! outline crosses it, some of them are not drawable, and the halving
//! either fills its empty corners and draws it whole (three held, see
//! [`crate::prepare::corner_fill`]) or leaves it out (one or two held).
//! Left out, the level-0 cells it held are drawn by nobody unless a
//! neighbouring patch overlaps them: along a silhouette, where the
//! neighbour faces away, the outline recedes by up to a level-0 cell, and
//! at 1000² that opened notches a few pixels deep along the bunny's ears.
//!
//! So a second level 1 ([`crate::prepare::patch::QUARTERED_ONE`], built
//! only for the pieces [`crate::RenderOptions::level_one_limit`] lifts)
//! draws its cells that hold some but not all of their level-0 cells by
//! the quarters they hold ([`QuarteredCell`]): their empty corners are
//! filled as the corner fill fills the others (extrapolated, then fitted
//! to the finer nodes inside, the corners already filled held), and the
//! drawer places only the sub-nodes of the held quarters
//! ([`crate::raster::cell_quarters`]). That level draws what level 0 draws,
//! neither dropping the cells over one or two quarters nor overhanging
//! the missing quarter of those over three.
//!
//! Levels above 1 keep their rule (cells holding two finer cells or more
//! are filled): their dropped cells are rarer, and a quarter of a level-2
//! cell is a level-1 cell.
//!
//! Cost: O(cells) per quartered level 1, built on first use; 8 bytes per
//! quartered cell (about 13 % of the bunny's level-1 cells).

use crate::grid::{QuarteredCell, CELL_DRAW};
use crate::prepare::corner_fill::FinerLevel;

/// The cells of the level halved from `fine` (`hc × hr` nodes) that hold
/// some but not all of the finer cells they span (fewer at a padded
/// side), with the quarters they hold; their flags in `drawn` (the halved
/// level's, per cell) are cleared, so that they are drawn by quarters
/// only. A cell holding none keeps its flag (an interior hole under a
/// coarse cell, which level 1 covers as before).
pub(crate) fn quartered_cells(
    fine: FinerLevel<'_>,
    [hc, hr]: [usize; 2],
    drawn: &mut [u8],
) -> Vec<QuarteredCell> {
    let (fc, fr) = (fine.cols - 1, fine.rows - 1);
    let (ccols, crows) = (hc - 1, hr - 1);
    let mut held = vec![0u8; ccols * crows];
    for (k, &f) in fine.cell_flags.iter().enumerate() {
        if f & CELL_DRAW != 0 {
            let (i, j) = (k % fc, k / fc);
            held[(j / 2) * ccols + i / 2] |= 1 << ((i % 2) + 2 * (j % 2));
        }
    }
    debug_assert!(fc <= 2 * ccols && fr <= 2 * crows);
    let mut cells = Vec::new();
    for (k, (&quarters, flag)) in held.iter().zip(drawn.iter_mut()).enumerate() {
        let (i, j) = (k % ccols, k / ccols);
        // Quarter (a, b) is bit a + 2 b; a padded side spans one column
        // or row of finer cells.
        let (two_columns, two_rows) = (2 * i + 1 < fc, 2 * j + 1 < fr);
        let spanned = 1
            | u8::from(two_columns) << 1
            | u8::from(two_rows) << 2
            | u8::from(two_columns && two_rows) << 3;
        if quarters != 0 && quarters != spanned {
            *flag &= !CELL_DRAW;
            cells.push(QuarteredCell {
                cell: k as u32,
                quarters,
            });
        }
    }
    cells
}
/// Per node of an `hc × hr` level, whether it is a corner of one of
/// `cells`.
pub(crate) fn quartered_corners(cells: &[QuarteredCell], [hc, hr]: [usize; 2]) -> Vec<bool> {
    let mut corner = vec![false; hc * hr];
    for c in cells {
        let (i, j) = (c.cell as usize % (hc - 1), c.cell as usize / (hc - 1));
        for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            corner[(j + dj) * hc + i + di] = true;
        }
    }
    corner
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Flat displacements of a `side × side` level 0 with cell flags
    /// `flags`, as the halving reads it.
    fn level_zero<'a>(side: usize, d: &'a [u16], flags: &'a [u8]) -> FinerLevel<'a> {
        FinerLevel {
            cols: side,
            rows: side,
            displacements: &d[..side * side],
            cell_flags: flags,
            spacing: 1,
        }
    }

    #[test]
    fn cells_holding_one_or_two_quarters_are_listed_with_them() {
        // A 5 × 5 finer grid (4 × 4 cells) halves to 3 × 3 (2 × 2 cells).
        // Finer cells drawn: all of coarse cell (0, 0), one of (1, 0), two of
        // (0, 1), none of (1, 1).
        let mut flags = vec![0u8; 16];
        for (i, j) in [(0, 0), (1, 0), (0, 1), (1, 1), (3, 0), (0, 2), (0, 3)] {
            flags[j * 4 + i] = CELL_DRAW;
        }
        let d = vec![100u16; 25];
        let fine = level_zero(5, &d, &flags);
        let mut drawn = [CELL_DRAW, 0, 0, 0];
        let cells = quartered_cells(fine, [3, 3], &mut drawn);
        assert_eq!(
            cells,
            vec![
                QuarteredCell {
                    cell: 1,
                    quarters: 0b0010
                },
                QuarteredCell {
                    cell: 2,
                    quarters: 0b0101
                },
            ]
        );
        let corners = quartered_corners(&cells, [3, 3]);
        let expected = [
            false, true, true, //
            true, true, true, //
            true, true, false,
        ];
        assert_eq!(corners, expected);
    }

    #[test]
    fn a_cell_holding_all_its_quarters_is_not_quartered() {
        let d = vec![7u16; 9];
        let fine = level_zero(3, &d, &[CELL_DRAW; 4]);
        assert!(quartered_cells(fine, [2, 2], &mut [CELL_DRAW]).is_empty());
        // Three of four held: drawn by quarters, no longer whole.
        let fine = level_zero(3, &d, &[CELL_DRAW, CELL_DRAW, CELL_DRAW, 0]);
        let mut drawn = [CELL_DRAW];
        let cells = quartered_cells(fine, [2, 2], &mut drawn);
        assert_eq!(
            cells,
            vec![QuarteredCell {
                cell: 0,
                quarters: 0b0111
            }]
        );
        assert_eq!(drawn, [0]);
    }
}
