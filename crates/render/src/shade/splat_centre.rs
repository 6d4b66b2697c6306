//! Splatted samples placed at their pixel centres, once per visible pixel.
//!
//! A splat ([`crate::raster::splat`]) records each pixel of its footprint
//! as its node, with no per-pixel work. After a band is drawn, this pass
//! moves every visible splatted sample from its node to the point of the
//! surface under the pixel centre, so the resolve pass interpolates
//! normals and colours there as it does for subdivided cells:
//!
//! 1. the pixel centre's offset from the node (fixed point) is mapped to
//!    cell steps by the piece's inverse screen lattice (found once per
//!    piece at planning, [`crate::plan::work::Item::lattice`]), rounded to
//!    `1 / SPLAT_STEPS` of a cell and clamped to one cell each way;
//! 2. the steps name one of the four cells around the node, clamped to the
//!    piece; a cell that is not drawn (facing away, an empty corner) gives
//!    the node itself, as before this pass.
//!
//! So shading costs one mapping per visible pixel, not per written pixel
//! (overdraw is about 3 written pixels per visible one on the bunny).
//!
//! Cost: O(pixels of the band) to find the splatted samples, a few dozen
//! operations for each.

use crate::fixed::{Node, XY_FRAC_BITS};
use crate::grid::CELL_DRAW;
use crate::plan::work::ChunkWork;
use crate::raster::band::{Sample, PATCH_SAMPLE};
use crate::raster::cell_bilinear::sub_word;
use crate::raster::splat::SPLAT_STEPS;

/// Half a pixel in position units.
const HALF: i32 = 1 << (XY_FRAC_BITS - 1);

/// What the pass needs of one splatted piece.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SplatLattice<'a> {
    /// Its `cols × rows` projected nodes.
    nodes: &'a [Node],
    /// Its cell flags, `(cols - 1) × (rows - 1)`.
    flags: &'a [u8],
    /// Nodes per row (0: not a splatted piece).
    cols: usize,
    /// Position units to cell steps (see [`crate::plan::work::Item::lattice`]).
    inverse: [f32; 4],
}

/// The splatted pieces of a frame by draw-item index (as
/// [`crate::shade::resolve::Resolve::items`]). Built once per frame.
#[derive(Debug, Default)]
pub(crate) struct SplatLattices<'a> {
    pieces: Vec<SplatLattice<'a>>,
    /// Whether any item is splatted (else the pass is skipped).
    pub(crate) any: bool,
}

impl<'a> SplatLattices<'a> {
    /// The table of the draw items `items` (`(chunk, item)`) of `chunks`.
    pub(crate) fn new(items: &[(u32, u32)], chunks: &'a [ChunkWork]) -> Self {
        let mut table = Self::default();
        table.pieces.reserve(items.len());
        for &(c, i) in items {
            let chunk = &chunks[c as usize];
            let item = &chunk.items[i as usize];
            if item.splat[0] == 0 {
                table.pieces.push(SplatLattice::default());
                continue;
            }
            let (cols, rows) = (item.cols as usize, item.rows as usize);
            let (n, f) = (item.first as usize, item.flags as usize);
            table.pieces.push(SplatLattice {
                nodes: &chunk.nodes[n..n + cols * rows],
                flags: &chunk.cell_flags[f..f + (cols - 1) * (rows - 1)],
                cols,
                inverse: item.lattice,
            });
            table.any = true;
        }
        table
    }
}

/// Places every visible splatted sample of a band (rows from `y0`, `width`
/// pixels each) at its pixel centre (see the module header).
pub(crate) fn place_splatted_samples(
    table: &SplatLattices<'_>,
    y0: i32,
    width: usize,
    px: &mut [Sample],
) {
    if !table.any {
        return;
    }
    for (row, line) in px.chunks_exact_mut(width).enumerate() {
        let cy = ((y0 + row as i32) << XY_FRAC_BITS) + HALF;
        for (x, s) in line.iter_mut().enumerate() {
            if s.w2 & PATCH_SAMPLE == 0 {
                continue;
            }
            let piece = &table.pieces[(s.w2 & !PATCH_SAMPLE) as usize];
            if piece.cols != 0 {
                let cx = ((x as i32) << XY_FRAC_BITS) + HALF;
                s.w0 = piece.place(s.w0, cx, cy);
            }
        }
    }
}

impl SplatLattice<'_> {
    /// The sub-node word of the point at pixel centre `(cx, cy)` (position
    /// units) near the node that sample word `sub` records.
    #[inline(always)]
    fn place(&self, sub: u32, cx: i32, cy: i32) -> u32 {
        let cols = self.cols;
        let rows = self.nodes.len() / cols;
        let steps = SPLAT_STEPS as i32;
        let (i, j) = (
            (sub >> 24) as usize + ((sub >> 8) & 0xff != 0) as usize,
            ((sub >> 16) & 0xff) as usize + (sub & 0xff != 0) as usize,
        );
        let node = &self.nodes[j * cols + i];
        let (dx, dy) = ((cx - node[0]) as f32, (cy - node[1]) as f32);
        let [a, b, c, d] = self.inverse;
        let s = to_steps(a * dx + b * dy, steps);
        let t = to_steps(c * dx + d * dy, steps);
        let (ci, a) = cell_and_step(i, s, cols, steps);
        let (cj, b) = cell_and_step(j, t, rows, steps);
        if self.flags[cj * (cols - 1) + ci] & CELL_DRAW == 0 {
            // Not a drawn cell: the node itself, as a corner of that cell.
            let corner = |n: usize, c: usize| ((n - c) as i32 * steps) as u32;
            return sub_word(ci, cj, corner(i, ci), corner(j, cj));
        }
        sub_word(ci, cj, a as u32, b as u32)
    }
}

