//! Cell rendering with a C1-smooth surface: Catmull-Rom subdivision.
//!
//! For magnified views, bilinear cells show the grid as creases in the
//! shading and as polygonal silhouettes. This scheme evaluates, over each
//! cell, the bicubic Catmull-Rom spline of the 4 × 4 projected nodes around
//! it (positions, depth and attributes alike): it interpolates the nodes
//! and is C1 across cells. Missing neighbours (grid border, empty nodes)
//! are extrapolated linearly (`p[-1] = 2 p[0] - p[1]`), which makes the
//! spline end like the bilinear cell there.
//!
//! Sub-nodes are placed as in [`crate::raster::cell_bilinear`] (same `nu × nv`
//! pattern and edge rule); the planner picks them with a 30 % margin since
//! the curved cell can bulge beyond its corners' extent.
//!
//! Arithmetic in f32 on the fixed-point values (exact to 2^-7 px at 8192 px
//! wide). Cost per sub-node: 4 multiply-adds per channel (x, y, depth)
//! plus the depth test; per cell row, 16 per channel.
//!
//! Based on: E. Catmull, R. Rom, "A class of local interpolating splines",
//! 1974.

use crate::fixed::{Node, EMPTY_NODE};
use crate::grid::cell_drawable;
use crate::raster::band::{patch_word, splat_sample, BandTarget};
use crate::raster::cell_bilinear::{sub_word, MAX_SUBDIVISION};

/// Catmull-Rom weights at parameter `t` in [0, 1].
#[inline]
fn weights(t: f32) -> [f32; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    ]
}

/// Position and depth of a node.
type Values = [f32; 3];

/// The 4 × 4 neighbourhood of cell `(i, j)`, extrapolated where missing.
fn gather(nodes: &[Node], cols: usize, rows: usize, i: usize, j: usize) -> [[Values; 4]; 4] {
    let get = |di: i32, dj: i32| -> Option<Values> {
        let (x, y) = (i as i32 + di, j as i32 + dj);
        if x < 0 || y < 0 || x >= cols as i32 || y >= rows as i32 {
            return None;
        }
        let n = &nodes[y as usize * cols + x as usize];
        (n[0] != EMPTY_NODE).then(|| [n[0] as f32, n[1] as f32, n[2] as f32])
    };
    let extrapolate =
        |p0: &Values, p1: &Values| -> Values { std::array::from_fn(|c| 2.0 * p0[c] - p1[c]) };
    let mut g = [[[0f32; 3]; 4]; 4];
    // Centre columns 0 and 1 (grid offsets), all four rows.
    for c in 0..2 {
        let p0 = get(c as i32, 0).unwrap_or_default();
        let p1 = get(c as i32, 1).unwrap_or_default();
        g[1][c + 1] = p0;
        g[2][c + 1] = p1;
        g[0][c + 1] = get(c as i32, -1).unwrap_or_else(|| extrapolate(&p0, &p1));
        g[3][c + 1] = get(c as i32, 2).unwrap_or_else(|| extrapolate(&p1, &p0));
    }
    // Outer columns, each row.
    for (r, row) in g.iter_mut().enumerate() {
        let (a, b) = (row[1], row[2]);
        row[0] = get(-1, r as i32 - 1).unwrap_or_else(|| extrapolate(&a, &b));
        row[3] = get(2, r as i32 - 1).unwrap_or_else(|| extrapolate(&b, &a));
    }
    g
}

fn weight_table(n: u32) -> [[f32; 4]; MAX_SUBDIVISION as usize + 1] {
    let mut w = [[0f32; 4]; MAX_SUBDIVISION as usize + 1];
    for (a, wa) in w.iter_mut().enumerate().take(n as usize + 1) {
        *wa = weights(a as f32 / n as f32);
    }
    w
}

/// Draws the drawable cells of a `cols × rows` piece with Catmull-Rom
/// patches cut into `nu × nv` (each at most [`MAX_SUBDIVISION`]).
#[allow(clippy::too_many_arguments)] // the piece's geometry and its two subdivisions
pub(crate) fn draw_cells_smooth(
    t: &mut BandTarget<'_>,
    nodes: &[Node],
    cols: usize,
    rows: usize,
    nu: u32,
    nv: u32,
    item: u32,
) {
    let (nu, nv) = (nu.min(MAX_SUBDIVISION), nv.min(MAX_SUBDIVISION));
    let (wu, wv) = (weight_table(nu), weight_table(nv));
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows);
    // The spline can bulge past its cell; allow a margin before rejecting.
    let margin = 2;
    for j in 0..rows - 1 {
        for i in 0..cols - 1 {
            let k = j * cols + i;
            if !cell_drawable(nodes, k, cols) {
                continue;
            }
            let ys = [k, k + 1, k + cols, k + cols + 1].map(|q| nodes[q][1] >> 16);
            if ys.iter().all(|&y| y < y_lo - margin) || ys.iter().all(|&y| y >= y_hi + margin) {
                continue;
            }
            let right = (i + 2 >= cols || !cell_drawable(nodes, k + 1, cols)) as u32;
            let top = (j + 2 >= rows || !cell_drawable(nodes, k + cols, cols)) as u32;
            let g = gather(nodes, cols, rows, i, j);
            for (b, wb) in wv[..(nv + top) as usize].iter().enumerate() {
                // Collapse the rows: one cubic per column.
                let mut q = [[0f32; 3]; 4];
                for (c, qc) in q.iter_mut().enumerate() {
                    for (ch, v) in qc.iter_mut().enumerate() {
                        *v = wb[0] * g[0][c][ch]
                            + wb[1] * g[1][c][ch]
                            + wb[2] * g[2][c][ch]
                            + wb[3] * g[3][c][ch];
                    }
                }
                for (a, wa) in wu[..(nu + right) as usize].iter().enumerate() {
                    let v = |ch: usize| {
                        wa[0] * q[0][ch] + wa[1] * q[1][ch] + wa[2] * q[2][ch] + wa[3] * q[3][ch]
                    };
                    let (x, y) = (v(0) as i32, v(1) as i32);
                    let sub = sub_word(i, j, a as u32, b as u32);
                    splat_sample(t, x >> 16, y >> 16, v(2) as i32, patch_word(sub, item));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_interpolate_and_sum_to_one() {
        assert_eq!(weights(0.0), [0.0, 1.0, 0.0, 0.0]);
        assert_eq!(weights(1.0), [0.0, 0.0, 1.0, 0.0]);
        for k in 0..=10 {
            let s: f32 = weights(k as f32 / 10.0).iter().sum();
            assert!((s - 1.0).abs() < 1e-6);
        }
    }
}
