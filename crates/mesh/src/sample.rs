//! Area-weighted random points on a mesh surface, reproducible from a seed.
//!
//! Each sample picks a face with probability proportional to its area (binary search in the
//! f64 running sum of areas), then a uniform point in the face with the square-root mapping
//! `w = (1 - sqrt(r1), sqrt(r1) (1 - r2), sqrt(r1) r2)`. Random numbers come from
//! [`SplitMix64`], written here so results are identical on every platform and
//! independent of any external crate's version.
//!
//! Sample `k` uses the generator's draws `3k..3k + 3`, and SplitMix64 can jump to any draw
//! ([`SplitMix64::skip`]), so a [`SurfaceSampler`] can produce any range of the sequence on
//! its own (in parallel, a chunk at a time, without holding all samples):
//! [`SurfaceSampler::samples_by_face`] returns a range's samples ordered by face, which
//! walks the area table in order instead of a random binary search per sample (the table of a
//! million faces does not fit in cache).
//!
//! Cost: O(F) to build the area table, O(log F) per sample (amortized less by face order).
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

    /// Skips the next `draws` values, in constant time.
    pub fn skip(&mut self, draws: u64) {
        self.state = self
            .state
            .wrapping_add(0x9E37_79B9_7F4A_7C15u64.wrapping_mul(draws));
    }

    /// A uniform value in `[0, 1)` with 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// `count` points spread uniformly by area over `mesh`, reproducible from `seed`. Empty when
/// the mesh has no area.
pub fn sample_surface(mesh: &TriangleMesh, count: usize, seed: u64) -> Vec<SurfaceSample> {
    let Some(sampler) = SurfaceSampler::new(mesh) else {
        return Vec::new();
    };
    let mut rng = SplitMix64::new(seed);
    (0..count)
        .map(|_| {
            let draws = [rng.next_f64(), rng.next_f64(), rng.next_f64()];
            let face = sampler.face_of(draws[0] * sampler.total, 0);
            sampler.sample_in(face, draws)
        })
        .collect()
}

/// The band (of `bands` equal bands of `[0, 1)`) of a sample's first draw, the one that
/// picks its face.
pub fn band_of(first_draw: f64, bands: usize) -> usize {
    ((first_draw * bands as f64) as usize).min(bands.max(1) - 1)
}

/// The area table of a mesh, to draw the samples of [`sample_surface`] by ranges.
#[derive(Clone, Debug)]
pub struct SurfaceSampler<'a> {
    mesh: &'a TriangleMesh,
    /// Running sum of face areas (f64).
    cumulative: Vec<f64>,
    total: f64,
}

