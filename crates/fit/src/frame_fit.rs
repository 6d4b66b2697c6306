//! The orientation of a patch: z from the region's normal cone, x and y from the smallest
//! rectangle around the region's projection on the plane normal to z.
//!
//! Inputs: the cone axis (unit) and the region's vertex positions. Output: a right-handed
//! orthonormal basis `(x̂, ŷ, ẑ)` with `ẑ` = the axis, and the rectangle `[u0, u1] × [v0, v1]`
//! of the projected vertices in `(x̂, ŷ)` coordinates.
//!
//! Method: project the vertices on a first basis of the plane, take their convex hull
//! (Andrew's monotone chain, in f64), then run rotating calipers over the hull: the
//! minimum-area enclosing rectangle has one side on a hull edge (Freeman & Shapira), so each
//! hull edge is tried with three pointers (farthest along the edge, farthest behind, farthest
//! across) that only move forward. Ties keep the first edge, so the result is deterministic.
//!
//! Cost: O(n log n) for the hull of n points, O(h) for the calipers over h hull points.
//!
//! Based on: H. Freeman, R. Shapira, "Determining the minimum-area encasing rectangle for an
//! arbitrary closed curve", CACM 1975; G. Toussaint, "Solving geometric problems with the
//! rotating calipers", MELECON 1983; A. M. Andrew, "Another efficient algorithm for convex
//! hulls in two dimensions", IPL 1979.

use glam::{DVec2, Vec3};

/// A right-handed orthonormal basis with `z` the cone axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Basis {
    pub(crate) x: Vec3,
    pub(crate) y: Vec3,
    pub(crate) z: Vec3,
}

/// An oriented rectangle in the plane of a basis: `[min.x, max.x] × [min.y, max.y]` in
/// `(x̂, ŷ)` coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlaneRect {
    pub(crate) basis: Basis,
    pub(crate) min: DVec2,
    pub(crate) max: DVec2,
}

/// Any right-handed orthonormal basis whose z is `axis` (unit).
///
/// The helper vector is the world axis least aligned with `axis`, so the result is a
/// continuous, deterministic function of the axis away from those switch points.
pub(crate) fn basis_from_axis(axis: Vec3) -> Basis {
    let z = axis;
    let a = z.abs();
    let helper = if a.x <= a.y && a.x <= a.z {
        Vec3::X
    } else if a.y <= a.z {
        Vec3::Y
    } else {
        Vec3::Z
    };
    let x = helper.cross(z).normalize();
    let y = z.cross(x);
    Basis { x, y, z }
}

/// The convex hull of `points`, counter-clockwise, without collinear points. Fewer than three
/// points come back when the input is degenerate (all equal or collinear).
pub(crate) fn convex_hull(points: &mut [DVec2]) -> Vec<DVec2> {
    points.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    let mut unique: Vec<DVec2> = Vec::with_capacity(points.len());
    for &p in points.iter() {
        if unique.last() != Some(&p) {
            unique.push(p);
        }
    }
    if unique.len() < 3 {
        return unique;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(unique.len() + 1);
    for &p in &unique {
        while hull.len() >= 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
            hull.pop();
        }
        hull.push(p);
    }
    let lower_len = hull.len() + 1;
    for &p in unique.iter().rev().skip(1) {
        while hull.len() >= lower_len && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
        {
            hull.pop();
        }
        hull.push(p);
    }
    hull.pop();
    hull
}

/// The minimum-area rectangle around `points` (given in the plane coordinates of `basis`),
/// returned in a rotated basis with the same z whose x runs along the rectangle's side.
pub(crate) fn min_area_rect(basis: Basis, points: &mut [DVec2]) -> PlaneRect {
    let hull = convex_hull(points);
    let (dir, min, max) = match hull.len() {
        0 => (DVec2::X, DVec2::ZERO, DVec2::ZERO),
        1 => (DVec2::X, hull[0], hull[0]),
        2 => {
            let d = (hull[1] - hull[0]).normalize_or(DVec2::X);
            rect_along(d, &hull)
        }
        _ => calipers(&hull),
    };
    // Rotate the basis so that x runs along `dir`; y = z × x keeps it right-handed.
    let x = (basis.x.as_dvec3() * dir.x + basis.y.as_dvec3() * dir.y)
        .as_vec3()
        .normalize();
    let y = basis.z.cross(x).normalize();
    PlaneRect {
        basis: Basis { x, y, z: basis.z },
        min,
        max,
    }
}

/// The bounding rectangle of `points` in the frame whose x axis is the unit vector `d`.
fn rect_along(d: DVec2, points: &[DVec2]) -> (DVec2, DVec2, DVec2) {
    let n = d.perp();
    let (mut min, mut max) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for &p in points {
        let q = DVec2::new(p.dot(d), p.dot(n));
        min = min.min(q);
        max = max.max(q);
    }
    (d, min, max)
}

