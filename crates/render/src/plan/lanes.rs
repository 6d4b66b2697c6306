//! Lane conversions of the trilinear projection: a screen point held in
//! four `f32` lanes (x, y, depth, 0) to the fixed-point `[x, y, depth]` of
//! [`crate::fixed`] in one packed truncation.
//!
//! Input: screen positions in pixels and normalized depth. Output: `i32`
//! fixed-point words. Invariant: every result equals the scalar
//! conversions (`position_to_fixed`, `depth_to_fixed`) of the same input,
//! for every input (huge, infinite and NaN lanes take the scalar form;
//! tested on random and edge values).
//!
//! Cost: a clamp, a multiply and one packed truncation per point.

use glam::Vec4;

use crate::fixed::{depth_to_fixed, position_to_fixed, XY_ONE, Z_FAR};

/// Lower and upper clamps of [`fixed_lanes`]: the depth lane only.
const LANE_LO: Vec4 = Vec4::new(f32::NEG_INFINITY, f32::NEG_INFINITY, 0.0, 0.0);
const LANE_HI: Vec4 = Vec4::new(f32::INFINITY, f32::INFINITY, 2.0, 0.0);
/// Fixed-point scales of [`fixed_lanes`]: positions, depth.
const LANE_SCALE: Vec4 = Vec4::new(XY_ONE, XY_ONE, Z_FAR as f32, 0.0);

/// The fixed-point `[x, y, depth]` of a screen point in lanes `x, y, z`
/// (lane `w` 0): exactly `position_to_fixed(s.x)`,
/// `position_to_fixed(s.y)`, `depth_to_fixed(s.z)`, for every input.
///
/// Why: the saturating `as` conversions stay scalar (five instructions
/// each plus the repacking; callgrind, `profile_sphere 500 1`). When every
/// lane is below 2^31 in magnitude (always, inside the guard band), the
/// lanes are truncated in one packed step (`cvttps2dq` on x86-64; elsewhere
/// [`Vec4::trunc`] and the integers read by adding `1.5 · 2^52` in `f64`,
/// which puts an integer below 2^51 in the low mantissa bits, two's
/// complement); other inputs (huge, infinite, NaN) take the scalar form.
#[inline(always)]
pub(crate) fn fixed_lanes(s: Vec4) -> [i32; 3] {
    const LIMIT: f32 = 2_147_483_648.0; // 2^31
    let q = scaled_lanes(s);
    if q.abs().cmplt(Vec4::splat(LIMIT)).all() {
        truncate_lanes(q)
    } else {
        [
            position_to_fixed(s.x),
            position_to_fixed(s.y),
            depth_to_fixed(s.z),
        ]
    }
}

/// [`fixed_lanes`] for a point whose lanes are known to stay below 2^31
/// once scaled (and finite).
#[cfg(test)]
fn fixed_lanes_in_range(s: Vec4) -> [i32; 3] {
    truncate_lanes(scaled_lanes(s))
}

/// The lanes [`fixed_lanes`] truncates: positions in 1/65536 px, depth
/// clamped to `[0, 2]` and in units of [`Z_FAR`].
#[inline(always)]
pub(crate) fn scaled_lanes(s: Vec4) -> Vec4 {
    s.max(LANE_LO).min(LANE_HI) * LANE_SCALE
}

/// Lanes `x, y, z` of `q` (each below 2^31 in magnitude) truncated to
/// integers (see [`fixed_lanes`]).
#[inline(always)]
pub(crate) fn truncate_lanes(q: Vec4) -> [i32; 3] {
    let b = truncate_lanes4(q);
    [b[0], b[1], b[2]]
}

/// The four lanes of `q` (each below 2^31 in magnitude) truncated to
/// integers. Why all four: the two halves convert as two packed `f64`
/// pairs and store as one word group (callgrind, `profile_sphere 500 1`).
#[inline(always)]
pub(crate) fn truncate_lanes4(q: Vec4) -> [i32; 4] {
    // Why `cvttps2dq` straight to integers on x86-64 (SSE2, always there,
    // so the check folds away; pulp's token makes the intrinsic safe): it
    // truncates every lane below 2^31 exactly, in one instruction where
    // the portable form below rounds in `f32` (an emulated `roundps`
    // without SSE4.1) and reads the integers back through `f64`
    // (callgrind, bunny 500²).
    #[cfg(target_arch = "x86_64")]
    if let Some(sse2) = pulp::core_arch::x86::Sse2::try_new() {
        return pulp::bytemuck::cast(sse2._mm_cvttps_epi32(q.into()));
    }
    const MAGIC: f64 = 6_755_399_441_055_744.0; // 1.5 · 2^52
    let t = q.trunc().to_array();
    let bits = |v: f32| (v as f64 + MAGIC).to_bits() as i32;
    [bits(t[0]), bits(t[1]), bits(t[2]), bits(t[3])]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    /// The packed conversion equals the scalar ones for every kind of
    /// input: small and large, negative, fractional, at the 2^31 and 2^23
    /// edges, infinite and NaN.
    #[test]
    fn fixed_lanes_equal_the_scalar_conversions() {
        let mut rng = XorShift(0x5eed_1234_abcd_0001);
        let edges = [
            0.0,
            -0.0,
            1.0 / 65536.0,
            -1.0 / 65536.0,
            0.999_999_9,
            -0.999_999_9,
            127.999_99,
            128.0,
            -128.000_01,
            32_767.998,
            32_768.0,
            -32_768.0,
            -32_769.0,
            1e9,
            -1e9,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MIN_POSITIVE,
            2.1,
            -2.1,
        ];
        for case in 0..200_000 {
            let pick = |rng: &mut XorShift| match rng.below(4) {
                0 => edges[rng.below(edges.len() as u32) as usize],
                1 => (rng.unit() - 0.5) * 1024.0,
                2 => (rng.unit() - 0.5) * 70_000.0,
                _ => f32::from_bits(rng.next_u32()),
            };
            let s = Vec4::new(pick(&mut rng), pick(&mut rng), pick(&mut rng), 0.0);
            let want = [
                position_to_fixed(s.x),
                position_to_fixed(s.y),
                depth_to_fixed(s.z),
            ];
            assert_eq!(fixed_lanes(s), want, "case {case}: {s:?}");
            let q = s * LANE_SCALE;
            if s.is_finite() && q.x.abs() < 2_147_483_648.0 && q.y.abs() < 2_147_483_648.0 {
                assert_eq!(fixed_lanes_in_range(s), want, "case {case}: {s:?}");
            }
        }
    }
}
