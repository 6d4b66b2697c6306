//! Bilinear cells with exact outlines: the sub-node drawer of
//! [`crate::raster::cell_bilinear`], except that along a cell's open sides
//! ([`crate::plan::open_sides`]) a sub-node is written only when the centre
//! of the pixel holding it lies inside the cell.
//!
//! Why: a sub-node is written to the pixel that holds it, so every pixel a
//! magnified cell's outline touches is written, on average half a pixel
//! past the true edge, where a triangle rasterizer (and the source drawn
//! by one) covers a pixel only when its centre is inside. Inside a surface
//! that reach only meets the neighbouring cell; on an outline it draws the
//! surface over the background.
//!
//! Exactness: a cell's sides are straight on screen (a bilinear cell's
//! side interpolates two corners linearly), and every pixel whose centre
//! lies in the cell holds a sub-node (the subdivision keeps sub-cells below
//! a pixel), so the test keeps exactly the pixels whose centres lie on the
//! inner side of every open side (inclusive), as the triangle path would.
//! A cell whose corners do not turn one way (a fold, a degenerate cell) has
//! no straight outline and draws as before (an exact test for folded cells,
//! by inverting the bilinear map per sub-node, was tried: fuze 27.13 →
//! 27.10 dB, so it was not kept).
//!
//! Cost: the cells without an open side draw as in
//! [`crate::raster::cell_bilinear`]; an open cell pays one edge function
//! per open side and sub-node (pieces cut finer than
//! [`crate::plan::open_sides::OPEN_SIDE_CUT`] only).

use crate::fixed::Node;
use crate::grid::{
    CELL_DRAW, CELL_EXACT, CELL_OPEN, CELL_OPEN_BOTTOM, CELL_OPEN_LEFT, CELL_OPEN_RIGHT,
    CELL_OPEN_TOP,
};
use crate::raster::band::{patch_word, splat_sample, BandTarget};
use crate::raster::cell_bilinear::{
    cell_in_band, draw_cell, next_row, setup, sub_word, BilinearPiece, Reciprocals, EXT,
};
use crate::raster::cell_exact::draw_exact_cell;

/// Draws the cells of a piece with open sides, cut into `nu × nv`: cells
/// without an open side as [`crate::raster::cell_bilinear`] does, the
/// others clipped at their open sides, and cells flagged
/// [`CELL_EXACT`] by pixel-centre coverage ([`crate::raster::cell_exact`]).
/// Inlined so that it runs with the band's instruction set ([`crate::isa`]).
#[inline(always)]
pub(crate) fn draw_cells_open(
    t: &mut BandTarget<'_>,
    piece: &BilinearPiece<'_>,
    nu: u32,
    nv: u32,
    item: u32,
) {
    let r = Reciprocals::new(nu, nv);
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows);
    let (cols, nodes) = (piece.cols, piece.nodes);
    let rows_of_cells = piece.flags.chunks_exact(cols - 1).zip(piece.spans);
    for (j, (row_flags, &[lo, hi])) in rows_of_cells.take(piece.rows - 1).enumerate() {
        if hi < y_lo || lo >= y_hi {
            continue;
        }
        let below = &nodes[j * cols..(j + 1) * cols];
        let above = &nodes[(j + 1) * cols..(j + 2) * cols];
        // As in `cell_bilinear`: a row a pixel inside the band, in a piece
        // inside the image's columns, needs no per-cell box or clipping.
        let row_inside = piece.inside_columns && lo > y_lo && hi < y_hi - 1;
        for (i, &f) in row_flags.iter().enumerate() {
            if f & CELL_DRAW == 0 {
                continue;
            }
            let c = [&below[i], &below[i + 1], &above[i], &above[i + 1]];
            let inside = row_inside
                || match cell_in_band(t, c, piece.inside_columns) {
                    Some(inside) => inside,
                    None => continue,
                };
            // Every cell places its last column and row (see
            // `draw_open_cell`).
            let (cut, sub0) = ([nu, 1, nv, 1], sub_word(i, j, 0, 0));
            if f & CELL_EXACT != 0 {
                draw_exact_cell(t, c, r, [nu, nv], sub0, 0, item);
                continue;
            }
            match Shape::of(c, f) {
                Shape::Plain if inside => {
                    draw_cell::<false>(t, c, r, cut, patch_word(sub0, item));
                }
                Shape::Plain => draw_cell::<true>(t, c, r, cut, patch_word(sub0, item)),
                Shape::Open(outline) => draw_open_cell(t, c, r, [nu, nv], sub0, item, &outline),
            }
        }
    }
}

/// How a cell of a piece with open sides is drawn.
#[derive(Debug, Clone, Copy)]
enum Shape {
    /// As in [`crate::raster::cell_bilinear`]: no side is open, or its
    /// corners do not all turn one way (a fold or a degenerate cell: no
    /// straight outline to clip at).
    Plain,
    /// Convex with open sides: clipped at them.
    Open(Outline),
}

