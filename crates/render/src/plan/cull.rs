//! Visibility: the frustum test with a guard band, and back-face culling by
//! a per-patch normal cone.
//!
//! **Frustum.** The 8 corners of a patch's bounding box (in patch space:
//! node range × displacement range, so the box follows the patch frame) are
//! mapped to window clip coordinates `(X, Y, W)`. The box is *outside* when
//! all corners fail one plane of the view frustum (near, far, the four
//! sides). It is *inside* when every corner is in front of the near plane
//! and within the guard band (the viewport widened by `guard_band` of its
//! size on each side): such a patch is drawn as is, its off-screen pixels
//! discarded. Anything else is *partial* and goes to [`crate::plan::split`].
//!
//! **Normal cone.** Built once per patch ([`crate::prepare::cone`]). A
//! patch faces away when the angle between its cone axis
//! and the direction to the eye exceeds 90° + the cone's half angle + the
//! angle the patch's bounding sphere subtends from the eye (Shirman and
//! Abi-Ezzi's conservative test), so no visible cell is ever dropped.
//!
//! Based on: L. A. Shirman, S. S. Abi-Ezzi, "The cone of normals technique
//! for fast processing of curved patches", Eurographics 1993.
//!
//! Cost: 8 corner transforms and one cone test per patch.

use std::sync::LazyLock;

use glam::{DVec3, Mat3, Vec3};

use crate::prepare::cone::NormalCone;

/// True when no point of the sphere `(centre, radius)` can see a normal of
/// `cone` facing the eye: the angle between the cone's axis and the
/// direction to the eye exceeds 90° + the cone's half angle + the angle
/// the sphere spreads from the eye. Compared as cosines (the cone keeps
/// its half angle's sine and cosine), so no inverse trigonometry per
/// patch: the `acos` and `asin` calls of the angle forms (here, in
/// [`cone_faces_eye`] and in [`crate::plan::sides`]) were about 0.5 M
/// instructions of each bunny frame (callgrind, 500²).
#[inline(always)]
pub(crate) fn cone_faces_away(cone: &NormalCone, centre: DVec3, radius: f64, eye: DVec3) -> bool {
    let to_eye = eye - centre;
    let distance = to_eye.length();
    if distance <= radius * 1.000_001 || cone.half_angle >= std::f64::consts::FRAC_PI_2 {
        return false;
    }
    let (sin_h, cos_h) = cone.sin_cos;
    let (sin_s, cos_s) = spread(radius, distance);
    // Half angle + spread at or past 90°: the limit is at or past 180°,
    // which no angle exceeds.
    if sin_s >= cos_h {
        return false;
    }
    // angle > 90° + (h + s)  ⟺  cos(angle) < −sin(h + s).
    let cos_angle = to_eye.dot(cone.axis) / distance;
    cos_angle < -(sin_h * cos_s + cos_h * sin_s) - COS_SLACK
}

/// Extra angle (radians) by which a normal cone must face the eye before
/// its patch skips the per-cell back-face test ([`cone_faces_eye`]): room
/// for the trilinear traversal's and the fixed point's errors in the
/// projected cells.
pub(crate) const FRONT_MARGIN: f64 = 0.1;

/// `sin` and `cos` of [`FRONT_MARGIN`], computed once.
static FRONT_MARGIN_SIN_COS: LazyLock<(f64, f64)> = LazyLock::new(|| FRONT_MARGIN.sin_cos());

/// How far (in cosine) the cone and portal tests lean to the safe side:
/// their cosine forms round differently from the angle forms they stand
/// for.
pub(crate) const COS_SLACK: f64 = 1e-12;

/// `sin` and `cos` of the angle by which a sphere of `radius` seen from
/// `distance` (larger) spreads around its centre's direction.
#[inline(always)]
pub(crate) fn spread(radius: f64, distance: f64) -> (f64, f64) {
    let s = radius / distance;
    (s, (1.0 - s * s).max(0.0).sqrt())
}

