//! Pass 1a of the range image: where each point lands in a view's pixels and its height
//! carried to that pixel centre, branch-free over the point columns so that it vectorises.

use glam::Vec3;

use super::{ImageGeometry, PointColumns, MAX_GRADIENT, MIN_POINT_COSINE};

/// Marks a point that is not drawn in a view.
pub(super) const NOT_DRAWN: u32 = u32::MAX;

/// The projection of points onto one view's pixels (pass 1a of the module documentation).
pub(super) struct Projector {
    u: Vec3,
    w: Vec3,
    d: Vec3,
    /// Image axes divided by the pixel size.
    su: Vec3,
    sw: Vec3,
    /// Image origin in pixels.
    sx0: f32,
    sy0: f32,
    /// Upper bounds of the pixel coordinates (`width − 0.5`, `height − 0.5`).
    right: f32,
    top: f32,
    width: usize,
    pixel: f32,
}

impl Projector {
    pub(super) fn new(geometry: &ImageGeometry) -> Projector {
        let basis = geometry.basis;
        // `floor_pixel` is exact below 2^23 (a side within the pixel budget is).
        debug_assert!(geometry.width.max(geometry.height) < INTEGER_FLOAT as usize);
        // The projection with the pixel size folded in: `fx = p · su − sx0`.
        let inv = 1.0 / geometry.pixel;
        // Pixel centres lie at integers; the image spans [−0.5, width − 0.5) × [−0.5,
        // height − 0.5).
        Projector {
            u: basis.u,
            w: basis.w,
            d: basis.direction,
            su: basis.u * inv,
            sw: basis.w * inv,
            sx0: geometry.x0 * inv,
            sy0: geometry.y0 * inv,
            right: geometry.width as f32 - 0.5,
            top: geometry.height as f32 - 0.5,
            width: geometry.width,
            pixel: geometry.pixel,
        }
    }

    /// Each point of `range`: its pixel (or [`NOT_DRAWN`]) and its height carried to the
    /// pixel centre, into `out_pixel` and `out_height` (`range.len()` long). Branch-free over
    /// the columns, so it vectorises; the z-buffer is left to the caller.
    pub(super) fn project(
        &self,
        points: &PointColumns,
        range: std::ops::Range<usize>,
        oriented: bool,
        (out_pixel, out_height): (&mut [u32], &mut [f32]),
    ) {
        let n = range.len();
        let Projector {
            u,
            w,
            d,
            su,
            sw,
            sx0,
            sy0,
            right,
            top,
            width,
            pixel,
        } = *self;
        let [px, py, pz, nx, ny, nz] = points.columns(range);
        // Every slice cut to `n`, so the loop has no bounds checks (which would stop the SIMD).
        let (px, py, pz, nx, ny, nz) = (&px[..n], &py[..n], &pz[..n], &nx[..n], &ny[..n], &nz[..n]);
        let (out_pixel, out_height) = (&mut out_pixel[..n], &mut out_height[..n]);
        for j in 0..n {
            let (x, y, z) = (px[j], py[j], pz[j]);
            let (ax, ay, az) = (nx[j], ny[j], nz[j]);
            let fx = x * su.x + y * su.y + z * su.z - sx0;
            let fy = x * sw.x + y * sw.y + z * sw.z - sy0;
            let h = x * d.x + y * d.y + z * d.z;
            let n_d = ax * d.x + ay * d.y + az * d.z;
            let n_u = ax * u.x + ay * u.y + az * u.z;
            let n_w = ax * w.x + ay * w.y + az * w.z;
            let is_unknown = ax == 0.0 && ay == 0.0 && az == 0.0;
            let facing = faces_view(n_d, is_unknown, oriented);
            // Outside the image: a far outlier beyond the robust bounds.
            let inside = fx >= -0.5 && fy >= -0.5 && fx < right && fy < top;
            // Nearest pixel centre: `⌊f + 0.5⌋` wherever the point is inside.
            let (cx, cy) = (floor_pixel(fx + 0.5), floor_pixel(fy + 0.5));
            let carry = tangent_carry(n_u, n_w, n_d, is_unknown, cx - fx, cy - fy);
            out_height[j] = h + carry * pixel;
            let k = pixel_index(cy)
                .wrapping_mul(width as u32)
                .wrapping_add(pixel_index(cx));
            out_pixel[j] = if facing && inside { k } else { NOT_DRAWN };
        }
    }
}

/// Whether a point is drawn in a view, from its normal's component `n_d` along the view
/// direction: not at a grazing angle nor, with `oriented` normals, seen from behind; always
/// when its normal `is_unknown`.
#[inline(always)] // Inside the vectorised loop of `Projector::project`.
fn faces_view(n_d: f32, is_unknown: bool, oriented: bool) -> bool {
    let toward = if oriented { n_d } else { n_d.abs() };
    is_unknown || toward >= MIN_POINT_COSINE
}

/// The height change, in pixels, from a point to the pixel centre `(dx, dy)` pixels away
/// along its tangent plane: its normal `(n_u, n_w, n_d)` in the view's axes gives the depth
/// gradient, clamped to [`MAX_GRADIENT`]; none when the normal `is_unknown`.
#[inline(always)] // Inside the vectorised loop of `Projector::project`.
fn tangent_carry(n_u: f32, n_w: f32, n_d: f32, is_unknown: bool, dx: f32, dy: f32) -> f32 {
    let to_gradient = if is_unknown { 0.0 } else { -1.0 / n_d };
    let (gx, gy) = (n_u * to_gradient, n_w * to_gradient);
    let g2 = gx * gx + gy * gy;
    let clamp = if g2 > MAX_GRADIENT * MAX_GRADIENT {
        MAX_GRADIENT / g2.sqrt()
    } else {
        1.0
    };
    (gx * dx + gy * dy) * clamp
}

/// `2^23`: every `f32` in `[2^23, 2^24)` is an integer, one apart.
const INTEGER_FLOAT: f32 = 8_388_608.0;

/// `⌊t⌋` of a pixel coordinate `t`, exact for `0 ≤ t < 2^23` (an image side is at most
/// [`PIXEL_BUDGET`](crate::PIXEL_BUDGET)` / 2` pixels); `t` is clamped to that range (a point
/// outside it is outside the image and not drawn).
///
/// Why not `t as i32`: Rust's saturating conversion has no packed SSE2 form, so the
/// projection loop converted each lane alone: 18 of its 46 instructions a point (723 M of
/// 9.32 G for the evenly spread 1 M scan set, callgrind). Adding `2^23` rounds to the nearest
/// integer (the FPU's rounding), one step down when that rounded up: all packed operations.
#[inline(always)] // Inside the vectorised loop of `Projector::project`.
fn floor_pixel(t: f32) -> f32 {
    let t = t.clamp(0.0, INTEGER_FLOAT - 1.0);
    let nearest = (t + INTEGER_FLOAT) - INTEGER_FLOAT;
    if nearest > t {
        nearest - 1.0
    } else {
        nearest
    }
}

/// The integer of a [`floor_pixel`] result (`0 ≤ c < 2^23`, an integer), from the bits of
/// `c + 2^23` (whose mantissa is `c`): a packed integer subtraction.
#[inline(always)] // Inside the vectorised loop of `Projector::project`.
fn pixel_index(c: f32) -> u32 {
    (c + INTEGER_FLOAT).to_bits() - INTEGER_FLOAT.to_bits()
}
