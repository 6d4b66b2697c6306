//! The rendered image: RGBA8 colour and linear eye depth per pixel, the
//! supersampling reduction from the internal image, and the PNG
//! encodings.
//!
//! Output depth PNG: 16-bit grey, 0 = no surface, otherwise
//! `1 + round(65534 · (w - near) / (far - near))` with `w` the linear eye
//! depth.
//!
//! Cost: O(pixels) to reduce and encode.

use crate::error::RenderError;

/// The PNG row filter of [`RenderedImage::encode_png`].
const PNG_FILTER: image::codecs::png::FilterType = image::codecs::png::FilterType::Up;

/// `rgba` (`width × height` RGBA8 pixels, row 0 at the top) as PNG bytes,
/// every row filtered by the `Up` filter and compressed by the `png`
/// crate's fast deflate (the viewer's screenshots use it too, so they
/// equal `spatch render`'s files byte for byte). Why a fixed filter: the
/// adaptive filter tries all five filters on every row and was most of
/// the encoding (12.7 M instructions of a one-frame bunny render at 500²;
/// callgrind, `spatch render bunny.spatch -o out.png --threads 1`); the
/// decoded pixels are the same, only the file's bytes differ
/// (docs/performance-log.md, seventeenth round).
pub fn encode_rgba_png(width: u32, height: u32, rgba: &[u8]) -> Result<Vec<u8>, RenderError> {
    use image::codecs::png::{CompressionType, PngEncoder};
    use image::ImageEncoder;
    if rgba.len() as u64 != u64::from(width) * u64::from(height) * 4 {
        return Err(RenderError::Bug("colour buffer size"));
    }
    let mut out = Vec::new();
    PngEncoder::new_with_quality(&mut out, CompressionType::Fast, PNG_FILTER)
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|source| RenderError::Encode {
            what: "colour",
            source,
        })?;
    Ok(out)
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
        finite_count(&self.depth)
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

    /// The colour image as PNG bytes (RGBA8), by [`encode_rgba_png`].
    pub fn encode_png(&self) -> Result<Vec<u8>, RenderError> {
        encode_rgba_png(self.width, self.height, self.rgba.as_flattened())
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

/// How many of the eye depths `depth` are finite (pixels showing a
/// surface). Why a sum of 32-bit flags from the exponent bits: the
/// compiler runs it in vector lanes, where a filtered count went pixel by
/// pixel.
#[inline(always)]
pub(crate) fn finite_count(depth: &[f32]) -> usize {
    let finite = |d: &f32| u32::from(d.to_bits() & 0x7f80_0000 != 0x7f80_0000);
    depth.iter().map(finite).sum::<u32>() as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_colour_png_decodes_to_the_pixels() {
        // Transparent background, a gradient, noise and a repeated row: every
        // kind of row the fixed filter and the fast deflate see.
        let (width, height) = (37, 23);
        let mut rng = crate::test_rng::XorShift(0x9e37_79b9);
        let rgba: Vec<[u8; 4]> = (0..width * height)
            .map(|k| match (k / width) % 4 {
                0 => [0; 4],
                1 => [k as u8, (k * 3) as u8, 200, 255],
                _ => [0, 1, 2, 3].map(|_| rng.below(256) as u8),
            })
            .collect();
        let depth = vec![f32::INFINITY; rgba.len()];
        let image = RenderedImage::from_internal(rgba.clone(), depth, width, height, 1, 1.0, 2.0);
        let png = image.encode_png().unwrap();
        let decoded = image::load_from_memory(&png).unwrap().to_rgba8();
        assert_eq!(decoded.dimensions(), (width, height));
        assert_eq!(decoded.into_raw(), rgba.as_flattened());
    }

    #[test]
    fn covered_pixels_are_those_with_a_finite_depth() {
        // Finite depths (0, negative, tiny, huge) against infinities and
        // NaNs of every sign, in counts that leave vector remainders.
        let kinds = [
            0.0,
            -0.0,
            1.5,
            -3.0e38,
            f32::MIN_POSITIVE,
            f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            -f32::NAN,
        ];
        let (width, height) = (13, 7);
        let depth: Vec<f32> = (0..width * height)
            .map(|k| kinds[(k * 7) % kinds.len()])
            .collect();
        let expected = depth.iter().filter(|d| d.is_finite()).count();
        let rgba = vec![[0u8; 4]; depth.len()];
        let image =
            RenderedImage::from_internal(rgba, depth, width as u32, height as u32, 1, 1.0, 2.0);
        assert_eq!(image.covered_count(), expected);
        assert!(expected > 0 && expected < width * height);
    }
}