/// True when every normal of `cone` faces the eye from every point of the
/// sphere `(centre, radius)`, by at least [`FRONT_MARGIN`]: no cell of the
/// patch can face away, so the per-cell back-face test is skipped. Why:
/// the test cost ≈ 30 instructions per cell and found nothing on ≈ 70 % of
/// the sphere's drawn patches (callgrind, `profile_sphere 500 1`).
/// Conservative: a patch that fails it keeps the test. Compared as
/// cosines, as [`cone_faces_away`] is.
#[inline(always)]
pub(crate) fn cone_faces_eye(cone: &NormalCone, centre: DVec3, radius: f64, eye: DVec3) -> bool {
    let to_eye = eye - centre;
    let distance = to_eye.length();
    if distance <= radius * 1.000_001 {
        return false;
    }
    // g = half angle + margin.
    let ((sin_h, cos_h), (sin_m, cos_m)) = (cone.sin_cos, *FRONT_MARGIN_SIN_COS);
    let (sin_g, cos_g) = (sin_h * cos_m + cos_h * sin_m, cos_h * cos_m - sin_h * sin_m);
    let (sin_s, cos_s) = spread(radius, distance);
    // g + s at or past 90°: no angle is below 90° − (g + s).
    if cos_g <= 0.0 || sin_s >= cos_g {
        return false;
    }
    // angle < 90° − (g + s)  ⟺  cos(angle) > sin(g + s).
    let cos_angle = to_eye.dot(cone.axis) / distance;
    cos_angle > sin_g * cos_s + cos_g * sin_s + COS_SLACK
}

/// Where a box lies with respect to the view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum BoxClass {
    Outside,
    Inside,
    Partial,
}

/// Frustum and guard-band limits in window clip coordinates.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frustum {
    pub(crate) width: f32,
    pub(crate) height: f32,
    pub(crate) near: f32,
    pub(crate) far: f32,
    pub(crate) guard: f32,
}

