//! Open sides: which sides of a magnified piece's drawn cells are outlines
//! of the surface, where the bilinear drawer clips its sub-nodes at the
//! cell's true edge ([`crate::raster::cell_edges`]).
//!
//! A side is open when the cell past it, in the same piece, faces away
//! this frame (the back-face test left it out): the surface folds out of
//! sight there, and nothing of it is drawn beyond that side. Sides on the
//! patch's border, toward an empty or trimmed cell or toward another piece
//! stay closed: there another patch (or piece) usually continues the
//! surface, and where two patches' borders do not quite meet, the
//! sub-nodes' half-pixel reach closes the seam (clipping those sides too
//! opened cracks inside fuze's surface: holes 0.015 % → 0.13 %).
//!
//! With [`crate::RenderOptions::exact_outlines`], pieces of patches that
//! carry colour go further ([`exact_outlines`]): every drawn cell is flagged [`crate::grid::CELL_EXACT`] and drawn by
//! pixel-centre coverage ([`crate::raster::cell_exact`]), which also gets
//! the outline right inside folded cells and along patch borders.
//!
//! Input: the level, the piece's node range and its cell flags (after the
//! back-face test). Output: the flags with [`crate::grid::CELL_OPEN`] bits.
//! Cost: O(cells of the piece), only for pieces cut finer than
//! [`OPEN_SIDE_CUT`] with a cell facing away.

use crate::grid::{
    CELL_DRAW, CELL_EXACT, CELL_OPEN_BOTTOM, CELL_OPEN_LEFT, CELL_OPEN_RIGHT, CELL_OPEN_TOP,
};
use crate::plan::split::NodeRange;
use crate::prepare::mip::MipLevel;

/// Pieces whose cells are cut into more than this many sub-cells per side
/// (cells of about 5 px and more) get open sides. Why: their sub-nodes are
/// dense, so every pixel their outline touches was written, about half a
/// pixel past the true edge on average (fuze, unlit: most of its error at
/// silhouettes). Why not fewer: the perfect sphere's silhouette pieces are
/// cut 4-5 and its frame rose 4.8 % with a limit of 3 (1.4 % with 5, fuze
/// 27.10 → 27.05 dB; callgrind, `--threads 1`).
pub(crate) const OPEN_SIDE_CUT: u32 = 5;

/// Whether the pieces of `level` draw every cell by pixel-centre coverage
/// ([`crate::raster::cell_exact`]): when its patch carries colour. Why
/// colour: a coloured surface's outline is drawn in its own colours over
/// whatever lies behind, so the sub-nodes' half-pixel reach past the
/// outline cost textured models most of their image error (fuze, unlit:
/// 28.18 → 30.3 dB with colour grids); the frames of colourless scenes
/// (the bunny and the sphere of issue 21's frame targets) keep the cheaper
/// sub-node path and their images.
pub(crate) fn exact_outlines(level: &MipLevel) -> bool {
    level.colours.is_some()
}

/// Flags every drawn cell of a piece ([`CELL_DRAW`] set in `flags`) to be
/// drawn by pixel-centre coverage ([`CELL_EXACT`]).
pub(crate) fn mark_exact_cells(flags: &mut [u8]) {
    for f in flags.iter_mut() {
        *f |= (*f & CELL_DRAW) * CELL_EXACT;
    }
}

