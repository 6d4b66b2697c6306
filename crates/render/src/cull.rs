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

use spatch_format::Sides;

use crate::mip::MipLevel;
use crate::options::Culling;
use crate::traverse::CELL_DRAW;

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
/// are the columns of `rotation`: the axis is the normalized sum of the
/// unit normals at the four corners of every drawable cell, the half angle
/// the largest angle between the axis and one of them, plus
/// [`CONE_MARGIN`]. Why lanes throughout (a cell's four corners summed and
/// tested side by side, kept as three lane vectors): the sum and the
/// angles over a list of normals were two thirds of this function, and
/// the function a quarter of a one-frame render of the perfect sphere
/// (callgrind, `spatch render sphere.spatch`).
pub(crate) fn compute_normal_cone(
    level: &MipLevel,
    ratios: (f32, f32),
    rotation: &DMat3,
) -> NormalCone {
    let cols = level.cols;
    let mut corners: Vec<[Vec4; 3]> = Vec::with_capacity(level.drawable_cells as usize);
    let mut sum = [Vec4::ZERO; 3];
    let node_rows = level.displacements.chunks_exact(cols);
    let rows = node_rows.clone().zip(node_rows.skip(1));
    for (flags, (below, above)) in level.cell_flags.chunks_exact(cols - 1).zip(rows) {
        let cells = flags.iter().zip(below.windows(2).zip(above.windows(2)));
        for (&flag, (b, a)) in cells {
            if flag & CELL_DRAW == 0 {
                continue;
            }
            let [d00, d10, d01, d11] = [b[0], b[1], a[0], a[1]].map(i32::from);
            // The four corners' differences over one spacing, doubled (the
            // form of a node normal's differences).
            let du = [d10 - d00, d10 - d00, d11 - d01, d11 - d01].map(|g| 2 * g);
            let dv = [d01 - d00, d11 - d10, d01 - d00, d11 - d10].map(|g| 2 * g);
            let n = corner_normals(du, dv, ratios);
            for (s, c) in sum.iter_mut().zip(n) {
                *s += c;
            }
            corners.push(n);
        }
    }
    let axis = Vec3::new(
        sum[0].element_sum(),
        sum[1].element_sum(),
        sum[2].element_sum(),
    )
    .normalize_or(Vec3::Z);
    let [ax, ay, az] = axis.to_array().map(Vec4::splat);
    // The cosines in `Vec3::dot`'s order, lane by lane.
    let min_cos = corners
        .iter()
        .fold(Vec4::ONE, |m, [x, y, z]| m.min(*x * ax + *y * ay + *z * az))
        .min_element()
        .clamp(-1.0, 1.0);
    let half_angle = (min_cos as f64).acos() + CONE_MARGIN;
    NormalCone {
        axis: (*rotation * axis.as_dvec3()).normalize(),
        half_angle,
    }
}

/// The unit normals
/// [`reconstruct_normal`](crate::normal_buffer::reconstruct_normal)`(gi, gj, rx, ry).normalize()` of
/// four corners as lanes `[x, y, z]`, with the same operations in the same
/// order as one by one, so each lane equals its one-by-one value.
#[inline]
fn corner_normals(gi: [i32; 4], gj: [i32; 4], (rx, ry): (f32, f32)) -> [Vec4; 3] {
    // As `reconstruct_normal`: `(-g · r · 0.5, ..., 1)`.
    let lanes = |g: [i32; 4], r: f32| Vec4::from_array(g.map(|g| -(g as f32))) * r * 0.5;
    let (x, y) = (lanes(gi, rx), lanes(gj, ry));
    // As `Vec3::normalize`: times `1 / sqrt(x·x + y·y + z·z)`, with z = 1.
    let inverse = Vec4::ONE / (x * x + y * y + Vec4::ONE).sqrt();
    [x * inverse, y * inverse, inverse]
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

/// An opening of the scene's surface in model space: a sphere and a slab
/// holding one boundary loop ([`spatch_format::Opening`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Portal {
    pub(crate) centre: DVec3,
    pub(crate) radius: f64,
    /// Unit normal of the slab's plane (through `centre`).
    pub(crate) normal: DVec3,
    pub(crate) half_thickness: f64,
}

