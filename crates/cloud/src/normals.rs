//! Point normals by principal component analysis of each point's neighbourhood.
//!
//! Input: positions, their [`PointTree`], a neighbour count `k`. Output: one unit normal per
//! point, the eigenvector of the smallest eigenvalue of the covariance of the `k` nearest
//! points (the point included); a zero vector where the neighbourhood has no plane (all
//! points coincide or lie on a line). Normals are *unoriented*: the sign is arbitrary, and
//! the rest of the pipeline only uses them up to sign (depth extrapolation inside a pixel and
//! grazing-angle tests).
//!
//! The 3×3 symmetric eigenproblem is solved in closed form (trigonometric eigenvalues, then
//! the eigenvector as the largest cross product of two rows of `A − λI`), in f64 on the
//! centred and rescaled covariance.
//!
//! Invariants: deterministic; each normal depends only on its own neighbourhood.
//!
//! Cost: one k-nearest query per point, O(n log n), parallel over chunks of points.
//!
//! Based on: H. Hoppe, T. DeRose, T. Duchamp, J. McDonald, W. Stuetzle, "Surface
//! reconstruction from unorganized points", SIGGRAPH 1992; O. K. Smith, "Eigenvalues of a
//! symmetric 3×3 matrix", CACM 4(4), 1961.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::spacing::PointTree;

/// Points per parallel work item.
const CHUNK: usize = 4096;

/// PCA normals of every point (see the module documentation).
pub fn estimate_normals(positions: &[Vec3], tree: &PointTree, neighbours: usize) -> Vec<Vec3> {
    let chunks: Vec<Vec<Vec3>> = positions
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut found = Vec::with_capacity(neighbours);
            let mut local = Vec::with_capacity(neighbours);
            chunk
                .iter()
                .map(|&p| {
                    tree.nearest_k(p, neighbours, &mut found);
                    local.clear();
                    local.extend(found.iter().map(|&(_, id)| positions[id.index()]));
                    plane_normal(&local)
                })
                .collect()
        })
        .collect();
    chunks.concat()
}

/// The normal of the least-squares plane through `points`, or zero when there is none.
pub fn plane_normal(points: &[Vec3]) -> Vec3 {
    if points.len() < 3 {
        return Vec3::ZERO;
    }
    let centre = points.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / points.len() as f64;
    let mut c = [0.0f64; 6]; // xx xy xz yy yz zz
    for p in points {
        let d = p.as_dvec3() - centre;
        c[0] += d.x * d.x;
        c[1] += d.x * d.y;
        c[2] += d.x * d.z;
        c[3] += d.y * d.y;
        c[4] += d.y * d.z;
        c[5] += d.z * d.z;
    }
    smallest_eigenvector(c).as_vec3()
}

/// The unit eigenvector of the smallest eigenvalue of the symmetric matrix
/// `[[a0, a1, a2], [a1, a3, a4], [a2, a4, a5]]`, or zero when it is not unique.
pub fn smallest_eigenvector(a: [f64; 6]) -> DVec3 {
    let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return DVec3::ZERO;
    }
    let [a00, a01, a02, a11, a12, a22] = a.map(|v| v / scale);
    let q = (a00 + a11 + a22) / 3.0;
    let p1 = a01 * a01 + a02 * a02 + a12 * a12;
    let p2 = (a00 - q).powi(2) + (a11 - q).powi(2) + (a22 - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    if p < 1e-12 {
        // A multiple of the identity: every direction is an eigenvector.
        return DVec3::ZERO;
    }
    let (b00, b11, b22) = ((a00 - q) / p, (a11 - q) / p, (a22 - q) / p);
    let (b01, b02, b12) = (a01 / p, a02 / p, a12 / p);
    let det = b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02)
        + b02 * (b01 * b12 - b11 * b02);
    let r = (det / 2.0).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let largest = q + 2.0 * p * phi.cos();
    let smallest = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let middle = 3.0 * q - largest - smallest;
    // The smallest eigenvalue must be separated from the middle one for a unique normal.
    // (`acos` near ±1 loses half the digits, so the margin is 1e-6, not machine epsilon.)
    if middle - smallest < 1e-6 * (largest - smallest) {
        return DVec3::ZERO;
    }
    let rows = [
        DVec3::new(a00 - smallest, a01, a02),
        DVec3::new(a01, a11 - smallest, a12),
        DVec3::new(a02, a12, a22 - smallest),
    ];
    let crosses = [
        rows[0].cross(rows[1]),
        rows[0].cross(rows[2]),
        rows[1].cross(rows[2]),
    ];
    let best = crosses
        .into_iter()
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))
        .unwrap_or(DVec3::ZERO);
    best.try_normalize().unwrap_or(DVec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn eigenvector_of_a_rotated_diagonal_matrix() {
        let q = DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
        let m = glam::DMat3::from_quat(q)
            * glam::DMat3::from_diagonal(DVec3::new(3.0, 2.0, 0.01))
            * glam::DMat3::from_quat(q).transpose();
        let a = [
            m.x_axis.x, m.y_axis.x, m.z_axis.x, m.y_axis.y, m.z_axis.y, m.z_axis.z,
        ];
        let v = smallest_eigenvector(a);
        let expected = q * DVec3::Z;
        assert!(v.dot(expected).abs() > 1.0 - 1e-9, "{v} vs {expected}");
    }

    #[test]
    fn plane_normal_of_a_tilted_grid_and_degenerate_inputs() {
        let n = Vec3::new(1.0, 2.0, 3.0).normalize();
        let u = n.any_orthonormal_vector();
        let w = n.cross(u);
        let pts: Vec<Vec3> = (0..16)
            .map(|k| u * (k % 4) as f32 + w * (k / 4) as f32 + Vec3::splat(5.0))
            .collect();
        assert!(plane_normal(&pts).dot(n).abs() > 0.9999);
        let line: Vec<Vec3> = (0..5).map(|k| Vec3::X * k as f32).collect();
        assert_eq!(plane_normal(&line), Vec3::ZERO);
        assert_eq!(plane_normal(&[Vec3::ONE; 6]), Vec3::ZERO);
    }
}
