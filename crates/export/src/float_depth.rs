//! The float depth that the TIFF and EXR writers store: `width × height` values, checked
//! against the size, with every non-finite value (no surface) written as NaN.

use crate::ExportError;

/// `depth` as the values a float depth file stores (NaN where no surface), or
/// [`ExportError::DepthSize`] when it does not hold `width × height` values or a side is 0.
pub(crate) fn float_depth_values(
    width: u32,
    height: u32,
    depth: &[f32],
) -> Result<Vec<f32>, ExportError> {
    if depth.len() as u64 != u64::from(width) * u64::from(height) || width == 0 || height == 0 {
        return Err(ExportError::DepthSize {
            width,
            height,
            values: depth.len(),
        });
    }
    Ok(depth
        .iter()
        .map(|&d| if d.is_finite() { d } else { f32::NAN })
        .collect())
}
