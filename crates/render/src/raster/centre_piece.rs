//! The pieces drawn by pixel-centre coverage: their rows of drawn cells
//! walked, each cell's outline sides found and the kernel chosen per cell.
//!
//! Two kinds of piece take this path ([`CentreStyle`]):
//! - pixel-sized cells under `--centre-limit` ([`CentreStyle::Cells`]),
//!   outline sides pushed out half a pixel, as far as the sub-nodes
//!   reach;
//! - the cells of patches with a colour grid ([`CentreStyle::Grid`], the
//!   default for those since stop 49), outline sides pushed out 0.15 px,
//!   as the sub-quads of [`crate::raster::cell_exact`] were, and folded
//!   cells (the silhouette of a smooth surface runs through them) drawn by
//!   those sub-quads. A pixel records its own place in the cell, so the
//!   resolve reads the colour grid where the source's texture is sampled.
//!
//! Per cell: a fold of a grid piece goes to the sub-quads (cut
//! [`FOLD_CUT`], places scaled to [`CENTRE_STEPS`]); every other cell to
//! the two-triangle kernels of [`crate::raster::cell_centres`]. Both read
//! the same 16-fractional-bit corners, and a sub-quad reaches its cell's
//! sides, so a folded cell and its neighbours leave no crack between
//! them.

use crate::fixed::{Node, XY_FRAC_BITS};
use crate::grid::{CELL_DRAW, CELL_RIGHT, CELL_TOP};
use crate::raster::band::BandTarget;
use crate::raster::cell_bilinear::{sub_word, BilinearPiece, Reciprocals};
use crate::raster::cell_centres::{
    draw_cell, triangle_areas, Sides, BOTTOM, CELL_MARGIN, CENTRE_STEPS, LEFT, RIGHT, TOP,
};
use crate::raster::cell_exact::draw_exact_cell;

/// How a piece drawn by pixel-centre coverage treats its outline and its
/// folded cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CentreStyle {
    /// Pixel-sized cells (`--centre-limit`): outline sides pushed out by
    /// [`CELL_MARGIN`], folded cells as two triangles with every side
    /// pushed out.
    Cells,
    /// Cells of a patch with a colour grid: outline sides pushed out by
    /// [`GRID_MARGIN`], folded cells drawn by sub-quads.
    Grid,
}

/// How far (position units) the outline sides of a colour-grid piece are
/// pushed out: 0.15 px, the sub-quads' margin. Why that little: the
/// texture detail a grid carries is wasted on pixels past the source's
/// outline (fuze unlit, 14 views: 30.26 dB at 0.148 px, 29.61 at 0.25 px,
/// 28.09 at 0.5 px).
pub(crate) const GRID_MARGIN: i32 = (0.15 * (1 << XY_FRAC_BITS) as f64) as i32;

/// Sub-quads per side of a folded cell of a colour-grid piece; their
/// places are recorded in [`CENTRE_STEPS`] (a multiple).
const FOLD_CUT: u32 = 4;

impl CentreStyle {
    /// The outline margin (position units).
    #[inline(always)]
    fn margin(self) -> i32 {
        match self {
            CentreStyle::Cells => CELL_MARGIN,
            CentreStyle::Grid => GRID_MARGIN,
        }
    }
}

/// Draws the drawn cells of a piece (flags as
/// [`crate::plan::measure::measure_cells`] sets them; the closing flags
/// name outline sides) by pixel-centre coverage in `style`. Why out of
/// line (one call per piece): inlined into the band's function its loops
/// spilled more registers (bunny 500² `--centre-limit 2`: 118.45 M per
/// frame against 117.73 M). It is scalar code (the sub-quads of folds
/// aside), so the portable copy loses little.
#[inline(never)]
pub(crate) fn draw_cells_centres(
    t: &mut BandTarget<'_>,
    piece: &BilinearPiece<'_>,
    style: CentreStyle,
    item: u32,
) {
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows);
    let (cols, nodes) = (piece.cols, piece.nodes);
    let rows_of_cells = piece.flags.chunks_exact(cols - 1).zip(piece.spans);
    for (j, (row_flags, &[lo, hi])) in rows_of_cells.take(piece.rows - 1).enumerate() {
        // The row's span covers its used nodes, hence its cells.
        if hi < y_lo || lo >= y_hi {
            continue;
        }
        let below = &nodes[j * cols..(j + 1) * cols];
        let above = &nodes[(j + 1) * cols..(j + 2) * cols];
        let under = j
            .checked_sub(1)
            .map(|k| &piece.flags[k * (cols - 1)..(k + 1) * (cols - 1)]);
        let cells = row_flags.iter().zip(below.windows(2)).zip(above.windows(2));
        let mut left_drawn = false;
        for (i, ((&f, b), a)) in cells.enumerate() {
            let drawn = f & CELL_DRAW != 0;
            if drawn {
                let outline = outline(f, left_drawn, under.map(|u| u[i]));
                let c = [&b[0], &b[1], &a[0], &a[1]];
                draw_piece_cell(t, c, outline, style, sub_word(i, j, 0, 0), item);
            }
            left_drawn = drawn;
        }
    }
}

