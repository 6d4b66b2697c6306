//! Quantization of heights along a patch's z axis into displacement codes.
//!
//! A height `h` (distance along `ẑ` from the frame origin) is stored as the
//! code `d = round(h / step)`, reconstructed as `d · step`. The worst-case
//! reconstruction error of a code inside the range is `step / 2`.
//!
//! [`QuantizerPolicy`] is the one rule every producer (the mesh fitter, its sharp-edge
//! patches, the point-cloud pipeline) chooses a patch's codes by: 8-bit codes unless
//! their step over the patch's height range would exceed the error budget, then 16-bit
//! codes.

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

/// How a producer chooses the quantizer of a patch from its height range: **8-bit codes
/// unless the error budget needs more.**
///
/// With 8-bit codes the step is `max(target_step, range / 254)`; when that exceeds
/// `max_step` (twice the error budget: the worst-case error is half a step), the patch gets
/// 16-bit codes with step `max(fine_step, range / 65534)` instead.
///
/// # Guarantees
/// [`QuantizerPolicy::choose`] returns 8-bit codes whenever their step is at most
/// `max_step`, so a patch's worst-case error is at most `max_step / 2` unless even 16-bit
/// codes cannot span its range with `fine_step`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuantizerPolicy {
    /// Finest step of 8-bit codes (model units, > 0): a flat patch still needs a step.
    pub target_step: f32,
    /// Coarsest 8-bit step allowed (model units): twice the error budget.
    pub max_step: f32,
    /// Step of 16-bit codes when 8 bits are too coarse (model units, > 0).
    pub fine_step: f32,
}

impl QuantizerPolicy {
    /// The policy of an error budget: 8-bit codes while half their step is at most
    /// `max_error`, else 16-bit codes of step `2 · max_error`; no step finer than `floor`.
    pub fn within_error(max_error: f32, floor: f32) -> Self {
        Self {
            target_step: floor,
            max_step: 2.0 * max_error,
            fine_step: (2.0 * max_error).max(floor),
        }
    }

    /// The quantizer of a patch whose heights span `range` (see the type's docs). Fails on
    /// a negative or non-finite range or a step that is not positive and finite.
    pub fn choose(&self, range: f32) -> Result<Quantizer, FormatError> {
        let eight = Quantizer::for_range(range, self.target_step, DisplacementWidth::Bits8)?;
        if eight.step() <= self.max_step {
            return Ok(eight);
        }
        Quantizer::for_range(range, self.fine_step, DisplacementWidth::Bits16)
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
    fn policy_keeps_eight_bits_within_the_budget() {
        let policy = QuantizerPolicy::within_error(0.1, 1e-5);
        let q = policy.choose(1.0).unwrap();
        assert_eq!(q.width(), DisplacementWidth::Bits8);
        assert!(q.max_error() <= 0.1);
        // 254 codes of 0.2 reach 50.8: the last range 8 bits can take.
        assert_eq!(
            policy.choose(50.0).unwrap().width(),
            DisplacementWidth::Bits8
        );
        let wide = policy.choose(100.0).unwrap();
        assert_eq!(wide.width(), DisplacementWidth::Bits16);
        assert!((wide.step() - 0.2).abs() < 1e-6);
        let flat = policy.choose(0.0).unwrap();
        assert_eq!(
            (flat.width(), flat.step()),
            (DisplacementWidth::Bits8, 1e-5)
        );
        assert!(policy.choose(f32::NAN).is_err());
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
