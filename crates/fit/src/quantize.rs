//! The displacement step of a region, and its codes.
//!
//! A region's filled nodes span heights `[h_min, h_max]` along ẑ. The step is the finest that
//! spans that range with 8-bit codes (`range / 254`), so each region spends its 254 codes on
//! its own relief. Only when half of that step exceeds the error budget (a fraction of the
//! node spacing, [`FitOptions::max_step_error`](crate::FitOptions::max_step_error)) does the
//! region get a finer step, `max(2 × budget, range / 65534)`, and 16-bit codes; each patch of
//! the region then stores the narrowest width its own codes need.
//!
//! Reconstruction: height = `h_min + code × step`; worst-case error `step / 2` (plus f32
//! rounding of the frame, about 1e-7 of the model's size).

use spatch_format::{Quantizer, QuantizerPolicy};

use crate::FitError;

/// The step and code width of a region whose heights span `range` (≥ 0), with node spacing
/// `spacing` and a budget of `max_error` (absolute) for half a step.
///
/// The rule is spatch-format's [`QuantizerPolicy::within_error`], shared with the
/// point-cloud pipeline. Public so that other producers (the sharp-edge patches of
/// `spatch-edges`) quantize exactly as the fitter does.
pub fn choose_quantizer(range: f32, spacing: f32, max_error: f32) -> Result<Quantizer, FitError> {
    // A flat region still needs a positive step; this floor is far below f32 noise of heights.
    let floor = spacing * 1e-5;
    Ok(QuantizerPolicy::within_error(max_error, floor).choose(range)?)
}

/// The code of height `h` above `h_min` (rounded, clamped to the quantizer's codes).
#[inline]
pub fn quantize_height(q: &Quantizer, h_min: f32, h: f32) -> u16 {
    let code = ((h - h_min) / q.step()).round();
    code.clamp(0.0, f32::from(q.width().max_code())) as u16
}

#[cfg(test)]
mod tests {
    use super::*;
    use spatch_format::DisplacementWidth;

    #[test]
    fn eight_bits_when_the_budget_allows() {
        let q = choose_quantizer(1.0, 1.0, 0.1).unwrap();
        assert_eq!(q.width(), DisplacementWidth::Bits8);
        assert!(q.max_error() <= 0.1);
        assert_eq!(quantize_height(&q, 0.0, 1.0), 254);
    }

    #[test]
    fn sixteen_bits_only_beyond_the_budget() {
        let q = choose_quantizer(100.0, 1.0, 0.1).unwrap();
        assert_eq!(q.width(), DisplacementWidth::Bits16);
        assert!((q.step() - 0.2).abs() < 1e-6);
        assert!(quantize_height(&q, 0.0, 100.0) > 254);
        let flat = choose_quantizer(0.0, 1.0, 0.1).unwrap();
        assert!(flat.step() > 0.0);
        assert_eq!(quantize_height(&flat, 0.0, 0.0), 0);
    }
}
