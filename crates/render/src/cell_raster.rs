//! Strongly magnified bilinear cells drawn by the pixel centres they cover.
//!
//! The subdivision of [`crate::cell_bilinear`] needs sub-cells under a pixel
//! in x and in y, with whole numbers of them, so a cell turned 45° gets about
//! twice as many samples as it covers pixels. For pieces cut into at least
//! [`RASTER_MIN_SUB_CELLS`] sub-cells per cell (cells of ≳ 7 px) the
//! subdivision stops at the cell and the cell's footprint is covered by pixel
//! centres instead: one sample per pixel centre inside it. DESIGN §5 item 5
//! ("recursive subdivision until sub-pixel") still describes the smaller
//! cells; these large ones are scan-converted like the triangle path does,
//! but into the same visibility buffer as the sub-nodes.
//!
//! Why only large cells: per cell, the set-up (edges, affine fit, spans) costs
//! as much as 20–30 sub-node samples, so on the sphere's 1.8 px cells at 500²
//! (9 samples each) and its 3.6 px cells at 1000² (≈ 36) it loses, and it
//! wins from ≈ 7 px cells on (callgrind, see docs/performance.md).
//!
//! Coverage: a convex quad `c00 c10 c11 c01` row by row, each row's span
//! where its four edge functions are `>= 0`; any other quad (concave, folded,
//! degenerate) as the union of the triangles `(c00, c10, c11)` and
//! `(c00, c11, c01)`, each with its own orientation, tested per pixel centre
//! on exact integers. Corners are rounded to 1/256 px, the same rounding for
//! the cells sharing them, and every edge is widened by [`MARGIN`] (an L1
//! bound of the edge length, no square root): a centre on a shared edge is
//! drawn by both cells (the depth test keeps one), so no crack opens,
//! neither between cells nor between patches whose border nodes differ by a
//! rounding.
//!
//! Attributes: `(u, v)` of a pixel centre from the cell's affine fit at its
//! centre (the Jacobian from the mean edges), stored clamped to the cell as
//! `a = round(255 u)`, `b = round(255 v)` in the sample's sub-word; the piece
//! carries `nu = nv =` [`SUB_DEN`], so the resolve pass divides by 255.
//! Depth: bilinear at a span's first pixel, then affine along the span.

use crate::cell_bilinear::sub_word;
use crate::framebuffer::BandTarget;
use crate::traverse::{Node, CELL_DRAW};

/// Pieces cut into at least this many sub-cells per cell (`nu · nv`) are
/// drawn here rather than by sub-nodes (bilinear cells only).
pub(crate) const RASTER_MIN_SUB_CELLS: u32 = 100;

/// Denominator of the `(a, b)` fields of a rasterized sample's sub-word.
pub(crate) const SUB_DEN: u16 = 255;

/// Fractional bits of the corner positions used by the edge functions.
const FRAC: u32 = 8;
/// One pixel in those units.
const ONE: i32 = 1 << FRAC;
/// How far outside an edge (in 1/256 px, measured along the L1 normal) a
/// pixel centre still counts as covered: 1/8 px.
const MARGIN: i32 = 32;

/// Draws the cells of a `cols × rows` piece as their flags say (see
/// [`crate::traverse::measure_cells`]; the closing flags are not needed
/// since each cell covers its own edges). Not inlined: keeps the band
/// loop's code as it was for the other paths (callgrind at 1000²).
#[inline(never)]
pub(crate) fn draw_cells_raster(
    t: &mut BandTarget<'_>,
    nodes: &[Node],
    flags: &[u8],
    spans: &[[i32; 2]],
    cols: usize,
    rows: usize,
    item: u32,
) {
    let (y_lo, y_hi) = (t.y0, t.y0 + t.rows);
    let rows_of_cells = flags.chunks_exact(cols - 1).zip(spans).take(rows - 1);
    for (j, (row_flags, &[lo, hi])) in rows_of_cells.enumerate() {
        if hi < y_lo || lo >= y_hi {
            continue;
        }
        let below = &nodes[j * cols..(j + 1) * cols];
        let above = &nodes[(j + 1) * cols..(j + 2) * cols];
        let cells = row_flags.iter().zip(below.windows(2)).zip(above.windows(2));
        for (i, ((&f, b), a)) in cells.enumerate() {
            if f & CELL_DRAW == 0 {
                continue;
            }
            raster_cell(t, [&b[0], &b[1], &a[1], &a[0]], sub_word(i, j, 0, 0), item);
        }
    }
}

