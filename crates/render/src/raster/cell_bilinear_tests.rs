//! Tests of the bilinear cell drawer (`raster::cell_bilinear`): the
//! hole-free property on random pieces (see that module's header), a
//! magnified cell, the unclipped row path against the clipped one, and the
//! fixed-cut copies against the generic kernel.

use crate::fixed::{test_node as node, Node, Z_FAR};
use crate::grid::{CELL_DRAW, CELL_RIGHT, CELL_TOP};
use crate::plan::subdivision::{choose_subdivision, SUBPIXEL_LIMIT};
use crate::raster::band::{BandTarget, Sample, PATCH_SAMPLE};
use crate::raster::cell_bilinear::{draw_cells, draw_cells_bilinear, draw_nodes, BilinearPiece};

/// Per row of cells of a piece of `cols`-node rows, the pixel rows its
/// nodes span (`[lo, hi]`), and whether every node lies strictly inside
/// the `w` columns of the image (the unclipped row path's contract).
fn row_spans(nodes: &[Node], cols: usize, crows: usize, w: usize) -> (Vec<[i32; 2]>, bool) {
    let spans = (0..crows)
        .map(|j| {
            let ys = nodes[j * cols..(j + 2) * cols].iter().map(|n| n[1] >> 16);
            [ys.clone().min().unwrap(), ys.max().unwrap()]
        })
        .collect();
    let x = nodes.iter().map(|n| n[0] >> 16);
    let inside_columns = x.clone().min().unwrap() > 0 && x.max().unwrap() < w as i32 - 1;
    (spans, inside_columns)
}

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
        let flags = crate::test_rng::random_drawn_cells(&mut rng, ccols, crows, 8);
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
        let Some((nu, nv)) = choose_subdivision(edges, SUBPIXEL_LIMIT) else {
            continue;
        };
        cut += (nu * nv > 1) as usize;
        let (spans, inside_columns) = row_spans(&nodes, cols, crows, w);
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
            let mut t =
                BandTarget::new(px, w as i32, (b * band_rows) as i32, (px.len() / w) as i32);
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

#[test]
fn a_magnified_cell_covers_every_pixel_centre_inside_it() {
    // One skewed cell spanning about 20 pixels.
    let nodes = [
        node(2.3, 3.1),
        node(21.7, 5.2),
        node(4.0, 19.9),
        node(18.2, 22.4),
    ];
    let (w, h) = (32, 32);
    let mut px = vec![Sample::EMPTY; w * h];
    let mut t = BandTarget::new(&mut px, w as i32, 0, h as i32);
    // Extents: |u_x| + |v_x| and |u_y| + |v_y| are below 22 px, so 24 is safe.
    let flags = [CELL_DRAW | CELL_RIGHT | CELL_TOP];
    let spans = [[0, 31]];
    let piece = BilinearPiece {
        nodes: &nodes,
        flags: &flags,
        spans: &spans,
        cols: 2,
        rows: 2,
        inside_columns: false,
    };
    draw_cells_bilinear(&mut t, &piece, 24, 24, PATCH_SAMPLE);
    // Every pixel centre strictly inside the quad (two triangles) is drawn.
    let inside = |px: f32, py: f32| {
        let tri = |a: (f32, f32), b: (f32, f32), c: (f32, f32)| {
            let e =
                |p: (f32, f32), q: (f32, f32)| (q.0 - p.0) * (py - p.1) - (q.1 - p.1) * (px - p.0);
            let (s0, s1, s2) = (e(a, b), e(b, c), e(c, a));
            (s0 > 0.2 && s1 > 0.2 && s2 > 0.2) || (s0 < -0.2 && s1 < -0.2 && s2 < -0.2)
        };
        let p = |k: usize| (nodes[k][0] as f32 / 65536.0, nodes[k][1] as f32 / 65536.0);
        tri(p(0), p(1), p(3)) || tri(p(0), p(3), p(2))
    };
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            if inside(x as f32 + 0.5, y as f32 + 0.5) {
                checked += 1;
                assert!(px[y * w + x].depth < Z_FAR, "hole at {x},{y}");
            }
        }
    }
    assert!(checked > 250);
}

