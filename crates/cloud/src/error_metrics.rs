//! The geometric error of a scene against the point cloud it was made from.
//!
//! Input: a [`PointCloud`], a [`Scene`] and the cloud's spacing. Output: a
//! [`CloudErrorReport`] with
//! - `cloud_to_patch`: every cloud point to the nearest point of the patch surface (what
//!   reveals holes: points no patch covers are far from every surface), with the share of
//!   points farther than twice the spacing;
//! - `node_to_cloud`: every filled node to the nearest cloud point (what reveals patches
//!   floating away from the data; a node between samples is at least a fraction of the
//!   spacing from any of them, so this is never near zero).
//!
//! Each is reported as max, RMS and 95th percentile, absolute and relative to the cloud's
//! bounding-box diagonal.
//!
//! The patch surface: every drawable cell (four filled corners) as the bilinear quad through
//! its nodes, the surface the renderer draws, searched exactly through a [`PatchSurface`]
//! (a flat grid of the cells searched by runs of points; see `patch_surface`). A scene without
//! drawable cells is measured against its nodes.
//!
//! The points are taken in Morton order (`morton_order.rs`): the conversion's own order when
//! it hands it on ([`measure_cloud_error_in_order`]), else sorted here. `node_to_cloud`
//! searches a hierarchy of boxes cut along the points' codes (`point_hierarchy.rs`), each
//! run of nodes from the previous node's nearest point; `cloud_to_patch` asks the patch
//! surface for the sorted points, whose runs of one grid cell then lie together in memory.
//!
//! Invariants: results do not depend on thread count, query order or the order handed on
//! (per-point distances are exact minima computed independently, and returned and summed
//! in the cloud's order).
//!
//! Cost: O((n + nodes) log(cells)) time with both threads: the hierarchy over the points
//! (one pass over their sorted codes) and the node queries run beside the other
//! direction's search. Memory: 12 bytes per point for the sorted positions, 8 for their
//! codes, 4 for the order, 12 for the shifted queries; four bytes per point and per node
//! for the distances, four per point for the owning patch, the cell index (about 64 bytes
//! per cell) and 32 bytes per node of the point hierarchy (about one per four points).
//!
//! Measured (docs/performance.md, "Error measurement"): 1 M points of a synthetic 12-scan
//! set, 23.6 s before (a kd-tree over cell centres, whose search radius grew with the
//! largest cell of the scene); now 7.5 G instructions against the conversion's 8.1 G (9.2 G
//! with a kd-tree over the cloud and no bound before the quad distances).
//!
//! Based on: the error measures of the design brief §6 (Hausdorff and RMS both ways).

use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;
use spatch_format::Scene;
use spatch_mesh::PointCloud;

use crate::morton_order::{morton_order, MortonFrame, PointOrder};
use crate::patch_surface::{PatchSurface, NO_PATCH};
use crate::point_hierarchy::PointHierarchy;
use crate::spacing::PointTree;
#[cfg(doc)]
use crate::CloudConversion;
use crate::CloudError;

/// Points per parallel work item.
const CHUNK: usize = 8192;

/// Distance statistics of one direction of the error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct DistanceStats {
    /// Distances measured.
    pub count: usize,
    /// Largest distance (model units; the one-sided Hausdorff distance).
    pub max: f64,
    /// Root mean square distance (model units).
    pub rms: f64,
    /// 95th percentile (model units).
    pub p95: f64,
    /// `max` over the cloud's bounding-box diagonal.
    pub max_rel: f64,
    /// `rms` over the cloud's bounding-box diagonal.
    pub rms_rel: f64,
}

impl DistanceStats {
    /// Statistics of `distances` (reordered in place); `diagonal` scales the relative
    /// figures.
    pub fn from_distances(distances: &mut [f32], diagonal: f64) -> DistanceStats {
        let count = distances.len();
        if count == 0 {
            return DistanceStats::default();
        }
        let max = f64::from(distances.iter().copied().fold(0.0f32, f32::max));
        let sum2: f64 = distances.iter().map(|&d| f64::from(d) * f64::from(d)).sum();
        let rms = (sum2 / count as f64).sqrt();
        let rank = ((count as f64 * 0.95).ceil() as usize).clamp(1, count) - 1;
        let (_, p95, _) = distances.select_nth_unstable_by(rank, f32::total_cmp);
        let p95 = f64::from(*p95);
        let rel = |v: f64| if diagonal > 0.0 { v / diagonal } else { 0.0 };
        DistanceStats {
            count,
            max,
            rms,
            p95,
            max_rel: rel(max),
            rms_rel: rel(rms),
        }
    }
}

