//! The path of pixel-sized and minified cells: every node of a piece is
//! splatted as a small square of pixels, with no sub-nodes.
//!
//! Input: a piece's projected nodes (fixed point, see [`crate::fixed`]) and
//! the largest `|x|`, `|y|` of its drawn cells' edges `[ux, uy, vx, vy]`.
//! Output: patch samples in the band's visibility buffer, one per pixel of
//! each node's footprint, each recorded as that node (so the deferred
//! resolve pass shades a visible pixel once, from its node's attributes).
//!
//! Coverage: a point `p(s, t)` of a bilinear cell lies, in each axis, within
//! `s·|u| + t·|v|` of corner `(0, 0)` (the cell's offset from that corner is
//! `s·((1-t)·u_bottom + t·u_top) + t·v_left`), so every point lies within
//! `(ux + vx) / 2` in x and `(uy + vy) / 2` in y of its nearest corner. A
//! node that writes every pixel whose centre lies within those reaches of
//! it ([`footprint_half_widths`]) therefore covers every pixel centre inside
//! the cells around it: the same hole-free bound as sub-nodes, with one
//! set-up per node instead of per cell. A node always writes the pixel that
//! holds it (`h ≥ 1/2`), so a piece whose cells are below a pixel is drawn
//! exactly as the nodes-only path draws it.
//!
//! Cost: O(nodes · footprint) stores, footprints of 1 × 1 to 3 × 3 pixels
//! for the default limit of the half-widths
//! ([`crate::RenderOptions::splat_limit`]); no per-cell work at raster time.
//!
//! Based on: point splatting with a footprint from the sampling density
//! (surfels: H. Pfister et al., "Surfels: surface elements as rendering
//! primitives", 2000; QSplat: S. Rusinkiewicz and M. Levoy, 2000), here
//! with a square footprint sized from the projected lattice so that the
//! splats of a patch's nodes close every gap between them.

use crate::fixed::{Node, EMPTY_NODE, XY_FRAC_BITS, XY_ONE};
use crate::grid::CELL_DRAW;
use crate::raster::band::{keep_nearer, patch_word, BandTarget};
use crate::raster::cell_bilinear::sub_word;

/// Half a pixel in position units.
const HALF: i32 = 1 << (XY_FRAC_BITS - 1);

/// The footprint half-widths `[hx, hy]`, in position units, that close
/// every gap of cells whose largest edges are `[ux, uy, vx, vy]` pixels:
/// the reach `(ux + vx) / 2` in x and `(uy + vy) / 2` in y of a cell's
/// nearest corner, each at least half a pixel, rounded up.
pub(crate) fn footprint_half_widths(edges: [f32; 4]) -> [i32; 2] {
    let [ux, uy, vx, vy] = edges;
    let fixed = |reach: f32| ((reach.max(0.5) * XY_ONE).ceil() as i32).max(HALF);
    [fixed(0.5 * (ux + vx)), fixed(0.5 * (uy + vy))]
}

/// The pixel range `lo..=hi` (one axis) whose centres lie within `half` of
/// the position `v` (both fixed point).
#[inline(always)]
fn covered_range(v: i32, half: i32) -> (i32, i32) {
    // Pixel `c` has its centre at `c + 1/2`: |c + 1/2 - v| <= half.
    let lo = v - half - HALF;
    let hi = v + half - HALF;
    (-((-lo) >> XY_FRAC_BITS), hi >> XY_FRAC_BITS)
}

/// Marks as unused (in the projected-node array of a `cols × rows` piece)
/// every node that no drawn cell has as a corner (cell flags `flags`, see
/// [`crate::plan::measure::measure_cells`]): nodes of cells facing away or
/// without four used corners, which the cells' splats do not need. Only
/// the position is overwritten; attributes stay for the resolve pass.
/// `scratch` holds one byte per cell column (reused).
pub(crate) fn drop_undrawn_nodes(
    nodes: &mut [Node],
    flags: &[u8],
    cols: usize,
    rows: usize,
    scratch: &mut Vec<u8>,
) {
    let ccols = cols - 1;
    // Per node row: the flags of the cells above and below it, or-ed per
    // column, padded by an undrawn cell on each side. Why two passes: the
    // first runs in byte lanes (callgrind, bunny 500²: a per-node test of
    // four cells cost 10 M instructions per frame).
    scratch.clear();
    scratch.resize(cols + 1, 0);
    for (j, row) in nodes.chunks_exact_mut(cols).take(rows).enumerate() {
        let below = &flags[j.saturating_sub(1) * ccols..][..ccols];
        let above = &flags[j.min(rows - 2) * ccols..][..ccols];
        for ((s, &b), &a) in scratch[1..cols].iter_mut().zip(below).zip(above) {
            *s = (a | b) & CELL_DRAW;
        }
        for (node, pair) in row.iter_mut().zip(scratch.windows(2)) {
            if pair[0] | pair[1] == 0 {
                node[0] = EMPTY_NODE;
            }
        }
    }
}

