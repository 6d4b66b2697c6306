//! A conventional scan-line triangle rasterizer: near-plane clipping in
//! clip space, set-up of attribute planes, then span filling row by row.
//!
//! Used for the triangle mode (each drawable cell as two triangles), for
//! single cells that cross the near plane after splitting, for cells too
//! large to subdivide, and for arbitrary meshes
//! ([`crate::rasterize_triangles`]).
//!
//! Conventions (those of OpenGL/Direct3D): a pixel is covered when its
//! centre `(x + 0.5, y + 0.5)` is inside the triangle; centres exactly on an
//! edge belong to the triangle on their right (left edges and top edges are
//! inclusive, as a top-left rule), so two triangles sharing an edge never
//! both cover, nor both miss, a pixel. Edge positions are evaluated from the
//! edge's endpoints in a fixed order, so both triangles agree bit for bit.
//!
//! Depth and attributes are perspective-correct: `1/W` and `attribute/W`
//! are planes in screen space, evaluated per pixel, and divided by the
//! interpolated `1/W` (one reciprocal per pixel that passes the span test).
//! Geometry is clipped against `W = near` (Sutherland-Hodgman on one plane),
//! so nothing behind the eye is ever projected; the side planes need no
//! clipping (spans are clamped to the image, in f32).
//!
//! Cost: O(1) set-up per triangle and band, O(pixels covered) spans.

use glam::Vec3;

use crate::fixed::{attr_to_fixed, depth_to_fixed};
use crate::raster::band::{store_if_nearer, BandTarget, Payload, Sample};

/// Attributes carried per vertex (the most any shading model needs).
pub(crate) const TRI_ATTRS: usize = 6;

/// A vertex in window clip coordinates `(X, Y, W)` with its attributes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ClipVertex {
    pub(crate) clip: Vec3,
    pub(crate) attrs: [f32; TRI_ATTRS],
}

/// A triangle after clipping and projection: per vertex `(x, y, 1/W)` and
/// `attribute / W`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScreenTriangle {
    pub(crate) v: [[f32; 3]; 3],
    pub(crate) a: [[f32; TRI_ATTRS]; 3],
    /// Shade frame (Phong).
    pub(crate) frame: u32,
    /// Colour (flat shading).
    pub(crate) flat: u32,
    /// The triangle is a cell of a patch with a colour grid, and its
    /// attributes 3 and 4 (before the division by `W`) are the patch
    /// position in level-0 grid units where the grid is read per pixel
    /// ([`crate::plan::cell_triangles`]).
    pub(crate) grid: bool,
    /// Pixel rows spanned (inclusive).
    pub(crate) y0: i32,
    pub(crate) y1: i32,
    /// Pixel columns spanned (inclusive), like the rows cut to the image.
    pub(crate) x0: i32,
    pub(crate) x1: i32,
}

/// What clipping did to a triangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ClipOutcome {
    /// Entirely behind the near plane, off-screen or degenerate.
    Dropped,
    /// Emitted unclipped.
    Whole,
    /// Cut by the near plane into this many triangles.
    Clipped(u8),
}

fn lerp_vertex(a: &ClipVertex, b: &ClipVertex, t: f32) -> ClipVertex {
    ClipVertex {
        clip: a.clip.lerp(b.clip, t),
        attrs: std::array::from_fn(|k| a.attrs[k] + (b.attrs[k] - a.attrs[k]) * t),
    }
}

