//! Closest point on a mesh surface to a query point, through a [`Bvh`].
//!
//! Inputs: a point and a search radius. Output: the nearest surface point within the radius
//! as a [`ClosestPoint`] (face, point, distance, barycentric weights), or `None`.
//!
//! The point–triangle distance is exact: the query is classified against the triangle's
//! Voronoi regions (three vertices, three edges, the face) and projected onto the matching
//! feature, in f32. Degenerate triangles (zero area) fall into an edge or vertex region and
//! give the right distance too. Traversal visits the nearer child box first and prunes every
//! box farther than the best distance so far; the stack is a fixed array, so queries allocate
//! nothing and take `&self` (callers parallelise over queries, e.g. with rayon).
//! Equal distances go to the lower face id, so results do not depend on the tree layout.
//!
//! Cost: O(log F) box and triangle tests for points near the surface; points far from it
//! (relative to the model size) visit more nodes unless the radius is small.
//!
//! Based on: Ericson, *Real-Time Collision Detection* (2005), section 5.1.5
//! ("Closest point on triangle to point").

use glam::Vec3;

use crate::bvh::{Bvh, MAX_DEPTH};
use crate::FaceId;

/// The nearest surface point to a query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// The face it lies on.
    pub face: FaceId,
    /// The point (mesh coordinates, relative to the origin).
    pub point: Vec3,
    /// Its distance to the query.
    pub distance: f32,
    /// Weights of the face's three corners (non-negative, summing to 1).
    pub barycentric: Vec3,
}

impl Bvh {
    /// The surface point nearest to `p` no farther than `max_distance` (use `f32::INFINITY`
    /// for no limit), or `None`.
    pub fn closest_point(&self, p: Vec3, max_distance: f32) -> Option<ClosestPoint> {
        if self.is_empty_root() || !p.is_finite() || max_distance.is_nan() || max_distance < 0.0 {
            return None;
        }
        let mut best_d2 = if max_distance.is_infinite() {
            f32::INFINITY
        } else {
            max_distance * max_distance
        };
        let mut best: Option<(FaceId, Vec3, Vec3)> = None;
        let mut stack = [0u32; MAX_DEPTH * 2 + 2];
        let mut top = 1usize;
        stack[0] = 0;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            if node.aabb().distance_squared(p) > best_d2 {
                continue;
            }
            if node.count > 0 {
                for k in node.first as usize..(node.first + node.count) as usize {
                    let (q, bary) = closest_on_triangle(p, &self.corners[k]);
                    let d2 = q.distance_squared(p);
                    let face = self.faces[k];
                    let better =
                        d2 < best_d2 || (d2 == best_d2 && best.is_none_or(|(f, _, _)| face < f));
                    if better {
                        best_d2 = d2;
                        best = Some((face, q, bary));
                    }
                }
            } else {
                let (a, b) = (node.first, node.first + 1);
                let da = self.nodes[a as usize].aabb().distance_squared(p);
                let db = self.nodes[b as usize].aabb().distance_squared(p);
                let (near, far, dn, df) = if da <= db {
                    (a, b, da, db)
                } else {
                    (b, a, db, da)
                };
                if df <= best_d2 {
                    stack[top] = far;
                    top += 1;
                }
                if dn <= best_d2 {
                    stack[top] = near;
                    top += 1;
                }
            }
        }
        best.map(|(face, point, barycentric)| ClosestPoint {
            face,
            point,
            distance: best_d2.sqrt(),
            barycentric,
        })
    }
}

/// Closest point of triangle `t` to `p`, with its barycentric weights (Ericson's method).
pub(crate) fn closest_on_triangle(p: Vec3, t: &[Vec3; 3]) -> (Vec3, Vec3) {
    let [a, b, c] = *t;
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Vec3::X);
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Vec3::Y);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let denom = d1 - d3;
        let v = if denom > 0.0 { d1 / denom } else { 0.0 };
        return (a + ab * v, Vec3::new(1.0 - v, v, 0.0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Vec3::Z);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let denom = d2 - d6;
        let w = if denom > 0.0 { d2 / denom } else { 0.0 };
        return (a + ac * w, Vec3::new(1.0 - w, 0.0, w));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let denom = (d4 - d3) + (d5 - d6);
        let w = if denom > 0.0 { (d4 - d3) / denom } else { 0.0 };
        return (b + (c - b) * w, Vec3::new(0.0, 1.0 - w, w));
    }
    let sum = va + vb + vc;
    if sum.abs() <= f32::MIN_POSITIVE || !sum.is_finite() {
        // Numerically flat: fall back to the nearest of the three edges.
        return nearest_edge_point(p, t);
    }
    let denom = 1.0 / sum;
    let v = (vb * denom).clamp(0.0, 1.0);
    let w = (vc * denom).clamp(0.0, 1.0 - v);
    (a + ab * v + ac * w, Vec3::new(1.0 - v - w, v, w))
}

/// Nearest point on the three edges (for triangles too flat for the face region).
fn nearest_edge_point(p: Vec3, t: &[Vec3; 3]) -> (Vec3, Vec3) {
    let mut best = (t[0], Vec3::X, f32::INFINITY);
    for (i, j) in [(0usize, 1usize), (1, 2), (2, 0)] {
        let e = t[j] - t[i];
        let len2 = e.length_squared();
        let s = if len2 > 0.0 {
            ((p - t[i]).dot(e) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = t[i] + e * s;
        let d = q.distance_squared(p);
        if d < best.2 {
            let mut bary = Vec3::ZERO;
            bary[i] = 1.0 - s;
            bary[j] += s;
            best = (q, bary, d);
        }
    }
    (best.0, best.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: [Vec3; 3] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 2.0, 0.0),
    ];

    #[test]
    fn each_voronoi_region() {
        let cases = [
            (Vec3::new(0.5, 0.5, 3.0), Vec3::new(0.5, 0.5, 0.0)), // face
            (Vec3::new(-1.0, -1.0, 0.0), T[0]),                   // vertex a
            (Vec3::new(3.0, -1.0, 1.0), T[1]),                    // vertex b
            (Vec3::new(-1.0, 3.0, 0.0), T[2]),                    // vertex c
            (Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 0.0, 0.0)), // edge ab
            (Vec3::new(-1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)), // edge ac
            (Vec3::new(2.0, 2.0, 0.0), Vec3::new(1.0, 1.0, 0.0)), // edge bc
        ];
        for (p, expected) in cases {
            let (q, bary) = closest_on_triangle(p, &T);
            assert!(
                (q - expected).length() < 1e-6,
                "{p} -> {q}, expected {expected}"
            );
            let rebuilt = T[0] * bary.x + T[1] * bary.y + T[2] * bary.z;
            assert!((rebuilt - q).length() < 1e-6);
            assert!((bary.x + bary.y + bary.z - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn degenerate_triangles_give_true_distances() {
        let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
        let (q, _) = closest_on_triangle(Vec3::new(1.5, 1.0, 0.0), &line);
        assert!((q - Vec3::new(1.5, 0.0, 0.0)).length() < 1e-6);
        let point = [Vec3::ONE; 3];
        let (q, _) = closest_on_triangle(Vec3::ZERO, &point);
        assert_eq!(q, Vec3::ONE);
    }
}
