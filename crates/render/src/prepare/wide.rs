//! Eight `f32` lanes for the preparation kernels ([`crate::prepare::cone`]),
//! one source for two instruction sets: two of glam's 128-bit vectors on
//! the portable build (SSE2), one 256-bit register where the CPU has AVX2
//! ([`crate::isa::Isa`]). Every operation is the same IEEE operation lane
//! by lane in both (no fused multiply-add; `min`, `max` and `select` with
//! the SSE instructions' semantics), so both compute the same values.
//!
//! Why explicit lanes: plain `[f32; 8]` loops were left scalar by the
//! compiler (the normal cone took twice its 128-bit time; callgrind,
//! `spatch render bunny.spatch -o out.png --threads 1`).
//!
//! Cost: one instruction per operation (two on the portable build).

use glam::{IVec4, Mat4, Vec4};

/// Lanes a [`Wide`] vector holds.
pub(crate) const LANES: usize = 8;

/// Eight `f32` lanes as plain values (for storing and reducing).
pub(crate) type Lanes = [f32; LANES];

/// The operations of eight `f32` lanes with one instruction set (the
/// implementor is the token that proves the CPU has it).
pub(crate) trait Wide: Copy {
    /// Eight lanes in registers.
    type V: Copy;
    /// `v` in every lane.
    fn splat(self, v: f32) -> Self::V;
    /// The first eight values of `s`.
    fn load(self, s: &[f32]) -> Self::V;
    /// The lanes as an array.
    fn lanes(self, v: Self::V) -> Lanes;
    /// `a + b`.
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a - b`.
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a * b`.
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a / b`.
    fn div(self, a: Self::V, b: Self::V) -> Self::V;
    /// The square root of `a`.
    fn sqrt(self, a: Self::V) -> Self::V;
    /// `a < b ? a : b` (SSE `minps`).
    fn min(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a > b ? a : b` (SSE `maxps`).
    fn max(self, a: Self::V, b: Self::V) -> Self::V;
    /// `a < b ? t : f`.
    fn select_lt(self, a: Self::V, b: Self::V, t: Self::V, f: Self::V) -> Self::V;
    /// The first eight values of `s` as `f32` (exact below 2^24).
    fn load_i32(self, s: &[i32]) -> Self::V;
    /// `a` rounded toward zero as `a as i32 as f32` does (through an
    /// integer: `-0.0` and `-0.5` give `+0.0`), for `|a| < 2^23`.
    fn trunc(self, a: Self::V) -> Self::V;
    /// Eight vectors `(x, y, z, 0)`, one per lane of `x`, `y`, `z`. Why
    /// written out (no `map`, no `from_fn`): the calls those left out of
    /// line ran without the caller's instruction set.
    #[inline(always)]
    fn columns(self, [x, y, z]: [Self::V; 3]) -> [Vec4; LANES] {
        let (x, y, z) = (self.lanes(x), self.lanes(y), self.lanes(z));
        let half = |h: usize| {
            let four = |v: &Lanes| Vec4::from_slice(&v[4 * h..4 * h + 4]);
            Mat4::from_cols(four(&x), four(&y), four(&z), Vec4::ZERO).transpose()
        };
        let (a, b) = (half(0), half(1));
        [
            a.x_axis, a.y_axis, a.z_axis, a.w_axis, b.x_axis, b.y_axis, b.z_axis, b.w_axis,
        ]
    }
}

/// The portable build's lanes: two of glam's 128-bit vectors (SSE2 on
/// x86-64).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Portable;

/// The first four values of `s` as a vector (one unaligned load).
#[inline(always)]
fn four(s: &[f32]) -> Vec4 {
    let lanes: [f32; 4] = s[..4].try_into().expect("four");
    Vec4::from(lanes)
}

impl Wide for Portable {
    type V = [Vec4; 2];
    #[inline(always)]
    fn splat(self, v: f32) -> Self::V {
        [Vec4::splat(v); 2]
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> Self::V {
        [four(s), four(&s[4..])]
    }
    #[inline(always)]
    fn lanes(self, [a, b]: Self::V) -> Lanes {
        let (a, b) = (a.to_array(), b.to_array());
        [a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]]
    }
    #[inline(always)]
    fn add(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] + b[0], a[1] + b[1]]
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] - b[0], a[1] - b[1]]
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] * b[0], a[1] * b[1]]
    }
    #[inline(always)]
    fn div(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0] / b[0], a[1] / b[1]]
    }
    #[inline(always)]
    fn sqrt(self, a: Self::V) -> Self::V {
        [a[0].sqrt(), a[1].sqrt()]
    }
    #[inline(always)]
    fn min(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0].min(b[0]), a[1].min(b[1])]
    }
    #[inline(always)]
    fn max(self, a: Self::V, b: Self::V) -> Self::V {
        [a[0].max(b[0]), a[1].max(b[1])]
    }
    #[inline(always)]
    fn select_lt(self, a: Self::V, b: Self::V, t: Self::V, f: Self::V) -> Self::V {
        let pick = |k: usize| Vec4::select(a[k].cmplt(b[k]), t[k], f[k]);
        [pick(0), pick(1)]
    }
    #[inline(always)]
    fn load_i32(self, s: &[i32]) -> Self::V {
        let four = |s: &[i32]| {
            let lanes: [i32; 4] = s[..4].try_into().expect("four");
            IVec4::from(lanes).as_vec4()
        };
        [four(s), four(&s[4..])]
    }
    #[inline(always)]
    fn trunc(self, a: Self::V) -> Self::V {
        // glam's SSE2 truncation goes through `cvttps2dq` below 2^23.
        [a[0].trunc(), a[1].trunc()]
    }
}

