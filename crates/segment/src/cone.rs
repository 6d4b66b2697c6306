//! Conservative bounding cones of unit normals.
//!
//! A [`NormalCone`] is a unit axis and a half-angle; it *contains* a unit vector when the
//! angle between them is at most the half-angle. This file computes:
//!
//! - [`NormalCone::including`]: the smallest cone containing a cone and one more direction
//!   (exact for that operation: the new cone is tangent to the old one on the far side and
//!   passes through the new direction);
//! - [`NormalCone::union`]: the smallest cone containing two cones;
//! - [`fit_cone`]: a tight cone around a list of normals (the better of the area-weighted
//!   mean axis and a few steps of a Bădoiu–Clarkson iteration on the sphere, each measured
//!   exactly by its largest angle).
//!
//! Invariant (conservative): a cone built by these functions contains every direction it was
//! built from. Each growing step pads the half-angle by [`ANGLE_PAD`] so that rounding in the
//! axis rotation can never leave an earlier direction outside; the incremental cones are
//! therefore never too small, but may be larger than the minimal enclosing cone (each step is
//! exact for the old *cone* and the new direction, not for the old *directions*; in practice
//! on meshes a few percent of the angle, and [`fit_cone`] tightens the reported cone at the
//! end of each stage). Adding a direction to a cone gives a half-angle that never decreases
//! when the old cone grows, so a direction refused by a region stays refused.
//!
//! Angles are measured with `atan2(|a × b|, a · b)`, accurate near 0 and π (unlike `acos`).
//!
//! Cost: O(1) per step; [`fit_cone`] O(k · [`FIT_ITERATIONS`]) for k normals.
//!
//! Based on: the "smallest enclosing cone of a cone and a vector" update used for normal
//! cones in Shirman & Abi-Ezzi, *The cone of normals technique for fast processing of curved
//! patches* (Eurographics 1993) and Sander et al., *Silhouette clipping* (SIGGRAPH 2000);
//! Bădoiu & Clarkson, *Optimal core-sets for balls* (2008), transported to the sphere.

use glam::Vec3;

/// Padding, in radians (about 0.0006°), added to a half-angle each time a cone grows, which
/// covers the rounding of the axis rotation.
pub const ANGLE_PAD: f32 = 1e-5;

/// Dot products within this of the smallest are re-measured exactly in [`fit_cone`] (a few
/// units of f32 rounding for unit vectors).
const DOT_MARGIN: f32 = 1e-6;

/// Iterations of the Bădoiu–Clarkson refinement in [`fit_cone`].
pub const FIT_ITERATIONS: usize = 12;

/// The angle in radians between two unit vectors, in `[0, π]`.
#[inline]
pub fn angle_between(a: Vec3, b: Vec3) -> f32 {
    a.cross(b).length().atan2(a.dot(b))
}

/// A cone of directions: every unit vector within `half_angle` of `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalCone {
    /// Unit axis.
    pub axis: Vec3,
    /// Half-angle in radians, in `[0, π]`.
    pub half_angle: f32,
}

impl NormalCone {
    /// The cone holding exactly one unit direction.
    pub fn around(direction: Vec3) -> NormalCone {
        NormalCone {
            axis: direction,
            half_angle: 0.0,
        }
    }

    /// Whether the unit vector `direction` lies inside the cone.
    #[inline]
    pub fn contains(&self, direction: Vec3) -> bool {
        angle_between(self.axis, direction) <= self.half_angle
    }

    /// Half-angle of [`NormalCone::including`] `direction`, without building it.
    #[inline]
    pub fn half_angle_including(&self, direction: Vec3) -> f32 {
        let d = angle_between(self.axis, direction);
        if d <= self.half_angle {
            self.half_angle
        } else {
            grown_half_angle(self.half_angle, d)
        }
    }

