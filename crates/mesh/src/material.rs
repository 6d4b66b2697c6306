//! Materials and textures: what colour a point of the surface has.
//!
//! Colour conventions (the same for every loader):
//!
//! - texture texels and vertex colours are **sRGB-encoded bytes**, RGBA;
//! - [`Material::base_colour`] is a **linear** RGBA factor (glTF's `baseColorFactor`, OBJ's
//!   `Kd` taken as linear), multiplied with the texture and the vertex colour in linear space;
//! - texture coordinates follow OBJ: `u` to the right, `v` **up**, `(0, 0)` the bottom-left
//!   corner of the image. The glTF loader flips `v` (glTF's origin is the top-left corner), so
//!   every [`TriangleMesh`](crate::TriangleMesh) uses this one convention. Texture lookups
//!   repeat outside `[0, 1]`.

use std::sync::OnceLock;

use glam::Vec2;

use crate::MeshError;

/// An RGBA8 image, rows from the top of the image down, 4 bytes per pixel (sRGB encoded).
///
/// # Guarantees
///
/// When built with [`Texture::new`], `rgba.len() == width * height * 4` and both sides are at
/// least 1. The fields are public for cheap access; [`Texture::sample_bilinear`] stays total
/// (returns opaque white) even when a hand-built texture breaks that rule.
#[derive(Clone, PartialEq, Eq)]
pub struct Texture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels, row-major from the top row, RGBA8 sRGB.
    pub rgba: Vec<u8>,
}

impl std::fmt::Debug for Texture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Texture({}x{})", self.width, self.height)
    }
}

impl Texture {
    /// A texture from RGBA8 pixels; refuses a byte count that is not `width * height * 4` or
    /// an empty image.
    pub fn new(width: u32, height: u32, rgba: Vec<u8>) -> Result<Texture, MeshError> {
        let expected = u64::from(width) * u64::from(height) * 4;
        if expected == 0 || rgba.len() as u64 != expected {
            return Err(MeshError::InvalidTexture {
                width,
                height,
                expected,
                actual: rgba.len() as u64,
            });
        }
        Ok(Texture {
            width,
            height,
            rgba,
        })
    }

    /// The texel at column `x`, row `y` (row 0 at the top), or `None` outside the image.
    pub fn texel(&self, x: u32, y: u32) -> Option<[u8; 4]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = (y as usize * self.width as usize + x as usize) * 4;
        let px = self.rgba.get(i..i + 4)?;
        Some([px[0], px[1], px[2], px[3]])
    }

    /// Bilinear sample at texture coordinate `uv` (v up, repeat wrap), in sRGB-encoded
    /// `0.0..=1.0` per channel.
    ///
    /// Texel `(x, y)` (row `y` from the top) has its centre at
    /// `u = (x + 0.5) / width`, `v = 1 - (y + 0.5) / height`; filtering is done on the encoded
    /// values, as GPUs do for non-sRGB textures. Non-finite `uv` samples texel `(0, 0)`.
    pub fn sample_bilinear(&self, uv: Vec2) -> [f32; 4] {
        let (w, h) = (self.width as usize, self.height as usize);
        if w == 0 || h == 0 || self.rgba.len() < w * h * 4 {
            return [1.0; 4];
        }
        // Work in f64: with f32, u = 1000.3 keeps only ~3 bits of fraction for a 1k texture.
        let x = f64::from(uv.x) * w as f64 - 0.5;
        let y = (1.0 - f64::from(uv.y)) * h as f64 - 0.5;
        let (x, y) = (
            if x.is_finite() { x } else { 0.0 },
            if y.is_finite() { y } else { 0.0 },
        );
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        // rem_euclid keeps huge or negative coordinates inside the image (repeat wrap).
        let xi = (x0.rem_euclid(w as f64) as usize).min(w - 1);
        let yi = (y0.rem_euclid(h as f64) as usize).min(h - 1);
        let xj = if xi + 1 == w { 0 } else { xi + 1 };
        let yj = if yi + 1 == h { 0 } else { yi + 1 };
        let px = |x: usize, y: usize| {
            let i = (y * w + x) * 4;
            [
                f32::from(self.rgba[i]),
                f32::from(self.rgba[i + 1]),
                f32::from(self.rgba[i + 2]),
                f32::from(self.rgba[i + 3]),
            ]
        };
        let (a, b, c, d) = (px(xi, yi), px(xj, yi), px(xi, yj), px(xj, yj));
        let mut out = [0.0f32; 4];
        for k in 0..4 {
            let top = a[k] + (b[k] - a[k]) * fx;
            let bottom = c[k] + (d[k] - c[k]) * fx;
            out[k] = (top + (bottom - top) * fy) * (1.0 / 255.0);
        }
        out
    }
}