/// Marks the open sides of every drawn cell of the piece `range` of
/// `level` in its cell flags `flags` (row-major, `CELL_DRAW` already
/// decided for this frame): the sides toward a cell of the piece that the
/// level draws but this frame left out as facing away. Returns true when
/// some side is open.
pub(crate) fn mark_open_sides(level: &MipLevel, range: NodeRange, flags: &mut [u8]) -> bool {
    let (ccols, crows) = (range.i1 - range.i0, range.j1 - range.j0);
    // Cell (ci, cj) of the piece is drawable but left out this frame.
    let away = |flags: &[u8], ci: usize, cj: usize| {
        flags[cj * ccols + ci] & CELL_DRAW == 0
            && level.cell_is_drawable(range.i0 + ci, range.j0 + cj)
    };
    let mut any = 0u8;
    for cj in 0..crows {
        for ci in 0..ccols {
            if flags[cj * ccols + ci] & CELL_DRAW == 0 {
                continue;
            }
            let mut open = 0;
            if cj > 0 && away(flags, ci, cj - 1) {
                open |= CELL_OPEN_BOTTOM;
            }
            if ci + 1 < ccols && away(flags, ci + 1, cj) {
                open |= CELL_OPEN_RIGHT;
            }
            if cj + 1 < crows && away(flags, ci, cj + 1) {
                open |= CELL_OPEN_TOP;
            }
            if ci > 0 && away(flags, ci - 1, cj) {
                open |= CELL_OPEN_LEFT;
            }
            flags[cj * ccols + ci] |= open;
            any |= open;
        }
    }
    any != 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::CELL_OPEN;
    use crate::prepare::mip::base_level;
    use spatch_format::{Frame, GridSize, Patch, EMPTY};

    fn level_of(cols: usize, rows: usize, empty: &[usize]) -> MipLevel {
        let grid = GridSize::new(cols as u32, rows as u32).unwrap();
        let frame = Frame::new(
            glam::Vec3::ZERO,
            glam::Vec3::X,
            glam::Vec3::Y,
            glam::Vec3::Z,
        )
        .unwrap();
        let mut d = vec![100u16; cols * rows];
        for &k in empty {
            d[k] = EMPTY;
        }
        let patch = Patch::new(frame, grid, d, None).unwrap();
        base_level(&patch).unwrap()
    }

    #[test]
    fn only_sides_toward_cells_facing_away_are_open() {
        // 4 x 4 nodes (3 x 3 cells); node 15 (the top right corner) empty,
        // so cell (2, 2) is not drawable; cell (0, 1) faces away this frame.
        let level = level_of(4, 4, &[15]);
        let range = NodeRange::whole(&level);
        let mut flags: Vec<u8> = level.cell_flags.iter().map(|f| f & CELL_DRAW).collect();
        flags[3] = 0;
        assert!(mark_open_sides(&level, range, &mut flags));
        let open = |i: usize, j: usize| flags[j * 3 + i] & CELL_OPEN;
        assert_eq!(open(0, 0), CELL_OPEN_TOP);
        assert_eq!(open(1, 1), CELL_OPEN_LEFT);
        assert_eq!(open(0, 2), CELL_OPEN_BOTTOM);
        // The grid's border and the empty cell (2, 2) close their sides.
        assert_eq!(open(1, 2), 0);
        assert_eq!(open(2, 1), 0);
        assert_eq!(open(0, 1), 0, "undrawn cells get no flags");
        assert_eq!(open(2, 2), 0);
    }

    #[test]
    fn only_coloured_levels_draw_exact_cells_and_only_drawn_cells_are_flagged() {
        let grey = level_of(3, 3, &[]);
        assert!(!exact_outlines(&grey));
        let mut coloured = grey.clone();
        coloured.colours = Some(vec![[9, 9, 9, 255]; 9]);
        assert!(exact_outlines(&coloured));
        let mut flags = [CELL_DRAW, 0, CELL_DRAW | CELL_OPEN_TOP, 2];
        mark_exact_cells(&mut flags);
        assert_eq!(
            flags,
            [
                CELL_DRAW | CELL_EXACT,
                0,
                CELL_DRAW | CELL_OPEN_TOP | CELL_EXACT,
                2
            ]
        );
    }

    #[test]
    fn trimmed_cells_and_other_pieces_close_their_sides() {
        // 3 x 2 cells; cell (2, 0) trimmed (another patch draws it).
        let mut level = level_of(4, 3, &[]);
        level.trim_cells(&[false, false, true, false, false, false]);
        let mut flags: Vec<u8> = level.cell_flags.iter().map(|f| f & CELL_DRAW).collect();
        assert!(!mark_open_sides(
            &level,
            NodeRange::whole(&level),
            &mut flags
        ));
        // A piece of the first two cell columns: (1, 1) faces away, and
        // the cells right of the piece are another piece's.
        let piece = NodeRange {
            i0: 0,
            j0: 0,
            i1: 2,
            j1: 2,
        };
        let mut flags = vec![CELL_DRAW, CELL_DRAW, CELL_DRAW, 0];
        assert!(mark_open_sides(&level, piece, &mut flags));
        assert_eq!(flags[1] & CELL_OPEN, CELL_OPEN_TOP);
        assert_eq!(flags[2] & CELL_OPEN, CELL_OPEN_RIGHT);
        assert_eq!(flags[0] & CELL_OPEN, 0);
    }
}