/// The outline sides of a drawn cell with flags `f`: its right and top
/// ones from the closing flags, its left one when the cell before it is
/// not drawn, its bottom one when the cell under it (flags `under`, none
/// in the first row) is not.
#[inline(always)]
fn outline(f: u8, left_drawn: bool, under: Option<u8>) -> u8 {
    let bottom = under.is_none_or(|u| u & CELL_DRAW == 0);
    (bottom as u8 * BOTTOM)
        | ((f & CELL_RIGHT != 0) as u8 * RIGHT)
        | ((f & CELL_TOP != 0) as u8 * TOP)
        | (!left_drawn as u8 * LEFT)
}

/// Draws one cell with corners `c` (`(0,0)`, `(1,0)`, `(0,1)`, `(1,1)`)
/// in `style` by the kernel that suits it (module header).
#[inline(always)]
fn draw_piece_cell(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    outline: u8,
    style: CentreStyle,
    sub0: u32,
    item: u32,
) {
    if style == CentreStyle::Grid && folds(c) {
        let shift = (CENTRE_STEPS / FOLD_CUT).trailing_zeros();
        let r = Reciprocals::new(FOLD_CUT, FOLD_CUT);
        return draw_exact_cell(t, c, r, [FOLD_CUT; 2], sub0, shift, item);
    }
    let sides = Sides {
        outline,
        margin: style.margin(),
    };
    draw_cell(t, c, sides, sub0, item);
}

