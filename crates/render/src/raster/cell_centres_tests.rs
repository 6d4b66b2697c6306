//! Tests of the pixel-centre cell kernel ([`super::cell_centres`]): every
//! pixel centre inside a cell written once, places within half a step,
//! depths within the corners.

use super::band::BandTarget;
use super::cell_centres::*;
use crate::fixed::{test_node as node, Node, Z_FAR};
use crate::raster::band::{Sample, PATCH_SAMPLE};
use crate::test_rng::XorShift;

/// A `w × w` band of empty samples.
fn band(w: usize) -> Vec<Sample> {
    vec![Sample::EMPTY; w * w]
}

fn target(px: &mut [Sample], w: usize) -> BandTarget<'_> {
    BandTarget::new(px, w as i32, 0, w as i32)
}

/// `outline` sides pushed out by the pixel-sized cells' margin.
fn sides(outline: u8) -> Sides {
    Sides {
        outline,
        margin: CELL_MARGIN,
    }
}

#[test]
fn a_jittered_lattice_of_cells_writes_every_pixel_centre_inside_once() {
    // Lattices of cells of 0.4–3 px with corners jittered by up to a
    // fifth of a cell, some on exact pixel centres and lines, some
    // mirrored: each cell drawn alone, the writes counted per pixel.
    let mut rng = XorShift(0xce17_7e55);
    let w = 40usize;
    let (mut checked, mut on_lines) = (0, 0);
    for round in 0..300 {
        let n = 3 + rng.below(10) as usize;
        let mirror = round % 3 == 0;
        let snap = round % 4 == 0;
        // Snapped lattices take cells of 2-3 px, so that neither the
        // jitter nor the snap folds a cell.
        let step = if snap {
            2.0 + rng.unit()
        } else {
            0.4 + 2.6 * rng.unit()
        };
        let pos = |i: usize, j: usize, r: &mut XorShift| {
            let jit = |r: &mut XorShift| step * 0.4 * (r.unit() - 0.5);
            let (mut x, mut y) = (
                2.0 + step * i as f32 + jit(r),
                2.0 + step * j as f32 + jit(r),
            );
            if snap {
                // On pixel centres and pixel lines, in halves.
                (x, y) = ((x * 2.0).round() / 2.0, (y * 2.0).round() / 2.0);
            }
            if mirror {
                x = 38.0 - x;
            }
            node(x, y)
        };
        let nodes: Vec<Node> = (0..(n + 1) * (n + 1))
            .map(|k| pos(k % (n + 1), k / (n + 1), &mut rng))
            .collect();
        let mut count = vec![0u32; w * w];
        for j in 0..n {
            for i in 0..n {
                let k = j * (n + 1) + i;
                let c = [
                    &nodes[k],
                    &nodes[k + 1],
                    &nodes[k + n + 1],
                    &nodes[k + n + 2],
                ];
                let mut px = band(w);
                draw_cell(&mut target(&mut px, w), c, sides(0), 0, PATCH_SAMPLE);
                for (n, s) in count.iter_mut().zip(&px) {
                    *n += (s.depth < Z_FAR) as u32;
                }
            }
        }
        // Inside the lattice's outline (its border nodes' inner hull,
        // shrunk by the jitter), every centre is written exactly once.
        let (lo, hi) = (2.0 + step * 0.3, 2.0 + step * (n as f32 - 0.3));
        for y in 0..w {
            for x in 0..w {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                let cx = if mirror { 38.0 - cx } else { cx };
                if cx > lo && cx < hi && cy > lo && cy < hi {
                    checked += 1;
                    on_lines += snap as usize;
                    assert_eq!(count[y * w + x], 1, "pixel {x},{y} round {round}");
                }
                assert!(count[y * w + x] <= 1, "double write {x},{y} round {round}");
            }
        }
    }
    assert!(checked > 20_000 && on_lines > 3_000, "{checked} {on_lines}");
}

#[test]
fn lazy_cells_write_the_pixels_places_and_depths_of_the_general_set_up() {
    // Jittered cells of 0.3-3 px, some snapped to pixel centres and
    // lines (ties for the top-left rule), some mirrored, some folded
    // (those take the general path in both), one in two with random
    // outline sides: the lazy set-up writes the same pixel set with
    // the same places as the plain per-centre test of six set-up
    // edges, depths within a unit.
    let mut rng = XorShift(0x1a7e_c0de);
    let w = 16usize;
    let (mut written, mut cells, mut grown) = (0, 0, 0);
    for round in 0..4000 {
        let len = 0.3 + 2.7 * rng.unit();
        let (x, y) = (5.0 + 4.0 * rng.unit(), 5.0 + 4.0 * rng.unit());
        let mut pos = |i: f32, j: f32| {
            let jit = |r: &mut XorShift| len * 0.6 * (r.unit() - 0.5);
            let (mut px, mut py) = (x + len * i + jit(&mut rng), y + len * j + jit(&mut rng));
            if round % 3 == 0 {
                (px, py) = ((px * 2.0).round() / 2.0, (py * 2.0).round() / 2.0);
            }
            if round % 4 == 1 {
                px = 20.0 - px;
            }
            node(px, py)
        };
        let mut c = [pos(0.0, 0.0), pos(1.0, 0.0), pos(0.0, 1.0), pos(1.0, 1.0)];
        for (k, n) in c.iter_mut().enumerate() {
            n[2] = 5000 + 7919 * k as i32 + rng.below(3000) as i32;
        }
        let c = [&c[0], &c[1], &c[2], &c[3]];
        let outline = if round % 2 == 0 {
            rng.below(16) as u8
        } else {
            0
        };
        let (mut fast, mut plain) = (band(w), band(w));
        draw_cell(
            &mut target(&mut fast, w),
            c,
            sides(outline),
            0,
            PATCH_SAMPLE,
        );
        draw_cell_general(
            &mut target(&mut plain, w),
            c,
            sides(outline),
            0,
            PATCH_SAMPLE,
        );
        for (k, (f, p)) in fast.iter().zip(&plain).enumerate() {
            let at = (k % w, k / w, round);
            assert_eq!(f.depth < Z_FAR, p.depth < Z_FAR, "pixel set {at:?}");
            if f.depth < Z_FAR {
                assert_eq!(f.w0(), p.w0(), "place {at:?}");
                assert!((f.depth - p.depth).abs() <= 1, "depth {at:?}");
                written += 1;
            }
        }
        cells += Lazy::<true>::new(c, outline, CELL_MARGIN).is_some() as usize;
        grown += (outline != 0) as usize;
    }
    assert!(
        written > 5_000 && cells > 2_500 && grown > 1_500,
        "{written} {cells} {grown}"
    );
}

