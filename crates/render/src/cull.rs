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
//! discarded. Anything else is *partial* and goes to [`crate::split`].
//!
//! **Normal cone.** Built once per patch from the exact normals of its
//! cells at their corners (one-sided displacement differences), widened by
//! [`CONE_MARGIN`]. A patch faces away when the angle between its cone axis
//! and the direction to the eye exceeds 90° + the cone's half angle + the
//! angle the patch's bounding sphere subtends from the eye (Shirman and
//! Abi-Ezzi's conservative test), so no visible cell is ever dropped.
//!
//! Based on: L. A. Shirman, S. S. Abi-Ezzi, "The cone of normals technique
//! for fast processing of curved patches", Eurographics 1993.
//!
//! Cost: 8 corner transforms and one cone test per patch.

use glam::{DMat3, DVec3, Mat3, Vec3, Vec4};

use crate::mip::MipLevel;

/// Extra half angle of every normal cone (radians), for the curvature of
/// bilinear cells between their corners.
pub(crate) const CONE_MARGIN: f64 = 0.03;

/// A cone bounding the normals of a patch, in model space.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NormalCone {
    pub(crate) axis: DVec3,
    pub(crate) half_angle: f64,
}

/// The normal cone of a level-0 grid with ratios `(rx, ry)` whose unit axes
/// are the columns of `rotation`.
pub(crate) fn compute_normal_cone(
    level: &MipLevel,
    ratios: (f32, f32),
    rotation: &DMat3,
) -> NormalCone {
    let (cols, rows) = (level.cols, level.rows);
    let d = |i: usize, j: usize| level.displacements[j * cols + i] as i32;
    let mut normals = Vec::with_capacity(4 * level.drawable_cells as usize);
    for j in 0..rows - 1 {
        for i in 0..cols - 1 {
            if !level.cell_is_drawable(i, j) {
                continue;
            }
            let (d00, d10, d01, d11) = (d(i, j), d(i + 1, j), d(i, j + 1), d(i + 1, j + 1));
            // The four corners' differences over one spacing, doubled (the
            // form of a node normal's differences).
            let du = [d10 - d00, d10 - d00, d11 - d01, d11 - d01].map(|g| 2 * g);
            let dv = [d01 - d00, d11 - d10, d01 - d00, d11 - d10].map(|g| 2 * g);
            normals.extend(corner_normals(du, dv, ratios));
        }
    }
    let sum: Vec3 = normals.iter().copied().sum();
    let axis = sum.normalize_or(Vec3::Z);
    let min_cos = normals
        .iter()
        .map(|n| n.dot(axis))
        .fold(1.0f32, f32::min)
        .clamp(-1.0, 1.0);
    let half_angle = (min_cos as f64).acos() + CONE_MARGIN;
    NormalCone {
        axis: (*rotation * axis.as_dvec3()).normalize(),
        half_angle,
    }
}

/// The unit normals
/// [`reconstruct_normal`](crate::normal_buffer::reconstruct_normal)`(gi, gj, rx, ry).normalize()` of
/// four corners, computed in four lanes with the same operations in the
/// same order, so each equals its one-by-one value. Why lanes: four
/// normalizations per cell were a quarter of a scene's preparation
/// (callgrind, `profile_sphere 500 1 1`).
#[inline]
fn corner_normals(gi: [i32; 4], gj: [i32; 4], (rx, ry): (f32, f32)) -> [Vec3; 4] {
    // As `reconstruct_normal`: `(-g · r · 0.5, ..., 1)`.
    let lanes = |g: [i32; 4], r: f32| Vec4::from_array(g.map(|g| -(g as f32))) * r * 0.5;
    let (x, y) = (lanes(gi, rx), lanes(gj, ry));
    // As `Vec3::normalize`: times `1 / sqrt(x·x + y·y + z·z)`, with z = 1.
    let inverse = Vec4::ONE / (x * x + y * y + Vec4::ONE).sqrt();
    let (x, y) = (x * inverse, y * inverse);
    std::array::from_fn(|k| Vec3::new(x[k], y[k], inverse[k]))
}

/// True when no point of the sphere `(centre, radius)` can see a normal of
/// `cone` facing the eye.
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
    use crate::normal_buffer::reconstruct_normal;

    #[test]
    fn corner_normals_in_lanes_equal_normals_one_by_one() {
        let mut rng = crate::test_rng::XorShift(0xc0de_5eed);
        for _ in 0..2000 {
            let g = |r: &mut crate::test_rng::XorShift| r.below(401) as i32 - 200;
            let gi = [g(&mut rng), g(&mut rng), g(&mut rng), g(&mut rng)];
            let gj = [g(&mut rng), g(&mut rng), g(&mut rng), g(&mut rng)];
            let ratios = (0.001 + rng.unit() * 0.2, 0.001 + rng.unit() * 0.2);
            let lanes = corner_normals(gi, gj, ratios);
            for k in 0..4 {
                let one = reconstruct_normal(gi[k], gj[k], ratios.0, ratios.1).normalize();
                assert_eq!(
                    lanes[k].to_array().map(f32::to_bits),
                    one.to_array().map(f32::to_bits)
                );
            }
        }
    }

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