/// Edge function of the edge `a → b` at the first candidate centre and its
/// steps per column and per row, times the orientation `s`, widened by the
/// margin (inside is `>= 0`).
#[inline(always)]
fn edge(a: [i32; 2], b: [i32; 2], s: i32) -> (i32, i32, i32) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    // E(q) = dx (qy - ay) - dy (qx - ax), at q = 0.
    let e = s * (dy * a[0] - dx * a[1]) + MARGIN * (dx.abs() + dy.abs());
    (e, -s * dy * ONE, s * dx * ONE)
}

/// Twice the signed area of the triangle `a b c`.
#[inline(always)]
fn area(a: [i32; 2], b: [i32; 2], c: [i32; 2]) -> i32 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// What the candidate loop needs besides the edges: the first candidate,
/// the sub-word and item, and the affine `(u, v)` and bilinear depth.
#[derive(Clone, Copy)]
struct Scan {
    c: [i32; 2],
    r: [i32; 2],
    sub0: u32,
    item: u32,
    uv: [f32; 2],
    du: [f32; 2],
    dv: [f32; 2],
    z0: i32,
    z: [f32; 3],
}

/// Covers the pixel centres of one cell with corners `p` in quad order
/// (`c00, c10, c11, c01`).
#[inline(always)]
fn raster_cell(t: &mut BandTarget<'_>, p: [&Node; 4], sub0: u32, item: u32) {
    let shift = 16 - FRAC;
    let q = p.map(|n| [n[0] >> shift, n[1] >> shift]);
    let x_min = q[0][0].min(q[1][0]).min(q[2][0]).min(q[3][0]);
    let x_max = q[0][0].max(q[1][0]).max(q[2][0]).max(q[3][0]);
    let y_min = q[0][1].min(q[1][1]).min(q[2][1]).min(q[3][1]);
    let y_max = q[0][1].max(q[1][1]).max(q[2][1]).max(q[3][1]);
    // Columns and rows whose centre (k + 1/2) lies within the margin of the
    // box, clamped to the image and the band: no per-pixel clipping.
    let half = ONE / 2;
    let c_lo = ((x_min - MARGIN - half + ONE - 1) >> FRAC).max(0);
    let c_hi = ((x_max + MARGIN - half) >> FRAC).min(t.width - 1);
    let r_lo = ((y_min - MARGIN - half + ONE - 1) >> FRAC).max(t.y0);
    let r_hi = ((y_max + MARGIN - half) >> FRAC).min(t.y0 + t.rows - 1);
    if c_lo > c_hi || r_lo > r_hi {
        return;
    }
    // Corners relative to the first candidate centre (small: i32 products).
    let (ox, oy) = ((c_lo << FRAC) + half, (r_lo << FRAC) + half);
    let r = q.map(|v| [v[0] - ox, v[1] - oy]);

    // Affine fit of (u, v) in pixels from the cell's centre.
    let f = r.map(|v| [v[0] as f32 / ONE as f32, v[1] as f32 / ONE as f32]);
    let ux = 0.5 * ((f[1][0] - f[0][0]) + (f[2][0] - f[3][0]));
    let uy = 0.5 * ((f[1][1] - f[0][1]) + (f[2][1] - f[3][1]));
    let vx = 0.5 * ((f[3][0] - f[0][0]) + (f[2][0] - f[1][0]));
    let vy = 0.5 * ((f[3][1] - f[0][1]) + (f[2][1] - f[1][1]));
    let cx = 0.25 * (f[0][0] + f[1][0] + f[2][0] + f[3][0]);
    let cy = 0.25 * (f[0][1] + f[1][1] + f[2][1] + f[3][1]);
    let det = ux * vy - uy * vx;
    let inv = if det.abs() > 1e-6 { 1.0 / det } else { 0.0 };
    let (dudx, dudy, dvdx, dvdy) = (vy * inv, -vx * inv, -uy * inv, ux * inv);
    // Depth relative to the first corner (keeps f32 precision).
    let z0 = p[0][2];
    let scan = Scan {
        c: [c_lo, c_hi],
        r: [r_lo, r_hi],
        sub0,
        item,
        uv: [0.5 - cx * dudx - cy * dudy, 0.5 - cx * dvdx - cy * dvdy],
        du: [dudx, dvdx],
        dv: [dudy, dvdy],
        z0,
        z: [
            (p[1][2] - z0) as f32,
            (p[3][2] - z0) as f32,
            (p[2][2] - p[1][2] - p[3][2] + z0) as f32,
        ],
    };

    let (a1, a2) = (area(r[0], r[1], r[2]), area(r[0], r[2], r[3]));
    let (a3, a4) = (area(r[1], r[2], r[3]), area(r[0], r[1], r[3]));
    let same = |a: i32| (a > 0 && a1 > 0) || (a < 0 && a1 < 0);
    if same(a2) && same(a3) && same(a4) {
        // Convex (the usual case): spans between the edges, no test per
        // candidate. Why: a per-candidate test costs as much as a sample of
        // the subdivision (callgrind, see docs/performance.md).
        span_cell(t, &scan, &f, a1.signum() as f32);
    } else {
        // Concave, folded or degenerate: the union of the two triangles,
        // each with its own orientation; a triangle without area covers
        // nothing.
        let tri = |a, b, c, s: i32| {
            if s == 0 {
                [(-1, 0, 0); 3]
            } else {
                [edge(a, b, s), edge(b, c, s), edge(c, a, s)]
            }
        };
        let (t1, t2) = (
            tri(r[0], r[1], r[2], a1.signum()),
            tri(r[0], r[2], r[3], a2.signum()),
        );
        let e = [t1[0], t1[1], t1[2], t2[0], t2[1], t2[2]];
        // Inside a triangle: the OR of its edge values has no sign bit;
        // inside either: the AND of the two ORs has none.
        scan_cell(t, &scan, e, |e: &[i32; 6]| {
            ((e[0] | e[1] | e[2]) & (e[3] | e[4] | e[5])) >= 0
        });
    }
}