/// A surface material: a name, a base colour factor and an optional texture.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name from the file (MTL `newmtl`, glTF material name) or a generated `material_N`.
    pub name: String,
    /// Linear RGBA factor multiplied with the texture and vertex colour; white means "no
    /// effect". Alpha is carried but spatch renders opaque.
    pub base_colour: [f32; 4],
    /// Base colour texture, if the material has one and it could be decoded.
    pub texture: Option<Texture>,
}

impl Material {
    /// A white, untextured material.
    pub fn white(name: impl Into<String>) -> Material {
        Material {
            name: name.into(),
            base_colour: [1.0; 4],
            texture: None,
        }
    }

    /// Whether this material gives the surface a colour: it has a texture or a base colour
    /// whose RGB is not white.
    pub fn has_colour(&self) -> bool {
        self.texture.is_some() || self.base_colour[..3].iter().any(|&c| c != 1.0)
    }
}

/// sRGB byte to linear `0..=1` (exact table of the sRGB transfer function).
pub(crate) fn srgb_to_linear(byte: u8) -> f32 {
    static TABLE: OnceLock<[f32; 256]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let mut t = [0.0f32; 256];
        for (i, v) in t.iter_mut().enumerate() {
            let c = i as f64 / 255.0;
            *v = if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            } as f32;
        }
        t
    })[byte as usize]
}

/// Encoded sRGB `0..=1` (possibly fractional, from filtering) to linear.
pub(crate) fn srgb_unit_to_linear(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear `0..=1` to an sRGB byte (rounded to nearest).
pub(crate) fn linear_to_srgb(c: f32) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    let e = if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0 + 0.5).clamp(0.0, 255.0) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker() -> Texture {
        // 2x2: top row red, green; bottom row blue, white.
        Texture::new(
            2,
            2,
            vec![
                255, 0, 0, 255, 0, 255, 0, 255, //
                0, 0, 255, 255, 255, 255, 255, 255,
            ],
        )
        .unwrap()
    }

    #[test]
    fn texel_centres_sample_exactly_with_v_up() {
        let t = checker();
        // Bottom-left texel is row 1, column 0: blue.
        assert_eq!(
            t.sample_bilinear(Vec2::new(0.25, 0.25)),
            [0.0, 0.0, 1.0, 1.0]
        );
        // Top-left: red.
        assert_eq!(
            t.sample_bilinear(Vec2::new(0.25, 0.75)),
            [1.0, 0.0, 0.0, 1.0]
        );
        // Repeat wrap: one period to the right and below.
        assert_eq!(
            t.sample_bilinear(Vec2::new(1.25, -0.25)),
            [1.0, 0.0, 0.0, 1.0]
        );
    }

    #[test]
    fn midway_between_texels_averages() {
        let t = checker();
        let s = t.sample_bilinear(Vec2::new(0.5, 0.75));
        assert!((s[0] - 0.5).abs() < 1e-6 && (s[1] - 0.5).abs() < 1e-6 && s[2] == 0.0);
        // Corner (0, 0) of the image wraps to all four texels.
        let s = t.sample_bilinear(Vec2::ZERO);
        assert!((s[0] - 0.5).abs() < 1e-6 && (s[1] - 0.5).abs() < 1e-6);
        assert!((s[2] - 0.5).abs() < 1e-6);
    }

    #[test]
    fn hostile_coordinates_do_not_panic() {
        let t = checker();
        for uv in [
            Vec2::new(f32::NAN, 0.5),
            Vec2::new(f32::INFINITY, -f32::INFINITY),
            Vec2::new(1e30, -1e30),
        ] {
            let s = t.sample_bilinear(uv);
            assert!(s.iter().all(|c| (0.0..=1.0).contains(c)));
        }
        let broken = Texture {
            width: 4,
            height: 4,
            rgba: vec![0; 3],
        };
        assert_eq!(broken.sample_bilinear(Vec2::ZERO), [1.0; 4]);
        assert!(Texture::new(2, 2, vec![0; 15]).is_err());
        assert!(Texture::new(0, 2, vec![]).is_err());
    }

    #[test]
    fn srgb_round_trips_every_byte() {
        for b in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(b)), b);
            assert!((srgb_unit_to_linear(f32::from(b) / 255.0) - srgb_to_linear(b)).abs() < 1e-6);
        }
    }
}
