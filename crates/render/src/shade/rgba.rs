//! Shaded colours to RGBA8: red, green and blue in `0..=255` truncated to
//! bytes as `c as i32 as u8` truncates them, one pixel at a time or four
//! lanes at once.
//!
//! Cost: O(1) per pixel.

use glam::{Vec3, Vec4};

/// Red, green and blue lanes in 0..=255 (as
/// [`crate::lighting::Material::shade4_with`] returns them) truncated to
/// bytes and packed as RGBA8 words (alpha 255), as `truncate_to_bytes`
/// gives them.
#[inline(always)]
pub(crate) fn pack_rgba(c: [Vec4; 3]) -> [u32; 4] {
    // Why spelled out: `array::map` here became an out-of-line call per
    // channel (~40 instructions per pixel group; callgrind,
    // `profile_sphere 500 1`).
    let bits = |v: Vec4| {
        let a = truncated_bits(v).to_array();
        [
            a[0].to_bits(),
            a[1].to_bits(),
            a[2].to_bits(),
            a[3].to_bits(),
        ]
    };
    let (r, g, b) = (bits(c[0]), bits(c[1]), bits(c[2]));
    // No masks: each lane's bits are `0x4b00_00vv` (`2^23 + v`, v < 256),
    // so the shifts push the exponent out of the word and the alpha byte
    // covers red's.
    let word = |k: usize| r[k] | g[k] << 8 | b[k] << 16 | 0xff00_0000;
    [word(0), word(1), word(2), word(3)]
}

/// RGB floats in 0..=255 (as [`crate::lighting::Material::shade`] returns
/// them) to RGBA8. Why through `i32`: the values are already in range, and the saturating
/// float-to-`u8` conversion costs about twice as many instructions; the
/// result is the same (truncation).
#[inline(always)]
pub(crate) fn to_rgba8(c: Vec3) -> [u8; 4] {
    [c.x as i32 as u8, c.y as i32 as u8, c.z as i32 as u8, 255]
}

/// Four colour values in 0..=255 truncated to bytes, as `c as i32 as u8`
/// does one at a time. Why: the scalar conversions with their saturation
/// checks were ~18 instructions per pixel (callgrind, `profile_sphere 500
/// 1`). Adding `2^23` rounds to an integer (kept in the low mantissa bits);
/// subtracting one where that rounded up gives the truncation.
#[inline(always)]
#[cfg(test)]
fn truncate_to_bytes(c: Vec4) -> [u8; 4] {
    truncated_bits(c).to_array().map(|v| v.to_bits() as u8)
}

/// `2^23 + trunc(c)` per lane: the truncated value sits in the low
/// mantissa bits (see `truncate_to_bytes`).
#[inline(always)]
fn truncated_bits(c: Vec4) -> Vec4 {
    const SHIFT: f32 = 8_388_608.0; // 2^23: the unit of the last mantissa bit is 1.
    let shifted = c + Vec4::splat(SHIFT);
    let nearest = shifted - Vec4::splat(SHIFT);
    // Exact: `shifted` is an integer in 2^23..2^23 + 256.
    shifted - Vec4::select(nearest.cmpgt(c), Vec4::ONE, Vec4::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;

    #[test]
    fn packed_words_hold_the_truncated_channels() {
        let mut rng = XorShift(0x5151_a5a5_0f0f_7777);
        for round in 0..5000 {
            let v = |rng: &mut XorShift| match round % 3 {
                // Integers and their neighbours (the rounding step's edges).
                0 => {
                    let k = rng.below(256) as f32;
                    let up = f32::from_bits(k.to_bits() + 1);
                    [k, up, k - 0.5, k + 0.5][rng.below(4) as usize].clamp(0.0, 255.0)
                }
                _ => rng.below(1 << 24) as f32 / (1 << 24) as f32 * 255.0,
            };
            let c =
                [0, 1, 2].map(|_| Vec4::new(v(&mut rng), v(&mut rng), v(&mut rng), v(&mut rng)));
            let want: [u32; 4] = std::array::from_fn(|k| {
                u32::from_le_bytes([
                    c[0][k] as i32 as u8,
                    c[1][k] as i32 as u8,
                    c[2][k] as i32 as u8,
                    255,
                ])
            });
            assert_eq!(pack_rgba(c), want, "{c:?}");
        }
    }

    #[test]
    fn bytes_are_truncated_like_a_scalar_conversion() {
        let mut v = 0.0f32;
        while v <= 255.0 {
            let next = f32::from_bits(v.to_bits() + 1).min(255.0);
            let c = Vec4::new(v, (v * 0.37).min(255.0), 255.0 - v, next);
            let expected = c.to_array().map(|x| x as i32 as u8);
            assert_eq!(truncate_to_bytes(c), expected, "{c:?}");
            v += 0.023_437_5;
        }
        // Exact integers and halves (ties of the rounding step).
        for k in 0..=255 {
            let c = Vec4::new(
                k as f32,
                k as f32 + 0.5,
                (k as f32 - 0.5).max(0.0),
                k as f32,
            );
            assert_eq!(truncate_to_bytes(c), c.to_array().map(|x| x as i32 as u8));
        }
    }
}
