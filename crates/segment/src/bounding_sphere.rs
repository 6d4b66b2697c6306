//! Conservative bounding spheres of point sets and of unions of spheres.
//!
//! The merge stage asks whether the union of two regions "still fits a patch"; it answers with
//! spheres: a set inside a sphere of diameter `D` spans at most `D` along any direction, so it
//! fits a square of side `D` in any plane and under any in-plane rotation.
//!
//! - [`bound_points`]: a sphere around points, the smaller of two candidates: the centre of the
//!   axis-aligned box with the farthest point's distance, and Ritter's two-pass sphere, each
//!   radius measured exactly from its centre.
//! - [`Sphere::union`]: the smallest sphere containing two spheres (exact).
//!
//! Invariant (conservative): every point and every sphere a result was built from lies
//! inside it; radii are padded by a relative [`RADIUS_PAD`] against rounding.
//!
//! Cost: [`bound_points`] three O(k) passes; [`Sphere::union`] O(1).
//!
//! Based on: Ritter, *An efficient bounding sphere*, Graphics Gems (1990).

use glam::Vec3;

/// Relative padding of radii (to the sphere's distance from the origin plus its radius).
pub(crate) const RADIUS_PAD: f32 = 1e-6;

/// A sphere: centre and radius (model units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sphere {
    /// Centre.
    pub(crate) centre: Vec3,
    /// Radius, non-negative.
    pub(crate) radius: f32,
}

impl Sphere {
    /// Diameter.
    pub(crate) fn diameter(&self) -> f32 {
        2.0 * self.radius
    }

    /// The smallest sphere containing both spheres (padded).
    pub(crate) fn union(&self, other: &Sphere) -> Sphere {
        let offset = other.centre - self.centre;
        let d = offset.length();
        if d + other.radius <= self.radius {
            return *self;
        }
        if d + self.radius <= other.radius {
            return *other;
        }
        let radius = 0.5 * (d + self.radius + other.radius);
        // d > 0 here: equal centres return above.
        let centre = self.centre + offset * ((radius - self.radius) / d);
        Sphere {
            centre,
            radius: padded(centre, radius),
        }
    }
}

fn padded(centre: Vec3, radius: f32) -> f32 {
    radius + RADIUS_PAD * (centre.abs().max_element() + radius)
}

/// A sphere around every point of `points` (see the module docs), or `None` for no points.
pub(crate) fn bound_points(points: &[Vec3]) -> Option<Sphere> {
    let first = *points.first()?;
    let (lo, hi) = points
        .iter()
        .fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let farthest_from = |c: Vec3| {
        points
            .iter()
            .map(|&p| (p.distance_squared(c), p))
            .fold((0.0f32, c), |best, x| if x.0 > best.0 { x } else { best })
    };
    let exact = |c: Vec3| Sphere {
        centre: c,
        radius: padded(c, farthest_from(c).0.sqrt()),
    };
    let boxed = exact((lo + hi) * 0.5);
    // Ritter: from a far pair, then grow to cover the stragglers.
    let (_, a) = farthest_from(first);
    let (_, b) = farthest_from(a);
    let mut centre = (a + b) * 0.5;
    let mut radius = 0.5 * a.distance(b);
    for &p in points {
        let d = p.distance(centre);
        if d > radius {
            let grown = 0.5 * (radius + d);
            centre += (p - centre) * ((grown - radius) / d);
            radius = grown;
        }
    }
    let ritter = exact(centre);
    Some(if ritter.radius < boxed.radius {
        ritter
    } else {
        boxed
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spheres_contain_their_points() {
        let points: Vec<Vec3> = (0..500)
            .map(|k| {
                let t = k as f32 * 0.37;
                Vec3::new(t.sin() * 3.0, (t * 1.3).cos(), (k % 17) as f32 * 0.1)
            })
            .collect();
        let s = bound_points(&points).expect("points");
        assert!(points.iter().all(|p| p.distance(s.centre) <= s.radius));
        assert!(s.radius < 3.5, "{s:?}");
        assert_eq!(bound_points(&[]), None);
    }

    #[test]
    fn union_contains_both() {
        let a = Sphere {
            centre: Vec3::ZERO,
            radius: 1.0,
        };
        let b = Sphere {
            centre: Vec3::new(4.0, 0.0, 0.0),
            radius: 0.5,
        };
        let u = a.union(&b);
        assert!((u.radius - 2.75).abs() < 1e-4);
        assert!(u.centre.distance(a.centre) + a.radius <= u.radius + 1e-6);
        assert!(u.centre.distance(b.centre) + b.radius <= u.radius + 1e-6);
        assert_eq!(a.union(&a), a);
    }
}