#[test]
fn sliver_cells_on_an_outline_keep_their_depth_within_their_corners() {
    // Cells with a corner a few position units off a side (triangles
    // of an area of a few units), every side pushed out: the margin
    // takes centres where the weights are huge; depths stay within
    // the corners' (they overflowed before).
    let mut rng = XorShift(0x5117e5);
    let w = 16usize;
    let mut written = 0;
    for _ in 0..400 {
        let (x, y) = (4.0 + 4.0 * rng.unit(), 4.0 + 4.0 * rng.unit());
        let len = 1.0 + 3.0 * rng.unit();
        let mut c = [
            node(x, y),
            node(x + len, y),
            node(x, y + len),
            node(x + len, y + len),
        ];
        // c11 onto the diagonal c00-c10 extended, a unit or two off.
        c[3][0] = c[1][0] + (c[1][0] - c[0][0]);
        c[3][1] = c[0][1] + rng.below(3) as i32;
        for (k, n) in c.iter_mut().enumerate() {
            n[2] = 1000 + 100_000 * k as i32;
        }
        let mut px = band(w);
        let all = BOTTOM | RIGHT | TOP | LEFT;
        draw_cell(
            &mut target(&mut px, w),
            [&c[0], &c[1], &c[2], &c[3]],
            sides(all),
            0,
            PATCH_SAMPLE,
        );
        for s in px.iter().filter(|s| s.depth < Z_FAR) {
            assert!((1000..=301_000).contains(&s.depth), "{}", s.depth);
            written += 1;
        }
    }
    assert!(written > 1_000, "{written}");
}

#[test]
fn a_pixel_records_its_place_in_the_cell_within_half_a_step() {
    // Parallelograms: the bilinear map is affine, so the place of a
    // pixel centre is known exactly; the depth too.
    let mut rng = XorShift(0x91ace5);
    let w = 24usize;
    let mut written = 0;
    for _ in 0..600 {
        let o = (4.0 + 8.0 * rng.unit(), 4.0 + 8.0 * rng.unit());
        let u = (0.5 + 3.0 * rng.unit(), 2.0 * (rng.unit() - 0.5));
        let v = (2.0 * (rng.unit() - 0.5), 0.5 + 3.0 * rng.unit());
        let mut c = [
            node(o.0, o.1),
            node(o.0 + u.0, o.1 + u.1),
            node(o.0 + v.0, o.1 + v.1),
            node(o.0 + u.0 + v.0, o.1 + u.1 + v.1),
        ];
        let z = [1000, 50_000, 90_000, 139_000];
        for k in 0..4 {
            c[k][2] = z[k];
        }
        let mut px = band(w);
        draw_cell(
            &mut target(&mut px, w),
            [&c[0], &c[1], &c[2], &c[3]],
            sides(0),
            0,
            PATCH_SAMPLE,
        );
        // Inverse of the affine map, from the nodes as drawn.
        let f = |n: &Node| (n[0] as f32 / 65536.0, n[1] as f32 / 65536.0);
        let (p0, p1, p2) = (f(&c[0]), f(&c[1]), f(&c[2]));
        let (ux, uy, vx, vy) = (p1.0 - p0.0, p1.1 - p0.1, p2.0 - p0.0, p2.1 - p0.1);
        let det = ux * vy - uy * vx;
        for (k, s) in px.iter().enumerate().filter(|(_, s)| s.depth < Z_FAR) {
            let (dx, dy) = ((k % w) as f32 + 0.5 - p0.0, (k / w) as f32 + 0.5 - p0.1);
            let (su, sv) = ((dx * vy - dy * vx) / det, (ux * dy - uy * dx) / det);
            let steps = CENTRE_STEPS as f32;
            let (a, b) = (((s.w0() >> 8) & 255) as f32, (s.w0() & 255) as f32);
            assert!((a - su * steps).abs() < 0.52, "u {su} recorded {a}");
            assert!((b - sv * steps).abs() < 0.52, "v {sv} recorded {b}");
            let depth = 1000.0 + 49_000.0 * su + 89_000.0 * sv;
            assert!((s.depth as f32 - depth).abs() < 8.0, "{} {depth}", s.depth);
            written += 1;
        }
    }
    assert!(written > 2_000, "{written}");
}
