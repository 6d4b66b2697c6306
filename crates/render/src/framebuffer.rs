//! The framebuffer: bands of rows with a depth buffer and a small G-buffer,
//! the per-pixel resolve (deferred Phong), supersampling reduction and the
//! final image with its PNG encodings.
//!
//! Per pixel during rasterization: depth (`i32`, fixed point, initialised
//! to the far plane) and three `u32` payload words.
//!
//! - A **patch sample** (a node or sub-node) is a visibility-buffer entry:
//!   word 2 is the draw item's index with [`PATCH_SAMPLE`] set, word 0 the
//!   cell and the sub-node's position in it (`ci << 24 | cj << 16 | a << 8 | b`).
//!   Placing a sample therefore interpolates only position and depth; the
//!   attributes (normal, albedo or colour) are interpolated bilinearly from
//!   the cell's corner nodes once per visible pixel, in the resolve pass.
//! - A **triangle sample** stores its shading inputs directly — Flat and
//!   Gouraud: the shaded colour in word 0; Phong: the packed normal, the
//!   packed albedo and the shade frame's index in words 0, 1, 2.
//!
//! The resolve pass shades each covered pixel once, so Phong costs one
//! shading per pixel however many samples were drawn over it.
//!
//! Depth test: strictly less, so of two equal depths the first drawn wins;
//! the drawing order within a band is fixed, hence the image does not
//! depend on the thread count.
//!
//! Output depth PNG: 16-bit grey, 0 = no surface, otherwise
//! `1 + round(65534 · (w - near) / (far - near))` with `w` the linear eye
//! depth.
//!
//! Cost: O(pixels) to clear and resolve; 16 bytes per internal pixel.

use glam::{Mat4, Vec3, Vec4};

use crate::error::RenderError;
use crate::fixed::Z_FAR;
use crate::options::Shading;
use crate::plan::{ChunkWork, Item};
use crate::shade::{unpack_normal, unpack_rgb, Lanes, Material, ShadeFrame};

/// A band's buffers, borrowed for drawing.
pub(crate) struct BandTarget<'a> {
    pub(crate) width: i32,
    pub(crate) y0: i32,
    pub(crate) rows: i32,
    /// One record per pixel of the band, row-major.
    pub(crate) px: &'a mut [Sample],
}

/// What a pixel holds during rasterization: its depth and three payload
/// words (see the module header). Why one record rather than four arrays:
/// the depth test and the payload stores touch one cache line and one
/// bounds check (callgrind, `profile_sphere 500 1`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Sample {
    pub(crate) depth: i32,
    pub(crate) w0: u32,
    pub(crate) w1: u32,
    pub(crate) w2: u32,
}

impl Sample {
    /// An empty pixel (depth at the far plane).
    pub(crate) const EMPTY: Sample = Sample {
        depth: Z_FAR,
        w0: 0,
        w1: 0,
        w2: 0,
    };
}

/// What a drawn sample stores besides its depth.
pub(crate) trait Payload<const N: usize> {
    /// Stores the payload of a sample that passed the depth test.
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, attrs: &[i32; N]);
}

/// Flag of word 2 marking a patch sample.
pub(crate) const PATCH_SAMPLE: u32 = 1 << 31;

/// Writes a patch sample (see the module header) if it is in the band and
/// passes the depth test.
#[inline(always)]
pub(crate) fn splat_sample(t: &mut BandTarget<'_>, px: i32, py: i32, z: i32, sub: u32, item: u32) {
    let row = py - t.y0;
    // Unsigned compares reject negatives too.
    if (px as u32) < t.width as u32 && (row as u32) < t.rows as u32 {
        let s = &mut t.px[row as usize * t.width as usize + px as usize];
        if z < s.depth {
            s.depth = z;
            s.w0 = sub;
            s.w2 = item;
        }
    }
}

