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

use glam::Vec3;

use crate::error::RenderError;
use crate::fixed::Z_FAR;
use crate::options::Shading;
use crate::plan::ChunkWork;
use crate::shade::{unpack_normal, unpack_rgb, Material, ShadeFrame};

/// A band's buffers, borrowed for drawing.
pub(crate) struct BandTarget<'a> {
    pub(crate) width: i32,
    pub(crate) y0: i32,
    pub(crate) rows: i32,
    pub(crate) depth: &'a mut [i32],
    pub(crate) c0: &'a mut [u32],
    pub(crate) c1: &'a mut [u32],
    pub(crate) c2: &'a mut [u32],
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
        let idx = row as usize * t.width as usize + px as usize;
        if z < t.depth[idx] {
            t.depth[idx] = z;
            t.c0[idx] = sub;
            t.c2[idx] = item;
        }
    }
}

/// [`splat_sample`] for a sample known to lie in the band and the image
/// (the slice index still checks, so a broken caller panics, never writes
/// elsewhere).
#[inline(always)]
pub(crate) fn splat_sample_inside(
    t: &mut BandTarget<'_>,
    px: i32,
    py: i32,
    z: i32,
    sub: u32,
    item: u32,
) {
    debug_assert!((px as u32) < t.width as u32 && ((py - t.y0) as u32) < t.rows as u32);
    let idx = (py - t.y0) as usize * t.width as usize + px as usize;
    if z < t.depth[idx] {
        t.depth[idx] = z;
        t.c0[idx] = sub;
        t.c2[idx] = item;
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
        if z < t.depth[idx] {
            t.depth[idx] = z;
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
        t.c0[idx] = self.0;
        t.c2[idx] = 0;
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
        t.c0[idx] = channel(a[0]) | channel(a[1]) << 8 | channel(a[2]) << 16 | 0xff00_0000;
        t.c2[idx] = 0;
    }
}

/// Phong: interpolated normal and albedo, and the shade frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhongPayload(pub(crate) u32);

impl Payload<6> for PhongPayload {
    #[inline(always)]
    fn store(&self, t: &mut BandTarget<'_>, idx: usize, a: &[i32; 6]) {
        t.c0[idx] = crate::shade::pack_fixed_normal(a[0], a[1], a[2]);
        t.c1[idx] = channel(a[3]) | channel(a[4]) << 8 | channel(a[5]) << 16;
        t.c2[idx] = self.0;
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
    depth: Vec<i32>,
    c0: Vec<u32>,
    c1: Vec<u32>,
    c2: Vec<u32>,
    /// Resolved colour and eye depth (f32::INFINITY where empty).
    pub(crate) rgba: Vec<[u8; 4]>,
    pub(crate) eye_depth: Vec<f32>,
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
        self.depth.clear();
        self.depth.resize(n, Z_FAR);
        for c in [&mut self.c0, &mut self.c1, &mut self.c2] {
            c.resize(n, 0);
        }
        self.rgba.resize(n, [0; 4]);
        self.eye_depth.resize(n, f32::INFINITY);
        self.times = BandTimes::default();
    }

    /// The buffers for drawing.
    pub(crate) fn target(&mut self) -> BandTarget<'_> {
        BandTarget {
            width: self.width,
            y0: self.y0,
            rows: self.rows,
            depth: &mut self.depth,
            c0: &mut self.c0,
            c1: &mut self.c1,
            c2: &mut self.c2,
        }
    }

    /// Shades every covered pixel into `rgba` and `eye_depth`.
    pub(crate) fn resolve(&mut self, r: &Resolve<'_>) {
        let scale = (r.far - r.near) / Z_FAR as f32;
        for k in 0..self.depth.len() {
            let z = self.depth[k];
            if z >= Z_FAR {
                self.rgba[k] = r.background;
                self.eye_depth[k] = f32::INFINITY;
                continue;
            }
            self.eye_depth[k] = r.near + z as f32 * scale;
            let word = self.c2[k];
            self.rgba[k] = if word & PATCH_SAMPLE != 0 {
                resolve_patch_sample(r, word & !PATCH_SAMPLE, self.c0[k])
            } else {
                match r.shading {
                    Shading::Flat | Shading::Gouraud => self.c0[k].to_le_bytes(),
                    Shading::Phong => {
                        let frame = &r.frames[word as usize];
                        let n = unpack_normal(self.c0[k]);
                        let albedo = unpack_rgb(self.c1[k]);
                        let c: Vec3 = r.material.shade(n, frame, albedo);
                        [c.x as u8, c.y as u8, c.z as u8, 255]
                    }
                }
            };
        }
    }
}

