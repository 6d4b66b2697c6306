//! Bilinear cells drawn by pixel-centre coverage: every sub-cell of the
//! subdivision of [`crate::raster::cell_bilinear`] is a small quad (two
//! triangles) that writes the pixels whose centres it holds, instead of
//! each sub-node writing the pixel that holds it.
//!
//! Why: a sub-node is written to the pixel that holds it, so every pixel a
//! cell's outline touches is written, on average half a pixel past the
//! true outline, where a triangle rasterizer (and the source drawn by one)
//! writes a pixel only when its centre is inside. Inside a surface that
//! reach only meets the neighbouring cell; along a silhouette it draws the
//! surface over the background. Open sides ([`crate::raster::cell_edges`])
//! clip it where a magnified cell's neighbour faces away; this drawer also
//! gets the outline right inside folded cells (the silhouette of a smooth
//! surface runs through cells whose corners turn both ways) and along
//! patch borders (a cap seen edge-on), which open sides cannot tell apart
//! from seams (fuze, unlit, 14 views: pixels only the patches cover 4,413
//! → 210 with no margin; docs/algorithms/render.md, "Pixel-centre
//! outlines").
//!
//! Each sub-quad is grown by [`EXACT_MARGIN_PX`] before its pixel centres
//! are tested. Why: two patches' borders do not quite meet everywhere, and
//! the nodes' bilinear outline lies a little inside the source's; with no
//! margin those showed as pixels only the source covers (fuze 386 → 1,879,
//! holes 0.065 → 0.33 %), with 0.15 px 615 and 0.105 %.
//!
//! A sample records the sub-node at the quad's corner nearest the pixel
//! centre (the resolve interpolates there; the first corner instead cost
//! fuze 0.4 dB, Spot 0.6 dB) and the nearest depth of the quad's corners.
//!
//! Cost: per sub-quad a box of its corners and, per candidate pixel centre
//! (usually none to two), its margins and five edge functions; only pieces
//! that ask for it (patches with colour, under
//! [`crate::RenderOptions::exact_outlines`], [`crate::plan::piece`]) and
//! the folded cells of colour-grid pieces
//! ([`crate::raster::centre_piece`]), whose other cells take one
//! pixel-centre test per centre. fuze's unlit frame: 27.2 M instructions
//! with sub-nodes, 176.7 M with this (callgrind, `--threads 1`, 500²).

use crate::fixed::Node;
use crate::raster::band::{patch_word, splat_sample, BandTarget};
use crate::raster::cell_bilinear::{next_row, setup, Reciprocals, EXT, MAX_SUBDIVISION};

/// How far (pixels, along each edge's normal) a sub-quad is grown before
/// the pixel centres inside it are written (see the module docs).
pub(crate) const EXACT_MARGIN_PX: f32 = 0.15;

/// A sub-node: position in pixels relative to the cell's origin, depth.
#[derive(Debug, Clone, Copy, Default)]
struct SubNode {
    x: f32,
    y: f32,
    z: i32,
}

/// One row of sub-nodes (at most [`MAX_SUBDIVISION`] + 1).
type SubRow = [SubNode; MAX_SUBDIVISION as usize + 1];