/// Clips a triangle against `W >= near`, projects it, and appends the
/// visible pieces to `out`.
pub(crate) fn clip_and_project(
    tri: &[ClipVertex; 3],
    near: f32,
    size: (f32, f32),
    frame: u32,
    flat: u32,
    out: &mut Vec<ScreenTriangle>,
) -> ClipOutcome {
    let inside = tri.map(|v| v.clip.z >= near);
    if inside.iter().all(|&i| i) {
        return if project(tri, size, frame, flat, out) {
            ClipOutcome::Whole
        } else {
            ClipOutcome::Dropped
        };
    }
    if !inside.iter().any(|&i| i) {
        return ClipOutcome::Dropped;
    }
    let mut poly = [tri[0]; 4];
    let mut len = 0;
    for k in 0..3 {
        let (a, b) = (&tri[k], &tri[(k + 1) % 3]);
        let (da, db) = (a.clip.z - near, b.clip.z - near);
        if da >= 0.0 {
            poly[len] = *a;
            len += 1;
        }
        if (da >= 0.0) != (db >= 0.0) {
            let mut v = lerp_vertex(a, b, da / (da - db));
            v.clip.z = near; // exactly on the plane despite rounding
            poly[len] = v;
            len += 1;
        }
    }
    let mut emitted = 0;
    for k in 1..len.saturating_sub(1) {
        if project(&[poly[0], poly[k], poly[k + 1]], size, frame, flat, out) {
            emitted += 1;
        }
    }
    if emitted == 0 {
        ClipOutcome::Dropped
    } else {
        ClipOutcome::Clipped(emitted)
    }
}

fn project(
    tri: &[ClipVertex; 3],
    size: (f32, f32),
    frame: u32,
    flat: u32,
    out: &mut Vec<ScreenTriangle>,
) -> bool {
    let mut v = [[0f32; 3]; 3];
    let mut a = [[0f32; TRI_ATTRS]; 3];
    for k in 0..3 {
        let iw = 1.0 / tri[k].clip.z;
        v[k] = [tri[k].clip.x * iw, tri[k].clip.y * iw, iw];
        a[k] = tri[k].attrs.map(|x| x * iw);
    }
    let area =
        (v[1][0] - v[0][0]) * (v[2][1] - v[0][1]) - (v[2][0] - v[0][0]) * (v[1][1] - v[0][1]);
    if !(area.is_finite() && area != 0.0) {
        return false;
    }
    let (x0, x1) = (
        v[0][0].min(v[1][0]).min(v[2][0]),
        v[0][0].max(v[1][0]).max(v[2][0]),
    );
    let (y0, y1) = (
        v[0][1].min(v[1][1]).min(v[2][1]),
        v[0][1].max(v[1][1]).max(v[2][1]),
    );
    // Covered rows are ceil(y0 - 0.5) ..< ceil(y1 - 0.5).
    let (r0, r1) = ((y0 - 0.5).ceil(), (y1 - 0.5).ceil() - 1.0);
    let (c0, c1) = ((x0 - 0.5).ceil(), (x1 - 0.5).ceil() - 1.0);
    if r1 < r0 || c1 < c0 || r1 < 0.0 || c1 < 0.0 || r0 >= size.1 || c0 >= size.0 {
        return false;
    }
    out.push(ScreenTriangle {
        v,
        a,
        frame,
        flat,
        grid: false,
        y0: r0.max(0.0) as i32,
        y1: r1.min(size.1 - 1.0) as i32,
        x0: c0.max(0.0) as i32,
        x1: c1.min(size.0 - 1.0) as i32,
    });
    true
}

/// `v.ceil() as i32` without `ceil`, which the portable target (no
/// SSE4.1) calls in the C library: the truncation, plus one where it fell
/// below `v` (saturating as the conversion does; 0 for NaN). Why: the
/// triangle loops run on the portable target (`crate::frame::tiles`), and
/// `ceilf`, called twice a row there and by the projection, took 4.9 % of a
/// one-thread `bun_zipper_res4` frame (`perf`).
#[inline(always)]
fn ceil_i32(v: f32) -> i32 {
    let t = v as i32;
    t.saturating_add(((t as f32) < v) as i32)
}

/// x of the edge `p → q` (with `p.y <= q.y`) at height `y`.
#[inline(always)]
fn edge_x(p: &[f32; 3], q: &[f32; 3], y: f32) -> f32 {
    let dy = q[1] - p[1];
    if dy == 0.0 {
        p[0]
    } else {
        p[0] + (y - p[1]) * (q[0] - p[0]) / dy
    }
}

