//! The patch frame: an origin and three orthogonal, right-handed axes whose
//! lengths are the node spacing (`|ax|`, `|ay|`) and the displacement step
//! (`|az|`).
//!
//! Stored as 40 bytes: origin (3 × f32), unit rotation quaternion (4 × f32),
//! lengths (3 × f32). The quaternion maps the unit axes X, Y, Z onto the
//! directions of `ax`, `ay`, `az`.
//!
//! A frame may also carry an origin *residual* (`P_exact - P` as f32, see
//! [`Frame::precise_origin`]): a merged scene places a far part's patches
//! with it, and the optional ORGR section stores it (docs/format.md).

use glam::{DVec3, Mat3, Quat, Vec3};

use crate::FormatError;

/// Largest |cos| allowed between two frame axes in [`Frame::new`]
/// (about 0.006°). Fitted frames are orthogonal to about 1e-7.
pub const ORTHOGONALITY_TOLERANCE: f32 = 1e-4;

/// Largest deviation of a stored quaternion's length from 1 accepted when a
/// frame is decoded.
const QUATERNION_NORM_TOLERANCE: f32 = 1e-3;

/// A patch frame.
///
/// # Guarantees
/// All numbers are finite; the lengths are positive; the quaternion's norm is
/// within 1e-3 of 1 (it is normalized before use); the axes are orthogonal
/// and right-handed (`ax × ay` points along `az`); the origin residual is
/// finite and at most one f32 ulp of the origin per coordinate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    origin: Vec3,
    residual: Vec3,
    rotation: Quat,
    lengths: [f32; 3],
}

impl Frame {
    /// Builds a frame from an origin and three axes.
    ///
    /// The axes must be finite, non-zero, orthogonal within
    /// [`ORTHOGONALITY_TOLERANCE`] (as cosines) and right-handed. The stored
    /// rotation is the nearest rotation to the normalized axes, with `w >= 0`.
    pub fn new(origin: Vec3, ax: Vec3, ay: Vec3, az: Vec3) -> Result<Self, FormatError> {
        if !(origin.is_finite() && ax.is_finite() && ay.is_finite() && az.is_finite()) {
            return Err(FormatError::InvalidFrame {
                reason: "non-finite origin or axis",
            });
        }
        let lengths = [ax.length(), ay.length(), az.length()];
        if lengths.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
            return Err(FormatError::InvalidFrame {
                reason: "axis length is zero or overflows",
            });
        }
        let (ux, uy, uz) = (ax / lengths[0], ay / lengths[1], az / lengths[2]);
        let worst_cos = ux.dot(uy).abs().max(ux.dot(uz).abs()).max(uy.dot(uz).abs());
        if worst_cos > ORTHOGONALITY_TOLERANCE {
            return Err(FormatError::InvalidFrame {
                reason: "axes are not orthogonal",
            });
        }
        if ux.cross(uy).dot(uz) <= 0.0 {
            return Err(FormatError::InvalidFrame {
                reason: "axes are left-handed (ax x ay must point along az)",
            });
        }
        // Gram-Schmidt removes the residual skew so the matrix is a rotation.
        let y = (uy - ux * ux.dot(uy)).normalize();
        let z = ux.cross(y);
        let mut rotation = Quat::from_mat3(&Mat3::from_cols(ux, y, z)).normalize();
        if rotation.w < 0.0 {
            rotation = -rotation;
        }
        Ok(Self {
            origin,
            residual: Vec3::ZERO,
            rotation,
            lengths,
        })
    }

    /// Builds a frame from its stored parts (as decoded from a file).
    ///
    /// The quaternion is kept bit for bit; it must be within 1e-3 of unit
    /// length and is normalized whenever axes are computed.
    pub fn from_parts(
        origin: Vec3,
        rotation: Quat,
        lengths: [f32; 3],
    ) -> Result<Self, FormatError> {
        if !(origin.is_finite() && rotation.is_finite()) {
            return Err(FormatError::InvalidFrame {
                reason: "non-finite origin or rotation",
            });
        }
        if (rotation.length() - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
            return Err(FormatError::InvalidFrame {
                reason: "rotation quaternion is not of unit length",
            });
        }
        if lengths.iter().any(|l| !(l.is_finite() && *l > 0.0)) {
            return Err(FormatError::InvalidFrame {
                reason: "axis length is not a positive finite number",
            });
        }
        Ok(Self {
            origin,
            residual: Vec3::ZERO,
            rotation,
            lengths,
        })
    }

    /// The origin `P` (node `(0, 0)` at displacement 0), relative to the
    /// scene offset.
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The origin in f64 relative to the scene offset: `P + residual`.
    ///
    /// Frames built by producers have no residual, so this is `P`; a frame
    /// moved by [`Self::with_precise_origin`] keeps what f32 rounding of `P`
    /// lost, to within 2^-24 of the residual (3.5e-15·|P|: 4e-8 at 1e7).
    pub fn precise_origin(&self) -> DVec3 {
        self.origin.as_dvec3() + self.residual.as_dvec3()
    }

    /// `P_exact - P` (zero unless the frame was placed by
    /// [`Self::with_precise_origin`] or read with an ORGR section).
    pub fn origin_residual(&self) -> Vec3 {
        self.residual
    }

    /// The stored rotation quaternion (maps X, Y, Z onto the axis directions).
    pub fn rotation(&self) -> Quat {
        self.rotation
    }

    /// `[|ax|, |ay|, |az|]`: node spacing along x and y, displacement step.
    pub fn lengths(&self) -> [f32; 3] {
        self.lengths
    }

    /// The unit axis directions `[x̂, ŷ, ẑ]`: the stored quaternion normalized
    /// and applied to X, Y, Z by the exact f32 expression of docs/format.md §1.1
    /// (the same bits on every platform).
    pub fn unit_axes(&self) -> [Vec3; 3] {
        crate::axes::unit_axes(self.rotation)
    }

    /// The scaled axes `[ax, ay, az]`.
    pub fn axes(&self) -> [Vec3; 3] {
        let [x, y, z] = self.unit_axes();
        [
            x * self.lengths[0],
            y * self.lengths[1],
            z * self.lengths[2],
        ]
    }

    /// The same frame moved to another origin (no residual).
    pub fn with_origin(&self, origin: Vec3) -> Result<Self, FormatError> {
        Self::from_parts(origin, self.rotation, self.lengths)
    }

    /// The same frame moved to `origin` given in f64: `P` is its f32
    /// rounding and the residual keeps the rest (see
    /// [`Self::precise_origin`]). Fails when `P` overflows f32.
    pub fn with_precise_origin(&self, origin: DVec3) -> Result<Self, FormatError> {
        let rounded = origin.as_vec3();
        let residual = (origin - rounded.as_dvec3()).as_vec3();
        self.with_origin(rounded)?.with_residual(residual)
    }

    /// The same frame with origin residual `residual` (as read from an
    /// ORGR section). The residual must be finite and at most one f32 ulp
    /// of the origin per coordinate (what f32 rounding can leave).
    pub fn with_residual(&self, residual: Vec3) -> Result<Self, FormatError> {
        let fits = (0..3).all(|k| {
            let (o, r) = (self.origin[k], residual[k]);
            r.is_finite() && r.abs() <= ulp(o)
        });
        if !fits {
            return Err(FormatError::InvalidFrame {
                reason: "origin residual is larger than the origin's f32 rounding",
            });
        }
        Ok(Self { residual, ..*self })
    }
}