impl Shape {
    /// The shape of the cell with corners `c` (`(0,0)`, `(1,0)`, `(0,1)`,
    /// `(1,1)`) and flags `f`.
    fn of(c: [&Node; 4], f: u8) -> Shape {
        if f & CELL_OPEN == 0 {
            return Shape::Plain;
        }
        // Around the cell: (0,0) → (1,0) → (1,1) → (0,1).
        let ring = [c[0], c[1], c[3], c[2]];
        let p = |k: usize| (ring[k % 4][0] as i64, ring[k % 4][1] as i64);
        let turn = |k: usize| {
            let (a, b, d) = (p(k), p(k + 1), p(k + 2));
            (b.0 - a.0) * (d.1 - b.1) - (b.1 - a.1) * (d.0 - b.0)
        };
        let turns = [turn(0), turn(1), turn(2), turn(3)];
        let sign = if turns.iter().all(|&t| t > 0) {
            1
        } else if turns.iter().all(|&t| t < 0) {
            -1
        } else {
            return Shape::Plain;
        };
        let sides = [
            CELL_OPEN_BOTTOM,
            CELL_OPEN_RIGHT,
            CELL_OPEN_TOP,
            CELL_OPEN_LEFT,
        ];
        let mut outline = Outline {
            lines: [[0; 4]; 4],
            count: 0,
        };
        for (k, &bit) in sides.iter().enumerate() {
            if f & bit != 0 {
                let (a, b) = (p(k), p(k + 1));
                outline.lines[outline.count] = [sign * (b.0 - a.0), sign * (b.1 - a.1), a.0, a.1];
                outline.count += 1;
            }
        }
        Shape::Open(outline)
    }
}

/// The open sides of a convex cell as edge functions: pixel centre
/// `(x, y)` (fixed point) is inside side `k` when
/// `a[k] · (y − py[k]) − b[k] · (x − px[k]) >= 0`.
#[derive(Debug, Clone, Copy)]
struct Outline {
    lines: [[i64; 4]; 4],
    count: usize,
}

impl Outline {
    /// True when the centre of pixel `(px, py)` lies on the inner side of
    /// every open side (or on one).
    #[inline(always)]
    fn covers(&self, px: i32, py: i32) -> bool {
        let (x, y) = (((px as i64) << 16) + 0x8000, ((py as i64) << 16) + 0x8000);
        self.lines[..self.count]
            .iter()
            .all(|&[a, b, x0, y0]| a * (y - y0) - b * (x - x0) >= 0)
    }
}