/// Draws one cell with corners `c` (`(0,0)`, `(1,0)`, `(0,1)`, `(1,1)`)
/// cut `nu × nv`: each sub-quad writes the pixel centres it holds, grown
/// by [`EXACT_MARGIN_PX`]. The cell places its whole area (no closing
/// column or row is needed: a sub-quad reaches the cell's sides). A
/// sample's place `(a, b)` is recorded shifted left by `shift` (0 for the
/// piece's own cut; a pixel-centre piece records places in sixteenths of
/// its cells and passes `log2(16 / nu)`).
/// Inlined so that it runs with the band's instruction set ([`crate::isa`]).
#[inline(always)]
pub(crate) fn draw_exact_cell(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    r: Reciprocals,
    [nu, nv]: [u32; 2],
    sub0: u32,
    shift: u32,
    item: u32,
) {
    let s = |ch: usize| setup(c[0][ch], c[1][ch], c[2][ch], c[3][ch], r);
    let (sx, sy, sz) = (s(0), s(1), s(2));
    // Whole pixels of the first corner: the rest is small, exact in `f32`.
    let (ox, oy) = (c[0][0] >> 16, c[0][1] >> 16);
    let xy_shift = 16 + EXT;
    let origin = [(ox as i64) << xy_shift, (oy as i64) << xy_shift];
    let scale = 1.0 / (1u64 << xy_shift) as f32;
    let mut start = [sx[0], sy[0], sz[0]];
    let mut step = [sx[2], sy[2], sz[2]];
    let mut rows = [[SubNode::default(); MAX_SUBDIVISION as usize + 1]; 2];
    for b in 0..=nv {
        let row = &mut rows[(b & 1) as usize];
        let mut v = start;
        for node in row.iter_mut().take(nu as usize + 1) {
            *node = SubNode {
                x: (v[0] - origin[0]) as f32 * scale,
                y: (v[1] - origin[1]) as f32 * scale,
                z: (v[2] >> EXT) as i32,
            };
            v[0] += step[0];
            v[1] += step[1];
            v[2] += step[2];
        }
        if b > 0 {
            let (lo, hi) = (&rows[((b - 1) & 1) as usize], &rows[(b & 1) as usize]);
            let word = sub0 + ((b - 1) << shift);
            draw_quad_row(t, [lo, hi], nu, [ox, oy], word, shift, item);
        }
        next_row(&mut start, &mut step, [sx, sy, sz]);
    }
}

/// Draws the `nu` sub-quads between two rows of sub-nodes; `word` is the
/// sub-word of the row's first sub-node, places shifted by `shift`.
#[inline(always)]
fn draw_quad_row(
    t: &mut BandTarget<'_>,
    [lo, hi]: [&SubRow; 2],
    nu: u32,
    origin: [i32; 2],
    word: u32,
    shift: u32,
    item: u32,
) {
    for a in 0..nu as usize {
        let q = [lo[a], lo[a + 1], hi[a], hi[a + 1]];
        let z = q[0].z.min(q[1].z).min(q[2].z).min(q[3].z);
        let sub = word + ((a as u32) << (8 + shift));
        let (x0, x1) = pixel_span(q.map(|p| p.x));
        let (y0, y1) = pixel_span(q.map(|p| p.y));
        // Why: most sub-quads of a cell cut finer than its pixels hold no
        // pixel centre, and the margins cost five square roots.
        if x0 > x1 || y0 > y1 {
            continue;
        }
        let quad = Quad::new(q);
        for py in y0..=y1 {
            for px in x0..=x1 {
                let (x, y) = (px as f32 + 0.5, py as f32 + 0.5);
                if quad.covers(x, y) {
                    let sub = sub + (nearest_corner(&q, x, y) << shift);
                    let word = patch_word(sub, item);
                    splat_sample(t, origin[0] + px, origin[1] + py, z, word);
                }
            }
        }
    }
}

/// The sub-word offset (`a << 8 | b` of 0 or 1 each) of the corner of the
/// sub-quad `q` (`(0,0)`, `(1,0)`, `(0,1)`, `(1,1)`) nearest `(x, y)`: the
/// resolve interpolates there.
#[inline(always)]
fn nearest_corner(q: &[SubNode; 4], x: f32, y: f32) -> u32 {
    let d = |p: SubNode| (p.x - x) * (p.x - x) + (p.y - y) * (p.y - y);
    let (mut best, mut k) = (d(q[0]), 0);
    for (j, &p) in q.iter().enumerate().skip(1) {
        if d(p) < best {
            (best, k) = (d(p), j);
        }
    }
    ((k as u32 & 1) << 8) | (k as u32 >> 1)
}

/// The pixels (relative) whose centres may lie within [`EXACT_MARGIN_PX`]
/// of `[min, max]` of `v`: first and last, inclusive (empty when first >
/// last).
#[inline(always)]
fn pixel_span(v: [f32; 4]) -> (i32, i32) {
    let lo = v[0].min(v[1]).min(v[2]).min(v[3]);
    let hi = v[0].max(v[1]).max(v[2]).max(v[3]);
    (
        (lo - 0.5 - EXACT_MARGIN_PX).ceil() as i32,
        (hi - 0.5 + EXACT_MARGIN_PX).floor() as i32,
    )
}