/// Whether `culling` lets the back of a patch with `sides` and bounding
/// sphere `(centre, radius)` be culled this frame (its normal cone and
/// cells then face-tested): always under [`Culling::Back`], never under
/// [`Culling::None`]; under [`Culling::Auto`] as the patch's [`Sides`] say,
/// a patch of an open surface only when no opening can lie between the eye
/// and it ([`seen_through_portals`]).
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
    use crate::mip::base_level;
    use crate::normal_buffer::reconstruct_normal;
    use spatch_format::{Frame, GridSize, Patch, EMPTY};

    #[test]
    fn corner_normals_in_lanes_equal_normals_one_by_one() {
        let mut rng = crate::test_rng::XorShift(0xc0de_5eed);
        for _ in 0..2000 {
            let g = |r: &mut crate::test_rng::XorShift| r.below(401) as i32 - 200;
            let gi = [g(&mut rng), g(&mut rng), g(&mut rng), g(&mut rng)];
            let gj = [g(&mut rng), g(&mut rng), g(&mut rng), g(&mut rng)];
            let ratios = (0.001 + rng.unit() * 0.2, 0.001 + rng.unit() * 0.2);
            let [x, y, z] = corner_normals(gi, gj, ratios);
            for k in 0..4 {
                let one = reconstruct_normal(gi[k], gj[k], ratios.0, ratios.1).normalize();
                assert_eq!(
                    [x[k], y[k], z[k]].map(f32::to_bits),
                    one.to_array().map(f32::to_bits)
                );
            }
        }
    }

    #[test]
    fn the_cone_holds_every_corner_normal_around_their_mean() {
        // Random grids, some nodes empty, some steps steep: the axis is the
        // direction of the corners' mean normal (summed one by one in cell
        // order, up to rounding) and the half angle reaches the farthest.
        let mut rng = crate::test_rng::XorShift(0xc09e_5eed);
        let frame = Frame::new(
            glam::Vec3::ZERO,
            glam::Vec3::X,
            glam::Vec3::Y,
            glam::Vec3::Z,
        )
        .unwrap();
        let mut checked = 0;
        for case in 0..300 {
            let (cols, rows) = (2 + rng.below(16) as usize, 2 + rng.below(16) as usize);
            let step = [1, 3, 40][case % 3];
            let d: Vec<u16> = (0..cols * rows)
                .map(|_| match rng.below(12) {
                    0 => EMPTY,
                    _ => (30_000 + rng.below(step * 8)) as u16,
                })
                .collect();
            let grid = GridSize::new(cols as u32, rows as u32).unwrap();
            let patch = Patch::new(frame, grid, d.clone(), None).unwrap();
            let Some(level) = base_level(&patch) else {
                continue;
            };
            let ratios = (0.01 + rng.unit() * 0.3, 0.01 + rng.unit() * 0.3);
            let cone = compute_normal_cone(&level, ratios, &DMat3::IDENTITY);
            let at = |i: usize, j: usize| d[j * cols + i] as i32;
            let mut corners = Vec::new();
            for j in 0..rows - 1 {
                for i in 0..cols - 1 {
                    if !level.cell_is_drawable(i, j) {
                        continue;
                    }
                    let (d00, d10, d01, d11) =
                        (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
                    let (b, t) = (2 * (d10 - d00), 2 * (d11 - d01));
                    let (l, r) = (2 * (d01 - d00), 2 * (d11 - d10));
                    for (gi, gj) in [(b, l), (b, r), (t, l), (t, r)] {
                        corners.push(reconstruct_normal(gi, gj, ratios.0, ratios.1).normalize());
                    }
                }
            }
            let mean = corners.iter().copied().sum::<Vec3>().normalize_or(Vec3::Z);
            assert!(
                cone.axis.angle_between(mean.as_dvec3()) < 1e-5,
                "case {case}"
            );
            let widest = corners
                .iter()
                .map(|n| n.as_dvec3().angle_between(cone.axis))
                .fold(0.0, f64::max);
            assert!(
                widest <= cone.half_angle - CONE_MARGIN + 1e-4,
                "case {case}"
            );
            assert!(
                widest >= cone.half_angle - CONE_MARGIN - 1e-3,
                "case {case}"
            );
            checked += 1;
        }
        assert!(checked > 250, "{checked}");
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