#[test]
fn rows_inside_a_band_draw_as_the_clipped_path_does() {
    // Random jittered pieces near the image's and the bands' edges, some
    // cells undrawn: the unclipped row path must give the same samples
    // as the per-cell boxes (which clip), and never write out of band.
    let mut rng = crate::test_rng::XorShift(0x5eed_ce11);
    let (w, h) = (48usize, 48usize);
    let mut rows_taken = 0;
    for _ in 0..400 {
        let (cols, rows) = (2 + rng.below(5) as usize, 2 + rng.below(5) as usize);
        let step = 0.6 + 2.0 * rng.unit();
        let (ox, oy) = (1.5 + 30.0 * rng.unit(), 1.5 + 30.0 * rng.unit());
        let nodes: Vec<Node> = (0..cols * rows)
            .map(|k| {
                let (i, j) = ((k % cols) as f32, (k / cols) as f32);
                let jitter = |r: &mut crate::test_rng::XorShift| 0.4 * (r.unit() - 0.5);
                node(
                    ox + step * i + jitter(&mut rng),
                    oy + step * j + jitter(&mut rng),
                )
            })
            .collect();
        let (ccols, crows) = (cols - 1, rows - 1);
        let flags = crate::test_rng::random_drawn_cells(&mut rng, ccols, crows, 6);
        let (spans, inside_columns) = row_spans(&nodes, cols, crows, w);
        let (y0, band_rows) = (rng.below(40) as i32, 4 + rng.below(20) as i32);
        let band_rows = band_rows.min(h as i32 - y0);
        let draw = |inside_columns: bool| {
            let mut px = vec![Sample::EMPTY; w * band_rows as usize];
            let mut t = BandTarget::new(&mut px, w as i32, y0, band_rows);
            let piece = BilinearPiece {
                nodes: &nodes,
                flags: &flags,
                spans: &spans,
                cols,
                rows,
                inside_columns,
            };
            draw_cells_bilinear(&mut t, &piece, 2, 3, PATCH_SAMPLE);
            px.iter()
                .map(|s| (s.depth, s.w0(), s.w2()))
                .collect::<Vec<_>>()
        };
        if inside_columns {
            rows_taken += spans
                .iter()
                .filter(|&&[lo, hi]| lo > y0 && hi < y0 + band_rows - 1)
                .count();
        }
        assert_eq!(draw(inside_columns), draw(false));
    }
    assert!(rows_taken > 200, "the row path ran for {rows_taken} rows");
}

#[test]
fn the_fixed_cut_copies_draw_what_the_generic_kernel_draws() {
    // Random jittered pieces with varied depths and undrawn cells, each
    // fixed cut against the generic copy (cuts at run time): the same
    // samples, payloads and depth-test winners.
    let mut rng = crate::test_rng::XorShift(0x0c07_5eed);
    let w = 40usize;
    let cuts = [
        (1, 2),
        (2, 1),
        (2, 2),
        (2, 3),
        (3, 2),
        (3, 3),
        (4, 1),
        (4, 2),
        (2, 4),
        (3, 1),
        (1, 3),
    ];
    let mut drawn = 0;
    for round in 0..600 {
        let (nu, nv) = cuts[round % cuts.len()];
        let (cols, rows) = (2 + rng.below(5) as usize, 2 + rng.below(5) as usize);
        let step = 0.5 + 2.5 * rng.unit();
        let (ox, oy) = (-2.0 + 30.0 * rng.unit(), -2.0 + 30.0 * rng.unit());
        let nodes: Vec<Node> = (0..cols * rows)
            .map(|k| {
                let (i, j) = ((k % cols) as f32, (k / cols) as f32);
                let jitter = 0.5 * (rng.unit() - 0.5);
                let mut n = node(ox + step * (i + 0.3 * j) + jitter, oy + step * j);
                n[2] = rng.below(1 << 20) as i32;
                n
            })
            .collect();
        let (ccols, crows) = (cols - 1, rows - 1);
        let flags = crate::test_rng::random_drawn_cells(&mut rng, ccols, crows, 5);
        let spans = vec![[-10, 60]; crows];
        let piece = BilinearPiece {
            nodes: &nodes,
            flags: &flags,
            spans: &spans,
            cols,
            rows,
            inside_columns: false,
        };
        let (y0, band_rows) = (rng.below(20) as i32, 10 + rng.below(20) as i32);
        let draw = |fixed: bool| {
            let mut px = vec![Sample::EMPTY; w * band_rows as usize];
            let mut t = BandTarget::new(&mut px, w as i32, y0, band_rows);
            if fixed {
                draw_cells_bilinear(&mut t, &piece, nu, nv, PATCH_SAMPLE);
            } else {
                draw_cells::<0, 0, false>(&mut t, &piece, nu, nv, PATCH_SAMPLE);
            }
            px
        };
        let (fixed, generic) = (draw(true), draw(false));
        drawn += fixed.iter().filter(|s| s.depth < Z_FAR).count();
        assert_eq!(fixed, generic, "cut {nu} x {nv}, round {round}");
    }
    assert!(drawn > 5_000, "{drawn} samples compared");
}