/// How a triangle's `1/w` and attributes change across the screen: each `(d/dx, d/dy)`.
struct Gradients<const N: usize> {
    /// Of `1/w`.
    w: (f32, f32),
    /// Of each attribute (already divided by `w`).
    attrs: [(f32, f32); N],
}

impl<const N: usize> Gradients<N> {
    /// The gradients of `tri`, or `None` when it has no area.
    #[inline(always)]
    fn of(tri: &ScreenTriangle) -> Option<Gradients<N>> {
        let e1 = [tri.v[1][0] - tri.v[0][0], tri.v[1][1] - tri.v[0][1]];
        let e2 = [tri.v[2][0] - tri.v[0][0], tri.v[2][1] - tri.v[0][1]];
        let det = e1[0] * e2[1] - e2[0] * e1[1];
        if det == 0.0 {
            return None;
        }
        let inv_det = 1.0 / det;
        // Plane of a quantity q with values q0, q1, q2: (dq/dx, dq/dy).
        let plane = |q0: f32, q1: f32, q2: f32| {
            let (d1, d2) = (q1 - q0, q2 - q0);
            (
                (d1 * e2[1] - d2 * e1[1]) * inv_det,
                (d2 * e1[0] - d1 * e2[0]) * inv_det,
            )
        };
        Some(Gradients {
            w: plane(tri.v[0][2], tri.v[1][2], tri.v[2][2]),
            attrs: std::array::from_fn(|c| plane(tri.a[0][c], tri.a[1][c], tri.a[2][c])),
        })
    }
}

/// Fills a projected triangle into the band.
#[inline(always)]
pub(crate) fn draw_triangle<const N: usize, P: Payload<N>>(
    t: &mut BandTarget<'_>,
    tri: &ScreenTriangle,
    depth_map: (f32, f32),
    payload: &P,
) {
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| tri.v[a][1].total_cmp(&tri.v[b][1]));
    let [p0, p1, p2] = order.map(|k| tri.v[k]);
    let Some(gradients) = Gradients::<N>::of(tri) else {
        return;
    };
    let (ox, oy) = (tri.v[0][0], tri.v[0][1]);
    let row_lo = ceil_i32(p0[1] - 0.5).max(t.y0);
    let row_hi = ceil_i32(p2[1] - 0.5).min(t.y0 + t.rows);
    for y in row_lo..row_hi {
        let yc = y as f32 + 0.5;
        let xa = edge_x(&p0, &p2, yc);
        let xb = if yc < p1[1] {
            edge_x(&p0, &p1, yc)
        } else {
            edge_x(&p1, &p2, yc)
        };
        let (xl, xr) = if xa < xb { (xa, xb) } else { (xb, xa) };
        let x_lo = ceil_i32(xl - 0.5).max(0);
        let x_hi = ceil_i32(xr - 0.5).min(t.width);
        if x_lo >= x_hi {
            continue;
        }
        let (dx, dy) = (x_lo as f32 + 0.5 - ox, yc - oy);
        let w_plane = gradients.w;
        let iw = tri.v[0][2] + w_plane.0 * dx + w_plane.1 * dy;
        let av: [f32; N] = std::array::from_fn(|c| {
            tri.a[0][c] + gradients.attrs[c].0 * dx + gradients.attrs[c].1 * dy
        });
        // The span lies in the band's row `y` and in the image's columns,
        // so its pixels are one slice (no bounds test per pixel).
        let start = (y - t.y0) as usize * t.width as usize;
        let span = &mut t.px[start + x_lo as usize..start + x_hi as usize];
        fill_span(span, (iw, av), &gradients, depth_map, payload);
    }
}