/// `v` rounded to a whole step, clamped to one cell (`±steps`).
#[inline(always)]
fn to_steps(v: f32, steps: i32) -> i32 {
    let s = steps as f32;
    // Truncation of a value made non-negative rounds to nearest.
    (v.clamp(-s, s) + s + 0.5) as i32 - steps
}

/// The cell (along one axis, of `n` nodes) holding a point `s` steps from
/// node `k`, and its step within that cell; clamped to the piece.
#[inline(always)]
fn cell_and_step(k: usize, s: i32, n: usize, steps: i32) -> (usize, i32) {
    if s < 0 {
        if k == 0 {
            (0, 0)
        } else {
            (k - 1, steps + s)
        }
    } else if k + 1 < n {
        (k, s)
    } else {
        (k - 1, steps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::{NODE_WIDTH, XY_ONE};

    fn node(x: f32, y: f32) -> Node {
        let mut n = [0; NODE_WIDTH];
        (n[0], n[1]) = ((x * XY_ONE) as i32, (y * XY_ONE) as i32);
        n
    }

    /// A 3 × 3 lattice of 2-pixel cells rotated by `angle`, its inverse
    /// lattice, and the pixel position of lattice point `(u, v)`.
    fn lattice(angle: f32) -> (Vec<Node>, [f32; 4], impl Fn(f32, f32) -> [f32; 2]) {
        let (c, s) = (angle.cos() * 2.0, angle.sin() * 2.0);
        let at = move |u: f32, v: f32| [10.0 + c * u - s * v, 10.0 + s * u + c * v];
        let nodes = (0..9)
            .map(|k| at((k % 3) as f32, (k / 3) as f32))
            .map(|[x, y]| node(x, y))
            .collect();
        let det = c * c + s * s;
        let k = SPLAT_STEPS as f32 / (det * XY_ONE);
        (nodes, [c * k, s * k, -s * k, c * k], at)
    }

    #[test]
    fn pixel_centres_land_in_their_cell_at_their_place() {
        for angle in [0.0f32, 0.4, 1.9, -2.5] {
            let (nodes, inverse, at) = lattice(angle);
            let flags = [CELL_DRAW; 4];
            let piece = SplatLattice {
                nodes: &nodes,
                flags: &flags,
                cols: 3,
                inverse,
            };
            // Points inside the four cells around the middle node (1, 1),
            // recorded as that node (cell (1, 1), corner (0, 0)).
            for (u, v) in [(0.3f32, 0.6f32), (1.5, 1.25), (1.875, 0.125), (0.5, 1.5)] {
                let [x, y] = at(u, v);
                let (cx, cy) = ((x * XY_ONE) as i32, (y * XY_ONE) as i32);
                let got = piece.place(sub_word(1, 1, 0, 0), cx, cy);
                let (ci, cj) = ((got >> 24) as f32, ((got >> 16) & 0xff) as f32);
                let steps = SPLAT_STEPS as f32;
                let a = ((got >> 8) & 0xff) as f32 / steps;
                let b = (got & 0xff) as f32 / steps;
                assert!((ci + a - u).abs() <= 0.5 / steps + 1e-3, "{angle} {u} {got:x}");
                assert!((cj + b - v).abs() <= 0.5 / steps + 1e-3, "{angle} {v} {got:x}");
            }
        }
    }

    #[test]
    fn undrawn_cells_and_the_border_keep_the_node() {
        let (nodes, inverse, at) = lattice(0.3);
        // Cell (0, 0) not drawn.
        let flags = [0, CELL_DRAW, CELL_DRAW, CELL_DRAW];
        let piece = SplatLattice {
            nodes: &nodes,
            flags: &flags,
            cols: 3,
            inverse,
        };
        let fixed = |[x, y]: [f32; 2]| ((x * XY_ONE) as i32, (y * XY_ONE) as i32);
        let (cx, cy) = fixed(at(0.6, 0.5));
        let steps = SPLAT_STEPS;
        let got = piece.place(sub_word(0, 0, steps, steps), cx, cy);
        assert_eq!(got, sub_word(0, 0, steps, steps));
        // Past the piece's left border from node (0, 2): clamped to it.
        let (cx, cy) = fixed(at(-0.5, 2.0));
        let got = piece.place(sub_word(0, 1, 0, steps), cx, cy);
        assert_eq!(got, sub_word(0, 1, 0, steps));
    }

    #[test]
    fn steps_round_to_nearest_and_clamp_to_a_cell() {
        assert_eq!(to_steps(0.49, 8), 0);
        assert_eq!(to_steps(0.51, 8), 1);
        assert_eq!(to_steps(-0.51, 8), -1);
        assert_eq!(to_steps(-3.4, 8), -3);
        assert_eq!(to_steps(12.0, 8), 8);
        assert_eq!(to_steps(-12.0, 8), -8);
        assert_eq!(cell_and_step(2, -3, 5, 8), (1, 5));
        assert_eq!(cell_and_step(4, 3, 5, 8), (3, 8));
        assert_eq!(cell_and_step(0, -3, 5, 8), (0, 0));
    }
}