#[test]
fn the_row_walk_places_the_samples_of_the_per_cell_kernel() {
    // Random jittered pieces cut as the row walk's copies are (1 x 2,
    // 2 x 1, 2 x 2, 4 x 1, 4 x 2, 2 x 4), some cells undrawn,
    // with depths that grow (or shrink) along the sub-node grid so that no
    // two samples tie: whatever the drawing order, every pixel keeps the
    // same sample only if both kernels place the same samples (positions,
    // depths, sub-words). The row walk runs for the rows inside the band;
    // the per-cell kernel (`draw_cells::<0, 0, false>`) draws every row.
    let mut rng = crate::test_rng::XorShift(0x0a1c_3a1c);
    let (w, h) = (64usize, 64usize);
    let cuts = [(1, 2), (2, 1), (2, 2), (4, 1), (4, 2), (2, 4)];
    let (mut walked, mut drawn) = (0, 0);
    for round in 0..1500 {
        let (nu, nv) = cuts[round % cuts.len()];
        let (cols, rows) = (2 + rng.below(7) as usize, 2 + rng.below(7) as usize);
        let step = 0.5 + 2.0 * rng.unit();
        let (ox, oy) = (2.0 + 30.0 * rng.unit(), 2.0 + 30.0 * rng.unit());
        let shear = 0.6 * (rng.unit() - 0.5);
        let sign = if round % 2 == 0 { 1 } else { -1 };
        let nodes: Vec<Node> = (0..cols * rows)
            .map(|k| {
                let (i, j) = (k % cols, k / cols);
                let jitter = |r: &mut crate::test_rng::XorShift| 0.6 * (r.unit() - 0.5);
                let (x, y) = (step * i as f32, step * j as f32);
                let mut n = node(
                    ox + x + shear * y + jitter(&mut rng),
                    oy + y + jitter(&mut rng),
                );
                // Sub-node (a, b) of cell (i, j) gets depth
                // 1024 (nu i + a) + nv j + b (times `sign`, from 2^20).
                n[2] = (1 << 20) + sign * (1024 * (nu * i) as i32 + (nv * j) as i32);
                n
            })
            .collect();
        let (ccols, crows) = (cols - 1, rows - 1);
        let flags = crate::test_rng::random_drawn_cells(&mut rng, ccols, crows, 5);
        let (spans, inside_columns) = row_spans(&nodes, cols, crows, w);
        let piece = BilinearPiece {
            nodes: &nodes,
            flags: &flags,
            spans: &spans,
            cols,
            rows,
            inside_columns,
        };
        let (y0, band_rows) = (rng.below(30) as i32, 8 + rng.below(40) as i32);
        let band_rows = band_rows.min(h as i32 - y0);
        let draw = |walk: bool| {
            let mut px = vec![Sample::EMPTY; w * band_rows as usize];
            let mut t = BandTarget::new(&mut px, w as i32, y0, band_rows);
            if walk {
                draw_cells_bilinear(&mut t, &piece, nu as u32, nv as u32, PATCH_SAMPLE);
            } else {
                draw_cells::<0, 0, false>(&mut t, &piece, nu as u32, nv as u32, PATCH_SAMPLE);
            }
            px
        };
        if inside_columns {
            walked += spans
                .iter()
                .filter(|&&[lo, hi]| lo > y0 && hi < y0 + band_rows - 1)
                .count();
        }
        let (walk, cells) = (draw(true), draw(false));
        drawn += walk.iter().filter(|s| s.depth < Z_FAR).count();
        assert_eq!(walk, cells, "cut {nu} x {nv}, round {round}");
    }
    assert!(
        walked > 1500 && drawn > 10_000,
        "{walked} rows walked, {drawn} samples"
    );
}