    /// The smallest cone containing this cone and the unit vector `direction` (padded, see the
    /// module docs).
    pub fn including(&self, direction: Vec3) -> NormalCone {
        let d = angle_between(self.axis, direction);
        if d <= self.half_angle {
            return *self;
        }
        NormalCone {
            axis: rotate_towards(self.axis, direction, 0.5 * (d - self.half_angle)),
            half_angle: grown_half_angle(self.half_angle, d),
        }
    }

    /// The smallest cone containing both cones (padded, see the module docs).
    pub fn union(&self, other: &NormalCone) -> NormalCone {
        let d = angle_between(self.axis, other.axis);
        if d + other.half_angle <= self.half_angle {
            return *self;
        }
        if d + self.half_angle <= other.half_angle {
            return *other;
        }
        NormalCone {
            axis: rotate_towards(
                self.axis,
                other.axis,
                0.5 * (d + other.half_angle - self.half_angle),
            ),
            half_angle: grown_half_angle(self.half_angle, d + other.half_angle),
        }
    }
}

/// Half-angle of the cone tangent to a cone of half-angle `half` on one side and reaching
/// angle `far` from its axis on the other: the mean of the two, padded, at most π.
#[inline]
fn grown_half_angle(half: f32, far: f32) -> f32 {
    (0.5 * (half + far) + ANGLE_PAD).min(std::f32::consts::PI)
}

/// `axis` rotated by `angle` radians in the plane through `axis` and `towards` (both unit),
/// towards `towards`. When the two are (anti)parallel the plane is any plane through `axis`.
fn rotate_towards(axis: Vec3, towards: Vec3, angle: f32) -> Vec3 {
    let side = towards - axis * axis.dot(towards);
    let side = side
        .try_normalize()
        .unwrap_or_else(|| axis.any_orthonormal_vector());
    let (s, c) = angle.sin_cos();
    (axis * c + side * s).normalize()
}

