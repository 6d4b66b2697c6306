//! A depth image as a single-channel 32-bit float TIFF, the form GIS and
//! image tools (GDAL, QGIS, ImageJ, Python's tifffile) read as a raster.
//!
//! Input: row-major depths, top row first, in model units (the renderer's
//! linear eye depth); non-finite values (no surface) are written as NaN.
//! Output: an uncompressed baseline TIFF, `SampleFormat` IEEE float,
//! `BitsPerSample` 32, little-endian. Values are stored exactly.
//!
//! Cost: one pass; 4 bytes per pixel plus a few hundred bytes of header.

use std::io::Cursor;

use tiff::encoder::{colortype::Gray32Float, TiffEncoder};

use crate::float_depth::float_depth_values;
use crate::ExportError;

/// `depth` (`width × height` values) as float TIFF bytes.
pub fn encode_depth_tiff(width: u32, height: u32, depth: &[f32]) -> Result<Vec<u8>, ExportError> {
    let values = float_depth_values(width, height, depth)?;
    let mut out = Cursor::new(Vec::new());
    TiffEncoder::new(&mut out)
        .and_then(|mut encoder| encoder.write_image::<Gray32Float>(width, height, &values))
        .map_err(|e| ExportError::Tiff(e.to_string()))?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiff::decoder::{Decoder, DecodingResult};

    #[test]
    fn depths_read_back_exactly_with_nan_for_no_surface() {
        let depth = [1.5, f32::INFINITY, 1e7 + 0.5, 0.001, 3.25, 7.0];
        let bytes = encode_depth_tiff(3, 2, &depth).unwrap();
        let mut decoder = Decoder::new(Cursor::new(bytes)).unwrap();
        assert_eq!(decoder.dimensions().unwrap(), (3, 2));
        let DecodingResult::F32(values) = decoder.read_image().unwrap() else {
            panic!("not a float image");
        };
        assert!(values[1].is_nan());
        for k in [0, 2, 3, 4, 5] {
            assert_eq!(values[k], depth[k]);
        }
    }

    #[test]
    fn a_wrong_size_is_an_error() {
        assert!(encode_depth_tiff(3, 3, &[0.0; 6]).is_err());
        assert!(encode_depth_tiff(0, 0, &[]).is_err());
    }
}
