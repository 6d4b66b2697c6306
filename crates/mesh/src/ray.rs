//! Ray casting against a [`Bvh`]: the nearest triangle hit along a ray, optionally only
//! among faces a filter accepts.
//!
//! Inputs: origin and direction (any non-zero length; `t` is measured in units of the
//! direction's length), an interval `[t_min, t_max]`. Output: the nearest hit in the interval
//! as a [`RayHit`] (face, `t`, barycentric weights of the face's corners), or `None`.
//!
//! Triangle test: Möller–Trumbore in f32, double-sided. To keep rays from slipping through
//! the shared edge of two triangles, the barycentric test accepts points up to
//! [`EDGE_TOLERANCE`] outside a triangle (relative to its edges); the returned barycentric
//! weights are clamped back into the triangle. Rays parallel to a triangle (|det| below
//! `1e-12` of the squared mesh scale times the direction length) miss it.
//!
//! Traversal: nearest child first, boxes tested with the slab method (reciprocal direction,
//! IEEE infinities for axis-parallel rays); the stack is a fixed array, so queries allocate
//! nothing. Ties in `t` go to the lower face id, so results do not depend on tree order.
//!
//! Cost: O(log F) box tests and a few triangle tests for typical rays.
//!
//! Based on: Möller and Trumbore, *Fast, Minimum Storage Ray/Triangle Intersection* (JGT
//! 1997); Williams et al., *An Efficient and Robust Ray–Box Intersection Algorithm* (JGT
//! 2005).

use glam::Vec3;

use crate::bvh::{Bvh, MAX_DEPTH};
use crate::FaceId;

/// How far outside a triangle (in barycentric units) a hit still counts, so that rays through
/// a shared edge hit one of its triangles.
pub const EDGE_TOLERANCE: f32 = 1e-6;

/// A ray's nearest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The face hit.
    pub face: FaceId,
    /// Ray parameter: the hit point is `origin + t * dir`.
    pub t: f32,
    /// Weights of the face's three corners (non-negative, summing to 1).
    pub barycentric: Vec3,
}

