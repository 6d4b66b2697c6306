//! The unit axes of a stored frame quaternion, as an exact f32 expression.
//!
//! Input: the quaternion `(x, y, z, w)` as stored in FRAM (norm within 1e-3 of
//! 1). Output: the unit axes `x̂, ŷ, ẑ` = the normalized quaternion applied to
//! X, Y and Z. Every operation is one IEEE-754 single-precision operation
//! (round to nearest, no fused multiply-add) in the order written here and in
//! docs/format.md §1.1, so any reader on any platform that follows the text gets
//! the same bits. The order is the one glam 0.34 uses on x86-64 (SSE2), which
//! this crate used before writing it out: files and renders did not change
//! (`the_written_out_axes_match_glam_bit_for_bit` checks it on x86-64).
//!
//! Cost: 36 multiplications, 27 additions, one square root and four divisions
//! per frame.

use glam::{Quat, Vec3};

/// The stored quaternion divided by its norm `sqrt((x·x + z·z) + (y·y + w·w))`.
fn normalize(q: Quat) -> [f32; 4] {
    let n = ((q.x * q.x + q.z * q.z) + (q.y * q.y + q.w * q.w)).sqrt();
    [q.x / n, q.y / n, q.z / n, q.w / n]
}

/// `v` rotated by the unit quaternion `q = (b, w)`:
/// `(v·(w·w − b·b) + b·((v·b)·2)) + (b × v)·(w·2)`, with
/// `b·b = (x·x + y·y) + z·z`, `v·b = (v₀·x + v₁·y) + v₂·z` and
/// `b × v = (y·v₂ − v₁·z, z·v₀ − v₂·x, x·v₁ − v₀·y)`.
fn rotate(q: [f32; 4], v: [f32; 3]) -> [f32; 3] {
    let [x, y, z, w] = q;
    let b = [x, y, z];
    let bb = (x * x + y * y) + z * z;
    let c = w * w - bb;
    let vb2 = ((v[0] * x + v[1] * y) + v[2] * z) * 2.0;
    let cross = [
        y * v[2] - v[1] * z,
        z * v[0] - v[2] * x,
        x * v[1] - v[0] * y,
    ];
    let w2 = w * 2.0;
    let mut out = [0.0; 3];
    for k in 0..3 {
        out[k] = (v[k] * c + b[k] * vb2) + cross[k] * w2;
    }
    out
}

/// The unit axes `[x̂, ŷ, ẑ]` of the stored quaternion `q`: `q` normalized,
/// then applied to `(1, 0, 0)`, `(0, 1, 0)` and `(0, 0, 1)` (the terms with 0
/// and 1 are evaluated too; they only decide the sign of a zero).
pub(crate) fn unit_axes(q: Quat) -> [Vec3; 3] {
    let q = normalize(q);
    let axis = |v| Vec3::from_array(rotate(q, v));
    [
        axis([1.0, 0.0, 0.0]),
        axis([0.0, 1.0, 0.0]),
        axis([0.0, 0.0, 1.0]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quaternions near unit length in every octant, from a fixed sequence.
    fn quaternions() -> Vec<Quat> {
        let mut state = 0x2545_f491_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            (state as f32 / u32::MAX as f32) * 2.0 - 1.0
        };
        let mut out = vec![Quat::IDENTITY, Quat::from_xyzw(0.0, 0.0, 1.0, 0.0)];
        for _ in 0..20_000 {
            let q = Quat::from_xyzw(next(), next(), next(), next());
            let len = q.length();
            if len > 0.1 {
                // Off unit length by up to 1e-3, as the reader accepts.
                out.push(q * ((1.0 + next() * 1e-3) / len));
            }
        }
        out
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_written_out_axes_match_glam_bit_for_bit() {
        for q in quaternions() {
            let n = q.normalize();
            let glam = [n * Vec3::X, n * Vec3::Y, n * Vec3::Z];
            let ours = unit_axes(q);
            for k in 0..3 {
                assert_eq!(
                    ours[k].to_array().map(f32::to_bits),
                    glam[k].to_array().map(f32::to_bits),
                    "{q:?} axis {k}"
                );
            }
        }
    }

    #[test]
    fn pinned_axes_of_one_quaternion() {
        // The bits an independent reader must get for this stored quaternion
        // (computed by the expression of docs/format.md §1.1).
        let q = Quat::from_xyzw(0.1, -0.7, 0.3, 0.64);
        let bits = unit_axes(q).map(|a| a.to_array().map(f32::to_bits));
        assert_eq!(bits, PINNED, "{bits:x?}");
    }

    const PINNED: [[u32; 3]; 3] = [
        [0xbe24_50be, 0x3e79_f4bb, 0x3f74_d57d],
        [0xbf06_329b, 0x3f4c_c78e, 0xbe95_9058],
        [0xbf56_1a05, 0xbf0c_581a, 0xb9d1_d200],
    ];

    #[test]
    fn the_axes_are_orthonormal() {
        for q in quaternions() {
            let [x, y, z] = unit_axes(q);
            assert!((x.length() - 1.0).abs() < 1e-5 && (z.length() - 1.0).abs() < 1e-5);
            assert!(x.dot(y).abs() < 1e-5 && x.cross(y).dot(z) > 0.999);
        }
    }
}