/// Covers a convex cell with corners `f` (pixels from the first candidate
/// centre, quad order, orientation `s`) row by row: the span of a row is
/// where the four widened edge functions are all `>= 0`, found by one
/// multiplication per edge; `(u, v)` and depth step by integers along it.
#[inline(always)]
fn span_cell(t: &mut BandTarget<'_>, sc: &Scan, f: &[[f32; 2]; 4], s: f32) {
    let margin = MARGIN as f32 / ONE as f32;
    // Edge k: E(x, y) = a x + b y + c >= 0 inside; per row, the bound on
    // the column offset k is -(b y + c) / a: from below when a > 0, from
    // above when a < 0; a row misses an edge with a = 0 when b y + c < 0.
    let mut ea = [0f32; 4];
    let mut eb = [0f32; 4];
    let mut ec = [0f32; 4];
    for k in 0..4 {
        let (p, q) = (f[k], f[(k + 1) % 4]);
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        ea[k] = -s * dy;
        eb[k] = s * dx;
        ec[k] = s * (dy * p[0] - dx * p[1]) + margin * (dx.abs() + dy.abs());
    }
    let inv = ea.map(|a| if a != 0.0 { -1.0 / a } else { 0.0 });
    let ncols = sc.c[1] - sc.c[0];
    let width = t.width as usize;
    // Fixed-point steps: (u, v) scaled to the sub-word's 0..=255 with 16
    // fractional bits, depth (relative to corner 0) with 16.
    let fu = SUB_DEN as f32 * 65536.0;
    let dzdx = sc.z[0] * sc.du[0] + sc.z[1] * sc.du[1];
    let step = [(sc.du[0] * fu) as i32, (sc.du[1] * fu) as i32];
    let zstep = (dzdx * 65536.0) as i64;
    for (y, row) in (sc.r[0]..=sc.r[1]).enumerate() {
        let y = y as f32;
        let (mut lo, mut hi) = (0f32, ncols as f32);
        for k in 0..4 {
            let rest = eb[k] * y + ec[k];
            let bound = rest * inv[k];
            if ea[k] > 0.0 {
                lo = lo.max(bound);
            } else if ea[k] < 0.0 {
                hi = hi.min(bound);
            } else if rest < 0.0 {
                hi = -1.0;
            }
        }
        if hi < lo {
            continue;
        }
        // 0 <= lo <= hi here: truncation is floor, and ceil is one more
        // when lo has a fraction. Why: `ceil`/`floor` are libm calls
        // without SSE4.1.
        let k1 = hi as i32;
        let mut k0 = lo as i32;
        k0 += ((k0 as f32) < lo) as i32;
        if k1 < k0 {
            continue;
        }
        let x = k0 as f32;
        let u = sc.uv[0] + sc.du[0] * x + sc.dv[0] * y;
        let v = sc.uv[1] + sc.du[1] * x + sc.dv[1] * y;
        // Depth at (u, v) from the cell's affine fit (bilinear at the
        // span start, affine along it).
        let (uc, vc) = (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
        let zr = sc.z[0] * uc + sc.z[1] * vc + sc.z[2] * uc * vc;
        let mut z = ((sc.z0 as i64) << 16) + (zr * 65536.0) as i64;
        let mut a = (u * fu + 32768.0) as i32;
        let mut b = (v * fu + 32768.0) as i32;
        let base = (row - t.y0) as usize * width + (sc.c[0] + k0) as usize;
        for px in &mut t.px[base..=base + (k1 - k0) as usize] {
            let zi = (z >> 16) as i32;
            if zi < px.depth {
                // Clamped to the cell: margin pixels lie slightly outside.
                let ai = (a >> 16).clamp(0, SUB_DEN as i32) as u32;
                let bi = (b >> 16).clamp(0, SUB_DEN as i32) as u32;
                px.depth = zi;
                px.w0 = sc.sub0 | ai << 8 | bi;
                px.w2 = sc.item;
            }
            z += zstep;
            a = a.wrapping_add(step[0]);
            b = b.wrapping_add(step[1]);
        }
    }
}

/// Walks the candidate centres of a cell, writing a sample at each one
/// that `inside` accepts.
#[inline(always)]
fn scan_cell<const N: usize>(
    t: &mut BandTarget<'_>,
    s: &Scan,
    edges: [(i32, i32, i32); N],
    inside: impl Fn(&[i32; N]) -> bool,
) {
    let mut row_e = edges.map(|e| e.0);
    let sx = edges.map(|e| e.1);
    let sy = edges.map(|e| e.2);
    let den = SUB_DEN as f32;
    let width = t.width as usize;
    let mut row_uv = s.uv;
    for row in s.r[0]..=s.r[1] {
        let base = (row - t.y0) as usize * width;
        let mut e = row_e;
        let mut uv = row_uv;
        for col in s.c[0]..=s.c[1] {
            if inside(&e) {
                let u = uv[0].clamp(0.0, 1.0);
                let v = uv[1].clamp(0.0, 1.0);
                let z = s.z0 + (s.z[0] * u + s.z[1] * v + s.z[2] * u * v) as i32;
                let px = &mut t.px[base + col as usize];
                if z < px.depth {
                    let a = (u * den + 0.5) as u32;
                    let b = (v * den + 0.5) as u32;
                    px.depth = z;
                    px.w0 = s.sub0 | a << 8 | b;
                    px.w2 = s.item;
                }
            }
            for k in 0..N {
                e[k] += sx[k];
            }
            uv[0] += s.du[0];
            uv[1] += s.du[1];
        }
        for k in 0..N {
            row_e[k] += sy[k];
        }
        row_uv[0] += s.dv[0];
        row_uv[1] += s.dv[1];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::Z_FAR;
    use crate::framebuffer::{Sample, PATCH_SAMPLE};
    use crate::traverse::{CELL_RIGHT, CELL_TOP};

    fn node(x: f32, y: f32, z: i32) -> Node {
        let mut n = [0; 9];
        n[0] = (x * 65536.0) as i32;
        n[1] = (y * 65536.0) as i32;
        n[2] = z;
        n
    }

    fn target(px: &mut [Sample], w: usize, h: usize) -> BandTarget<'_> {
        BandTarget {
            width: w as i32,
            y0: 0,
            rows: h as i32,
            px,
        }
    }

    /// Is `(x, y)` inside the polygon `poly` by at least `d` (either
    /// orientation)?
    fn inside_by(poly: &[(f32, f32)], x: f32, y: f32, d: f32) -> bool {
        let n = poly.len();
        let sides: Vec<f32> = (0..n)
            .map(|k| {
                let (a, b) = (poly[k], poly[(k + 1) % n]);
                let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
                ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) / len
            })
            .collect();
        sides.iter().all(|&s| s > d) || sides.iter().all(|&s| s < -d)
    }

    #[test]
    fn a_grid_of_small_cells_has_no_crack_and_one_sample_per_centre() {
        // A 5 × 5 grid of nodes, sheared and rotated, cells ≈ 2–3 px.
        let (cols, rows) = (5, 5);
        let mut nodes = Vec::new();
        for j in 0..rows {
            for i in 0..cols {
                let (s, t) = (i as f32, j as f32);
                let x = 3.1 + 2.1 * s - 1.3 * t + 0.05 * s * t;
                let y = 6.3 + 0.9 * s + 1.9 * t;
                nodes.push(node(x, y, 1000 + 10 * i as i32 + 20 * j as i32));
            }
        }
        let flags = vec![CELL_DRAW | CELL_RIGHT | CELL_TOP; (cols - 1) * (rows - 1)];
        let spans = vec![[0, 31]; rows - 1];
        let (w, h) = (24, 24);
        let mut px = vec![Sample::EMPTY; w * h];
        let mut t = target(&mut px, w, h);
        draw_cells_raster(&mut t, &nodes, &flags, &spans, cols, rows, PATCH_SAMPLE);
        let p = |i: usize, j: usize| {
            let n = &nodes[j * cols + i];
            (n[0] as f32 / 65536.0, n[1] as f32 / 65536.0)
        };
        let outline: Vec<(f32, f32)> = (0..cols - 1)
            .map(|i| p(i, 0))
            .chain((0..rows - 1).map(|j| p(cols - 1, j)))
            .chain((1..cols).rev().map(|i| p(i, rows - 1)))
            .chain((1..rows).rev().map(|j| p(0, j)))
            .collect();
        let mut inside = 0;
        for y in 0..h {
            for x in 0..w {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                let s = &px[y * w + x];
                if inside_by(&outline, cx, cy, 0.01) {
                    inside += 1;
                    assert!(s.depth < Z_FAR, "crack at {x},{y}");
                    // The stored (u, v) maps back near the pixel centre:
                    // within the margin (a neighbour's widened edge, clamped
                    // to its cell) plus the affine fit's error.
                    let (ci, cj) = ((s.w0 >> 24) as usize, ((s.w0 >> 16) & 0xff) as usize);
                    let (u, v) = (
                        ((s.w0 >> 8) & 0xff) as f32 / 255.0,
                        (s.w0 & 0xff) as f32 / 255.0,
                    );
                    let lerp = |k: usize| {
                        let c = |i: usize, j: usize| {
                            let q = p(i, j);
                            if k == 0 {
                                q.0
                            } else {
                                q.1
                            }
                        };
                        (1.0 - u) * (1.0 - v) * c(ci, cj)
                            + u * (1.0 - v) * c(ci + 1, cj)
                            + (1.0 - u) * v * c(ci, cj + 1)
                            + u * v * c(ci + 1, cj + 1)
                    };
                    let (ex, ey) = (lerp(0) - cx, lerp(1) - cy);
                    assert!(ex.abs() < 0.2 && ey.abs() < 0.2, "({x},{y}): {ex} {ey}");
                } else if !inside_by(&outline, cx, cy, -0.2) {
                    assert_eq!(s.depth, Z_FAR, "outside sample at {x},{y}");
                }
            }
        }
        assert!(inside > 60);
    }

    #[test]
    fn a_concave_cell_is_covered_whole() {
        // c11 pulled inside: the quad c00 c10 c11 c01 is concave at c11.
        let nodes = [
            node(1.2, 1.3, 500),
            node(12.7, 1.1, 500),
            node(1.4, 12.6, 500),
            node(4.1, 4.3, 500),
        ];
        let (w, h) = (16, 16);
        let mut px = vec![Sample::EMPTY; w * h];
        let mut t = target(&mut px, w, h);
        draw_cells_raster(&mut t, &nodes, &[CELL_DRAW], &[[0, 15]], 2, 2, PATCH_SAMPLE);
        let quad = [(1.2, 1.3), (12.7, 1.1), (4.1, 4.3), (1.4, 12.6)];
        let tri = |a: (f32, f32), b: (f32, f32), c: (f32, f32), x: f32, y: f32| {
            inside_by(&[a, b, c], x, y, 0.01)
        };
        let mut checked = 0;
        for y in 0..h {
            for x in 0..w {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                // The quad splits along its reflex diagonal c00–c11.
                if tri(quad[0], quad[1], quad[2], cx, cy) || tri(quad[0], quad[2], quad[3], cx, cy)
                {
                    checked += 1;
                    assert!(px[y * w + x].depth < Z_FAR, "hole at {x},{y}");
                }
            }
        }
        assert!(checked > 10);
    }
}
