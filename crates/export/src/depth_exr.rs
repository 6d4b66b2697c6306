//! A depth image as an OpenEXR file with one 32-bit float channel `Z`, the
//! channel name compositing and 3D tools (Blender, Nuke, OpenImageIO, Python's
//! OpenEXR) look for depth under.
//!
//! Input: row-major depths, top row first, in model units (the renderer's
//! linear eye depth); non-finite values (no surface) are written as NaN,
//! as the float TIFF does ([`crate::encode_depth_tiff`]), so both files
//! hold the same bits.
//! Output: a single-part scan-line EXR, ZIP compression in blocks of 16
//! lines (lossless: values come back bit for bit), written with the
//! pure-Rust `exr` crate.
//!
//! Cost: one pass to copy the values, then one ZIP pass over 4 bytes per
//! pixel.

use std::io::Cursor;

use exr::prelude::{AnyChannel, AnyChannels, Encoding, FlatSamples, Image, Layer, WritableImage};
use exr::prelude::{LayerAttributes, SmallVec};

use crate::float_depth::float_depth_values;
use crate::ExportError;

/// The channel name the depth is stored under.
pub const DEPTH_EXR_CHANNEL: &str = "Z";

/// `depth` (`width × height` values) as EXR bytes with one float channel
/// named [`DEPTH_EXR_CHANNEL`].
pub fn encode_depth_exr(width: u32, height: u32, depth: &[f32]) -> Result<Vec<u8>, ExportError> {
    let values = float_depth_values(width, height, depth)?;
    let channel = AnyChannel::new(DEPTH_EXR_CHANNEL, FlatSamples::F32(values));
    let size = (width as usize, height as usize);
    let layer = Layer::new(
        size,
        LayerAttributes::default(),
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(SmallVec::from_iter([channel])),
    );
    let mut out = Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut out)
        .map_err(|e| ExportError::Exr(e.to_string()))?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;
    use exr::prelude::{read, ReadChannels, ReadLayers};

    fn read_z(bytes: Vec<u8>) -> (usize, usize, Vec<f32>) {
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .from_buffered(Cursor::new(bytes))
            .unwrap();
        let layer = image.layer_data;
        let channels = &layer.channel_data.list;
        assert_eq!(channels.len(), 1);
        assert_eq!(channels[0].name.to_string(), DEPTH_EXR_CHANNEL);
        let FlatSamples::F32(values) = &channels[0].sample_data else {
            panic!("not a float channel");
        };
        (layer.size.0, layer.size.1, values.clone())
    }

    #[test]
    fn depths_read_back_bit_for_bit_with_nan_for_no_surface() {
        let depth = [
            1.5,
            f32::INFINITY,
            1e7 + 0.5,
            0.001,
            3.25,
            f32::NEG_INFINITY,
        ];
        let (width, height, values) = read_z(encode_depth_exr(3, 2, &depth).unwrap());
        assert_eq!((width, height), (3, 2));
        assert!(values[1].is_nan() && values[5].is_nan());
        for k in [0, 2, 3, 4] {
            assert_eq!(values[k].to_bits(), depth[k].to_bits());
        }
    }

    #[test]
    fn rows_stay_in_order_over_several_compression_blocks() {
        // 40 rows span three 16-line ZIP blocks; every value is distinct.
        let depth: Vec<f32> = (0..5 * 40).map(|k| 0.25 + k as f32 * 1.0e-3).collect();
        let (_, height, values) = read_z(encode_depth_exr(5, 40, &depth).unwrap());
        assert_eq!(height, 40);
        assert_eq!(values, depth);
    }

    #[test]
    fn a_wrong_size_is_an_error() {
        assert!(encode_depth_exr(3, 3, &[0.0; 6]).is_err());
        assert!(encode_depth_exr(0, 0, &[]).is_err());
    }
}