/// Cloud points to the patch surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct CloudToPatch {
    /// The distance statistics.
    #[serde(flatten)]
    pub distance: DistanceStats,
    /// Share of the points (0..=1) farther than twice the spacing from every patch.
    pub share_beyond_2x_spacing: f64,
}

/// The geometric error of a scene against its point cloud.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct CloudErrorReport {
    /// Every cloud point to the nearest patch surface.
    pub cloud_to_patch: CloudToPatch,
    /// Every filled node to the nearest cloud point.
    pub node_to_cloud: DistanceStats,
    /// The spacing used for `share_beyond_2x_spacing` (model units).
    pub spacing: f64,
    /// The cloud's bounding-box diagonal (model units).
    pub diagonal: f64,
    /// Wall time of the measurement (seconds).
    pub seconds: f64,
}

/// The per-point and per-node distances behind a [`CloudErrorReport`], for callers that
/// want more than the summary (histograms, per-patch figures).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CloudErrorDistances {
    /// Every cloud point (cloud order) to the nearest point of the patch surface.
    pub to_patch: Vec<f32>,
    /// The patch of that nearest point, per cloud point (`u32::MAX` never occurs: the scene
    /// has a filled node).
    pub owners: Vec<u32>,
    /// Every filled node (patch order, then node order) to the nearest cloud point.
    pub to_cloud: Vec<f32>,
}

/// Measures both distances of every point and node (see the module documentation).
///
/// Fails with [`CloudError::EmptyCloud`] when the cloud has no point and
/// [`CloudError::EmptyScene`] when the scene has no filled node.
pub fn cloud_error_distances(
    cloud: &PointCloud,
    scene: &Scene,
) -> Result<CloudErrorDistances, CloudError> {
    let sorted = sort_points(cloud, None)?;
    measure_sorted(cloud, scene, &sorted)
}

/// The cloud's points in Morton order (`morton_order.rs`).
struct SortedPoints {
    /// The cloud index of each sorted point.
    order: Vec<u32>,
    /// The sorted positions (cloud coordinates).
    positions: Vec<Vec3>,
    /// Their Morton codes in `frame`, increasing.
    codes: Vec<u64>,
    /// The frame of the codes.
    frame: MortonFrame,
}

/// The points of `cloud` in Morton order: from `given` (a conversion's order of this cloud)
/// when it is one for this cloud's frame, else sorted here. Fails with
/// [`CloudError::EmptyCloud`] on no point.
fn sort_points(cloud: &PointCloud, given: Option<&PointOrder>) -> Result<SortedPoints, CloudError> {
    if cloud.is_empty() {
        return Err(CloudError::EmptyCloud {
            dropped_non_finite: 0,
        });
    }
    let bounds = cloud.bounds();
    let frame = MortonFrame::new(&bounds);
    if let Some(order) = given.filter(|o| o.indices().len() == cloud.len()) {
        // A point order is a permutation (only the pipeline makes one); a cloud other than
        // the converted one would show in codes out of order.
        let positions: Vec<Vec3> = order
            .indices()
            .par_iter()
            .map(|&i| cloud.positions[i as usize])
            .collect();
        let codes: Vec<u64> = positions.par_iter().map(|&p| frame.code(p)).collect();
        if codes.par_windows(2).all(|w| w[0] <= w[1]) {
            return Ok(SortedPoints {
                order: order.indices().to_vec(),
                positions,
                codes,
                frame,
            });
        }
    }
    let pairs = morton_order(&cloud.positions, &bounds);
    Ok(SortedPoints {
        order: pairs.par_iter().map(|&(_, i)| i).collect(),
        positions: pairs
            .par_iter()
            .map(|&(_, i)| cloud.positions[i as usize])
            .collect(),
        codes: pairs.par_iter().map(|&(c, _)| c).collect(),
        frame,
    })
}

/// [`CloudErrorDistances`] of the `sorted` points of `cloud` (in the cloud's order).
fn measure_sorted(
    cloud: &PointCloud,
    scene: &Scene,
    sorted: &SortedPoints,
) -> Result<CloudErrorDistances, CloudError> {
    // Scene coordinates of cloud coordinates: add `shift`.
    let shift: Vec3 = (cloud.origin - scene.offset()).as_vec3();
    let (nodes, node_patches) = filled_nodes(scene);
    if nodes.is_empty() {
        return Err(CloudError::EmptyScene);
    }
    let queries: Vec<Vec3> = sorted.positions.par_iter().map(|&p| p + shift).collect();
    let (to_cloud, to_patch) = rayon::join(
        || nodes_to_cloud(&nodes, shift, sorted),
        || points_to_patches(scene, &queries, &sorted.order, (&nodes, &node_patches)),
    );
    let (to_patch, owners) = to_patch?;
    Ok(CloudErrorDistances {
        to_patch,
        owners,
        to_cloud: to_cloud?,
    })
}

