//! Eight `f32` lanes in one AVX register, for the resolve pass's groups of
//! eight pixels (`shade::resolve_wide`): the operations glam's
//! `Vec4` gives the groups of four, each the same IEEE operation per lane,
//! so a lane's result is bit for bit the four-lane one. Through pulp's
//! [`V3`] token, so no `unsafe`; worth it only inlined into the AVX2 copy
//! of the band kernels ([`crate::isa`]), where each is one instruction.
//!
//! Cost: one instruction per operation for eight lanes.

use std::arch::x86_64::{__m256, __m256i, _CMP_LT_OQ};
use std::ops::{Add, BitAnd, Div, Mul, MulAssign, Sub};

use glam::Vec4;
use pulp::x86::V3;

/// Eight `f32` lanes (or a mask of eight lanes, all bits set or clear).
#[derive(Debug, Clone, Copy)]
pub(crate) struct F8 {
    v: __m256,
    s: V3,
}

impl F8 {
    /// `x` in every lane.
    #[inline(always)]
    pub(crate) fn splat(s: V3, x: f32) -> Self {
        Self {
            v: s.avx._mm256_set1_ps(x),
            s,
        }
    }

    /// `lo` in lanes 0–3, `hi` in lanes 4–7.
    #[inline(always)]
    pub(crate) fn halves(s: V3, lo: Vec4, hi: Vec4) -> Self {
        Self {
            v: s.avx._mm256_setr_m128(lo.into(), hi.into()),
            s,
        }
    }

    /// The integers `i` as floats (each exactly as `i as f32`).
    #[inline(always)]
    pub(crate) fn from_ints(s: V3, i: [i32; 8]) -> Self {
        Self {
            v: s.avx._mm256_cvtepi32_ps(pulp::cast(i)),
            s,
        }
    }

    #[inline(always)]
    fn with(self, v: __m256) -> Self {
        Self { v, s: self.s }
    }

    /// The lanes as floats.
    #[inline(always)]
    pub(crate) fn to_array(self) -> [f32; 8] {
        pulp::cast(self.v)
    }

    /// The square root of every lane.
    #[inline(always)]
    pub(crate) fn sqrt(self) -> Self {
        self.with(self.s.avx._mm256_sqrt_ps(self.v))
    }

    /// `min` as glam's `Vec4::min` (`minps`: `self < o ? self : o`).
    #[inline(always)]
    pub(crate) fn min(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_min_ps(self.v, o.v))
    }

    /// `max` as glam's `Vec4::max` (`maxps`: `self > o ? self : o`).
    #[inline(always)]
    pub(crate) fn max(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_max_ps(self.v, o.v))
    }

    /// The mask of lanes where `self < o` (ordered, as `cmpltps`).
    #[inline(always)]
    pub(crate) fn cmplt(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_cmp_ps::<_CMP_LT_OQ>(self.v, o.v))
    }

    /// The mask of lanes where `self > o` (as `cmpgtps`: `o < self`).
    #[inline(always)]
    pub(crate) fn cmpgt(self, o: Self) -> Self {
        o.cmplt(self)
    }

    /// `a` where `mask` is set, else `b` (a mask of [`Self::cmplt`]).
    #[inline(always)]
    pub(crate) fn select(mask: Self, a: Self, b: Self) -> Self {
        mask.with(mask.s.avx._mm256_blendv_ps(b.v, a.v, mask.v))
    }

    /// The lanes' bits as integers.
    #[inline(always)]
    pub(crate) fn bits(self) -> __m256i {
        self.s.avx._mm256_castps_si256(self.v)
    }
}

impl Add for F8 {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_add_ps(self.v, o.v))
    }
}

impl Sub for F8 {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_sub_ps(self.v, o.v))
    }
}

impl Mul for F8 {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_mul_ps(self.v, o.v))
    }
}

impl MulAssign for F8 {
    #[inline(always)]
    fn mul_assign(&mut self, o: Self) {
        *self = *self * o;
    }
}

impl Div for F8 {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_div_ps(self.v, o.v))
    }
}

impl BitAnd for F8 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, o: Self) -> Self {
        self.with(self.s.avx._mm256_and_ps(self.v, o.v))
    }
}

/// The `x`, `y`, `z` and `w` lanes of eight vectors, `v[k]` in lane `k`.
/// Why halves, then a four-lane transpose in each: one insert per pair
/// of vectors and the eight shuffles a four-lane transpose takes, for
/// twice the lanes.
#[inline(always)]
pub(crate) fn transpose8(s: V3, v: &[Vec4; 8]) -> [F8; 4] {
    let avx = s.avx;
    let a0 = F8::halves(s, v[0], v[4]).v;
    let a1 = F8::halves(s, v[1], v[5]).v;
    let a2 = F8::halves(s, v[2], v[6]).v;
    let a3 = F8::halves(s, v[3], v[7]).v;
    // Per half: x0 x1 y0 y1, x2 x3 y2 y3, z0 z1 w0 w1, z2 z3 w2 w3.
    let t0 = avx._mm256_unpacklo_ps(a0, a1);
    let t1 = avx._mm256_unpacklo_ps(a2, a3);
    let t2 = avx._mm256_unpackhi_ps(a0, a1);
    let t3 = avx._mm256_unpackhi_ps(a2, a3);
    let f = |v: __m256| F8 { v, s };
    [
        f(avx._mm256_shuffle_ps::<0x44>(t0, t1)),
        f(avx._mm256_shuffle_ps::<0xee>(t0, t1)),
        f(avx._mm256_shuffle_ps::<0x44>(t2, t3)),
        f(avx._mm256_shuffle_ps::<0xee>(t2, t3)),
    ]
}

/// [`transpose8`] without the `w` lanes.
#[inline(always)]
pub(crate) fn transpose8_xyz(s: V3, v: &[Vec4; 8]) -> [F8; 3] {
    let [x, y, z, _] = transpose8(s, v);
    [x, y, z]
}

/// Eight RGB lane triples (0..=255) packed as `shade::rgba::pack_rgba`
/// packs four: truncated, alpha 255.
#[inline(always)]
pub(crate) fn pack_rgba8(s: V3, c: [F8; 3]) -> [[u8; 4]; 8] {
    let avx2 = s.avx2;
    // Why spelled out rather than `array::map`: see `pack_rgba`.
    let r = truncated_bits(s, c[0]).bits();
    let g = avx2._mm256_slli_epi32::<8>(truncated_bits(s, c[1]).bits());
    let b = avx2._mm256_slli_epi32::<16>(truncated_bits(s, c[2]).bits());
    let alpha = s.avx._mm256_set1_epi32(0xff00_0000_u32 as i32);
    let word = avx2._mm256_or_si256(avx2._mm256_or_si256(r, g), avx2._mm256_or_si256(b, alpha));
    pulp::cast(word)
}

/// `2^23 + trunc(c)` per lane, as `rgba::truncated_bits` computes it.
#[inline(always)]
fn truncated_bits(s: V3, c: F8) -> F8 {
    const SHIFT: f32 = 8_388_608.0;
    let shifted = c + F8::splat(s, SHIFT);
    let nearest = shifted - F8::splat(s, SHIFT);
    let one = F8::select(nearest.cmpgt(c), F8::splat(s, 1.0), F8::splat(s, 0.0));
    shifted - one
}
