//! The colour map: an equirectangular RGBA image (longitude −180° at the left
//! edge, +180° at the right; latitude +90° at the top row).

use std::path::Path;

use crate::EarthError;

/// The built-in colour map (NASA Visible Earth, halved to 1024×512; see
/// `testdata/earth/SOURCE.md`).
pub const DEFAULT_MAP_JPEG: &[u8] = include_bytes!("../../../testdata/earth/earth_1024x512.jpg");

/// Maps wider than this are halved (2×2 box filter) until they fit, as the
/// original work halved its 2048×1024 map to 1024×512.
pub const DEFAULT_MAX_MAP_WIDTH: u32 = 1024;

/// An equirectangular RGBA8 (sRGB) image.
///
/// # Guarantees
/// `rgba.len() == width * height * 4`; both sides are at least 2.
#[derive(Clone, PartialEq, Eq)]
pub struct ColourMap {
    width: u32,
    height: u32,
    rgba: Vec<u8>,
}

impl std::fmt::Debug for ColourMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ColourMap({}x{})", self.width, self.height)
    }
}

impl ColourMap {
    /// A map from raw RGBA8 pixels (rows from the top).
    pub fn from_rgba(width: u32, height: u32, rgba: Vec<u8>) -> Result<Self, EarthError> {
        if width < 2 || height < 2 || rgba.len() as u64 != u64::from(width) * u64::from(height) * 4
        {
            return Err(EarthError::UnusableImage {
                path: "<pixels>".into(),
                problem: format!(
                    "{width}x{height} map with {} bytes (needs at least 2x2)",
                    rgba.len()
                ),
            });
        }
        Ok(Self {
            width,
            height,
            rgba,
        })
    }

    /// Decodes a PNG or JPEG file, halving it until it is at most
    /// `max_width` wide.
    pub fn load(path: &Path, max_width: u32) -> Result<Self, EarthError> {
        let image = image::open(path).map_err(|source| EarthError::Image {
            path: path.to_path_buf(),
            source,
        })?;
        Self::from_image(image, path, max_width)
    }

    /// The built-in map.
    pub fn built_in() -> Result<Self, EarthError> {
        let image =
            image::load_from_memory(DEFAULT_MAP_JPEG).map_err(|source| EarthError::Image {
                path: "<built-in map>".into(),
                source,
            })?;
        Self::from_image(image, Path::new("<built-in map>"), DEFAULT_MAX_MAP_WIDTH)
    }

    fn from_image(
        image: image::DynamicImage,
        path: &Path,
        max_width: u32,
    ) -> Result<Self, EarthError> {
        let rgba = image.to_rgba8();
        let (width, height) = rgba.dimensions();
        let mut map = Self::from_rgba(width, height, rgba.into_raw()).map_err(|_| {
            EarthError::UnusableImage {
                path: path.to_path_buf(),
                problem: format!("a {width}x{height} map is too small (needs at least 2x2)"),
            }
        })?;
        while map.width > max_width.max(2) && map.width >= 4 && map.height >= 4 {
            map = map.halved();
        }
        Ok(map)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels, RGBA8, rows from the top.
    pub fn rgba(&self) -> &[u8] {
        &self.rgba
    }

    /// Pixel `(x, y)` (no bounds wrap; callers stay inside).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let at = ((y * self.width + x) * 4) as usize;
        [
            self.rgba[at],
            self.rgba[at + 1],
            self.rgba[at + 2],
            self.rgba[at + 3],
        ]
    }

    /// Each side halved (odd last rows and columns dropped), 2×2 box filter.
    pub fn halved(&self) -> Self {
        let (w, h) = (self.width / 2, self.height / 2);
        let mut rgba = vec![0; (w * h * 4) as usize];
        for y in 0..h {
            for x in 0..w {
                let quad = [
                    self.pixel(2 * x, 2 * y),
                    self.pixel(2 * x + 1, 2 * y),
                    self.pixel(2 * x, 2 * y + 1),
                    self.pixel(2 * x + 1, 2 * y + 1),
                ];
                for c in 0..4 {
                    let sum: u32 = quad.iter().map(|p| u32::from(p[c])).sum();
                    rgba[((y * w + x) * 4) as usize + c] = ((sum + 2) / 4) as u8;
                }
            }
        }
        Self {
            width: w,
            height: h,
            rgba,
        }
    }
}