/// The length of a side `(dx, dy)`, rounded once to `f32`: the squares
/// are exact in `f64`, so only their sum, its root and the conversion
/// round (what glibc's `hypotf` computes for finite values, so the margins
/// are the same bits). Why not `f32::hypot`: a library call per side, five
/// per sub-quad, was a sixth of a Spot frame at 1000² (`perf`).
#[inline(always)]
fn side_length(dx: f32, dy: f32) -> f32 {
    let (x, y) = (f64::from(dx), f64::from(dy));
    (x * x + y * y).sqrt() as f32
}

/// A sub-quad as two triangles `(p00, p10, p11)` and `(p00, p11, p01)`,
/// each side with its margin (its length × [`EXACT_MARGIN_PX`]).
struct Quad {
    p: [SubNode; 4],
    /// Margins of the sides p00→p10, p10→p11, p11→p00, p11→p01, p01→p00.
    m: [f32; 5],
}

impl Quad {
    #[inline(always)]
    fn new(q: [SubNode; 4]) -> Quad {
        let len = |a: SubNode, b: SubNode| side_length(b.x - a.x, b.y - a.y) * EXACT_MARGIN_PX;
        Quad {
            p: q,
            m: [
                len(q[0], q[1]),
                len(q[1], q[3]),
                len(q[3], q[0]),
                len(q[3], q[2]),
                len(q[2], q[0]),
            ],
        }
    }