#[cfg(target_arch = "x86_64")]
impl Wide for pulp::x86::V3 {
    type V = pulp::f32x8;
    #[inline(always)]
    fn splat(self, v: f32) -> Self::V {
        self.splat_f32x8(v)
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> Self::V {
        let lanes: Lanes = s[..LANES].try_into().expect("eight");
        pulp::bytemuck::cast(lanes)
    }
    #[inline(always)]
    fn lanes(self, v: Self::V) -> Lanes {
        pulp::bytemuck::cast(v)
    }
    #[inline(always)]
    fn add(self, a: Self::V, b: Self::V) -> Self::V {
        self.add_f32x8(a, b)
    }
    #[inline(always)]
    fn sub(self, a: Self::V, b: Self::V) -> Self::V {
        self.sub_f32x8(a, b)
    }
    #[inline(always)]
    fn mul(self, a: Self::V, b: Self::V) -> Self::V {
        self.mul_f32x8(a, b)
    }
    #[inline(always)]
    fn div(self, a: Self::V, b: Self::V) -> Self::V {
        self.div_f32x8(a, b)
    }
    #[inline(always)]
    fn sqrt(self, a: Self::V) -> Self::V {
        self.sqrt_f32x8(a)
    }
    #[inline(always)]
    fn min(self, a: Self::V, b: Self::V) -> Self::V {
        self.min_f32x8(a, b)
    }
    #[inline(always)]
    fn max(self, a: Self::V, b: Self::V) -> Self::V {
        self.max_f32x8(a, b)
    }
    #[inline(always)]
    fn select_lt(self, a: Self::V, b: Self::V, t: Self::V, f: Self::V) -> Self::V {
        self.select_f32x8(self.cmp_lt_f32x8(a, b), t, f)
    }
    #[inline(always)]
    fn load_i32(self, s: &[i32]) -> Self::V {
        let lanes: [i32; LANES] = s[..LANES].try_into().expect("eight");
        self.convert_i32x8_to_f32x8(pulp::bytemuck::cast(lanes))
    }
    #[inline(always)]
    fn trunc(self, a: Self::V) -> Self::V {
        self.convert_i32x8_to_f32x8(self.convert_f32x8_to_i32x8(a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both instruction sets give every operation's lanes bit for bit as
    /// one `f32` at a time does.
    #[test]
    fn every_instruction_set_computes_each_lane_as_one_by_one() {
        let mut rng = crate::test_rng::XorShift(0x1a9e_5eed);
        for _ in 0..500 {
            let mut value = || (rng.unit() - 0.5) * 400.0;
            let (a, b): (Lanes, Lanes) = (
                std::array::from_fn(|_| value()),
                std::array::from_fn(|_| value()),
            );
            let expected: [Lanes; 7] = [
                std::array::from_fn(|l| a[l] + b[l]),
                std::array::from_fn(|l| a[l] - b[l]),
                std::array::from_fn(|l| a[l] * b[l]),
                std::array::from_fn(|l| a[l] / b[l]),
                std::array::from_fn(|l| a[l].abs().sqrt()),
                std::array::from_fn(|l| a[l].min(b[l])),
                std::array::from_fn(|l| if a[l] < b[l] { b[l] } else { a[l] * 2.0 }),
            ];
            check(Portable, &a, &b, &expected);
            #[cfg(target_arch = "x86_64")]
            if let Some(v3) = pulp::x86::V3::try_new() {
                check(v3, &a, &b, &expected);
            }
        }
    }

    fn check<W: Wide>(w: W, a: &Lanes, b: &Lanes, expected: &[Lanes; 7]) {
        let (va, vb) = (w.load(a), w.load(b));
        let abs: Lanes = a.map(f32::abs);
        let twice = w.mul(va, w.splat(2.0));
        let got = [
            w.add(va, vb),
            w.sub(va, vb),
            w.mul(va, vb),
            w.div(va, vb),
            w.sqrt(w.load(&abs)),
            w.min(va, vb),
            w.select_lt(va, vb, vb, twice),
        ];
        for (g, e) in got.iter().zip(expected) {
            assert_eq!(w.lanes(*g).map(f32::to_bits), e.map(f32::to_bits));
        }
        let max = w.lanes(w.max(va, vb));
        let negative_zero = w.lanes(w.trunc(w.mul(w.splat(-0.25), w.splat(1.0))));
        assert_eq!(negative_zero.map(f32::to_bits), [0; LANES]);
        let ints: [i32; LANES] = a.map(|v| v as i32);
        let (from_ints, cut) = (w.lanes(w.load_i32(&ints)), w.lanes(w.trunc(va)));
        let columns = w.columns([va, vb, twice]);
        for l in 0..LANES {
            assert_eq!(max[l], a[l].max(b[l]));
            assert_eq!(from_ints[l], ints[l] as f32);
            assert_eq!(cut[l].to_bits(), (a[l] as i32 as f32).to_bits());
            assert_eq!(columns[l], Vec4::new(a[l], b[l], w.lanes(twice)[l], 0.0));
        }
    }
}
