//! Area-weighted random points on a mesh surface, reproducible from a seed.
//!
//! Each sample picks a face with probability proportional to its area (binary search in the
//! f64 running sum of areas), then a uniform point in the face with the square-root mapping
//! `w = (1 - sqrt(r1), sqrt(r1) (1 - r2), sqrt(r1) r2)`. Random numbers come from
//! [`SplitMix64`], written here so results are identical on every platform and
//! independent of any external crate's version.
//!
//! Cost: O(F) to build the area table, O(log F) per sample.
//!
//! Based on: Turk, *Generating Random Points in Triangles* (Graphics Gems, 1990); Osada et
//! al., *Shape Distributions* (ACM TOG 2002), eq. 1; Steele, Lea and Flood, *Fast Splittable
//! Pseudorandom Number Generators* (OOPSLA 2014) for SplitMix64.

use glam::Vec3;

use crate::{FaceId, TriangleMesh};

/// A point on the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceSample {
    /// The face it lies on.
    pub face: FaceId,
    /// The point (mesh coordinates).
    pub point: Vec3,
    /// Weights of the face's corners.
    pub barycentric: Vec3,
}

/// The SplitMix64 generator: 64 bits of state, full period, good enough for sampling.
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator started from `seed`.
    pub fn new(seed: u64) -> SplitMix64 {
        SplitMix64 { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform value in `[0, 1)` with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// `count` points spread uniformly by area over `mesh`, reproducible from `seed`. Empty when
/// the mesh has no area.
pub fn sample_surface(mesh: &TriangleMesh, count: usize, seed: u64) -> Vec<SurfaceSample> {
    let mut cumulative = Vec::with_capacity(mesh.triangles.len());
    let mut total = 0.0f64;
    for f in mesh.faces() {
        let [a, b, c] = mesh.face_positions(f).map(Vec3::as_dvec3);
        total += 0.5 * (b - a).cross(c - a).length();
        cumulative.push(total);
    }
    if !(total > 0.0 && total.is_finite()) {
        return Vec::new();
    }
    let mut rng = SplitMix64::new(seed);
    (0..count)
        .map(|_| {
            let target = rng.next_f64() * total;
            // First face whose running sum exceeds the target (zero-area faces never do).
            let i = cumulative
                .partition_point(|&c| c <= target)
                .min(cumulative.len() - 1);
            let face = FaceId(i as u32);
            let s = rng.next_f64().sqrt();
            let r2 = rng.next_f64();
            let barycentric = Vec3::new((1.0 - s) as f32, (s * (1.0 - r2)) as f32, (s * r2) as f32);
            SurfaceSample {
                face,
                point: mesh.point_at(face, barycentric),
                barycentric,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_follow_area_and_are_reproducible() {
        // Two triangles of areas 0.5 and 3: the second gets 6/7 of the samples.
        let mesh = TriangleMesh::new(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::Y,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(5.0, 0.0, 0.0),
                Vec3::new(2.0, 2.0, 0.0),
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        )
        .unwrap();
        let a = sample_surface(&mesh, 20_000, 7);
        assert_eq!(a, sample_surface(&mesh, 20_000, 7));
        assert_ne!(a, sample_surface(&mesh, 20_000, 8));
        let second = a.iter().filter(|s| s.face == FaceId(1)).count() as f64 / 20_000.0;
        assert!((second - 6.0 / 7.0).abs() < 0.01, "{second}");
        for s in &a {
            assert!(s.barycentric.min_element() >= 0.0);
            assert!((s.barycentric.element_sum() - 1.0).abs() < 1e-5);
        }
    }

    #[test]
    fn no_area_no_samples() {
        let mesh = TriangleMesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 2]]).unwrap();
        assert!(sample_surface(&mesh, 10, 1).is_empty());
    }
}
