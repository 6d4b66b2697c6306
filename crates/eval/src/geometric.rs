//! Geometric error of a scene against its source mesh (DESIGN §6).
//!
//! Two one-sided distances, both reported as max (the one-sided Hausdorff distance), RMS and
//! 95th percentile, absolute and divided by the source's bounding-box diagonal:
//!
//! - **node → surface**: every filled node to the nearest point of the source's triangles
//!   (the source's BVH, `spatch_mesh::Bvh::closest_point`). It bounds how far the stored
//!   samples are from the truth: quantization, frame rounding, a wrong layer.
//! - **surface → patch**: points spread uniformly by area over the source
//!   (`spatch_mesh::sample_surface`) to the nearest point of the patch surface, every drawable
//!   cell taken as the bilinear quad through its four nodes (`spatch_cloud::PatchSurface`: an
//!   exact search through a flat grid of cell boxes; `spatch_cloud::distance_to_quad` states
//!   the accuracy of the distance to one quad). It reveals what the nodes cannot: holes,
//!   cracks between patches, missed pieces of surface.
//!
//! Scene positions are moved into the mesh's coordinates by the difference of the two f64
//! offsets, so a model far from the world origin is measured without f32 loss.
//!
//! The samples are measured band by band, about [`QUERY_BATCH`] at a time: band `k` of `B`
//! holds the samples whose face-picking draw lies in `[k / B, (k + 1) / B)`, so the samples of
//! one run of consecutive faces (`SurfaceSampler::samples_by_face_in_band`; each band scans
//! the whole seeded sequence [`SAMPLE_CHUNK`] draws at a time in parallel and computes only
//! its own samples). Faces that follow each other in the file are usually near each other,
//! so a band covers a part of the model and its queries share the cells they read: on the 1
//! M-triangle plane about ten samples a grid cell instead of one when each batch was a
//! range of the sequence spread over the whole model. They are queried grouped by grid cell
//! (`PatchSurface::nearest_all`), so the
//! `max(100_000, 10 × F)` samples are never held at once: memory is four bytes per sample for its distance (and
//! four for its patch where per-patch figures need it), not the 28 of a stored sample plus 12
//! of its point. The figures are those of the whole sequence, whatever the chunking.
//!
//! Cost: O(N log F) for N nodes, O(S log C) for S samples and C drawable cells; both parallel
//! (rayon), with results independent of the thread count.

use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Deserializer, Serialize};
use spatch_cloud::PatchSurface;
use spatch_format::Scene;
use spatch_mesh::{Bvh, SurfaceSampler, TriangleMesh};

/// Fewest source samples for [`surface_to_patch`] (DESIGN §6).
pub const MIN_SAMPLES: usize = 100_000;
/// Samples per source face when that gives more than [`MIN_SAMPLES`].
pub const SAMPLES_PER_FACE: usize = 10;
/// Source samples drawn together (one parallel work item).
pub const SAMPLE_CHUNK: usize = 1 << 16;
/// Source samples measured together: enough that, sorted by grid cell, neighbouring queries
/// share the nodes and cells they read (a 1 M-triangle source has about 4 M cells).
pub const QUERY_BATCH: usize = 1 << 20;

/// Summary of a set of distances: one named one-way error of a report.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ErrorStats {
    /// How many distances were measured.
    pub samples: usize,
    /// Largest distance (model units); infinite when the scene has nothing to measure against
    /// (serialized as `null`, read back as infinite).
    #[serde(deserialize_with = "null_as_infinite")]
    pub max: f64,
    /// Root mean square distance.
    #[serde(deserialize_with = "null_as_infinite")]
    pub rms: f64,
    /// 95th percentile.
    #[serde(deserialize_with = "null_as_infinite")]
    pub p95: f64,
    /// `max` divided by the source's bounding-box diagonal.
    #[serde(deserialize_with = "null_as_infinite")]
    pub max_rel: f64,
    /// `rms` divided by the source's bounding-box diagonal.
    #[serde(deserialize_with = "null_as_infinite")]
    pub rms_rel: f64,
}

/// JSON has no infinity: serde_json writes it as `null`, so `null` reads back as infinite.
fn null_as_infinite<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

impl From<&spatch_cloud::DistanceStats> for ErrorStats {
    fn from(d: &spatch_cloud::DistanceStats) -> Self {
        ErrorStats {
            samples: d.count,
            max: d.max,
            rms: d.rms,
            p95: d.p95,
            max_rel: d.max_rel,
            rms_rel: d.rms_rel,
        }
    }
}