/// The gap between `|x|` and the next larger f32 (the smallest subnormal
/// step at zero).
fn ulp(x: f32) -> f32 {
    let a = x.abs();
    f32::from_bits(a.to_bits() + 1) - a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_round_trip_through_the_quaternion() {
        let ax = Vec3::new(0.0, 2.0, 0.0);
        let ay = Vec3::new(0.0, 0.0, 3.0);
        let az = Vec3::new(0.01, 0.0, 0.0);
        let f = Frame::new(Vec3::ONE, ax, ay, az).unwrap();
        let [gx, gy, gz] = f.axes();
        assert!((gx - ax).length() < 1e-6);
        assert!((gy - ay).length() < 1e-6);
        assert!((gz - az).length() < 1e-8);
        assert!(f.rotation().w >= 0.0);
    }

    #[test]
    fn refuses_left_handed_skewed_and_degenerate_axes() {
        assert!(Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, -Vec3::Z).is_err());
        assert!(Frame::new(Vec3::ZERO, Vec3::X, Vec3::new(0.01, 1.0, 0.0), Vec3::Z).is_err());
        assert!(Frame::new(Vec3::ZERO, Vec3::ZERO, Vec3::Y, Vec3::Z).is_err());
        assert!(Frame::new(Vec3::NAN, Vec3::X, Vec3::Y, Vec3::Z).is_err());
        assert!(
            Frame::from_parts(Vec3::ZERO, Quat::from_xyzw(0.0, 0.0, 0.0, 2.0), [1.0; 3]).is_err()
        );
    }

    #[test]
    fn a_precise_origin_keeps_what_f32_rounding_loses() {
        let f = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        for p in [
            DVec3::new(1e7 + 0.123_456, -3e6 - 0.5e-3, 0.25),
            DVec3::new(1e4 + 1e-5, 1e6 + 7e-7, -1e7 - 0.333),
            DVec3::new(1e-30, 0.0, -0.1),
        ] {
            let g = f.with_precise_origin(p).unwrap();
            let err = (g.precise_origin() - p).abs().max_element();
            assert!(err <= 4e-15 * p.abs().max_element(), "{p}: {err}");
            assert_eq!(g.origin(), p.as_vec3());
        }
        assert!(f.with_residual(Vec3::new(0.0, 1e-3, 0.0)).is_err());
        assert!(f.with_residual(Vec3::new(f32::NAN, 0.0, 0.0)).is_err());
        let far = f.with_origin(Vec3::splat(1e7)).unwrap();
        assert!(far.with_residual(Vec3::splat(0.5)).is_ok());
        assert!(far.with_residual(Vec3::splat(1.5)).is_err());
    }
}
