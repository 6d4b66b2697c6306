//! Blinn-Phong shading with lights moved into patch space.
//!
//! The light is directional and the viewer at infinity, so the light
//! direction `L` and half vector `H` are constants in world space. For each
//! patch they are rotated once into patch space (`R^T L`, `R^T H`) and kept
//! in a [`ShadeFrame`]; normals reconstructed in patch space from
//! displacement differences are then shaded without ever being rotated to
//! world space. Meshes use one world-space frame.
//!
//! Two-sided lighting, per shaded sample: a frame of a surface whose back
//! may show carries `V`, the unit direction from its patch's centre to the
//! eye in the same space; a sample whose normal has `n·V < 0` is shaded
//! with `-L` and `-H`, which is the same as flipping its normal. A frame
//! whose back is culled has `V = 0` and never flips. Deciding per sample,
//! not per patch, keeps the front cells of a patch whose cone axis faces
//! away (a bent or overlapping patch of a scan) lit from the front.
//!
//! Colour: `albedo · (ambient + diffuse · max(0, n·L)) + 255 · specular ·
//! max(0, n·H)^shininess` (the specular term only where `n·L > 0`), clamped
//! to 0..=255. `powi` (repeated multiplication) keeps results independent of
//! the platform's libm.
//!
//! Packed formats: normals as three signed 10-bit fields (`round(511 · c)`),
//! colours as RGBA8 in a `u32` (little-endian byte order).
//!
//! Cost: one normalization, two dot products and one `powi` per shaded
//! sample.

use glam::{DMat3, DVec3, Vec3, Vec4};

use crate::options::Lighting;
#[cfg(target_arch = "x86_64")]
use crate::wide::F8;

/// Light and half vector in the space where normals are expressed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ShadeFrame {
    pub(crate) light: Vec3,
    pub(crate) half: Vec3,
    /// Unit direction to the eye for a two-sided frame, zero for a frame
    /// that is never flipped.
    pub(crate) view: Vec3,
}

impl ShadeFrame {
    /// A one-sided frame (never flipped) with `light` and `half`.
    pub(crate) fn one_sided(light: Vec3, half: Vec3) -> Self {
        Self {
            light,
            half,
            view: Vec3::ZERO,
        }
    }
}

/// World-space light and half vector of one frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct WorldLight {
    pub(crate) light: DVec3,
    pub(crate) half: DVec3,
}

impl WorldLight {
    /// The light of `lighting` for an eye frame `[right, up, back]`.
    pub(crate) fn new(lighting: &Lighting, basis: [DVec3; 3]) -> Self {
        let [x, y, z] = lighting.direction.map(f64::from);
        let light = (basis[0] * x + basis[1] * y + basis[2] * z).normalize();
        let half = (light + basis[2]).normalize_or(basis[2]);
        Self { light, half }
    }

    /// The frame for normals in a space whose unit axes (in world space)
    /// are the columns of `rotation`; `to_eye` (world space, any length)
    /// makes it two-sided: samples whose normal faces away from it are
    /// shaded as if flipped.
    pub(crate) fn frame_in(&self, rotation: &DMat3, to_eye: Option<DVec3>) -> ShadeFrame {
        let inv = rotation.transpose();
        let view = to_eye.map_or(DVec3::ZERO, |v| inv * v.normalize_or_zero());
        ShadeFrame {
            light: (inv * self.light).as_vec3(),
            half: (inv * self.half).as_vec3(),
            view: view.as_vec3(),
        }
    }
}

/// Precomputed material terms.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Material {
    ambient: f32,
    diffuse: f32,
    specular: f32,
    shininess: i32,
    /// `log2(shininess)` when it is a power of two, else `u32::MAX`.
    squarings: u32,
}

impl Material {
    pub(crate) fn new(lighting: &Lighting) -> Self {
        Self {
            ambient: lighting.ambient,
            diffuse: lighting.diffuse,
            specular: lighting.specular * 255.0,
            shininess: lighting.shininess as i32,
            squarings: if lighting.shininess.is_power_of_two() {
                lighting.shininess.trailing_zeros()
            } else {
                u32::MAX
            },
        }
    }