/// Every node (scene coordinates; `shift` takes cloud coordinates to them) to the nearest
/// point, through the hierarchy of the sorted points, each run of nodes starting from the
/// previous node's nearest point.
fn nodes_to_cloud(
    nodes: &[Vec3],
    shift: Vec3,
    sorted: &SortedPoints,
) -> Result<Vec<f32>, CloudError> {
    let tree = PointHierarchy::build(&sorted.positions, &sorted.codes, sorted.frame).ok_or(
        CloudError::TooManyPoints {
            points: sorted.positions.len(),
            max: u32::MAX as usize / 2,
        },
    )?;
    Ok(nodes
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| {
            let tree = &tree;
            let mut hint = None;
            chunk.iter().map(move |&q| {
                let (d2, at) = tree.nearest(q - shift, hint);
                hint = Some(at);
                d2.sqrt()
            })
        })
        .collect())
}

/// Every filled node (scene coordinates) and the index of its patch.
fn filled_nodes(scene: &Scene) -> (Vec<Vec3>, Vec<u32>) {
    scene
        .patches()
        .par_iter()
        .enumerate()
        .flat_map_iter(|(k, p)| p.filled_nodes().map(move |(_, _, q)| (q, k as u32)))
        .unzip()
}

/// Distances from `points` (scene coordinates) to the patch surface and the owning patches,
/// each at position `place[k]` for `points[k]`; against the `nodes` (of `node_patches`)
/// when no cell is drawable.
fn points_to_patches(
    scene: &Scene,
    points: &[Vec3],
    place: &[u32],
    (nodes, node_patches): (&[Vec3], &[u32]),
) -> Result<(Vec<f32>, Vec<u32>), CloudError> {
    if let Some(surface) = PatchSurface::new(scene, Vec3::ZERO) {
        return Ok(surface.nearest_all_placed(points, Some(place)));
    }
    let tree = PointTree::build(nodes)?;
    let found: Vec<(f32, u32)> = points
        .par_iter()
        .map(|&q| {
            let (d2, id) = tree.nearest(q);
            let owner = node_patches.get(id.index()).copied().unwrap_or(NO_PATCH);
            (d2.sqrt(), owner)
        })
        .collect();
    let mut distances = vec![0.0f32; points.len()];
    let mut owners = vec![NO_PATCH; points.len()];
    for (&at, &(d, o)) in place.iter().zip(&found) {
        distances[at as usize] = d;
        owners[at as usize] = o;
    }
    Ok((distances, owners))
}

/// Measures `cloud_to_patch` and `node_to_cloud` (see the module documentation).
///
/// Fails with [`CloudError::EmptyCloud`] when the cloud has no point and
/// [`CloudError::EmptyScene`] when the scene has no filled node.
pub fn measure_cloud_error(
    cloud: &PointCloud,
    scene: &Scene,
    spacing: f32,
) -> Result<CloudErrorReport, CloudError> {
    measure_cloud_error_in_order(cloud, scene, spacing, None)
}

/// [`measure_cloud_error`] starting from `order`, the spatial order of the points that the
/// conversion of `cloud` kept ([`CloudConversion::point_order`]), instead of sorting them
/// again (sorted here when it is `None` or not an order of this cloud). The same figures.
///
/// Fails as [`measure_cloud_error`] does.
pub fn measure_cloud_error_in_order(
    cloud: &PointCloud,
    scene: &Scene,
    spacing: f32,
    order: Option<&PointOrder>,
) -> Result<CloudErrorReport, CloudError> {
    let started = std::time::Instant::now();
    let sorted = sort_points(cloud, order)?;
    let distances = measure_sorted(cloud, scene, &sorted)?;
    let diagonal = f64::from(cloud.bounds().diagonal());
    let seconds = started.elapsed().as_secs_f64();
    Ok(CloudErrorReport::from_distances(
        &distances, spacing, diagonal, seconds,
    ))
}