/// Writes a triangle sample with its payload if it is in the band and
/// passes the depth test.
#[inline(always)]
pub(crate) fn splat<const N: usize, P: Payload<N>>(
    t: &mut BandTarget<'_>,
    px: i32,
    py: i32,
    z: i32,
    attrs: &[i32; N],
    payload: &P,
) {
    let row = py - t.y0;
    if (px as u32) < t.width as u32 && (row as u32) < t.rows as u32 {
        let idx = row as usize * t.width as usize + px as usize;
        if z < t.px[idx].depth {
            t.px[idx].depth = z;
            payload.store(t, idx, attrs);
        }
    }
}

/// Flat shading: one colour for the whole cell or triangle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FlatPayload(pub(crate) u32);

impl Payload<0> for FlatPayload {
    #[inline(always)]
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, _: &[i32; 0]) {
        t.px[idx].w0 = self.0;
        t.px[idx].w2 = 0;
    }
}

/// Gouraud: interpolated colour (attributes 0..3, 0..=255 in fixed point).
#[derive(Debug, Clone, Copy)]
pub(crate) struct GouraudPayload;

#[inline(always)]
fn channel(v: i32) -> u32 {
    (v >> crate::fixed::ATTR_FRAC_BITS).clamp(0, 255) as u32
}

impl Payload<3> for GouraudPayload {
    #[inline(always)]
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, a: &[i32; 3]) {
        t.px[idx].w0 = channel(a[0]) | channel(a[1]) << 8 | channel(a[2]) << 16 | 0xff00_0000;
        t.px[idx].w2 = 0;
    }
}

/// Phong: interpolated normal and albedo, and the shade frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhongPayload(pub(crate) u32);

impl Payload<6> for PhongPayload {
    #[inline(always)]
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, a: &[i32; 6]) {
        let s = &mut t.px[idx];
        s.w0 = crate::shade::pack_fixed_normal(a[0], a[1], a[2]);
        s.w1 = channel(a[3]) | channel(a[4]) << 8 | channel(a[5]) << 16;
        s.w2 = self.0;
    }
}

/// Time spent in one band, nanoseconds.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BandTimes {
    pub(crate) cells: u64,
    pub(crate) triangles: u64,
    pub(crate) resolve: u64,
}

/// The buffers of one band of rows.
#[derive(Debug, Default)]
pub(crate) struct Band {
    pub(crate) y0: i32,
    pub(crate) rows: i32,
    pub(crate) width: i32,
    px: Vec<Sample>,
    pub(crate) times: BandTimes,
}

/// How the resolve pass turns payloads into colours.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Resolve<'a> {
    pub(crate) shading: Shading,
    /// Draw items by index: `(chunk, item)`.
    pub(crate) items: &'a [(u32, u32)],
    pub(crate) chunks: &'a [ChunkWork],
    pub(crate) frames: &'a [ShadeFrame],
    pub(crate) material: Material,
    /// The albedo of nodes without colours, as stored in nodes (rounded to
    /// the attribute grid).
    pub(crate) base_albedo: Vec3,
    pub(crate) background: [u8; 4],
    pub(crate) near: f32,
    pub(crate) far: f32,
}

impl Band {
    /// Sizes and clears the buffers for rows `y0..y0 + rows` of `width`.
    pub(crate) fn reset(&mut self, y0: i32, rows: i32, width: i32) {
        let n = (rows * width) as usize;
        self.y0 = y0;
        self.rows = rows;
        self.width = width;
        self.px.clear();
        self.px.resize(n, Sample::EMPTY);
        self.times = BandTimes::default();
    }

