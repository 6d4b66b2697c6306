//! View directions spread evenly over the sphere, each with an orthonormal image basis.
//!
//! Input: a count `n ≥ 1`. Output: `n` [`ViewBasis`] values whose directions lie on a
//! spherical Fibonacci lattice: point `k` has height `z = 1 − (2k + 1)/n` and longitude
//! `k · golden angle`, so every direction covers about the same area `4π/n` of the sphere and
//! no two cluster. The largest angle from any direction on the sphere to its nearest view is
//! about `1.1 · sqrt(4π/n)` radians (about 27° for 20 views).
//!
//! Invariants: every basis is orthonormal and right-handed (`u × w = direction`); the output
//! depends only on `n` (deterministic).
//!
//! Cost: O(n).
//!
//! Based on: Á. González, "Measurement of areas on a sphere using Fibonacci and
//! latitude–longitude lattices", Mathematical Geosciences 42 (2010).

use glam::Vec3;

/// An orthographic viewing direction with its image axes.
///
/// # Guarantees
/// `u`, `w`, `direction` are unit length, pairwise orthogonal, and `u × w = direction`.
/// The viewer looks along `-direction`: a surface is seen from the front when its normal
/// points along `direction`, and a larger height `p · direction` is nearer the viewer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewBasis {
    /// Unit vector towards the viewer.
    pub direction: Vec3,
    /// Unit image x axis.
    pub u: Vec3,
    /// Unit image y axis.
    pub w: Vec3,
}

impl ViewBasis {
    /// The basis of one direction (normalised; a zero vector gives +Z).
    pub fn new(direction: Vec3) -> ViewBasis {
        let direction = direction.normalize_or(Vec3::Z);
        // Start from the world axis least aligned with the direction.
        let helper = if direction.x.abs() < 0.57 {
            Vec3::X
        } else if direction.y.abs() < 0.57 {
            Vec3::Y
        } else {
            Vec3::Z
        };
        let u = (helper - direction * helper.dot(direction)).normalize();
        let w = direction.cross(u);
        ViewBasis { direction, u, w }
    }
}

/// `count` view bases with directions on a spherical Fibonacci lattice (see the module
/// documentation). `count == 0` gives an empty list.
pub fn view_directions(count: usize) -> Vec<ViewBasis> {
    let golden_angle = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let n = count as f64;
    (0..count)
        .map(|k| {
            let z = 1.0 - (2.0 * k as f64 + 1.0) / n;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden_angle * k as f64;
            let d = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
            ViewBasis::new(d)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bases_are_orthonormal_and_right_handed() {
        for basis in view_directions(37) {
            let ViewBasis { direction, u, w } = basis;
            assert!((direction.length() - 1.0).abs() < 1e-5);
            assert!((u.length() - 1.0).abs() < 1e-5);
            assert!((w.length() - 1.0).abs() < 1e-5);
            assert!(u.dot(w).abs() < 1e-5 && u.dot(direction).abs() < 1e-5);
            assert!((u.cross(w) - direction).length() < 1e-5);
        }
    }

    #[test]
    fn every_direction_is_near_a_view() {
        let views = view_directions(20);
        // Probe the sphere densely; the covering radius must stay under 35 degrees.
        let probes = view_directions(2000);
        let worst = probes
            .iter()
            .map(|p| {
                views
                    .iter()
                    .map(|v| v.direction.dot(p.direction))
                    .fold(-1.0f32, f32::max)
            })
            .fold(1.0f32, f32::min);
        assert!(worst > 35f32.to_radians().cos(), "worst cosine {worst}");
    }
}
