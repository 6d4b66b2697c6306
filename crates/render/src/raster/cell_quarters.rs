//! Cells drawn by the quarters they hold ([`QuarteredCell`]: level 1's
//! cells along a patch's outline, see [`crate::prepare::quarters`]).
//!
//! A cell cut `nu × nv` is drawn by the sub-nodes of its quarters only:
//! sub-node `(a, b)` is placed when a held quarter `(qa, qb)` has it
//! within half a sub-cell, so that the sub-node any point of a held
//! quarter rounds to is placed and the covering argument of
//! [`crate::raster::cell_bilinear`] holds inside the held quarters. Along
//! an axis, the first half (`qa = 0`) reaches `a ≤ ⌈nu / 2⌉` and the
//! second `a ≥ nu / 2` (integer division), so the sub-nodes of a row form
//! one run. Every quartered cell places its last column and row: its
//! neighbours do not count it as drawn, and close toward it themselves.
//!
//! Cost: as a cell of the sub-node drawer with clipping, per quartered
//! cell that a band holds.

use crate::fixed::Z_FAR;
use crate::grid::QuarteredCell;
use crate::raster::band::{patch_word, BandTarget};
use crate::raster::cell_bilinear::{
    cell_in_band, draw_cell_runs, sub_word, BilinearPiece, Reciprocals,
};

/// Draws the cells `cells` of a whole-level `piece` cut `nu × nv` by the
/// quarters each holds.
#[inline(always)]
pub(crate) fn draw_quartered_cells(
    t: &mut BandTarget<'_>,
    piece: &BilinearPiece<'_>,
    cells: &[QuarteredCell],
    [nu, nv]: [u32; 2],
    item: u32,
) {
    let (cols, nodes) = (piece.cols, piece.nodes);
    let r = Reciprocals::new(nu, nv);
    for cell in cells {
        let k = cell.cell as usize;
        let (ci, cj) = (k % (cols - 1), k / (cols - 1));
        let first = cj * cols + ci;
        let c = [
            &nodes[first],
            &nodes[first + 1],
            &nodes[first + cols],
            &nodes[first + cols + 1],
        ];
        let Some(inside) = cell_in_band(t, c, piece.inside_columns) else {
            continue;
        };
        // Short of the far plane (a sample there would read as empty): the
        // samples lie between the corners' depths.
        let deepest = c.iter().map(|n| n[2]).max().unwrap_or(0) as i64;
        let bias = QUARTER_DEPTH_BIAS.min(Z_FAR as i64 - 1 - deepest).max(0);
        let cut = ([nu, nv], r, bias);
        let run = |b: u32| quarter_run(cell.quarters, [nu, nv], b);
        let word = patch_word(sub_word(ci, cj, 0, 0), item);
        if inside {
            draw_cell_runs::<false>(t, c, cut, word, run);
        } else {
            draw_cell_runs::<true>(t, c, cut, word, run);
        }
    }
}

/// The run `a0..=a1` of sub-nodes that row `b` of a cell cut `nu × nv`
/// places for the held `quarters` (see the module header), or `None`.
#[inline(always)]
pub(crate) fn quarter_run(quarters: u8, [nu, nv]: [u32; 2], b: u32) -> Option<(u32, u32)> {
    let first_half = if 2 * b <= nv + 1 { quarters & 0b11 } else { 0 };
    let second_half = if 2 * b + 1 >= nv { quarters >> 2 } else { 0 };
    match first_half | second_half {
        0 => None,
        1 => Some((0, nu.div_ceil(2))),
        2 => Some((nu / 2, nu)),
        _ => Some((0, nu)),
    }
}

/// How far (fixed-point depth, 1/1024 of the frame's depth range) the
/// samples of a quartered cell are pushed back. Why: its filled corners
/// only approximate the surface past its held quarters, which a
/// neighbouring patch also covers; pushed back, the neighbour's real
/// surface wins there (the bunny at 500² with every level-1 cell
/// quartered: 24.66 → 24.71 dB against the source, holes unchanged).
pub(crate) const QUARTER_DEPTH_BIAS: i64 = (Z_FAR >> 10) as i64;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_reach_half_a_sub_cell_past_each_held_quarter() {
        // Cut 3: the first half takes a = 0..=2, the second 1..=3.
        assert_eq!(quarter_run(0b0001, [3, 3], 0), Some((0, 2)));
        assert_eq!(quarter_run(0b0001, [3, 3], 2), Some((0, 2)));
        assert_eq!(quarter_run(0b0001, [3, 3], 3), None);
        assert_eq!(quarter_run(0b0010, [3, 3], 1), Some((1, 3)));
        assert_eq!(quarter_run(0b1000, [3, 3], 0), None);
        assert_eq!(quarter_run(0b1000, [3, 3], 1), Some((1, 3)));
        assert_eq!(quarter_run(0b1001, [3, 3], 1), Some((0, 3)));
        // Cut 4: halves meet at the middle sub-node.
        assert_eq!(quarter_run(0b0001, [4, 4], 2), Some((0, 2)));
        assert_eq!(quarter_run(0b0010, [4, 4], 2), Some((2, 4)));
        assert_eq!(quarter_run(0b0001, [4, 4], 3), None);
        // Cut 1 along a side: both halves take both ends.
        assert_eq!(quarter_run(0b0010, [1, 2], 0), Some((0, 1)));
        assert_eq!(quarter_run(0b0100, [1, 2], 2), Some((0, 1)));
    }

    /// Brute force: every point `(s, t)` of a held quarter rounds to a
    /// placed sub-node.
    #[test]
    fn every_point_of_a_held_quarter_rounds_to_a_placed_sub_node() {
        for nu in 1..=9u32 {
            for nv in 1..=9u32 {
                for quarters in 1..16u8 {
                    for step in 0..=64u32 {
                        for step_t in 0..=64u32 {
                            let (s, t) = (step as f32 / 64.0, step_t as f32 / 64.0);
                            let qa = usize::from(s > 0.5);
                            let qb = usize::from(t > 0.5);
                            let held = |qa: usize, qb: usize| quarters >> (qa + 2 * qb) & 1 != 0;
                            // A point on a half's boundary belongs to both.
                            let on_a = s == 0.5;
                            let on_b = t == 0.5;
                            let inside = held(qa, qb)
                                || (on_a && held(0, qb))
                                || (on_b && held(qa, 0))
                                || (on_a && on_b && held(0, 0));
                            if !inside {
                                continue;
                            }
                            let a = (s * nu as f32).round() as u32;
                            let b = (t * nv as f32).round() as u32;
                            let run = quarter_run(quarters, [nu, nv], b);
                            assert!(
                                run.is_some_and(|(a0, a1)| a0 <= a && a <= a1),
                                "cut {nu} x {nv}, quarters {quarters:04b}, ({s}, {t})"
                            );
                        }
                    }
                }
            }
        }
    }
}