/// Shades a patch sample: bilinear attributes of its cell at its sub-node.
#[inline]
fn resolve_patch_sample(r: &Resolve<'_>, item: u32, sub: u32) -> [u8; 4] {
    let (c, i) = r.items[item as usize];
    let chunk = &r.chunks[c as usize];
    let item = &chunk.items[i as usize];
    let cols = item.cols as usize;
    let (ci, cj) = ((sub >> 24) as usize, ((sub >> 16) & 0xff) as usize);
    let k = item.first as usize + cj * cols + ci;
    let nodes = &chunk.nodes;
    let s = ((sub >> 8) & 0xff) as f32 / item.nu as f32;
    let t = (sub & 0xff) as f32 / item.nv as f32;
    let (w00, w10, w01, w11) = ((1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t);
    let (n00, n10, n01, n11) = (
        &nodes[k],
        &nodes[k + 1],
        &nodes[k + cols],
        &nodes[k + cols + 1],
    );
    let at = |ch: usize| {
        attr_to_f32f(n00[ch]) * w00
            + attr_to_f32f(n10[ch]) * w10
            + attr_to_f32f(n01[ch]) * w01
            + attr_to_f32f(n11[ch]) * w11
    };
    let colour = match r.shading {
        Shading::Flat => Vec3::new(
            attr_to_f32f(n00[3]),
            attr_to_f32f(n00[4]),
            attr_to_f32f(n00[5]),
        ),
        Shading::Gouraud => Vec3::new(at(3), at(4), at(5)),
        Shading::Phong => {
            let n = Vec3::new(at(3), at(4), at(5));
            let albedo = Vec3::new(at(6), at(7), at(8));
            r.material.shade(n, &r.frames[item.frame as usize], albedo)
        }
    };
    [colour.x as u8, colour.y as u8, colour.z as u8, 255]
}

#[inline(always)]
fn attr_to_f32f(v: i32) -> f32 {
    v as f32 * (1.0 / crate::fixed::ATTR_ONE)
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
    /// Assembles bands of a `width × height` internal image reduced by
    /// `ssaa` per axis (box filter for colour, nearest surface for depth).
    pub(crate) fn from_bands(
        bands: &[Band],
        width: u32,
        height: u32,
        ssaa: u32,
        near: f64,
        far: f64,
    ) -> Self {
        let (w, h) = (width as usize, height as usize);
        let k = ssaa as usize;
        let (iw, ih) = (w * k, h * k);
        let mut rgba = vec![[0u8; 4]; w * h];
        let mut depth = vec![f32::INFINITY; w * h];
        if k == 1 {
            let mut at = 0;
            for band in bands {
                let n = band.rgba.len();
                rgba[at..at + n].copy_from_slice(&band.rgba);
                depth[at..at + n].copy_from_slice(&band.eye_depth);
                at += n;
            }
        } else {
            // Gather the internal image once, then reduce.
            let mut full_rgba = Vec::with_capacity(iw * ih);
            let mut full_depth = Vec::with_capacity(iw * ih);
            for band in bands {
                full_rgba.extend_from_slice(&band.rgba);
                full_depth.extend_from_slice(&band.eye_depth);
            }
            let samples = (k * k) as u32;
            for y in 0..h {
                for x in 0..w {
                    let mut sum = [0u32; 4];
                    let mut nearest = f32::INFINITY;
                    for sy in 0..k {
                        let row = (y * k + sy) * iw + x * k;
                        for s in row..row + k {
                            for (acc, c) in sum.iter_mut().zip(full_rgba[s]) {
                                *acc += c as u32;
                            }
                            nearest = nearest.min(full_depth[s]);
                        }
                    }
                    rgba[y * w + x] = sum.map(|v| ((v + samples / 2) / samples) as u8);
                    depth[y * w + x] = nearest;
                }
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