/// Places the sub-nodes of one cell cut `nu × nv` (as [`draw_cell`] with
/// clipping) whose pixel centres `clip` covers. In a piece with open sides
/// every cell places its last column and row too, whatever its
/// neighbours: a pixel centre inside a cell then has one of the cell's own
/// sub-nodes within reach, tested against the cell's own outline (or none).
/// Why: placed by a neighbour, that sub-node was tested against the
/// neighbour's outline, which cuts into this cell where an open side meets
/// a closed one or another open side at an angle (holes in
/// `closed_sides_draw_as_before_and_open_ones_never_add_a_pixel`).
fn draw_open_cell(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    r: Reciprocals,
    [nu, nv]: [u32; 2],
    sub0: u32,
    item: u32,
    clip: &Outline,
) {
    let s = |ch: usize| setup(c[0][ch], c[1][ch], c[2][ch], c[3][ch], r);
    let (sx, sy, sz) = (s(0), s(1), s(2));
    let xy_shift = 16 + EXT;
    let mut start = [sx[0], sy[0], sz[0]];
    let mut step = [sx[2], sy[2], sz[2]];
    for row_word in sub0..=sub0 + nv {
        let mut v = start;
        let mut word = row_word;
        for _ in 0..=nu {
            let (px, py) = ((v[0] >> xy_shift) as i32, (v[1] >> xy_shift) as i32);
            if clip.covers(px, py) {
                splat_sample(t, px, py, (v[2] >> EXT) as i32, patch_word(word, item));
            }
            word += 1 << 8;
            v[0] += step[0];
            v[1] += step[1];
            v[2] += step[2];
        }
        next_row(&mut start, &mut step, [sx, sy, sz]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::{test_node as node, Z_FAR};
    use crate::grid::{CELL_RIGHT, CELL_TOP};
    use crate::raster::band::{Sample, PATCH_SAMPLE};
    use crate::raster::cell_bilinear::draw_cells_bilinear;
    use crate::test_rng::XorShift;

    /// Draws a `cols × rows` piece with `flags` cut `cut × cut` into a
    /// `w × w` image; the covered pixels.
    fn draw(nodes: &[Node], flags: &[u8], cols: usize, cut: u32, w: usize) -> Vec<bool> {
        let rows = nodes.len() / cols;
        let mut px = vec![Sample::EMPTY; w * w];
        let mut t = BandTarget::new(&mut px, w as i32, 0, w as i32);
        let spans = vec![[-100, 100]; rows - 1];
        let piece = BilinearPiece {
            nodes,
            flags,
            spans: &spans,
            cols,
            rows,
            inside_columns: false,
        };
        if flags.iter().any(|f| f & CELL_OPEN != 0) {
            draw_cells_open(&mut t, &piece, cut, cut, PATCH_SAMPLE);
        } else {
            draw_cells_bilinear(&mut t, &piece, cut, cut, PATCH_SAMPLE);
        }
        px.iter().map(|s| s.depth < Z_FAR).collect()
    }

    /// Whether `(x, y)` lies inside the quad `q` (in ring order), by more
    /// than `margin` pixels (negative: within `-margin` outside).
    fn in_quad(q: [(f32, f32); 4], x: f32, y: f32, margin: f32) -> bool {
        let side = |a: (f32, f32), b: (f32, f32)| {
            let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
            ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) / len
        };
        let d = [
            side(q[0], q[1]),
            side(q[1], q[2]),
            side(q[2], q[3]),
            side(q[3], q[0]),
        ];
        d.iter().all(|&v| v > margin) || d.iter().all(|&v| -v > margin)
    }

    #[test]
    fn a_cell_open_on_every_side_covers_exactly_the_pixel_centres_inside() {
        let mut rng = XorShift(0x0e_d9e5);
        let w = 40;
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..200 {
            let (q, s) = rng.jittered_square(6.0, 12.0);
            let nodes = [
                node(q[0].0, q[0].1),
                node(q[1].0, q[1].1),
                node(q[3].0, q[3].1),
                node(q[2].0, q[2].1),
            ];
            let flags = [CELL_DRAW | CELL_RIGHT | CELL_TOP | CELL_OPEN];
            let cut = (s + 9.0).ceil() as u32;
            let covered = draw(&nodes, &flags, 2, cut, w);
            for y in 0..w {
                for x in 0..w {
                    let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                    if in_quad(q, cx, cy, 0.01) {
                        inside += 1;
                        assert!(covered[y * w + x], "hole at {x},{y}");
                    } else if !in_quad(q, cx, cy, -0.01) {
                        outside += 1;
                        assert!(!covered[y * w + x], "written past the edge at {x},{y}");
                    }
                }
            }
        }
        assert!(inside > 10_000 && outside > 100_000, "{inside} {outside}");
    }

    #[test]
    fn closed_sides_draw_as_before_and_open_ones_never_add_a_pixel() {
        // Random jittered pieces, some cells undrawn, random open sides:
        // the pixels drawn are those of the plain kernel, minus some along
        // the open sides only (every pixel dropped has its centre outside
        // the cell on an open side), and every pixel with its centre inside
        // a drawn cell stays.
        let mut rng = XorShift(0x51de_5eed);
        let w = 48;
        let mut dropped = 0;
        for _ in 0..300 {
            let (cols, rows) = (2 + rng.below(4) as usize, 2 + rng.below(4) as usize);
            let step = 3.0 + 5.0 * rng.unit();
            let nodes: Vec<Node> = (0..cols * rows)
                .map(|k| {
                    let (i, j) = ((k % cols) as f32, (k / cols) as f32);
                    let jit = 0.8 * (rng.unit() - 0.5);
                    node(2.0 + step * (i + 0.2 * j) + jit, 2.0 + step * j + jit)
                })
                .collect();
            let (ccols, crows) = (cols - 1, rows - 1);
            let mut flags = crate::test_rng::random_drawn_cells(&mut rng, ccols, crows, 5);
            let plain = draw(&nodes, &flags, cols, 14, w);
            for f in flags.iter_mut().filter(|f| **f & CELL_DRAW != 0) {
                *f |= (rng.below(16) as u8) << 3;
            }
            let open = draw(&nodes, &flags, cols, 14, w);
            for (k, (&p, &o)) in plain.iter().zip(&open).enumerate() {
                assert!(p || !o, "a pixel added at {k}");
                if p && !o {
                    dropped += 1;
                }
            }
            // Every pixel centre inside a drawn cell is still covered.
            let at = |i: usize, j: usize| {
                let n = nodes[j * cols + i];
                (n[0] as f32 / 65536.0, n[1] as f32 / 65536.0)
            };
            for cj in 0..crows {
                for ci in 0..ccols {
                    if flags[cj * ccols + ci] & CELL_DRAW == 0 {
                        continue;
                    }
                    let q = [
                        at(ci, cj),
                        at(ci + 1, cj),
                        at(ci + 1, cj + 1),
                        at(ci, cj + 1),
                    ];
                    for y in 0..w {
                        for x in 0..w {
                            if in_quad(q, x as f32 + 0.5, y as f32 + 0.5, 0.01) {
                                assert!(open[y * w + x], "hole at {x},{y}");
                            }
                        }
                    }
                }
            }
        }
        assert!(dropped > 1000, "{dropped} pixels dropped");
    }
}
