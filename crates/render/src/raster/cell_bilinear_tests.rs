//! The hole-free property of the bilinear cell drawer on random pieces
//! (see the module header of `raster::cell_bilinear`): every pixel centre
//! inside a drawn cell receives a sample.

use crate::fixed::{test_node as node, Node, Z_FAR};
use crate::grid::{close_cells, CELL_DRAW};
use crate::plan::subdivision::choose_subdivision;
use crate::raster::band::{BandTarget, Sample, PATCH_SAMPLE};
use crate::raster::cell_bilinear::{draw_cells_bilinear, draw_nodes, BilinearPiece};

/// Whether pixel centre `(x, y)` lies inside the strictly convex quad
/// with corners `q` (`[c00, c10, c01, c11]`) by more than `margin`
/// pixels; `None` when the quad is not strictly convex.
fn inside_quad(q: [(f32, f32); 4], x: f32, y: f32, margin: f32) -> Option<bool> {
    let ring = [q[0], q[1], q[3], q[2]];
    let (mut sign, mut inside) = (0.0f32, true);
    for k in 0..4 {
        let (a, b, c) = (ring[k], ring[(k + 1) % 4], ring[(k + 2) % 4]);
        let turn = (b.0 - a.0) * (c.1 - b.1) - (b.1 - a.1) * (c.0 - b.0);
        if turn.abs() < 1e-6 || (sign != 0.0 && turn.signum() != sign) {
            return None;
        }
        sign = turn.signum();
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let side = ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) / len;
        inside &= side * sign > margin;
    }
    Some(inside)
}

#[test]
fn random_pieces_leave_no_hole_inside_any_drawn_cell() {
    // Random sheared pieces whose cells range from a third of a pixel to
    // about three pixels, some cells undrawn, cut as planning cuts them
    // (`choose_subdivision` on the drawn cells' largest edges) and drawn
    // in bands of random height (clipped and unclipped cells): every
    // pixel centre inside a drawn cell's footprint (the convex quad of
    // its corners) gets a sample. A sub-cell limit of 1.3 px instead of
    // `SUBPIXEL_LIMIT` makes this fail.
    let mut rng = crate::test_rng::XorShift(0xc0_7c07);
    let (w, h) = (64usize, 64usize);
    let (mut checked, mut cut) = (0, 0);
    for round in 0..1500 {
        let (cols, rows) = (2 + rng.below(7) as usize, 2 + rng.below(7) as usize);
        let steps = |r: &mut crate::test_rng::XorShift, n: usize| {
            let mut at = vec![0.0f32];
            for _ in 1..n {
                let last = *at.last().unwrap();
                at.push(last + 0.3 + 2.7 * r.unit() * r.unit());
            }
            at
        };
        let (xs, ys) = (steps(&mut rng, cols), steps(&mut rng, rows));
        let (ox, oy) = (1.0 + 20.0 * rng.unit(), 1.0 + 20.0 * rng.unit());
        let shear = 0.5 * (rng.unit() - 0.5);
        let pos: Vec<(f32, f32)> = (0..cols * rows)
            .map(|k| {
                let (i, j) = (k % cols, k / cols);
                let jitter = 0.15 * (rng.unit() - 0.5);
                (
                    ox + xs[i] + shear * ys[j] + jitter,
                    oy + ys[j] + shear * xs[i],
                )
            })
            .collect();
        let nodes: Vec<Node> = pos.iter().map(|&(x, y)| node(x, y)).collect();
        let (ccols, crows) = (cols - 1, rows - 1);
        let mut flags: Vec<u8> = (0..ccols * crows)
            .map(|_| if rng.below(8) == 0 { 0 } else { CELL_DRAW })
            .collect();
        close_cells(&mut flags, ccols, crows);
        let drawn: Vec<usize> = (0..flags.len())
            .filter(|&k| flags[k] & CELL_DRAW != 0)
            .map(|k| k / ccols * cols + k % ccols)
            .collect();
        let mut edges = [0f32; 4];
        for &n in &drawn {
            let d = |a: usize, b: usize, ch: usize| (nodes[b][ch] - nodes[a][ch]).abs();
            let e = [
                d(n, n + 1, 0).max(d(n + cols, n + cols + 1, 0)),
                d(n, n + 1, 1).max(d(n + cols, n + cols + 1, 1)),
                d(n, n + cols, 0).max(d(n + 1, n + cols + 1, 0)),
                d(n, n + cols, 1).max(d(n + 1, n + cols + 1, 1)),
            ];
            for (m, v) in edges.iter_mut().zip(e) {
                *m = m.max(v as f32 / 65536.0);
            }
        }
        let Some((nu, nv)) = choose_subdivision(edges, 1.0) else {
            continue;
        };
        cut += (nu * nv > 1) as usize;
        let spans: Vec<[i32; 2]> = (0..crows)
            .map(|j| {
                let ys = nodes[j * cols..(j + 2) * cols].iter().map(|n| n[1] >> 16);
                [ys.clone().min().unwrap(), ys.max().unwrap()]
            })
            .collect();
        let x = nodes.iter().map(|n| n[0] >> 16);
        let inside_columns = x.clone().min().unwrap() > 0 && x.max().unwrap() < w as i32 - 1;
        let piece = BilinearPiece {
            nodes: &nodes,
            flags: &flags,
            spans: &spans,
            cols,
            rows,
            // The unclipped row path only where its contract holds.
            inside_columns: round % 2 == 0 && inside_columns,
        };
        let band_rows = 3 + rng.below(30) as usize;
        let mut image = vec![Sample::EMPTY; w * h];
        for (b, px) in image.chunks_mut(band_rows * w).enumerate() {
            let mut t = BandTarget {
                width: w as i32,
                y0: (b * band_rows) as i32,
                rows: (px.len() / w) as i32,
                px,
            };
            if (nu, nv) == (1, 1) {
                draw_nodes(&mut t, &nodes, cols, rows, PATCH_SAMPLE);
            } else {
                draw_cells_bilinear(&mut t, &piece, nu, nv, PATCH_SAMPLE);
            }
        }
        for &n in &drawn {
            let quad = [pos[n], pos[n + 1], pos[n + cols], pos[n + cols + 1]];
            for (y, x) in (0..h).flat_map(|y| (0..w).map(move |x| (y, x))) {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                if inside_quad(quad, cx, cy, 1e-3) == Some(true) {
                    checked += 1;
                    let hole = image[y * w + x].depth == Z_FAR;
                    assert!(!hole, "hole at {x},{y}: round {round}, cut {nu} x {nv}");
                }
            }
        }
    }
    assert!(
        checked > 15_000 && cut > 500,
        "{checked} centres, {cut} cut pieces"
    );
}