impl<'a> SurfaceSampler<'a> {
    /// The area table of `mesh`; `None` when the mesh has no area.
    pub fn new(mesh: &'a TriangleMesh) -> Option<SurfaceSampler<'a>> {
        let mut cumulative = Vec::with_capacity(mesh.triangles.len());
        let mut total = 0.0f64;
        for f in mesh.faces() {
            let [a, b, c] = mesh.face_positions(f).map(Vec3::as_dvec3);
            total += 0.5 * (b - a).cross(c - a).length();
            cumulative.push(total);
        }
        (total > 0.0 && total.is_finite()).then_some(SurfaceSampler {
            mesh,
            cumulative,
            total,
        })
    }

    /// Samples `range` of the sequence `sample_surface(mesh, _, seed)` draws, ordered by face
    /// (then by draw), not by index: the same points in an order that reads the area table
    /// in sequence.
    pub fn samples_by_face(&self, seed: u64, range: std::ops::Range<usize>) -> Vec<SurfaceSample> {
        let mut rng = SplitMix64::new(seed);
        rng.skip(3 * range.start as u64);
        let draws: Vec<[f64; 3]> = range
            .map(|_| [rng.next_f64(), rng.next_f64(), rng.next_f64()])
            .collect();
        self.samples_of_draws(draws)
    }

    /// The samples of `range` of the sequence whose first draw (the one that picks the face)
    /// falls in band `k` of `bands` equal bands of `[0, 1)` (see [`band_of`]), ordered by
    /// face as [`SurfaceSampler::samples_by_face`] orders them. The area table is
    /// cumulative, so a band's samples lie on one run of consecutive faces; every sample is
    /// in exactly one band. Draws outside the band are skipped, not computed.
    pub fn samples_by_face_in_band(
        &self,
        seed: u64,
        range: std::ops::Range<usize>,
        (k, bands): (usize, usize),
    ) -> Vec<SurfaceSample> {
        let mut rng = SplitMix64::new(seed);
        rng.skip(3 * range.start as u64);
        let mut draws = Vec::new();
        for _ in range {
            let first = rng.next_f64();
            if band_of(first, bands) == k {
                draws.push([first, rng.next_f64(), rng.next_f64()]);
            } else {
                rng.skip(2);
            }
        }
        self.samples_of_draws(draws)
    }

    /// The samples of `draws`, ordered by face (then by draw).
    fn samples_of_draws(&self, mut draws: Vec<[f64; 3]>) -> Vec<SurfaceSample> {
        draws.sort_unstable_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
        let mut face = 0;
        draws
            .into_iter()
            .map(|d| {
                face = self.face_of(d[0] * self.total, face);
                self.sample_in(face, d)
            })
            .collect()
    }

    /// The first face at or after `from` whose running sum exceeds `target` (zero-area faces
    /// never do); `from` must not be past it. Gallops from `from`, then bisects.
    fn face_of(&self, target: f64, from: usize) -> usize {
        let c = &self.cumulative;
        let last = c.len() - 1;
        let (mut lo, mut step) = (from.min(last), 1);
        while lo + step <= last && c[lo + step] <= target {
            lo += step;
            step *= 2;
        }
        let hi = (lo + step).min(last + 1);
        (lo + c[lo..hi].partition_point(|&x| x <= target)).min(last)
    }

    /// The point of `face` for the last two `draws` (the square-root mapping).
    fn sample_in(&self, face: usize, draws: [f64; 3]) -> SurfaceSample {
        let face = FaceId(face as u32);
        let s = draws[1].sqrt();
        let r2 = draws[2];
        let barycentric = Vec3::new((1.0 - s) as f32, (s * (1.0 - r2)) as f32, (s * r2) as f32);
        SurfaceSample {
            face,
            point: self.mesh.point_at(face, barycentric),
            barycentric,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_hold_every_sample_once_on_runs_of_faces() {
        let mesh = TriangleMesh::new(
            (0..40)
                .flat_map(|k| {
                    let x = k as f32;
                    [
                        Vec3::new(x, 0.0, 0.0),
                        Vec3::new(x + 1.0, 0.0, 0.0),
                        Vec3::new(x, 1.0 + x, 0.0),
                    ]
                })
                .collect(),
            (0..40).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect(),
        )
        .unwrap();
        let sampler = SurfaceSampler::new(&mesh).unwrap();
        let key = |s: &SurfaceSample| (s.face, s.point.x.to_bits(), s.point.y.to_bits());
        let mut all: Vec<_> = sampler
            .samples_by_face(5, 100..3100)
            .iter()
            .map(key)
            .collect();
        let mut banded = Vec::new();
        let mut last_face = None;
        for k in 0..7 {
            let band = sampler.samples_by_face_in_band(5, 100..3100, (k, 7));
            // Bands follow each other along the faces.
            if let (Some(last), Some(first)) = (last_face, band.first().map(|s| s.face)) {
                assert!(
                    last <= first,
                    "band {k} starts before the previous one ends"
                );
            }
            last_face = band.last().map(|s| s.face).or(last_face);
            banded.extend(band.iter().map(key));
        }
        all.sort_unstable();
        banded.sort_unstable();
        assert_eq!(all, banded);
    }

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
    fn ranges_by_face_are_the_sequence_reordered() {
        let mesh = TriangleMesh::new(
            (0..40)
                .map(|k| Vec3::new((k % 8) as f32, (k / 8) as f32, (k % 3) as f32 * 0.3))
                .collect(),
            (0..28)
                .map(|k| {
                    let (i, j) = (k % 7, k / 7);
                    let a = j * 8 + i;
                    [a, a + 1, a + 9]
                })
                .collect(),
        )
        .unwrap();
        let sequence = sample_surface(&mesh, 1000, 5);
        let sampler = SurfaceSampler::new(&mesh).unwrap();
        let key = |s: &SurfaceSample| (s.face, s.point.to_array().map(f32::to_bits));
        for range in [0..1000, 0..1, 317..640, 999..1000] {
            let mut expected = sequence[range.clone()].to_vec();
            let got = sampler.samples_by_face(5, range);
            assert!(got.windows(2).all(|w| w[0].face <= w[1].face));
            expected.sort_by_key(key);
            let mut got = got;
            got.sort_by_key(key);
            assert_eq!(got, expected);
        }
    }

    #[test]
    fn skip_jumps_draws() {
        let mut a = SplitMix64::new(11);
        for _ in 0..37 {
            a.next_u64();
        }
        let mut b = SplitMix64::new(11);
        b.skip(37);
        assert_eq!(a.next_u64(), b.next_u64());
    }

    #[test]
    fn no_area_no_samples() {
        let mesh = TriangleMesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 2]]).unwrap();
        assert!(sample_surface(&mesh, 10, 1).is_empty());
    }
}