/// A splatted piece as the band reads it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SplatPiece<'a> {
    /// Its `cols × rows` projected nodes, row by row.
    pub(crate) nodes: &'a [Node],
    /// Per row of cells, the pixel rows its used nodes span (inclusive).
    pub(crate) spans: &'a [[i32; 2]],
    /// Nodes per row.
    pub(crate) cols: usize,
    /// Rows of nodes.
    pub(crate) rows: usize,
    /// Footprint half-widths in x and y, position units (from
    /// [`footprint_half_widths`]).
    pub(crate) half: [i32; 2],
}

/// Splats every used node of a piece. Each node is recorded as a corner of
/// a cell it belongs to, as the nodes-only path records it.
pub(crate) fn draw_splats(t: &mut BandTarget<'_>, piece: &SplatPiece<'_>, item: u32) {
    let (cols, rows, half) = (piece.cols, piece.rows, piece.half);
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows - 1);
    let (x_hi, width) = (t.width - 1, t.width as usize);
    let reach = (half[1] + (1 << XY_FRAC_BITS) - 1) >> XY_FRAC_BITS;
    for (j, row) in piece.nodes.chunks_exact(cols).take(rows).enumerate() {
        // Skip a row of nodes whose footprints miss the band: its span is
        // within the span of a row of cells it bounds.
        let [lo, hi] = piece.spans[j.min(rows - 2)];
        if hi + reach < y_lo || lo - reach > y_hi {
            continue;
        }
        let (cj, b) = if j + 1 < rows { (j, 0) } else { (j - 1, 1) };
        for (i, node) in row.iter().enumerate() {
            if node[0] == EMPTY_NODE {
                continue;
            }
            let (r0, r1) = covered_range(node[1], half[1]);
            let (c0, c1) = covered_range(node[0], half[0]);
            let (r0, r1) = (r0.max(y_lo), r1.min(y_hi));
            let (c0, c1) = (c0.max(0), c1.min(x_hi));
            if r0 > r1 || c0 > c1 {
                continue;
            }
            let (ci, a) = if i + 1 < cols { (i, 0) } else { (i - 1, 1) };
            let word = patch_word(sub_word(ci, cj, a, b), item);
            let z = node[2];
            let (c0, c1) = (c0 as usize, c1 as usize + 1);
            for py in r0..=r1 {
                let base = (py - t.y0) as usize * width;
                // One bounds check per row of the footprint.
                for s in &mut t.px[base + c0..base + c1] {
                    keep_nearer(s, z, word);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::{NODE_WIDTH, Z_FAR};
    use crate::raster::band::Sample;
    use crate::test_rng::XorShift;

    fn fixed(v: f32) -> i32 {
        (v * XY_ONE) as i32
    }

    /// A node at pixel position `(x, y)` (depth 0).
    fn node(x: f32, y: f32) -> Node {
        let mut n = [0; NODE_WIDTH];
        (n[0], n[1]) = (fixed(x), fixed(y));
        n
    }

    /// Whether `p` lies inside the quadrilateral `q` (corners 00, 10, 11,
    /// 01 in order: a bilinear cell's straight edges), by ray crossings.
    fn inside(q: [[f32; 2]; 4], p: [f32; 2]) -> bool {
        let mut crossings = false;
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    crossings = !crossings;
                }
            }
        }
        crossings
    }

    #[test]
    fn half_widths_are_the_corner_reach_and_at_least_half_a_pixel() {
        assert_eq!(footprint_half_widths([0.2, 0.1, 0.1, 0.2]), [HALF, HALF]);
        let [hx, hy] = footprint_half_widths([1.0, 0.5, 0.75, 1.25]);
        assert_eq!([hx, hy], [fixed(0.875), fixed(0.875)]);
        let [hx, hy] = footprint_half_widths([2.0, 0.25, 1.0, 0.5]);
        assert_eq!([hx, hy], [fixed(1.5), HALF]);
    }

    #[test]
    fn covered_range_holds_the_centres_within_the_half_width() {
        // Half a pixel: exactly the pixel holding the point, except on a
        // centre-to-centre boundary, where both neighbours are within reach.
        assert_eq!(covered_range(fixed(3.3), HALF), (3, 3));
        assert_eq!(covered_range(fixed(3.0), HALF), (2, 3));
        // One pixel: the centres at 2.5, 3.5 are within 1 of 3.2, 4.5 is not.
        assert_eq!(covered_range(fixed(3.2), fixed(1.0)), (2, 3));
        assert_eq!(covered_range(fixed(3.6), fixed(1.0)), (3, 4));
        // Negative positions round the same way.
        assert_eq!(covered_range(fixed(-0.7), HALF), (-1, -1));
    }

    #[test]
    fn splats_cover_every_pixel_centre_inside_random_lattices() {
        // Random 5 × 4 pieces (rotated, sheared, perturbed lattices of
        // 0.4-1.6 px): every pixel centre inside a cell (the quadrilateral
        // of its straight edges) is written.
        let mut rng = XorShift(0x5eed_0f5a_1a77);
        let (w, h) = (32i32, 32i32);
        for _ in 0..200 {
            let (cols, rows) = (5, 4);
            let scale = 0.4 + 1.2 * rng.unit();
            let angle = rng.unit() * std::f32::consts::TAU;
            let shear = rng.unit() - 0.5;
            let (c, s) = (angle.cos() * scale, angle.sin() * scale);
            let nodes: Vec<Node> = (0..rows)
                .flat_map(|j| (0..cols).map(move |i| (i as f32, j as f32)))
                .map(|(i, j)| {
                    let (u, v) = (i + shear * j, j);
                    let jitter = |r: f32| (r - 0.5) * 0.2 * scale;
                    let (dx, dy) = (jitter(rng.unit()), jitter(rng.unit()));
                    node(16.0 + c * u - s * v + dx, 16.0 + s * u + c * v + dy)
                })
                .collect();
            let pos = |k: usize| [nodes[k][0] as f32 / XY_ONE, nodes[k][1] as f32 / XY_ONE];
            let mut edges = [0f32; 4];
            for j in 0..rows - 1 {
                for i in 0..cols - 1 {
                    let k = j * cols + i;
                    for (from, to) in [(k, k + 1), (k + cols, k + cols + 1)] {
                        edges[0] = edges[0].max((pos(to)[0] - pos(from)[0]).abs());
                        edges[1] = edges[1].max((pos(to)[1] - pos(from)[1]).abs());
                    }
                    for (from, to) in [(k, k + cols), (k + 1, k + cols + 1)] {
                        edges[2] = edges[2].max((pos(to)[0] - pos(from)[0]).abs());
                        edges[3] = edges[3].max((pos(to)[1] - pos(from)[1]).abs());
                    }
                }
            }
            let spans = vec![[0, h - 1]; rows - 1];
            let piece = SplatPiece {
                nodes: &nodes,
                spans: &spans,
                cols,
                rows,
                half: footprint_half_widths(edges),
            };
            let mut px = vec![Sample::EMPTY; (w * h) as usize];
            let mut t = BandTarget::new(&mut px, w, 0, h);
            draw_splats(&mut t, &piece, 7);
            for j in 0..rows - 1 {
                for i in 0..cols - 1 {
                    let k = j * cols + i;
                    let q = [pos(k), pos(k + 1), pos(k + cols + 1), pos(k + cols)];
                    for (py, px_row) in px.chunks_exact(w as usize).enumerate() {
                        for (x, s) in px_row.iter().enumerate() {
                            let centre = [x as f32 + 0.5, py as f32 + 0.5];
                            assert!(
                                !inside(q, centre) || s.depth < Z_FAR,
                                "pixel ({x}, {py}) inside cell ({i}, {j}) left empty"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn nodes_of_no_drawn_cell_are_dropped_and_the_others_kept() {
        // 4 × 3 nodes, cells (0, 0) and (2, 1) drawn.
        let (cols, rows) = (4, 3);
        let mut nodes: Vec<Node> = (0..cols * rows).map(|k| node(k as f32, 0.0)).collect();
        let flags = [CELL_DRAW, 0, 0, 0, 0, CELL_DRAW];
        drop_undrawn_nodes(&mut nodes, &flags, cols, rows, &mut Vec::new());
        let kept: Vec<usize> = (0..cols * rows)
            .filter(|&k| nodes[k][0] != EMPTY_NODE)
            .collect();
        assert_eq!(kept, vec![0, 1, 4, 5, 6, 7, 10, 11]);
    }
}