/// The two one-way errors of a cloud measurement under the names reports give them
/// (`cloud_to_patch`, `node_to_cloud`; docs/report-schema.md).
pub fn cloud_error_entries(
    e: &spatch_cloud::CloudErrorReport,
) -> impl Iterator<Item = (String, ErrorStats)> {
    [
        (
            "cloud_to_patch",
            ErrorStats::from(&e.cloud_to_patch.distance),
        ),
        ("node_to_cloud", ErrorStats::from(&e.node_to_cloud)),
    ]
    .into_iter()
    .map(|(name, stats)| (name.to_owned(), stats))
}

impl ErrorStats {
    /// Summarizes `distances` (reordered in place) relative to `diagonal`.
    pub fn from_distances(distances: &mut [f32], diagonal: f64) -> ErrorStats {
        let n = distances.len();
        if n == 0 {
            return ErrorStats {
                samples: 0,
                max: 0.0,
                rms: 0.0,
                p95: 0.0,
                max_rel: 0.0,
                rms_rel: 0.0,
            };
        }
        let max = distances.iter().copied().fold(0.0f32, f32::max) as f64;
        let sum_sq: f64 = distances.iter().map(|&d| f64::from(d) * f64::from(d)).sum();
        let rms = (sum_sq / n as f64).sqrt();
        let k = ((n as f64 * 0.95).ceil() as usize).clamp(1, n) - 1;
        let (_, p95, _) = distances.select_nth_unstable_by(k, f32::total_cmp);
        let p95 = f64::from(*p95);
        let rel = |x: f64| if diagonal > 0.0 { x / diagonal } else { 0.0 };
        ErrorStats {
            samples: n,
            max,
            rms,
            p95,
            max_rel: rel(max),
            rms_rel: rel(rms),
        }
    }
}

/// Both distances of a scene against its source.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GeometricError {
    /// Filled nodes to the source surface.
    pub node_to_surface: ErrorStats,
    /// Source samples to the patch surface.
    pub surface_to_patch: ErrorStats,
    /// The source's bounding-box diagonal, the scale of the relative figures.
    pub diagonal: f64,
}

/// The offset that moves scene-relative points into `mesh` coordinates.
fn scene_to_mesh(scene: &Scene, mesh: &TriangleMesh) -> Vec3 {
    (scene.offset() - mesh.origin).as_vec3()
}

/// Distance from every filled node of `scene` to the nearest point of `mesh` (whose BVH is
/// `bvh`), in patch order then node order.
///
/// Neighbouring nodes have neighbouring nearest points, so each search is bounded by the
/// distance to the previous node's nearest point (a point of the surface, so the nearest
/// is never farther): boxes beyond it are pruned from the root down. The distances are
/// those of an unbounded search.
pub fn node_to_surface_distances(scene: &Scene, mesh: &TriangleMesh, bvh: &Bvh) -> Vec<f32> {
    let shift = scene_to_mesh(scene, mesh);
    scene
        .patches()
        .par_iter()
        .flat_map_iter(|patch| {
            let mut previous: Option<Vec3> = None;
            patch.filled_nodes().map(move |(_, _, q)| {
                let q = q + shift;
                let found = previous
                    .and_then(|c| bvh.closest_point(q, bound_through(q, c)))
                    .or_else(|| bvh.closest_point(q, f32::INFINITY));
                previous = found.map(|c| c.point);
                found.map_or(f32::INFINITY, |c| c.distance)
            })
        })
        .collect()
}

/// A search radius from `q` that surely holds the surface point `c`: their distance with a
/// relative margin for rounding (the search falls back to no radius if it finds nothing).
fn bound_through(q: Vec3, c: Vec3) -> f32 {
    q.distance(c) * (1.0 + 1e-4) + f32::MIN_POSITIVE
}

/// [`ErrorStats`] of every filled node of `scene` to the nearest point of `mesh`.
pub fn node_to_surface(scene: &Scene, mesh: &TriangleMesh, bvh: &Bvh) -> ErrorStats {
    let mut d = node_to_surface_distances(scene, mesh, bvh);
    ErrorStats::from_distances(&mut d, f64::from(mesh.diagonal()))
}

/// Distance from each of `samples` (points in `mesh` coordinates, usually on its surface) to
/// the nearest point of the patch surface of `scene`; infinite when the scene has no drawable
/// cell.
pub fn surface_to_patch_distances(
    scene: &Scene,
    mesh: &TriangleMesh,
    samples: &[Vec3],
) -> Vec<f32> {
    nearest_patch_cells(scene, mesh.origin, samples).0
}