impl CloudErrorReport {
    /// The report of measured `distances`: `spacing` for the share beyond two spacings,
    /// `diagonal` for the relative figures, `seconds` the time the measurement took.
    pub fn from_distances(
        distances: &CloudErrorDistances,
        spacing: f32,
        diagonal: f64,
        seconds: f64,
    ) -> CloudErrorReport {
        let beyond = distances
            .to_patch
            .iter()
            .filter(|&&d| d > 2.0 * spacing)
            .count();
        let share = beyond as f64 / distances.to_patch.len().max(1) as f64;
        CloudErrorReport {
            cloud_to_patch: CloudToPatch {
                distance: DistanceStats::from_distances(&mut distances.to_patch.clone(), diagonal),
                share_beyond_2x_spacing: share,
            },
            node_to_cloud: DistanceStats::from_distances(&mut distances.to_cloud.clone(), diagonal),
            spacing: f64::from(spacing),
            diagonal,
            seconds,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{cloud_to_scene, CloudOptions};
    use glam::DVec3;

    /// A curved sheet sampled on a jittered grid, listed in a scrambled order (so that the
    /// conversion's order is not the cloud's own), away from the origin.
    fn sheet() -> PointCloud {
        let n = 70 * 70;
        let positions = (0..n)
            .map(|k| (k * 2_654_435_761usize) % n)
            .map(|k| {
                let (x, y) = ((k % 70) as f32 * 0.1, (k / 70) as f32 * 0.1);
                let jitter = ((k * 37 % 11) as f32 - 5.0) * 0.002;
                Vec3::new(x + jitter, y, 0.03 * (x - 3.0) * (x - 3.0) + jitter)
            })
            .collect();
        PointCloud {
            origin: DVec3::new(1e3, -2e3, 5.0),
            positions,
            colours: None,
            normals: None,
        }
    }

    #[test]
    fn the_conversions_order_gives_the_figures_of_a_fresh_sort() {
        let cloud = sheet();
        let conversion = cloud_to_scene(&cloud, &CloudOptions::default()).unwrap();
        let (scene, spacing) = (&conversion.scene, conversion.report.spacing);
        let order = conversion
            .point_order
            .as_ref()
            .expect("kept for a borrowed cloud");
        let mut indices = order.indices().to_vec();
        assert_ne!(indices, (0..cloud.len() as u32).collect::<Vec<_>>());
        indices.sort_unstable();
        assert_eq!(indices, (0..cloud.len() as u32).collect::<Vec<_>>());
        let untimed = |mut r: CloudErrorReport| {
            r.seconds = 0.0;
            r
        };
        let fresh = untimed(measure_cloud_error(&cloud, scene, spacing).unwrap());
        let handed = measure_cloud_error_in_order(&cloud, scene, spacing, Some(order));
        assert_eq!(untimed(handed.unwrap()), fresh);
        assert!(
            fresh.cloud_to_patch.distance.count == cloud.len() && fresh.node_to_cloud.count > 0
        );
        // The order of another cloud (the same points mirrored) is not taken for its own.
        let mut other = cloud.clone();
        other.positions.iter_mut().for_each(|p| p.x = -p.x);
        let fresh = untimed(measure_cloud_error(&other, scene, spacing).unwrap());
        let handed = measure_cloud_error_in_order(&other, scene, spacing, Some(order));
        assert_eq!(untimed(handed.unwrap()), fresh);
    }

    #[test]
    fn node_to_cloud_equals_a_linear_scan() {
        let cloud = sheet();
        let conversion = cloud_to_scene(&cloud, &CloudOptions::default()).unwrap();
        let distances = cloud_error_distances(&cloud, &conversion.scene).unwrap();
        let shift = (cloud.origin - conversion.scene.offset()).as_vec3();
        let (nodes, _) = filled_nodes(&conversion.scene);
        assert_eq!(distances.to_cloud.len(), nodes.len());
        for (&node, &d) in nodes.iter().zip(&distances.to_cloud) {
            let q = node - shift;
            let linear = cloud
                .positions
                .iter()
                .map(|&p| (p - q).length_squared())
                .fold(f32::INFINITY, f32::min);
            assert_eq!(d, linear.sqrt(), "{node}");
        }
        // Points in the cloud's order: each one's distance is that of its own surface query.
        let surface = PatchSurface::new(&conversion.scene, Vec3::ZERO).unwrap();
        for (k, &p) in cloud.positions.iter().enumerate().step_by(7) {
            let (d, owner) = surface.nearest(p + shift);
            assert_eq!((distances.to_patch[k], distances.owners[k]), (d, owner));
        }
    }

    #[test]
    fn percentile_and_rms() {
        let mut d: Vec<f32> = (1..=100).map(|k| k as f32).collect();
        let s = DistanceStats::from_distances(&mut d, 10.0);
        assert_eq!(s.count, 100);
        assert_eq!(s.max, 100.0);
        assert_eq!(s.p95, 95.0);
        assert!((s.rms - (338350.0f64 / 100.0).sqrt()).abs() < 1e-9);
        assert_eq!(s.max_rel, 10.0);
    }
}