/// Depth-tests and writes one row's `span` of a triangle, starting from the `1/w` and
/// attributes at its first pixel centre and stepping them by the x gradients.
#[inline(always)]
fn fill_span<const N: usize, P: Payload<N>>(
    span: &mut [Sample],
    (mut iw, mut av): (f32, [f32; N]),
    gradients: &Gradients<N>,
    (zs, zo): (f32, f32),
    payload: &P,
) {
    for s in span {
        let w = 1.0 / iw;
        let z = depth_to_fixed(w * zs + zo);
        let attrs = || std::array::from_fn(|c| attr_to_fixed(av[c] * w));
        store_if_nearer(s, z, attrs, payload);
        iw += gradients.w.0;
        av = std::array::from_fn(|c| av[c] + gradients.attrs[c].0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixed::Z_FAR;
    use crate::raster::band::{FlatPayload, Sample};

    fn vertex(x: f32, y: f32, w: f32) -> ClipVertex {
        ClipVertex {
            clip: Vec3::new(x * w, y * w, w),
            attrs: [0.0; TRI_ATTRS],
        }
    }

    #[test]
    fn two_triangles_sharing_an_edge_cover_each_centre_once() {
        let (w, h) = (16usize, 16usize);
        let quad = [
            vertex(1.3, 0.7, 2.0),
            vertex(14.2, 2.5, 3.0),
            vertex(12.9, 15.1, 2.5),
            vertex(0.4, 13.3, 2.0),
        ];
        let mut tris = Vec::new();
        for t in [[quad[0], quad[1], quad[2]], [quad[0], quad[2], quad[3]]] {
            assert_eq!(
                clip_and_project(&t, 0.1, (16.0, 16.0), 0, 0, &mut tris),
                ClipOutcome::Whole
            );
        }
        let mut hits = vec![0u32; w * h];
        for tri in &tris {
            let mut px = vec![Sample::EMPTY; w * h];
            let mut t = BandTarget::new(&mut px, w as i32, 0, h as i32);
            draw_triangle::<0, _>(&mut t, tri, (0.1, 0.0), &FlatPayload(1));
            for (h, d) in hits.iter_mut().zip(px.iter().map(|s| s.depth)) {
                *h += (d < Z_FAR) as u32;
            }
        }
        assert!(hits.iter().all(|&h| h <= 1), "a pixel was drawn twice");
        assert!(hits.iter().filter(|&&h| h == 1).count() > 150);
    }

    /// `ceil_i32` is `ceil` then the saturating conversion, at integers,
    /// halves, the neighbours of both, the conversion's limits and NaN.
    #[test]
    fn ceil_without_the_library_equals_ceil_then_the_conversion() {
        let mut values = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.0, -0.0];
        for k in [
            -3.0e9f32,
            -2147483648.0,
            -16777217.0,
            -1.5,
            -1.0,
            -0.5,
            0.5,
            1.0,
            2.5,
        ] {
            for v in [k, k * 1000.0, 2147483520.0, 2147483648.0] {
                values.extend([
                    v,
                    f32::from_bits(v.to_bits() + 1),
                    f32::from_bits(v.to_bits() - 1),
                ]);
            }
        }
        for v in values {
            assert_eq!(ceil_i32(v), v.ceil() as i32, "{v}");
        }
    }

    #[test]
    fn clipping_keeps_only_the_part_in_front_of_the_near_plane() {
        let tri = [
            vertex(5.0, 5.0, 2.0),
            vertex(10.0, 5.0, 2.0),
            vertex(7.0, 9.0, -1.0),
        ];
        let mut out = Vec::new();
        assert_eq!(
            clip_and_project(&tri, 0.5, (16.0, 16.0), 0, 0, &mut out),
            ClipOutcome::Clipped(2)
        );
        for t in &out {
            for v in &t.v {
                assert!(v[2] <= 1.0 / 0.5 + 1e-5 && v[2] > 0.0);
            }
        }
        let behind = [
            vertex(5.0, 5.0, -2.0),
            vertex(10.0, 5.0, -2.0),
            vertex(7.0, 9.0, -1.0),
        ];
        assert_eq!(
            clip_and_project(&behind, 0.5, (16.0, 16.0), 0, 0, &mut out),
            ClipOutcome::Dropped
        );
    }
}