/// For each of `points` (relative to `origin`): the distance to the nearest point of the
/// patch surface of `scene` (drawable cells as bilinear quads) and the index of the patch
/// that point belongs to. With no drawable cell every distance is infinite and every index
/// is [`NO_PATCH`].
pub fn nearest_patch_cells(
    scene: &Scene,
    origin: glam::DVec3,
    points: &[Vec3],
) -> (Vec<f32>, Vec<u32>) {
    let shift = (scene.offset() - origin).as_vec3();
    match PatchSurface::new(scene, shift) {
        Some(surface) => surface.nearest_all(points),
        None => (
            vec![f32::INFINITY; points.len()],
            vec![NO_PATCH; points.len()],
        ),
    }
}

/// The first `count` samples of `mesh` drawn from `seed` (the points of
/// `sample_surface(mesh, count, seed)`) to the patch surface of `scene`: `keep(distance,
/// patch)` of each, ordered by band of faces, then by chunk, then by face within a chunk
/// (see the module docs).
/// Empty when the mesh has no area; infinite distances and [`NO_PATCH`] when the scene has
/// no drawable cell.
pub fn sampled_surface_to_patch<T: Send>(
    scene: &Scene,
    mesh: &TriangleMesh,
    count: usize,
    seed: u64,
    keep: impl Fn(f32, u32) -> T + Sync,
) -> Vec<T> {
    let Some(sampler) = SurfaceSampler::new(mesh) else {
        return Vec::new();
    };
    let shift = (scene.offset() - mesh.origin).as_vec3();
    let Some(surface) = PatchSurface::new(scene, shift) else {
        return (0..count).map(|_| keep(f32::INFINITY, NO_PATCH)).collect();
    };
    let mut kept = Vec::with_capacity(count);
    let bands = count.div_ceil(QUERY_BATCH);
    let chunks: Vec<usize> = (0..count).step_by(SAMPLE_CHUNK).collect();
    for band in 0..bands {
        let points: Vec<Vec3> = chunks
            .par_iter()
            .flat_map_iter(|&from| {
                let range = from..(from + SAMPLE_CHUNK).min(count);
                sampler
                    .samples_by_face_in_band(seed, range, (band, bands))
                    .into_iter()
                    .map(|s| s.point)
            })
            .collect();
        let (distances, owners) = surface.nearest_all(&points);
        kept.par_extend(
            distances
                .into_par_iter()
                .zip(owners)
                .map(|(d, patch)| keep(d, patch)),
        );
    }
    kept
}

/// The patch index [`nearest_patch_cells`] gives a point when the scene has no drawable cell.
pub use spatch_cloud::NO_PATCH;

/// [`ErrorStats`] of `samples` (points on `mesh`) to the patch surface of `scene`.
pub fn surface_to_patch(scene: &Scene, mesh: &TriangleMesh, samples: &[Vec3]) -> ErrorStats {
    let mut d = surface_to_patch_distances(scene, mesh, samples);
    ErrorStats::from_distances(&mut d, f64::from(mesh.diagonal()))
}

/// The number of source samples DESIGN §6 asks for: `max(100_000, 10 × faces)`.
pub fn sample_count(mesh: &TriangleMesh) -> usize {
    MIN_SAMPLES.max(SAMPLES_PER_FACE * mesh.face_count())
}

/// Both distances, with [`sample_count`] samples drawn from `seed` (the BVH of the source
/// is dropped before the patch surface is indexed, so the two are never held together).
pub fn geometric_error(scene: &Scene, mesh: &TriangleMesh, seed: u64) -> GeometricError {
    let diagonal = f64::from(mesh.diagonal());
    let node_to_surface = {
        let bvh = Bvh::new(mesh);
        node_to_surface(scene, mesh, &bvh)
    };
    let mut distances = sampled_surface_to_patch(scene, mesh, sample_count(mesh), seed, |d, _| d);
    GeometricError {
        node_to_surface,
        surface_to_patch: ErrorStats::from_distances(&mut distances, diagonal),
        diagonal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_known_distances() {
        let mut d: Vec<f32> = (1..=100).map(|k| k as f32).collect();
        let s = ErrorStats::from_distances(&mut d, 200.0);
        assert_eq!(s.samples, 100);
        assert_eq!(s.max, 100.0);
        assert_eq!(s.p95, 95.0);
        assert!((s.rms - (338_350.0f64 / 100.0).sqrt()).abs() < 1e-9);
        assert_eq!(s.max_rel, 0.5);
        let empty = ErrorStats::from_distances(&mut [], 1.0);
        assert_eq!(empty.samples, 0);
    }
}