    /// Shades a (not necessarily unit) normal; returns RGB in 0..=255 floats.
    #[inline]
    pub(crate) fn shade(&self, normal: Vec3, frame: &ShadeFrame, albedo: Vec3) -> Vec3 {
        // `normalize_or_zero`, with its finiteness test as two compares
        // (same result: NaN fails both). Why: it was a dozen integer
        // instructions per shaded pixel (callgrind, `profile_sphere 500 1`).
        let rcp = 1.0 / normal.length();
        let n = if rcp > 0.0 && rcp < f32::INFINITY {
            normal * rcp
        } else {
            Vec3::ZERO
        };
        // Two-sided: multiplying by 1 is exact, so one-sided frames shade
        // bit for bit as without the test.
        let side = if n.dot(frame.view) < 0.0 { -1.0 } else { 1.0 };
        let nl = (side * n.dot(frame.light)).max(0.0);
        let nh = (side * n.dot(frame.half)).max(0.0);
        let spec = if nl > 0.0 {
            self.specular * self.power(nh)
        } else {
            0.0
        };
        (albedo * (self.ambient + self.diffuse * nl) + Vec3::splat(spec)).min(Vec3::splat(255.0))
    }
}

/// [`Material::shade4_with`] for any material.
pub(crate) const ANY_POWER: u32 = u32::MAX;

/// Four shading inputs, one per lane: each field holds one component of
/// four normals, lights, half vectors or albedos.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lanes {
    pub(crate) normal: [Vec4; 3],
    pub(crate) light: [Vec4; 3],
    pub(crate) half: [Vec4; 3],
    /// The frames' directions to the eye (zero: one-sided).
    pub(crate) view: [Vec4; 3],
    pub(crate) albedo: [Vec4; 3],
}

/// [`Lanes`] of eight samples ([`Material::shade8_with`]).
#[cfg(target_arch = "x86_64")]
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lanes8 {
    /// The instruction set the lanes live in.
    pub(crate) simd: pulp::x86::V3,
    pub(crate) normal: [F8; 3],
    pub(crate) light: [F8; 3],
    pub(crate) half: [F8; 3],
    /// The frames' directions to the eye (zero: one-sided).
    pub(crate) view: [F8; 3],
    pub(crate) albedo: [F8; 3],
}

impl Material {
    /// The number of squarings that give the specular power (`shininess`
    /// a power of two), else [`ANY_POWER`].
    pub(crate) fn squarings(&self) -> u32 {
        self.squarings
    }

