//! Quantization of heights along a patch's z axis into displacement codes.
//!
//! A height `h` (distance along `ẑ` from the frame origin) is stored as the
//! code `d = round(h / step)`, reconstructed as `d · step`. The worst-case
//! reconstruction error of a code inside the range is `step / 2`.

use crate::{DisplacementWidth, FormatError};

/// Maps heights to displacement codes of one width.
///
/// # Guarantees
/// `step` is positive and finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantizer {
    step: f32,
    width: DisplacementWidth,
}

impl Quantizer {
    /// A quantizer with the given step (`|az|`) and code width.
    pub fn new(step: f32, width: DisplacementWidth) -> Result<Self, FormatError> {
        if !(step.is_finite() && step > 0.0) {
            return Err(FormatError::InvalidQuantizer {
                reason: "step must be a positive finite number",
            });
        }
        Ok(Self { step, width })
    }

    /// The smallest step no finer than `target_step` that spans a height
    /// range of `range` with the codes of `width`.
    ///
    /// Returns `target_step` when the range fits; otherwise the step grows
    /// to `range / max_code` (so the worst-case error grows with it).
    pub fn for_range(
        range: f32,
        target_step: f32,
        width: DisplacementWidth,
    ) -> Result<Self, FormatError> {
        if !(range.is_finite() && range >= 0.0) {
            return Err(FormatError::InvalidQuantizer {
                reason: "height range must be finite and non-negative",
            });
        }
        // A hair above range/max_code so that rounding never lands past max_code.
        let needed = range / width.max_code() as f32 * (1.0 + 1e-6);
        Self::new(target_step.max(needed), width)
    }

    /// The step `|az|`.
    pub fn step(&self) -> f32 {
        self.step
    }

    /// The code width.
    pub fn width(&self) -> DisplacementWidth {
        self.width
    }

    /// Worst-case reconstruction error of an in-range height: `step / 2`.
    pub fn max_error(&self) -> f32 {
        self.step * 0.5
    }

    /// The code of height `h`, or `None` when it is below 0, above the
    /// width's range, or not finite.
    pub fn quantize(&self, h: f32) -> Option<u16> {
        let code = (h / self.step).round();
        (code.is_finite() && code >= 0.0 && code <= self.width.max_code() as f32)
            .then_some(code as u16)
    }

    /// The height of code `d`: `d · step`.
    pub fn dequantize(&self, d: u16) -> f32 {
        d as f32 * self.step
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn round_trip_stays_within_half_a_step(step in 1e-4f32..10.0, t in 0.0f32..1.0) {
            let q = Quantizer::new(step, DisplacementWidth::Bits8).unwrap();
            let h = t * step * 254.0;
            let d = q.quantize(h).unwrap();
            // f32 slack: a few ulps of the largest height.
            let slack = h.abs() * 4.0 * f32::EPSILON;
            prop_assert!((q.dequantize(d) - h).abs() <= q.max_error() + slack);
        }

        #[test]
        fn range_always_fits(range in 0.0f32..1e6, target in 1e-5f32..1.0) {
            for width in [DisplacementWidth::Bits8, DisplacementWidth::Bits16] {
                let q = Quantizer::for_range(range, target, width).unwrap();
                prop_assert!(q.quantize(range).is_some());
                prop_assert!(q.step() >= target);
            }
        }
    }

    #[test]
    fn out_of_range_heights_are_refused() {
        let q = Quantizer::new(0.5, DisplacementWidth::Bits8).unwrap();
        assert_eq!(q.quantize(-1.0), None);
        assert_eq!(q.quantize(127.0), Some(254));
        assert_eq!(q.quantize(128.0), None);
        assert_eq!(q.quantize(f32::NAN), None);
    }
}