    /// The buffers for drawing.
    pub(crate) fn target(&mut self) -> BandTarget<'_> {
        BandTarget {
            width: self.width,
            y0: self.y0,
            rows: self.rows,
            px: &mut self.px,
        }
    }

    /// Shades every pixel of the band into its rows of the image: colour
    /// into `rgba`, linear eye depth into `eye_depth` (`f32::INFINITY`
    /// where empty). Why the image's own rows: no band copy to gather, and
    /// the image's first touch happens on the pool (callgrind and
    /// `--bench`: the serial gather was ~1.3 ms of a 13.5 ms frame).
    pub(crate) fn resolve(&mut self, r: &Resolve<'_>, rgba: &mut [[u8; 4]], eye_depth: &mut [f32]) {
        debug_assert!(rgba.len() == self.px.len() && eye_depth.len() == self.px.len());
        if r.shading == Shading::Phong {
            self.resolve_phong(r, rgba, eye_depth);
            return;
        }
        let scale = (r.far - r.near) / Z_FAR as f32;
        // Why zipped slices: one length check per band instead of five
        // bounds checks per pixel (callgrind, `profile_sphere 500 1`).
        let pixels = self
            .px
            .iter()
            .zip(rgba.iter_mut().zip(eye_depth.iter_mut()));
        for (
            &Sample {
                depth: z,
                w0,
                w1: _,
                w2,
            },
            (rgba, eye),
        ) in pixels
        {
            if z >= Z_FAR {
                *rgba = r.background;
                *eye = f32::INFINITY;
                continue;
            }
            *eye = r.near + z as f32 * scale;
            *rgba = if w2 & PATCH_SAMPLE != 0 {
                resolve_patch_sample(r, w2 & !PATCH_SAMPLE, w0)
            } else {
                w0.to_le_bytes()
            };
        }
    }

    /// [`Self::resolve`] for Phong: covered pixels are gathered four at a
    /// time and shaded together ([`Material::shade4`], bit-identical to
    /// shading them one by one).
    fn resolve_phong(&mut self, r: &Resolve<'_>, rgba: &mut [[u8; 4]], eye_depth: &mut [f32]) {
        let scale = (r.far - r.near) / Z_FAR as f32;
        let mut batch = PhongBatch::default();
        let base = r.base_albedo.extend(0.0);
        for (k, s) in self.px.iter().enumerate() {
            if s.depth >= Z_FAR {
                rgba[k] = r.background;
                eye_depth[k] = f32::INFINITY;
                continue;
            }
            eye_depth[k] = r.near + s.depth as f32 * scale;
            let (normal, albedo, frame) = if s.w2 & PATCH_SAMPLE != 0 {
                phong_patch_inputs(r, s.w2 & !PATCH_SAMPLE, s.w0, base)
            } else {
                let n = unpack_normal(s.w0).extend(0.0);
                (n, unpack_rgb(s.w1).extend(0.0), s.w2)
            };
            batch.push(k, normal, &r.frames[frame as usize], albedo);
            if batch.len == 4 {
                batch.flush(&r.material, rgba);
            }
        }
        batch.flush(&r.material, rgba);
    }
}

/// Up to four Phong samples waiting to be shaded together: per sample its
/// pixel, normal, light, half vector and albedo (`xyz` lanes).
#[derive(Debug, Default)]
struct PhongBatch {
    len: usize,
    at: [usize; 4],
    normal: [Vec4; 4],
    light: [Vec4; 4],
    half: [Vec4; 4],
    albedo: [Vec4; 4],
}

impl PhongBatch {
    #[inline(always)]
    fn push(&mut self, at: usize, normal: Vec4, frame: &ShadeFrame, albedo: Vec4) {
        let k = self.len;
        self.at[k] = at;
        self.normal[k] = normal;
        self.light[k] = frame.light.extend(0.0);
        self.half[k] = frame.half.extend(0.0);
        self.albedo[k] = albedo;
        self.len = k + 1;
    }