/// A tight cone around `normals` (unit vectors, with non-negative `weights` of the same
/// length used for the mean axis), or `None` when there are none. When `hint` is given (a
/// cone known to contain every normal) the result is never wider than it.
///
/// Candidates: the hint, the normalized weighted mean (unweighted if the weights sum to zero
/// or the mean vanishes), and [`FIT_ITERATIONS`] steps of the Bădoiu–Clarkson iteration from
/// it (move the axis towards the farthest normal by `1 / (i + 1)` of the angle). Each
/// computed candidate's half-angle is its exact largest angle plus [`ANGLE_PAD`].
pub fn fit_cone(normals: &[Vec3], weights: &[f32], hint: Option<NormalCone>) -> Option<NormalCone> {
    debug_assert_eq!(normals.len(), weights.len());
    let first = *normals.first()?;
    let weighted: Vec3 = normals.iter().zip(weights).map(|(&n, &w)| n * w).sum();
    let plain: Vec3 = normals.iter().sum();
    let mut axis = weighted
        .try_normalize()
        .or_else(|| plain.try_normalize())
        .unwrap_or(first);
    // The farthest normal by the smallest dot product (cheap), then the exact angle over the
    // few normals whose dot product is within rounding of it (a dot product near 1 resolves
    // angles only to about 3e-4 rad, so it cannot give the half-angle itself).
    let farthest = |axis: Vec3| {
        let lowest = normals
            .iter()
            .map(|&n| axis.dot(n))
            .fold(f32::INFINITY, f32::min);
        let mut best = (0.0f32, first);
        for &n in normals {
            if axis.dot(n) <= lowest + DOT_MARGIN {
                let a = angle_between(axis, n);
                if a > best.0 {
                    best = (a, n);
                }
            }
        }
        best
    };
    let mut best = hint;
    for i in 0..=FIT_ITERATIONS {
        let (max_angle, far) = farthest(axis);
        let candidate = NormalCone {
            axis,
            half_angle: (max_angle + ANGLE_PAD).min(std::f32::consts::PI),
        };
        if best.is_none_or(|b| candidate.half_angle < b.half_angle) {
            best = Some(candidate);
        }
        if max_angle <= 0.0 {
            break;
        }
        axis = rotate_towards(axis, far, max_angle / (i as f32 + 2.0));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::{FRAC_PI_2, PI};

    fn dir(theta: f32, phi: f32) -> Vec3 {
        Vec3::new(
            theta.sin() * phi.cos(),
            theta.sin() * phi.sin(),
            theta.cos(),
        )
    }

    #[test]
    fn including_contains_old_cone_and_new_direction() {
        let mut cone = NormalCone::around(Vec3::Z);
        let mut seen = vec![Vec3::Z];
        for k in 0..200 {
            let n = dir(0.6 * ((k * 37 % 101) as f32 / 101.0), k as f32 * 2.4);
            cone = cone.including(n);
            seen.push(n);
            for &s in &seen {
                assert!(cone.contains(s), "step {k}: {s} outside {cone:?}");
            }
        }
        // Incremental cones are not minimal (the minimal one is at most 0.6 here).
        assert!(cone.half_angle <= 0.75, "{cone:?}");
    }

    #[test]
    fn including_two_directions_is_exact() {
        let cone = NormalCone::around(Vec3::X).including(Vec3::Y);
        assert!((cone.half_angle - FRAC_PI_2 / 2.0).abs() < 1e-4);
        assert!((cone.axis - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5);
    }

    #[test]
    fn opposite_directions_give_a_half_space() {
        let cone = NormalCone::around(Vec3::Z).including(-Vec3::Z);
        assert!((cone.half_angle - FRAC_PI_2).abs() < 1e-4);
        assert!(cone.contains(Vec3::Z) && cone.contains(-Vec3::Z));
        let whole = cone.including(cone.axis * -1.0);
        assert!(whole.half_angle <= PI);
    }

    #[test]
    fn union_contains_both_cones() {
        let a = NormalCone {
            axis: Vec3::Z,
            half_angle: 0.2,
        };
        let b = NormalCone {
            axis: dir(0.5, 1.0),
            half_angle: 0.1,
        };
        let u = a.union(&b);
        assert!((u.half_angle - 0.4).abs() < 1e-4);
        for k in 0..64 {
            let phi = k as f32 * PI / 32.0;
            // Boundary directions of each cone, slightly inside.
            let rim_a = rotate_towards(a.axis, dir(1.0, phi), 0.2 - 1e-4);
            let rim_b = rotate_towards(b.axis, dir(1.0, phi), 0.1 - 1e-4);
            assert!(u.contains(rim_a) && u.contains(rim_b));
        }
        assert_eq!(a.union(&NormalCone::around(Vec3::Z)), a);
    }

    #[test]
    fn fit_cone_is_tight_for_a_ring() {
        let ring: Vec<Vec3> = (0..36).map(|k| dir(0.3, k as f32 * 0.1745)).collect();
        let weights = vec![1.0; ring.len()];
        let cone = fit_cone(&ring, &weights, None).expect("non-empty");
        assert!((cone.half_angle - 0.3).abs() < 2e-3, "{cone:?}");
        assert!(ring.iter().all(|&n| cone.contains(n)));
        assert_eq!(fit_cone(&[], &[], None), None);
    }

    #[test]
    fn fit_cone_handles_a_lopsided_set() {
        // Many normals near +z, one at 40°: the mean axis is off-centre; the iteration fixes it.
        let mut normals = vec![Vec3::Z; 100];
        normals.push(dir(0.7, 0.0));
        normals.push(dir(0.1, PI));
        let weights = vec![1.0; normals.len()];
        let cone = fit_cone(&normals, &weights, None).expect("non-empty");
        assert!(normals.iter().all(|&n| cone.contains(n)));
        assert!(cone.half_angle < 0.45, "{cone:?}");
    }
}
