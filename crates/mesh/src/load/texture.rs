//! Decoding texture images (PNG, JPEG, TIFF) into [`Texture`]s.

use std::path::Path;

use crate::{LoadWarning, Texture};

/// Largest texture side accepted: larger images are refused (as a warning) rather than decoded,
/// so a hostile header cannot ask for gigabytes.
const MAX_TEXTURE_SIDE: u32 = 16_384;

/// Decodes the image file at `path` (format sniffed from its bytes, not its name) into RGBA8.
pub(crate) fn load_texture_file(path: &Path) -> Result<Texture, LoadWarning> {
    let fail = |reason: String| LoadWarning::TextureUnreadable {
        path: path.to_path_buf(),
        reason,
    };
    let reader = image::ImageReader::open(path)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| fail(e.to_string()))?;
    let mut reader = reader;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    reader.limits(limits);
    let image = reader.decode().map_err(|e| fail(e.to_string()))?;
    rgba_texture(image).ok_or_else(|| fail("the image is empty".to_owned()))
}

/// Decodes image bytes held in memory (glTF buffer views, data URIs).
pub(crate) fn load_texture_bytes(bytes: &[u8], name: &Path) -> Result<Texture, LoadWarning> {
    let fail = |reason: String| LoadWarning::TextureUnreadable {
        path: name.to_path_buf(),
        reason,
    };
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| fail(e.to_string()))?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    reader.limits(limits);
    let image = reader.decode().map_err(|e| fail(e.to_string()))?;
    rgba_texture(image).ok_or_else(|| fail("the image is empty".to_owned()))
}

fn rgba_texture(image: image::DynamicImage) -> Option<Texture> {
    let rgba = image.into_rgba8();
    let (width, height) = rgba.dimensions();
    Texture::new(width, height, rgba.into_raw()).ok()
}