    /// Shades the waiting samples into `rgba` (lanes past `len` hold
    /// earlier, finite samples and are computed but not written).
    fn flush(&mut self, m: &Material, rgba: &mut [[u8; 4]]) {
        if self.len == 0 {
            return;
        }
        // Samples are columns; a transpose gives one component per row.
        let rows = |v: &[Vec4; 4]| {
            let t = Mat4::from_cols(v[0], v[1], v[2], v[3]).transpose();
            [t.x_axis, t.y_axis, t.z_axis]
        };
        let lanes = Lanes {
            normal: rows(&self.normal),
            light: rows(&self.light),
            half: rows(&self.half),
            albedo: rows(&self.albedo),
        };
        let [red, green, blue] = m.shade4(&lanes).map(truncate_to_bytes);
        for k in 0..self.len {
            rgba[self.at[k]] = [red[k], green[k], blue[k], 255];
        }
        self.len = 0;
    }
}

/// RGB floats in 0..=255 (as [`Material::shade`] returns them) to RGBA8.
/// Why through `i32`: the values are already in range, and the saturating
/// float-to-`u8` conversion costs about twice as many instructions; the
/// result is the same (truncation).
#[inline(always)]
fn to_rgba8(c: Vec3) -> [u8; 4] {
    [c.x as i32 as u8, c.y as i32 as u8, c.z as i32 as u8, 255]
}

/// Four colour values in 0..=255 truncated to bytes, as `c as i32 as u8`
/// does one at a time. Why: the scalar conversions with their saturation
/// checks were ~18 instructions per pixel (callgrind, `profile_sphere 500
/// 1`). Adding `2^23` rounds to an integer (kept in the low mantissa bits);
/// subtracting one where that rounded up gives the truncation.
#[inline(always)]
fn truncate_to_bytes(c: Vec4) -> [u8; 4] {
    const SHIFT: f32 = 8_388_608.0; // 2^23: the unit of the last mantissa bit is 1.
    let nearest = (c + Vec4::splat(SHIFT)) - Vec4::splat(SHIFT);
    let down = nearest - Vec4::select(nearest.cmpgt(c), Vec4::ONE, Vec4::ZERO);
    (down + Vec4::splat(SHIFT))
        .to_array()
        .map(|v| v.to_bits() as u8)
}

/// The four attribute words `[from, from + 4)` of a node as floats.
#[inline(always)]
fn attr4(n: &crate::traverse::Node, from: usize) -> Vec4 {
    Vec4::new(
        attr_to_f32f(n[from]),
        attr_to_f32f(n[from + 1]),
        attr_to_f32f(n[from + 2]),
        attr_to_f32f(n[from + 3]),
    )
}

/// The cell of a patch sample: its item, its four corner nodes and the
/// bilinear weights of its sub-node.
#[inline(always)]
fn sample_cell<'r>(
    r: &Resolve<'r>,
    item: u32,
    sub: u32,
) -> (&'r Item, [&'r crate::traverse::Node; 4], [f32; 4]) {
    let (c, i) = r.items[item as usize];
    let chunk = &r.chunks[c as usize];
    let item = &chunk.items[i as usize];
    let cols = item.cols as usize;
    let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
    let k = item.first as usize + cj * cols + ci;
    // One slice for the four corners: a single bounds check.
    let quad = &chunk.nodes[k..k + cols + 2];
    let s = ((sub >> 8) & 0xff) as f32 / item.nu as f32;
    let t = (sub & 0xff) as f32 / item.nv as f32;
    (
        item,
        [&quad[0], &quad[1], &quad[cols], &quad[cols + 1]],
        [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t],
    )
}

/// Attribute words `[from, from + 4)` interpolated bilinearly. Why four
/// lanes at a time: the same products and sums in the same order as one
/// channel at a time (identical images), a quarter of the instructions
/// (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn lerp4(n: [&crate::traverse::Node; 4], w: [f32; 4], from: usize) -> Vec4 {
    attr4(n[0], from) * w[0]
        + attr4(n[1], from) * w[1]
        + attr4(n[2], from) * w[2]
        + attr4(n[3], from) * w[3]
}

