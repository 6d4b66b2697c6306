//! Rigid poses: the transform that takes a scan's own coordinates into the common frame.
//!
//! A [`Pose`] is a unit quaternion `q` and a translation `t`; it maps a point `p` of the
//! scan to `q * p * q⁻¹ + t` (rotate, then translate). The Stanford `.conf` convention and how
//! it was established from the bunny scans are in `docs/algorithms/scan.md`.
//!
//! Cost: one quaternion rotation per point (f64).

use glam::{DQuat, DVec3};

/// A rigid transform: rotation then translation.
///
/// # Guarantees
///
/// `rotation` is a finite unit quaternion (normalised on construction) and `translation` is
/// finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    rotation: DQuat,
    translation: DVec3,
}

impl Default for Pose {
    fn default() -> Self {
        Pose::IDENTITY
    }
}

impl Pose {
    /// The pose that leaves points where they are.
    pub const IDENTITY: Pose = Pose {
        rotation: DQuat::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// A pose from a rotation quaternion (any non-zero length; it is normalised) and a
    /// translation. Fails with [`PoseProblem`] when a value is not finite or the quaternion
    /// is zero.
    pub fn new(rotation: DQuat, translation: DVec3) -> Result<Pose, PoseProblem> {
        if !rotation.is_finite() || !translation.is_finite() {
            return Err(PoseProblem::NotFinite);
        }
        let length = rotation.length();
        if length <= 1e-12 {
            return Err(PoseProblem::ZeroQuaternion);
        }
        Ok(Pose {
            rotation: rotation / length,
            translation,
        })
    }

    /// The unit rotation.
    pub fn rotation(&self) -> DQuat {
        self.rotation
    }

    /// The translation (applied after the rotation).
    pub fn translation(&self) -> DVec3 {
        self.translation
    }

    /// Whether this pose moves nothing (exactly the identity).
    pub fn is_identity(&self) -> bool {
        self.translation == DVec3::ZERO
            && (self.rotation == DQuat::IDENTITY || self.rotation == -DQuat::IDENTITY)
    }

    /// `self` after `first`: the pose that applies `first`, then `self`.
    pub fn after(&self, first: &Pose) -> Pose {
        Pose {
            rotation: (self.rotation * first.rotation).normalize(),
            translation: self.rotation * first.translation + self.translation,
        }
    }

    /// Maps a point of the scan into the common frame.
    #[inline]
    pub fn apply_point(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation
    }

    /// Maps a direction (a normal): rotation only.
    #[inline]
    pub fn apply_vector(&self, v: DVec3) -> DVec3 {
        self.rotation * v
    }
}

/// Why a pose is not usable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PoseProblem {
    /// A component is NaN or infinite.
    #[error("the pose has a value that is not finite")]
    NotFinite,
    /// The quaternion has (nearly) zero length, so it names no rotation.
    #[error("the pose's quaternion has zero length")]
    ZeroQuaternion,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_then_translation() {
        let quarter = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
        let pose = Pose::new(quarter * 2.0, DVec3::new(0.0, 0.0, 1.0)).unwrap();
        let p = pose.apply_point(DVec3::X);
        assert!((p - DVec3::new(0.0, 1.0, 1.0)).length() < 1e-12, "{p}");
        assert!((pose.apply_vector(DVec3::X) - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn composition_matches_applying_twice() {
        let a = Pose::new(DQuat::from_rotation_x(0.3), DVec3::new(1.0, 2.0, 3.0)).unwrap();
        let b = Pose::new(DQuat::from_rotation_y(-1.1), DVec3::new(-4.0, 0.5, 0.0)).unwrap();
        let p = DVec3::new(0.2, -0.7, 5.0);
        let twice = b.apply_point(a.apply_point(p));
        assert!((b.after(&a).apply_point(p) - twice).length() < 1e-12);
    }

    #[test]
    fn bad_values_are_refused() {
        assert_eq!(
            Pose::new(DQuat::from_xyzw(0.0, 0.0, 0.0, 0.0), DVec3::ZERO),
            Err(PoseProblem::ZeroQuaternion)
        );
        assert_eq!(
            Pose::new(DQuat::IDENTITY, DVec3::new(f64::NAN, 0.0, 0.0)),
            Err(PoseProblem::NotFinite)
        );
        assert!(Pose::IDENTITY.is_identity());
    }
}