/// Rotating calipers over a counter-clockwise hull with at least three points.
fn calipers(hull: &[DVec2]) -> (DVec2, DVec2, DVec2) {
    let h = hull.len();
    let at = |k: usize| hull[k % h];
    let mut best: Option<(f64, DVec2)> = None;
    // Pointers to the hull points farthest along +d, along +n (inward normal) and along -d.
    let (mut far_d, mut far_n, mut far_back) = (0usize, 0usize, 0usize);
    for i in 0..h {
        let d = (at(i + 1) - at(i)).normalize_or_zero();
        if d == DVec2::ZERO {
            continue;
        }
        let n = d.perp();
        if i == 0 {
            // Start each pointer at the edge's end and sweep forward to its maximum.
            far_d = i + 1;
            far_n = i + 1;
        }
        far_d = far_d.max(i + 1);
        while at(far_d + 1).dot(d) > at(far_d).dot(d) {
            far_d += 1;
        }
        far_n = far_n.max(far_d);
        while at(far_n + 1).dot(n) > at(far_n).dot(n) {
            far_n += 1;
        }
        if i == 0 {
            far_back = far_n;
        }
        far_back = far_back.max(far_n);
        while at(far_back + 1).dot(d) < at(far_back).dot(d) {
            far_back += 1;
        }
        let width = (at(far_d) - at(far_back)).dot(d);
        let height = (at(far_n) - at(i)).dot(n);
        let area = width * height;
        if best.is_none_or(|(a, _)| area < a) {
            best = Some((area, d));
        }
    }
    let d = best.map_or(DVec2::X, |(_, d)| d);
    rect_along(d, hull)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute_force_area(points: &[DVec2]) -> f64 {
        let hull = convex_hull(&mut points.to_vec());
        let mut best = f64::INFINITY;
        for i in 0..hull.len() {
            let d = (hull[(i + 1) % hull.len()] - hull[i]).normalize();
            let (_, min, max) = rect_along(d, &hull);
            best = best.min((max - min).x * (max - min).y);
        }
        best
    }

    #[test]
    fn hull_of_a_square_with_inner_points() {
        let mut pts = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(0.5, 0.5),
            DVec2::new(0.5, 0.0),
        ];
        let hull = convex_hull(&mut pts);
        assert_eq!(hull.len(), 4);
    }

    #[test]
    fn rotated_rectangle_is_found() {
        let angle = 0.3f64;
        let (c, s) = (angle.cos(), angle.sin());
        let mut pts: Vec<DVec2> = [(0.0, 0.0), (4.0, 0.0), (4.0, 1.0), (0.0, 1.0), (2.0, 0.5)]
            .iter()
            .map(|&(x, y)| DVec2::new(c * x - s * y, s * x + c * y))
            .collect();
        let basis = basis_from_axis(Vec3::Z);
        let rect = min_area_rect(basis, &mut pts);
        let size = rect.max - rect.min;
        assert!((size.x * size.y - 4.0).abs() < 1e-6, "{size:?}");
        assert!(rect.basis.x.cross(rect.basis.y).dot(rect.basis.z) > 0.999);
    }

    #[test]
    fn calipers_match_brute_force_on_pseudo_random_sets() {
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64) / ((1u64 << 53) as f64)
        };
        for _ in 0..200 {
            let n = 3 + (next() * 40.0) as usize;
            let pts: Vec<DVec2> = (0..n)
                .map(|_| DVec2::new(next() * 3.0, next() * 1.5 + next()))
                .collect();
            let hull = convex_hull(&mut pts.clone());
            if hull.len() < 3 {
                continue;
            }
            let (_, min, max) = calipers(&hull);
            let area = (max - min).x * (max - min).y;
            let brute = brute_force_area(&pts);
            assert!(
                (area - brute).abs() <= 1e-9 * brute.max(1.0),
                "{area} vs {brute}"
            );
        }
    }

    #[test]
    fn degenerate_inputs() {
        let basis = basis_from_axis(Vec3::Y);
        let mut one = vec![DVec2::new(1.0, 2.0); 3];
        let r = min_area_rect(basis, &mut one);
        assert_eq!(r.min, r.max);
        let mut line = vec![DVec2::ZERO, DVec2::new(1.0, 1.0), DVec2::new(2.0, 2.0)];
        let r = min_area_rect(basis, &mut line);
        assert!((r.max - r.min).y.abs() < 1e-12);
        assert!(((r.max - r.min).x - 8f64.sqrt()).abs() < 1e-12);
    }
}