/// Shades a patch sample with flat or Gouraud colours: the cell's colour,
/// or the colours of its corners interpolated at its sub-node.
#[inline]
fn resolve_patch_sample(r: &Resolve<'_>, item: u32, sub: u32) -> [u8; 4] {
    let (_, n, w) = sample_cell(r, item, sub);
    let colour = match r.shading {
        Shading::Flat => Vec3::new(
            attr_to_f32f(n[0][3]),
            attr_to_f32f(n[0][4]),
            attr_to_f32f(n[0][5]),
        ),
        Shading::Gouraud | Shading::Phong => lerp4(n, w, 3).truncate(),
    };
    to_rgba8(colour)
}

/// The Phong inputs of a patch sample: interpolated normal (`xyz`) and
/// albedo (`xyz`; `base` for an item without colours), and its shade frame.
#[inline]
fn phong_patch_inputs(r: &Resolve<'_>, item: u32, sub: u32, base: Vec4) -> (Vec4, Vec4, u32) {
    let (item, n, w) = sample_cell(r, item, sub);
    // Lanes: normal x, y, z, albedo r.
    let a = lerp4(n, w, 3);
    // Why: a patch without colours has one albedo, and interpolating a
    // constant only adds rounding (~15 instructions per pixel).
    if item.uniform_albedo {
        return (a, base, item.frame);
    }
    let gb = |k: usize| Vec4::new(attr_to_f32f(n[k][7]), attr_to_f32f(n[k][8]), 0.0, 0.0);
    let b = gb(0) * w[0] + gb(1) * w[1] + gb(2) * w[2] + gb(3) * w[3];
    (a, Vec4::new(a.w, b.x, b.y, 0.0), item.frame)
}

#[inline(always)]
fn attr_to_f32f(v: i32) -> f32 {
    crate::fixed::attr_from_bits(v)
}

/// A rendered image: RGBA8 colour and linear eye depth per pixel, row 0 at
/// the top.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderedImage {
    width: u32,
    height: u32,
    rgba: Vec<[u8; 4]>,
    depth: Vec<f32>,
    near: f64,
    far: f64,
}