impl Bvh {
    /// The nearest hit with `t` in `[t_min, t_max]`, or `None`.
    pub fn ray_cast(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<RayHit> {
        self.ray_cast_filtered(origin, dir, t_min, t_max, |_| true)
    }

    /// The nearest hit with `t` in `[t_min, t_max]` on a face that `accept` returns `true`
    /// for. Rejected faces are see-through: the ray continues behind them.
    /// One function, though long: a hot kernel (every ray of a conversion walks its
    /// traversal loop).
    pub fn ray_cast_filtered(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        mut accept: impl FnMut(FaceId) -> bool,
    ) -> Option<RayHit> {
        if self.is_empty_root() || !origin.is_finite() || !dir.is_finite() || dir == Vec3::ZERO {
            return None;
        }
        let inv = dir.recip();
        let det_epsilon = 1e-12 * self.scale * self.scale * dir.length();
        let mut best: Option<RayHit> = None;
        let mut t_best = t_max;
        let mut stack = [0u32; MAX_DEPTH * 2 + 2];
        let mut top = 1usize;
        stack[0] = 0;
        while top > 0 {
            top -= 1;
            let node = self.nodes[stack[top] as usize];
            match slab(node.min, node.max, origin, inv, t_min, t_best) {
                Some(_) => {}
                None => continue,
            }
            if node.count > 0 {
                for k in node.first as usize..(node.first + node.count) as usize {
                    let face = self.faces[k];
                    let Some((t, bary)) = intersect(&self.corners[k], origin, dir, det_epsilon)
                    else {
                        continue;
                    };
                    if t < t_min || t > t_best {
                        continue;
                    }
                    if t == t_best && best.is_some_and(|b| b.face < face) {
                        continue;
                    }
                    if !accept(face) {
                        continue;
                    }
                    t_best = t;
                    best = Some(RayHit {
                        face,
                        t,
                        barycentric: bary,
                    });
                }
            } else {
                let (a, b) = (node.first, node.first + 1);
                let na = self.nodes[a as usize];
                let nb = self.nodes[b as usize];
                let ta = slab(na.min, na.max, origin, inv, t_min, t_best);
                let tb = slab(nb.min, nb.max, origin, inv, t_min, t_best);
                // Push the farther child first so the nearer one is visited first.
                match (ta, tb) {
                    (Some(ta), Some(tb)) => {
                        let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
                        stack[top] = far;
                        stack[top + 1] = near;
                        top += 2;
                    }
                    (Some(_), None) => {
                        stack[top] = a;
                        top += 1;
                    }
                    (None, Some(_)) => {
                        stack[top] = b;
                        top += 1;
                    }
                    (None, None) => {}
                }
            }
        }
        best
    }
}

/// Entry distance of the ray into the box within `[t_min, t_max]`, or `None` when it misses.
#[inline]
fn slab(min: Vec3, max: Vec3, origin: Vec3, inv: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
    let t0 = (min - origin) * inv;
    let t1 = (max - origin) * inv;
    // NaN arises from 0 * inf (origin on a slab plane of an axis-parallel ray): treat it as
    // "inside" on that axis by letting min/max ignore it (f32::min/max return the non-NaN).
    let near = t0.min(t1);
    let far = t0.max(t1);
    let enter = near.max_element().max(t_min);
    let exit = far.min_element().min(t_max);
    // A little slack so rays grazing a flat (zero-thickness) box still enter it.
    let slack = exit.abs().max(enter.abs()) * 1e-6;
    (enter <= exit + slack).then_some(enter)
}

/// Möller–Trumbore, double-sided. Returns `t` and clamped barycentric weights.
#[inline]
fn intersect(c: &[Vec3; 3], origin: Vec3, dir: Vec3, det_epsilon: f32) -> Option<(f32, Vec3)> {
    let e1 = c[1] - c[0];
    let e2 = c[2] - c[0];
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() <= det_epsilon || !det.is_finite() {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = origin - c[0];
    let u = s.dot(p) * inv_det;
    if !(-EDGE_TOLERANCE..=1.0 + EDGE_TOLERANCE).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv_det;
    if v < -EDGE_TOLERANCE || u + v > 1.0 + EDGE_TOLERANCE {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    let u = u.max(0.0);
    let v = v.max(0.0);
    let sum = u + v;
    let (u, v) = if sum > 1.0 {
        (u / sum, v / sum)
    } else {
        (u, v)
    };
    Some((t, Vec3::new(1.0 - u - v, u, v)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TriangleMesh;

    fn quad() -> TriangleMesh {
        TriangleMesh::new(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap()
    }

    #[test]
    fn hits_front_and_back() {
        let bvh = Bvh::new(&quad());
        let hit = bvh
            .ray_cast(Vec3::new(0.7, 0.2, 1.0), -Vec3::Z, 0.0, 10.0)
            .unwrap();
        assert_eq!(hit.face, FaceId(0));
        assert!((hit.t - 1.0).abs() < 1e-6);
        let p = Vec3::new(0.0, 0.0, 0.0) * hit.barycentric.x
            + Vec3::new(1.0, 0.0, 0.0) * hit.barycentric.y
            + Vec3::new(1.0, 1.0, 0.0) * hit.barycentric.z;
        assert!((p - Vec3::new(0.7, 0.2, 0.0)).length() < 1e-6);
        assert!(bvh
            .ray_cast(Vec3::new(0.7, 0.2, -1.0), Vec3::Z, 0.0, 10.0)
            .is_some());
        assert!(bvh
            .ray_cast(Vec3::new(0.7, 0.2, 1.0), Vec3::Z, 0.0, 10.0)
            .is_none());
        assert!(bvh
            .ray_cast(Vec3::new(0.7, 0.2, 1.0), -Vec3::Z, 0.0, 0.5)
            .is_none());
    }

    #[test]
    fn the_shared_diagonal_is_watertight() {
        let bvh = Bvh::new(&quad());
        for k in 1..100 {
            let x = k as f32 / 100.0;
            let hit = bvh.ray_cast(Vec3::new(x, x, 1.0), -Vec3::Z, 0.0, 10.0);
            assert!(
                hit.is_some(),
                "ray through the diagonal at {x} slipped through"
            );
        }
    }

    #[test]
    fn filter_sees_through_rejected_faces() {
        let mut mesh = quad();
        // A second quad above the first.
        mesh.positions
            .extend(mesh.positions.clone().iter().map(|p| *p + Vec3::Z * 0.5));
        mesh.triangles.push([4, 5, 6]);
        mesh.triangles.push([4, 6, 7]);
        let bvh = Bvh::new(&mesh);
        let origin = Vec3::new(0.7, 0.2, 1.0);
        assert_eq!(
            bvh.ray_cast(origin, -Vec3::Z, 0.0, 10.0).unwrap().face,
            FaceId(2)
        );
        let hit = bvh
            .ray_cast_filtered(origin, -Vec3::Z, 0.0, 10.0, |f| f.0 < 2)
            .unwrap();
        assert_eq!(hit.face, FaceId(0));
    }

    #[test]
    fn degenerate_rays_miss() {
        let bvh = Bvh::new(&quad());
        assert!(bvh.ray_cast(Vec3::ZERO, Vec3::ZERO, 0.0, 1.0).is_none());
        assert!(bvh.ray_cast(Vec3::NAN, Vec3::Z, 0.0, 1.0).is_none());
        let empty = Bvh::new(&TriangleMesh::default());
        assert!(empty.ray_cast(Vec3::ZERO, Vec3::Z, 0.0, 1.0).is_none());
    }
}