    /// True when `(x, y)` lies in either triangle grown by the margin
    /// (either orientation: a folded cell's sub-quads turn both ways).
    #[inline(always)]
    fn covers(&self, x: f32, y: f32) -> bool {
        let e = |a: SubNode, b: SubNode| (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
        let [p00, p10, p01, p11] = self.p;
        let diagonal = e(p11, p00);
        let in_tri = |e0: f32, e1: f32, e2: f32, m: [f32; 3]| {
            (e0 >= -m[0] && e1 >= -m[1] && e2 >= -m[2]) || (e0 <= m[0] && e1 <= m[1] && e2 <= m[2])
        };
        let m = self.m;
        in_tri(e(p00, p10), e(p10, p11), diagonal, [m[0], m[1], m[2]])
            || in_tri(-diagonal, e(p11, p01), e(p01, p00), [m[2], m[3], m[4]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::{test_node as node, Z_FAR};
    use crate::raster::band::{Sample, PATCH_SAMPLE};
    use crate::test_rng::XorShift;

    #[test]
    fn side_lengths_are_the_library_hypotenuse() {
        // glibc's `hypotf` is this computation; other C libraries may
        // round differently by an ulp.
        let ulps = if cfg!(all(target_os = "linux", target_env = "gnu")) {
            0
        } else {
            1
        };
        let mut rng = XorShift(0x51de_1e96);
        for k in 0..20_000 {
            let scale = [1e-3f32, 0.5, 3.0, 40.0][k % 4];
            let dx = (rng.unit() - 0.5) * scale;
            let dy = (rng.unit() - 0.5) * scale;
            let (ours, lib) = (side_length(dx, dy), dx.hypot(dy));
            let apart = ours.to_bits().abs_diff(lib.to_bits());
            assert!(apart <= ulps, "{dx} {dy}: {ours} against {lib}");
        }
    }

    /// Draws one cell with corners `q` (ring order) cut `cut × cut` into a
    /// `w × w` image; the covered pixels.
    fn draw(q: [(f32, f32); 4], cut: u32, w: usize) -> Vec<Sample> {
        let mut px = vec![Sample::EMPTY; w * w];
        let mut t = BandTarget::new(&mut px, w as i32, 0, w as i32);
        let n = [
            node(q[0].0, q[0].1),
            node(q[1].0, q[1].1),
            node(q[3].0, q[3].1),
            node(q[2].0, q[2].1),
        ];
        let r = Reciprocals::new(cut, cut);
        draw_exact_cell(
            &mut t,
            [&n[0], &n[1], &n[2], &n[3]],
            r,
            [cut, cut],
            0,
            0,
            PATCH_SAMPLE,
        );
        px
    }

    /// Signed distance (pixels) of `(x, y)` inside the convex quad `q`
    /// (ring order, either orientation): positive inside.
    fn inside_by(q: [(f32, f32); 4], x: f32, y: f32) -> f32 {
        let side = |a: (f32, f32), b: (f32, f32)| {
            let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
            ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) / len
        };
        let area: f32 = (0..4)
            .map(|k| q[k].0 * q[(k + 1) % 4].1 - q[(k + 1) % 4].0 * q[k].1)
            .sum();
        (0..4)
            .map(|k| area.signum() * side(q[k], q[(k + 1) % 4]))
            .fold(f32::MAX, f32::min)
    }

    /// True when the quad `q` (ring order) turns one way at every corner.
    fn convex(q: [(f32, f32); 4]) -> bool {
        let turn = |k: usize| {
            let (a, b, c) = (q[k], q[(k + 1) % 4], q[(k + 2) % 4]);
            (b.0 - a.0) * (c.1 - b.1) - (b.1 - a.1) * (c.0 - b.0)
        };
        let t = [turn(0), turn(1), turn(2), turn(3)];
        t.iter().all(|&v| v > 0.0) || t.iter().all(|&v| v < 0.0)
    }

    #[test]
    fn a_convex_cell_covers_the_pixel_centres_inside_it_and_few_past_the_margin() {
        let mut rng = XorShift(0xce11_e8ac);
        let w = 40;
        let (mut inside, mut outside, mut margin, mut far, mut worst) = (0, 0, 0, 0, 0f32);
        let mut nearest = 0f32;
        for _ in 0..200 {
            let (q, s) = rng.jittered_square(3.0, 15.0);
            if !convex(q) {
                continue;
            }
            let cut = (s + 9.0).ceil() as u32;
            let samples = draw(q, cut, w);
            let covered: Vec<bool> = samples.iter().map(|s| s.depth < Z_FAR).collect();
            // Where the recorded sub-node lies: the corner of its sub-quad
            // nearest the pixel centre, within half a sub-quad's diagonal.
            let at = |word: u32| {
                let (u, v) = (
                    ((word >> 8) & 255) as f32 / cut as f32,
                    (word & 255) as f32 / cut as f32,
                );
                let mix = |k: usize| {
                    let c = [q[0], q[1], q[3], q[2]].map(|p| if k == 0 { p.0 } else { p.1 });
                    (1.0 - u) * (1.0 - v) * c[0]
                        + u * (1.0 - v) * c[1]
                        + (1.0 - u) * v * c[2]
                        + u * v * c[3]
                };
                (mix(0), mix(1))
            };
            for (k, sample) in samples.iter().enumerate().filter(|(k, _)| covered[*k]) {
                let (x, y) = at(sample.w0());
                let (cx, cy) = ((k % w) as f32 + 0.5, (k / w) as f32 + 0.5);
                nearest = nearest.max((x - cx).hypot(y - cy));
            }
            for y in 0..w {
                for x in 0..w {
                    let d = inside_by(q, x as f32 + 0.5, y as f32 + 0.5);
                    if d > 0.01 {
                        inside += 1;
                        assert!(covered[y * w + x], "hole at {x},{y}");
                    } else if d < -0.01 {
                        outside += 1;
                        if covered[y * w + x] {
                            margin += 1;
                            worst = worst.max(-d);
                            far += (d < -(EXACT_MARGIN_PX + 0.01)) as usize;
                        }
                    }
                }
            }
        }
        // 0.49 px here; a sub-quad's far corner lies up to about 0.9 px away.
        assert!(nearest < 0.6, "shaded {nearest} px from the pixel centre");
        assert!(inside > 5_000 && outside > 100_000, "{inside} {outside}");
        // The margin writes some pixels just outside (1,217 here), a few of
        // them (53) farther than the margin where a sub-triangle's corner
        // is acute, but none as far as the sub-nodes' reach (up to 0.7 px).
        assert!(margin > 500 && far * 10 < margin, "{margin} {far}");
        assert!(
            worst < 2.0 * EXACT_MARGIN_PX,
            "written {worst} px past the outline"
        );
    }
}