/// Whether the two triangles of the cell with corners `c` do not turn the
/// same way on screen (or the lower one is flat): the surface folds away
/// inside it, and the two-triangle kernels' lazy set-up refuses it.
#[inline(always)]
fn folds(c: [&Node; 4]) -> bool {
    let [lower, upper] = triangle_areas(c);
    lower.signum() != upper.signum() || lower == 0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::{test_node as node, Z_FAR};
    use crate::raster::band::{Sample, PATCH_SAMPLE};

    fn cell(c: [Node; 4], style: CentreStyle, outline: u8) -> Vec<Sample> {
        let mut px = vec![Sample::EMPTY; 24 * 24];
        let mut t = BandTarget::new(&mut px, 24, 0, 24);
        let c = [&c[0], &c[1], &c[2], &c[3]];
        draw_piece_cell(&mut t, c, outline, style, 0, PATCH_SAMPLE);
        px
    }

    #[test]
    fn a_folded_grid_cell_is_drawn_by_sub_quads_with_places_in_centre_steps() {
        // c11 past the side c00-c01: the triangles turn opposite ways.
        let c = [(10.0, 10.0), (16.0, 10.3), (10.2, 16.0), (8.0, 14.0)].map(|(x, y)| node(x, y));
        assert!(folds([&c[0], &c[1], &c[2], &c[3]]));
        let grid = cell(c, CentreStyle::Grid, 0);
        let mut quads = vec![Sample::EMPTY; 24 * 24];
        let mut t = BandTarget::new(&mut quads, 24, 0, 24);
        let r = Reciprocals::new(FOLD_CUT, FOLD_CUT);
        let corners = [&c[0], &c[1], &c[2], &c[3]];
        draw_exact_cell(&mut t, corners, r, [FOLD_CUT; 2], 0, 0, PATCH_SAMPLE);
        let mut written = 0;
        for (g, q) in grid.iter().zip(&quads) {
            assert_eq!(g.depth, q.depth);
            if g.depth < Z_FAR {
                let scale = CENTRE_STEPS / FOLD_CUT;
                let (a, b) = ((q.w0() >> 8) & 255, q.w0() & 255);
                assert_eq!(g.w0(), ((a * scale) << 8) | (b * scale));
                written += 1;
            }
        }
        assert!(written > 10, "{written}");
        // The same cell as pixel-sized cells draws its two triangles.
        assert_ne!(cell(c, CentreStyle::Cells, 0), grid);
    }

    #[test]
    fn a_grid_piece_with_folded_cells_leaves_no_pixel_centre_inside_unwritten() {
        // Lattices of 2–4 px cells, one node in three pulled across a
        // neighbour so that cells fold: drawn as one piece in the grid
        // style, every pixel centre inside the lattice's outline is
        // written (folds by sub-quads beside two-triangle cells).
        let mut rng = crate::test_rng::XorShift(0x00f0_1ded);
        let (w, n) = (48usize, 8usize);
        let (mut folded, mut checked) = (0, 0);
        for _ in 0..60 {
            let step = 2.0 + 2.0 * rng.unit();
            let mut nodes: Vec<Node> = (0..(n + 1) * (n + 1))
                .map(|k| {
                    let (i, j) = ((k % (n + 1)) as f32, (k / (n + 1)) as f32);
                    let mut q = node(4.0 + step * i, 4.0 + step * j);
                    q[2] = 1000 + 10 * k as i32;
                    q
                })
                .collect();
            for j in 1..n {
                for i in 1..n {
                    if rng.below(3) == 0 {
                        // Up to 1.2 cells to the right: past its neighbour.
                        nodes[j * (n + 1) + i][0] += (step * 1.2 * rng.unit() * 65536.0) as i32;
                    }
                }
            }
            let mut flags = vec![CELL_DRAW; n * n];
            for k in 0..n {
                flags[k * n + n - 1] |= CELL_RIGHT;
                flags[(n - 1) * n + k] |= CELL_TOP;
            }
            for j in 0..n {
                for i in 0..n {
                    let k = j * (n + 1) + i;
                    let c = [
                        &nodes[k],
                        &nodes[k + 1],
                        &nodes[k + n + 1],
                        &nodes[k + n + 2],
                    ];
                    folded += folds(c) as usize;
                }
            }
            let spans = vec![[0, w as i32]; n];
            let piece = BilinearPiece {
                nodes: &nodes,
                flags: &flags,
                spans: &spans,
                cols: n + 1,
                rows: n + 1,
                inside_columns: false,
            };
            let mut px = vec![Sample::EMPTY; w * w];
            let mut t = BandTarget::new(&mut px, w as i32, 0, w as i32);
            draw_cells_centres(&mut t, &piece, CentreStyle::Grid, PATCH_SAMPLE);
            // The outline's left and bottom sides are straight, the right
            // and top ones too (border nodes do not move).
            let (lo, hi) = (4.0, 4.0 + step * n as f32);
            for y in 0..w {
                for x in 0..w {
                    let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                    if cx > lo && cx < hi && cy > lo && cy < hi {
                        checked += 1;
                        assert!(px[y * w + x].depth < Z_FAR, "pixel {x},{y}");
                    }
                }
            }
        }
        assert!(folded > 100 && checked > 20_000, "{folded} {checked}");
    }

    #[test]
    fn grid_outlines_reach_less_far_than_pixel_sized_cells_outlines() {
        // A square of 3 px holding 3 × 3 pixel centres, its right and top
        // sides 0.2 px short of the next ones: half a pixel of margin takes
        // those, the grid margin (0.15 px) does not.
        let c = [(10.3, 10.3), (13.3, 10.3), (10.3, 13.3), (13.3, 13.3)].map(|(x, y)| node(x, y));
        let all = BOTTOM | RIGHT | TOP | LEFT;
        let count = |px: &[Sample]| px.iter().filter(|s| s.depth < Z_FAR).count();
        assert_eq!(count(&cell(c, CentreStyle::Grid, all)), 9);
        assert_eq!(count(&cell(c, CentreStyle::Grid, 0)), 9);
        assert_eq!(count(&cell(c, CentreStyle::Cells, all)), 16);
    }
}