    /// [`Self::shade`] of four samples at once, lane by lane; returns the
    /// red, green and blue lanes. Every lane performs the same IEEE
    /// operations in the same order as [`Self::shade`], so the results are
    /// bit-identical (tested). Why: the resolve pass shades every covered
    /// pixel, and four lanes share each instruction (callgrind,
    /// `profile_sphere 500 1`).
    ///
    /// `SQUARINGS` is [`ANY_POWER`] or the material's [`Self::squarings`]:
    /// then the specular power is that many squarings, no choice at run
    /// time. Why: the choice and its register spills were ~10 instructions
    /// per group of four pixels (callgrind, `profile_sphere 500 1`).
    #[inline(always)]
    pub(crate) fn shade4_with<const SQUARINGS: u32>(&self, l: &Lanes) -> [Vec4; 3] {
        let [x, y, z] = l.normal;
        let dot = |a: [Vec4; 3], b: [Vec4; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let rcp = Vec4::ONE / (x * x + y * y + z * z).sqrt();
        let valid = rcp.cmpgt(Vec4::ZERO) & rcp.cmplt(Vec4::INFINITY);
        let n = [x, y, z].map(|c| Vec4::select(valid, c * rcp, Vec4::ZERO));
        let side = Vec4::select(dot(n, l.view).cmplt(Vec4::ZERO), -Vec4::ONE, Vec4::ONE);
        let nl = (side * dot(n, l.light)).max(Vec4::ZERO);
        let nh = (side * dot(n, l.half)).max(Vec4::ZERO);
        let p = if SQUARINGS == ANY_POWER {
            self.power4(nh)
        } else {
            debug_assert_eq!(SQUARINGS, self.squarings);
            squared(nh, SQUARINGS)
        };
        let spec = Vec4::select(
            nl.cmpgt(Vec4::ZERO),
            Vec4::splat(self.specular) * p,
            Vec4::ZERO,
        );
        let k = Vec4::splat(self.ambient) + Vec4::splat(self.diffuse) * nl;
        l.albedo.map(|a| (a * k + spec).min(Vec4::splat(255.0)))
    }

    /// [`Self::shade4_with`] of eight samples at once: the same IEEE
    /// operations in the same order in every lane, so bit-identical to
    /// [`Self::shade`] (tested). Why: the AVX2 copy of the resolve pass
    /// shades eight neighbouring pixels per instruction
    /// ([`crate::shade::resolve_wide`]).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    pub(crate) fn shade8_with<const SQUARINGS: u32>(&self, l: &Lanes8) -> [F8; 3] {
        let s = l.simd;
        let [x, y, z] = l.normal;
        let dot = |a: [F8; 3], b: [F8; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let (zero, one) = (F8::splat(s, 0.0), F8::splat(s, 1.0));
        let rcp = one / (x * x + y * y + z * z).sqrt();
        let valid = rcp.cmpgt(zero) & rcp.cmplt(F8::splat(s, f32::INFINITY));
        let n = [
            F8::select(valid, x * rcp, zero),
            F8::select(valid, y * rcp, zero),
            F8::select(valid, z * rcp, zero),
        ];
        let side = F8::select(dot(n, l.view).cmplt(zero), F8::splat(s, -1.0), one);
        let nl = (side * dot(n, l.light)).max(zero);
        let nh = (side * dot(n, l.half)).max(zero);
        let p = if SQUARINGS == ANY_POWER {
            self.power_any(nh, one)
        } else {
            debug_assert_eq!(SQUARINGS, self.squarings);
            squared(nh, SQUARINGS)
        };
        let spec = F8::select(nl.cmpgt(zero), F8::splat(s, self.specular) * p, zero);
        let k = F8::splat(s, self.ambient) + F8::splat(s, self.diffuse) * nl;
        let max = F8::splat(s, 255.0);
        let [r, g, b] = l.albedo;
        [
            (r * k + spec).min(max),
            (g * k + spec).min(max),
            (b * k + spec).min(max),
        ]
    }

    /// [`Self::power`] of four lanes. Why a `match` of unrolled squarings:
    /// the squaring loop with its set-up was ~24 instructions per group of
    /// four pixels, 5 straight multiplications for the default shininess
    /// 32 (callgrind, `profile_sphere 500 1`).
    #[inline(always)]
    fn power4(&self, x: Vec4) -> Vec4 {
        let sq = |p: Vec4| p * p;
        match self.squarings {
            0 => x,
            1 => sq(x),
            2 => sq(sq(x)),
            3 => sq(sq(sq(x))),
            4 => sq(sq(sq(sq(x)))),
            5 => sq(sq(sq(sq(sq(x))))),
            6 => sq(sq(sq(sq(sq(sq(x)))))),
            7 => sq(sq(sq(sq(sq(sq(sq(x))))))),
            8 => sq(sq(sq(sq(sq(sq(sq(sq(x)))))))),
            _ => self.power4_any(x),
        }
    }

    /// [`Self::power4`] for any shininess: [`Self::power_any`] out of line.
    #[inline(never)]
    fn power4_any(&self, x: Vec4) -> Vec4 {
        self.power_any(x, Vec4::ONE)
    }

    /// `x^shininess` of one sample ([`Self::power_any`]).
    #[inline(always)]
    fn power(&self, x: f32) -> f32 {
        self.power_any(x, 1.0)
    }

    /// `x^shininess` in any lanes (`one`: lanes of 1), bit-identical to
    /// [`powi`]. Why: for a power of two (the default, 32)
    /// square-and-multiply is just repeated squaring, which drops the
    /// loop's bit tests (callgrind, `profile_sphere 500 1`).
    #[inline(always)]
    fn power_any<T: Copy + std::ops::MulAssign>(&self, x: T, one: T) -> T {
        if self.squarings == u32::MAX {
            return powi(x, self.shininess as u32, one);
        }
        squared(x, self.squarings)
    }
}

/// `x` squared `n` times (`x^(2^n)`), the same multiplications in any
/// lanes.
#[inline(always)]
fn squared<T: Copy + std::ops::MulAssign>(mut x: T, n: u32) -> T {
    for _ in 0..n {
        x *= x;
    }
    x
}

/// `x^n` by the same square-and-multiply sequence as `f32::powi` (so the
/// result is bit-identical), inlined. Why: `powi` with a run-time exponent
/// is an out-of-line `__powisf2` call per shaded pixel (5 M instructions
/// per 500² sphere frame, callgrind `profile_sphere 500 1`).
/// Generic over the lanes: `f32`, `Vec4` or eight lanes (`one` is their 1).
#[inline]
fn powi<T: Copy + std::ops::MulAssign>(mut x: T, mut n: u32, one: T) -> T {
    let mut r = one;
    loop {
        if n & 1 != 0 {
            r *= x;
        }
        n >>= 1;
        if n == 0 {
            return r;
        }
        x *= x;
    }
}

/// Packs a normal (components in -1..=1) into three signed 10-bit fields.
#[cfg(test)]
#[inline]
pub(crate) fn pack_normal(n: Vec3) -> u32 {
    let q = |c: f32| ((c.clamp(-1.0, 1.0) * 511.0).round() as i32 & 0x3ff) as u32;
    q(n.x) | (q(n.y) << 10) | (q(n.z) << 20)
}

/// Packs a fixed-point normal (16 fractional bits) without float maths.
#[inline]
pub(crate) fn pack_fixed_normal(x: i32, y: i32, z: i32) -> u32 {
    // 511 / 65536 ≈ 1 / 128.25: a shift by 7 keeps the error under 0.3 %.
    let q = |c: i32| ((c >> 7).clamp(-511, 511) & 0x3ff) as u32;
    q(x) | (q(y) << 10) | (q(z) << 20)
}

/// Unpacks a normal packed by `pack_normal` (not normalized).
#[inline]
pub(crate) fn unpack_normal(p: u32) -> Vec3 {
    let f = |shift: u32| (((p >> shift) << 22) as i32 >> 22) as f32;
    Vec3::new(f(0), f(10), f(20))
}

/// Packs RGB floats (0..=255) and alpha 255 into a `u32`.
#[inline]
pub(crate) fn pack_colour(c: Vec3) -> u32 {
    u32::from_le_bytes([c.x as u8, c.y as u8, c.z as u8, 255])
}

/// Unpacks RGB from a packed colour.
#[inline]
pub(crate) fn unpack_rgb(p: u32) -> Vec3 {
    byte_lanes(p.to_le_bytes()).truncate()
}

/// Four bytes (a packed colour, or a stored albedo of
/// [`crate::prepare::level_shading::LevelShading::colours`]) as floats, each
/// exact.
#[inline(always)]
pub(crate) fn byte_lanes(c: [u8; 4]) -> Vec4 {
    // Why the bytes widened in one register on x86-64 (SSE2, always there,
    // so the check folds away; pulp's token makes the intrinsics safe): the
    // portable form converts the four bytes one by one and builds the
    // vector from scalars, four corners per coloured pixel (mannequin 500²:
    // 38.21 → 36.19 M instructions per frame, callgrind; see
    // docs/algorithms/render.md, "Resolve"). Both forms give the same
    // exact floats.
    #[cfg(target_arch = "x86_64")]
    if let Some(sse2) = pulp::core_arch::x86::Sse2::try_new() {
        let bytes = sse2._mm_cvtsi32_si128(i32::from_le_bytes(c));
        let zero = sse2._mm_setzero_si128();
        let words = sse2._mm_unpacklo_epi8(bytes, zero);
        let ints = sse2._mm_unpacklo_epi16(words, zero);
        return sse2._mm_cvtepi32_ps(ints).into();
    }
    glam::U8Vec4::from_array(c).as_vec4()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The widened bytes equal glam's one-by-one conversion for every byte
    /// in every channel, and a packed colour unpacks to its three bytes.
    #[test]
    fn byte_lanes_convert_every_byte_exactly() {
        for v in 0..=255u8 {
            for c in [
                [v, 0, 0, 0],
                [0, v, 0, 0],
                [0, 0, v, 0],
                [v, 255 - v, v / 2, v / 3],
            ] {
                let lanes = byte_lanes(c);
                assert_eq!(lanes, glam::U8Vec4::from_array(c).as_vec4(), "{c:?}");
                let rgb = Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
                assert_eq!(unpack_rgb(u32::from_le_bytes(c)), rgb, "{c:?}");
            }
        }
    }

    #[test]
    fn packed_normals_round_trip() {
        let n = Vec3::new(-0.3, 0.5, 0.81).normalize();
        let back = unpack_normal(pack_normal(n)).normalize();
        assert!((back - n).length() < 4e-3);
        let f = |v: f32| (v * 65536.0) as i32;
        let back = unpack_normal(pack_fixed_normal(f(n.x), f(n.y), f(n.z))).normalize();
        assert!((back - n).length() < 4e-3);
    }

    #[test]
    fn four_lanes_shade_exactly_like_one() {
        // A small deterministic generator: no dependency for a test.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
        };
        for shininess in [1, 2, 7, 32, 64, 100, 256] {
            let m = Material::new(&Lighting {
                shininess,
                ..Lighting::default()
            });
            for _ in 0..200 {
                let mut v = || Vec3::new(next(), next(), next());
                let samples: [(Vec3, ShadeFrame, Vec3); 4] = std::array::from_fn(|k| {
                    // Lane 3 gets a zero normal (the degenerate branch).
                    let n = if k == 3 { Vec3::ZERO } else { v() };
                    // Lanes 0 and 2 two-sided, lane 1 one-sided.
                    let frame = ShadeFrame {
                        light: v().normalize(),
                        half: v().normalize(),
                        view: if k == 1 { Vec3::ZERO } else { v().normalize() },
                    };
                    (n, frame, (v() + Vec3::ONE) * 127.0)
                });
                let lane = |f: &dyn Fn(usize) -> Vec3| {
                    let c: [Vec3; 4] = std::array::from_fn(f);
                    [0, 1, 2].map(|i| Vec4::from_array(c.map(|v| v[i])))
                };
                let lanes = Lanes {
                    normal: lane(&|k| samples[k].0),
                    light: lane(&|k| samples[k].1.light),
                    half: lane(&|k| samples[k].1.half),
                    view: lane(&|k| samples[k].1.view),
                    albedo: lane(&|k| samples[k].2),
                };
                let out = m.shade4_with::<ANY_POWER>(&lanes);
                if shininess == 32 {
                    assert_eq!(m.squarings(), 5);
                    let five = m.shade4_with::<5>(&lanes);
                    let bits = |v: Vec4| v.to_array().map(f32::to_bits);
                    assert!((0..3).all(|i| bits(five[i]) == bits(out[i])));
                }
                for (k, (n, frame, albedo)) in samples.iter().enumerate() {
                    let one = m.shade(*n, frame, *albedo);
                    for i in 0..3 {
                        assert_eq!(out[i][k].to_bits(), one[i].to_bits(), "lane {k}");
                    }
                }
            }
        }
    }

    #[test]
    fn power_matches_powi_for_every_shininess() {
        for shininess in [1, 2, 3, 8, 32, 33, 100, 256] {
            let m = Material::new(&Lighting {
                shininess,
                ..Lighting::default()
            });
            for x in [0.0f32, 0.3, 0.77, 0.999, 1.0] {
                assert_eq!(m.power(x).to_bits(), x.powi(shininess as i32).to_bits());
            }
        }
    }

    #[test]
    fn facing_light_is_brighter_than_grazing_and_clamped() {
        let m = Material::new(&Lighting::default());
        let frame = ShadeFrame {
            view: Vec3::ZERO,
            light: Vec3::Z,
            half: Vec3::Z,
        };
        let white = Vec3::splat(255.0);
        let lit = m.shade(Vec3::Z, &frame, white);
        let grazing = m.shade(Vec3::X, &frame, white);
        assert!(lit.x > grazing.x && lit.x <= 255.0);
        assert!((grazing.x - 255.0 * 0.15).abs() < 1e-3);
    }
}