impl RenderedImage {
    /// The `width × height` image from the internal image (`ssaa` times
    /// larger per axis) as the bands resolved it: kept as is for `ssaa = 1`,
    /// else reduced (box filter for colour, nearest surface for depth).
    pub(crate) fn from_internal(
        internal_rgba: Vec<[u8; 4]>,
        internal_depth: Vec<f32>,
        width: u32,
        height: u32,
        ssaa: u32,
        near: f64,
        far: f64,
    ) -> Self {
        let (w, h) = (width as usize, height as usize);
        let k = ssaa as usize;
        let iw = w * k;
        debug_assert_eq!(internal_rgba.len(), iw * h * k);
        if k == 1 {
            return Self {
                width,
                height,
                rgba: internal_rgba,
                depth: internal_depth,
                near,
                far,
            };
        }
        let mut rgba = vec![[0u8; 4]; w * h];
        let mut depth = vec![f32::INFINITY; w * h];
        let samples = (k * k) as u32;
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 4];
                let mut nearest = f32::INFINITY;
                for sy in 0..k {
                    let row = (y * k + sy) * iw + x * k;
                    for s in row..row + k {
                        for (acc, c) in sum.iter_mut().zip(internal_rgba[s]) {
                            *acc += c as u32;
                        }
                        nearest = nearest.min(internal_depth[s]);
                    }
                }
                rgba[y * w + x] = sum.map(|v| ((v + samples / 2) / samples) as u8);
                depth[y * w + x] = nearest;
            }
        }
        Self {
            width,
            height,
            rgba,
            depth,
            near,
            far,
        }
    }

    /// The colour and depth buffers, for [`crate::Renderer::recycle`].
    pub(crate) fn into_buffers(self) -> (Vec<[u8; 4]>, Vec<f32>) {
        (self.rgba, self.depth)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Pixels, row-major from the top-left, RGBA8.
    pub fn pixels(&self) -> &[[u8; 4]] {
        &self.rgba
    }
    /// Linear eye depth per pixel; `f32::INFINITY` where no surface.
    pub fn depth(&self) -> &[f32] {
        &self.depth
    }
    /// The near plane used.
    pub fn near(&self) -> f64 {
        self.near
    }
    /// The far plane used.
    pub fn far(&self) -> f64 {
        self.far
    }
    /// True when pixel `(x, y)` shows a surface.
    pub fn is_covered(&self, x: u32, y: u32) -> bool {
        self.depth[(y * self.width + x) as usize].is_finite()
    }
    /// Number of pixels showing a surface.
    pub fn covered_count(&self) -> usize {
        self.depth.iter().filter(|d| d.is_finite()).count()
    }

    /// PSNR (dB) of the RGB channels against `other` (same size), or `None`
    /// when the images are identical or differ in size.
    pub fn psnr(&self, other: &RenderedImage) -> Option<f64> {
        if self.width != other.width || self.height != other.height {
            return None;
        }
        let mut sum = 0u64;
        for (a, b) in self.rgba.iter().zip(&other.rgba) {
            for c in 0..3 {
                let d = a[c] as i64 - b[c] as i64;
                sum += (d * d) as u64;
            }
        }
        if sum == 0 {
            return None;
        }
        let mse = sum as f64 / (self.rgba.len() * 3) as f64;
        Some(10.0 * (255.0 * 255.0 / mse).log10())
    }

    /// The colour image as PNG bytes (RGBA8).
    pub fn encode_png(&self) -> Result<Vec<u8>, RenderError> {
        let bytes: Vec<u8> = self.rgba.iter().flatten().copied().collect();
        let buffer = image::RgbaImage::from_raw(self.width, self.height, bytes)
            .ok_or(RenderError::Bug("colour buffer size"))?;
        let mut out = std::io::Cursor::new(Vec::new());
        buffer
            .write_to(&mut out, image::ImageFormat::Png)
            .map_err(|source| RenderError::Encode {
                what: "colour",
                source,
            })?;
        Ok(out.into_inner())
    }

    /// The depth image as 16-bit greyscale PNG bytes (see the module header).
    pub fn encode_depth_png(&self) -> Result<Vec<u8>, RenderError> {
        let span = self.far - self.near;
        let values: Vec<u16> = self
            .depth
            .iter()
            .map(|&d| {
                if d.is_finite() {
                    let t = ((d as f64 - self.near) / span).clamp(0.0, 1.0);
                    1 + (t * 65534.0).round() as u16
                } else {
                    0
                }
            })
            .collect();
        let buffer = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::from_raw(
            self.width,
            self.height,
            values,
        )
        .ok_or(RenderError::Bug("depth buffer size"))?;
        let mut out = std::io::Cursor::new(Vec::new());
        buffer
            .write_to(&mut out, image::ImageFormat::Png)
            .map_err(|source| RenderError::Encode {
                what: "depth",
                source,
            })?;
        Ok(out.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_are_truncated_like_a_scalar_conversion() {
        let mut v = 0.0f32;
        while v <= 255.0 {
            let next = f32::from_bits(v.to_bits() + 1).min(255.0);
            let c = Vec4::new(v, (v * 0.37).min(255.0), 255.0 - v, next);
            let expected = c.to_array().map(|x| x as i32 as u8);
            assert_eq!(truncate_to_bytes(c), expected, "{c:?}");
            v += 0.023_437_5;
        }
        // Exact integers and halves (ties of the rounding step).
        for k in 0..=255 {
            let c = Vec4::new(
                k as f32,
                k as f32 + 0.5,
                (k as f32 - 0.5).max(0.0),
                k as f32,
            );
            assert_eq!(truncate_to_bytes(c), c.to_array().map(|x| x as i32 as u8));
        }
    }
}
