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

use glam::{DVec3, Mat3, Vec3};

use spatch_format::Sides;

use crate::options::Culling;
use crate::prepare::cone::NormalCone;
use crate::prepare::scene::Portal;

/// True when no point of the sphere `(centre, radius)` can see a normal of
/// `cone` facing the eye.
#[inline(always)]
pub(crate) fn cone_faces_away(cone: &NormalCone, centre: DVec3, radius: f64, eye: DVec3) -> bool {
    let to_eye = eye - centre;
    let distance = to_eye.length();
    if distance <= radius * 1.000_001 || cone.half_angle >= std::f64::consts::FRAC_PI_2 {
        return false;
    }
    let spread = (radius / distance).asin();
    let angle = (to_eye.dot(cone.axis) / distance).clamp(-1.0, 1.0).acos();
    angle > std::f64::consts::FRAC_PI_2 + cone.half_angle + spread
}

/// Extra angle (radians) by which a normal cone must face the eye before
/// its patch skips the per-cell back-face test ([`cone_faces_eye`]): room
/// for the trilinear traversal's and the fixed point's errors in the
/// projected cells.
pub(crate) const FRONT_MARGIN: f64 = 0.1;

/// True when every normal of `cone` faces the eye from every point of the
/// sphere `(centre, radius)`, by at least [`FRONT_MARGIN`]: no cell of the
/// patch can face away, so the per-cell back-face test is skipped. Why:
/// the test cost ≈ 30 instructions per cell and found nothing on ≈ 70 % of
/// the sphere's drawn patches (callgrind, `profile_sphere 500 1`).
/// Conservative: a patch that fails it keeps the test.
#[inline(always)]
pub(crate) fn cone_faces_eye(cone: &NormalCone, centre: DVec3, radius: f64, eye: DVec3) -> bool {
    let to_eye = eye - centre;
    let distance = to_eye.length();
    if distance <= radius * 1.000_001 {
        return false;
    }
    let spread = (radius / distance).asin();
    let angle = (to_eye.dot(cone.axis) / distance).clamp(-1.0, 1.0).acos();
    angle + cone.half_angle + spread + FRONT_MARGIN < std::f64::consts::FRAC_PI_2
}

/// Whether `culling` lets the back of a patch with `sides` and bounding
/// sphere `(centre, radius)` be culled this frame (its normal cone and
/// cells then face-tested): always under [`Culling::Back`], never under
/// [`Culling::None`]; under [`Culling::Auto`] as the patch's [`Sides`] say,
/// a patch of an open surface only when no opening can lie between the eye
/// and it ([`seen_through_portals`]).
#[inline(always)]
pub(crate) fn back_culled(
    (culling, sides): (Culling, Sides),
    portals: &[Portal],
    eye: DVec3,
    centre: DVec3,
    radius: f64,
) -> bool {
    match (culling, sides) {
        (Culling::Back, _) | (Culling::Auto, Sides::Front) => true,
        (Culling::None, _) | (Culling::Auto, Sides::Both) => false,
        (Culling::Auto, Sides::ThroughOpenings) => {
            !seen_through_portals(portals, eye, centre, radius)
        }
    }
}

/// True when a line from `eye` to a point of the sphere `(centre, radius)`
/// may cross one of `portals` before reaching it. Why this is safe: a line
/// of sight from outside the model to the back of an open surface crosses
/// a surface spanning one of its boundary loops, which fits inside the
/// loop's sphere and slab. Conservative: a portal does not count when the
/// eye and the whole patch sphere lie on one side of its slab (the line
/// never crosses it), or the patch lies entirely nearer than it; else the
/// cone from the eye around the portal's sphere is tested against the
/// patch's sphere (angles widened by [`PORTAL_MARGIN`]). Cost: a few
/// operations per portal.
pub(crate) fn seen_through_portals(
    portals: &[Portal],
    eye: DVec3,
    centre: DVec3,
    radius: f64,
) -> bool {
    let to_patch = centre - eye;
    let patch_distance = to_patch.length();
    if patch_distance <= radius {
        return true;
    }
    let patch_spread = (radius / patch_distance).asin();
    portals.iter().any(|portal| {
        let to_portal = portal.centre - eye;
        let distance = to_portal.length();
        if distance <= portal.radius {
            return true;
        }
        let h = portal.half_thickness;
        let eye_side = (eye - portal.centre).dot(portal.normal);
        let patch_side = (centre - portal.centre).dot(portal.normal);
        let one_side = (eye_side > h && patch_side - radius > h)
            || (eye_side < -h && patch_side + radius < -h);
        if one_side || patch_distance + radius < distance - portal.radius {
            return false;
        }
        let spread = (portal.radius / distance).asin();
        let cos = to_patch.dot(to_portal) / (patch_distance * distance);
        cos.clamp(-1.0, 1.0).acos() <= spread + patch_spread + PORTAL_MARGIN
    })
}

/// Extra angle (radians) of the portal test, for the rounding of the
/// stored opening and patch spheres.
pub(crate) const PORTAL_MARGIN: f64 = 1e-3;

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
        let cone = NormalCone {
            axis: DVec3::Z,
            half_angle: 0.2,
        };
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

    #[test]
    fn a_patch_is_seen_through_a_portal_only_beyond_it_and_in_its_cone() {
        let eye = DVec3::new(0.0, 0.0, 10.0);
        // A disc in the plane z = 0 would be edge-on: the slab is the
        // plane x = 0, seen face-on from the eye on the z axis... so use
        // a slab facing the eye: normal z, thin.
        let portal = [Portal {
            centre: DVec3::ZERO,
            radius: 1.0,
            normal: DVec3::Z,
            half_thickness: 0.1,
        }];
        let seen = |c: DVec3, r: f64| seen_through_portals(&portal, eye, c, r);
        // Behind the opening, in line with it: seen.
        assert!(seen(DVec3::new(0.0, 0.0, -3.0), 0.5));
        // Behind it but far off to the side: not seen.
        assert!(!seen(DVec3::new(8.0, 0.0, -3.0), 0.5));
        // In line but entirely nearer than the opening: not seen through it.
        assert!(!seen(DVec3::new(0.0, 0.0, 5.0), 0.5));
        // Reaching into the opening's cone: seen.
        assert!(seen(DVec3::new(2.0, 0.0, -3.0), 1.5));
        // Eye and patch on the same side of the slab: not through it.
        let side = [Portal {
            normal: DVec3::Y,
            ..portal[0]
        }];
        let above = DVec3::new(0.0, 5.0, 10.0);
        assert!(!seen_through_portals(
            &side,
            above,
            DVec3::new(0.0, 1.0, -3.0),
            0.5
        ));
        assert!(seen_through_portals(
            &side,
            above,
            DVec3::new(0.0, -1.0, -3.0),
            0.5
        ));
        // No portal at all: never; the eye inside the opening: always.
        assert!(!seen_through_portals(&[], eye, DVec3::ZERO, 1.0));
        assert!(seen_through_portals(
            &portal,
            DVec3::new(0.0, 0.5, 0.0),
            DVec3::new(9.0, 0.0, 0.0),
            0.1
        ));
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