impl Frustum {
    /// Classifies the box `[lo, hi]` of patch-local coordinates `(u, v, t)`
    /// under the local map `(m, t0)`.
    #[inline(always)]
    pub(crate) fn classify(&self, m: &Mat3, t0: Vec3, lo: Vec3, hi: Vec3) -> BoxClass {
        let mut outside = [true; 6];
        let mut inside = true;
        let (gx, gy) = (self.guard * self.width, self.guard * self.height);
        for k in 0..8 {
            let p = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let c = *m * p + t0;
            let (x, y, w) = (c.x, c.y, c.z);
            let planes = [
                w - self.near,
                self.far - w,
                x,
                self.width * w - x,
                y,
                self.height * w - y,
            ];
            for (o, v) in outside.iter_mut().zip(planes) {
                *o &= v < 0.0;
            }
            inside &= w >= self.near
                && w <= 2.0 * self.far
                && x + gx * w >= 0.0
                && (self.width + gx) * w - x >= 0.0
                && y + gy * w >= 0.0
                && (self.height + gy) * w - y >= 0.0;
        }
        if outside.iter().any(|&o| o) {
            BoxClass::Outside
        } else if inside {
            BoxClass::Inside
        } else {
            BoxClass::Partial
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cone_facing_the_eye_is_kept_and_one_facing_away_is_culled() {
        let cone = NormalCone::new(DVec3::Z, 0.2);
        assert!(!cone_faces_away(
            &cone,
            DVec3::ZERO,
            1.0,
            DVec3::new(0.0, 0.0, 10.0)
        ));
        assert!(cone_faces_away(
            &cone,
            DVec3::ZERO,
            1.0,
            DVec3::new(0.0, 0.0, -10.0)
        ));
        // Edge-on: kept.
        assert!(!cone_faces_away(
            &cone,
            DVec3::ZERO,
            1.0,
            DVec3::new(10.0, 0.0, 0.0)
        ));
        // Eye inside the bounding sphere: kept.
        assert!(!cone_faces_away(
            &cone,
            DVec3::ZERO,
            1.0,
            DVec3::new(0.0, 0.0, -0.5)
        ));
        // Facing the eye entirely: only straight on, not edge-on or inside.
        let eye = |x: f64, z: f64| DVec3::new(x, 0.0, z);
        assert!(cone_faces_eye(&cone, DVec3::ZERO, 1.0, eye(0.0, 10.0)));
        assert!(cone_faces_eye(&cone, DVec3::ZERO, 1.0, eye(3.0, 10.0)));
        assert!(!cone_faces_eye(&cone, DVec3::ZERO, 1.0, eye(10.0, 3.0)));
        assert!(!cone_faces_eye(&cone, DVec3::ZERO, 1.0, eye(10.0, 0.0)));
        assert!(!cone_faces_eye(&cone, DVec3::ZERO, 1.0, eye(0.0, -10.0)));
        assert!(!cone_faces_eye(&cone, DVec3::ZERO, 1.0, eye(0.0, 0.5)));
    }

    /// The cosine forms decide as the angle forms they stand for (`acos`
    /// of the direction's cosine against sums of `asin` spreads), except
    /// within a hair of the boundary, where they lean to the safe side.
    #[test]
    fn cosine_tests_agree_with_the_angle_forms() {
        use crate::test_rng::XorShift;
        use std::f64::consts::FRAC_PI_2;
        let mut rng = XorShift(0x2021_cafe);
        let mut unit = move || rng.unit() as f64;
        let (mut away, mut facing) = (0, 0);
        for _ in 0..20_000 {
            let dir = |u: &mut dyn FnMut() -> f64| {
                DVec3::new(u() - 0.5, u() - 0.5, u() - 0.5).normalize_or(DVec3::X)
            };
            let cone = NormalCone::new(dir(&mut unit), 1.7 * unit());
            let (centre, radius) = (dir(&mut unit) * unit(), 0.05 + unit());
            let eye = dir(&mut unit) * (0.5 + 6.0 * unit());
            let to_eye = eye - centre;
            let d = to_eye.length();
            let angle = (to_eye.dot(cone.axis) / d).clamp(-1.0, 1.0).acos();
            if d > radius * 1.000_001 {
                let s = (radius / d).asin();
                let a = angle - (FRAC_PI_2 + cone.half_angle + s);
                if a.abs() > 1e-9 && cone.half_angle < FRAC_PI_2 {
                    assert_eq!(cone_faces_away(&cone, centre, radius, eye), a > 0.0);
                    away += (a > 0.0) as u32;
                }
                let f = angle + cone.half_angle + s + FRONT_MARGIN - FRAC_PI_2;
                if f.abs() > 1e-9 {
                    assert_eq!(cone_faces_eye(&cone, centre, radius, eye), f < 0.0);
                    facing += (f < 0.0) as u32;
                }
            }
        }
        // Both answers occur often enough to mean something.
        assert!(away > 1000 && facing > 1000, "{away} {facing}");
    }

    #[test]
    fn boxes_are_classified_against_the_frustum_and_guard_band() {
        // Identity-like map: (u, v, t) -> (X, Y, W) = (u, v, t).
        let f = Frustum {
            width: 100.0,
            height: 100.0,
            near: 1.0,
            far: 100.0,
            guard: 0.1,
        };
        let m = Mat3::IDENTITY;
        let inside = f.classify(
            &m,
            Vec3::ZERO,
            Vec3::new(10.0, 10.0, 2.0),
            Vec3::new(20.0, 20.0, 3.0),
        );
        assert_eq!(inside, BoxClass::Inside);
        let behind = f.classify(
            &m,
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, -3.0),
            Vec3::new(1.0, 1.0, -2.0),
        );
        assert_eq!(behind, BoxClass::Outside);
        let crossing = f.classify(
            &m,
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(1.0, 1.0, 2.0),
        );
        assert_eq!(crossing, BoxClass::Partial);
    }
}
