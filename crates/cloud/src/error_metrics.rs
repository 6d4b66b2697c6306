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
//! The patch surface: every drawable cell (four filled corners) as two triangles split along
//! the diagonal from node `(i, j)` to `(i+1, j+1)`. A cell is bilinear in the renderer; the
//! two triangles differ from the bilinear quad by at most a quarter of the cell's twist
//! (`|h00 − h10 − h01 + h11| / 4` along the normal), which for cells of continuous scan
//! surface is a small fraction of the spacing. A scene without drawable cells is measured
//! against its nodes.
//!
//! The search is exact for this surface: a kd-tree over cell centres yields candidates in
//! order of centre distance; a cell whose centre is farther than `best + R` (R the largest
//! centre-to-corner distance of any cell) cannot hold a nearer point, so the scan stops
//! there (with a radius query as fall-back when the 16 nearest centres do not settle it).
//!
//! Invariants: results do not depend on thread count (per-point distances are computed
//! independently and collected in point order).
//!
//! Cost: O((n + nodes) log(cells)) time, O(cells + n) memory.
//!
//! Based on: the error measures of the design brief §6 (Hausdorff and RMS both ways);
//! C. Ericson, "Real-Time Collision Detection", §5.1.5 (closest point on a triangle).

use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;
use spatch_format::Scene;
use spatch_mesh::PointCloud;

use crate::spacing::PointTree;
use crate::{CloudError, PointId};

/// Points per parallel work item.
const CHUNK: usize = 8192;

/// Nearest cell centres examined before falling back to a radius query.
const CANDIDATES: usize = 16;

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

/// The patch surface as triangles, with a kd-tree over cell centres.
struct CellSurfaceIndex {
    /// Corners `[p00, p10, p01, p11]` per drawable cell (scene coordinates).
    cells: Vec<[Vec3; 4]>,
    tree: PointTree,
    /// Largest centre-to-corner distance of any cell.
    reach: f32,
}

impl CellSurfaceIndex {
    /// Collects the drawable cells of `scene`; `None` when there are none.
    fn build(scene: &Scene) -> Result<Option<CellSurfaceIndex>, CloudError> {
        let mut cells = Vec::new();
        for patch in scene.patches() {
            let grid = patch.grid();
            let (cols, rows) = (usize::from(grid.cols()), usize::from(grid.rows()));
            for j in 0..rows - 1 {
                for i in 0..cols - 1 {
                    if !patch.cell_is_drawable(i, j) {
                        continue;
                    }
                    let corner =
                        |a: usize, b: usize| patch.node_position(a, b).unwrap_or(Vec3::ZERO);
                    cells.push([
                        corner(i, j),
                        corner(i + 1, j),
                        corner(i, j + 1),
                        corner(i + 1, j + 1),
                    ]);
                }
            }
        }
        if cells.is_empty() {
            return Ok(None);
        }
        let centres: Vec<Vec3> = cells
            .iter()
            .map(|c| (c[0] + c[1] + c[2] + c[3]) * 0.25)
            .collect();
        let reach = cells
            .iter()
            .zip(&centres)
            .map(|(c, m)| c.iter().map(|p| p.distance(*m)).fold(0.0f32, f32::max))
            .fold(0.0f32, f32::max);
        let tree = PointTree::build(&centres)?;
        Ok(Some(CellSurfaceIndex { cells, tree, reach }))
    }

    fn cell_distance(&self, cell: PointId, q: Vec3) -> f32 {
        let [a, b, c, d] = self.cells[cell.index()];
        let first = closest_on_triangle(q, a, b, d).distance_squared(q);
        let second = closest_on_triangle(q, a, d, c).distance_squared(q);
        first.min(second).sqrt()
    }

    /// Exact distance from `q` to the surface.
    fn distance(&self, q: Vec3, scratch: &mut Vec<(f32, PointId)>) -> f32 {
        self.tree.nearest_k(q, CANDIDATES, scratch);
        let mut best = f32::INFINITY;
        let mut settled = false;
        for &(d2, id) in scratch.iter() {
            if d2.sqrt() - self.reach >= best {
                settled = true;
                break;
            }
            best = best.min(self.cell_distance(id, q));
        }
        if !settled && scratch.len() == CANDIDATES {
            let radius = best + self.reach;
            self.tree.within(q, radius * radius, scratch);
            for &(_, id) in scratch.iter() {
                best = best.min(self.cell_distance(id, q));
            }
        }
        best
    }
}

/// The closest point to `p` on triangle `abc`.
fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let sum = va + vb + vc;
    if sum == 0.0 || !sum.is_finite() {
        // Degenerate triangle: the nearest of its corners.
        return [a, b, c]
            .into_iter()
            .min_by(|x, y| x.distance_squared(p).total_cmp(&y.distance_squared(p)))
            .unwrap_or(a);
    }
    let denom = 1.0 / sum;
    a + ab * (vb * denom) + ac * (vc * denom)
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
    let started = std::time::Instant::now();
    if cloud.is_empty() {
        return Err(CloudError::EmptyCloud {
            dropped_non_finite: 0,
        });
    }
    let diagonal = f64::from(cloud.bounds().diagonal());
    // Scene coordinates of cloud coordinates: add `shift`.
    let shift: Vec3 = (cloud.origin - scene.offset()).as_vec3();
    let nodes: Vec<Vec3> = scene
        .patches()
        .iter()
        .flat_map(|p| p.filled_nodes().map(|(_, _, q)| q))
        .collect();
    if nodes.is_empty() {
        return Err(CloudError::EmptyScene);
    }
    let surface = CellSurfaceIndex::build(scene)?;
    let node_tree = if surface.is_none() {
        Some(PointTree::build(&nodes)?)
    } else {
        None
    };
    let mut to_patch: Vec<f32> = cloud
        .positions
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut scratch = Vec::with_capacity(CANDIDATES);
            chunk
                .iter()
                .map(|&p| {
                    let q = p + shift;
                    match (&surface, &node_tree) {
                        (Some(s), _) => s.distance(q, &mut scratch),
                        (None, Some(t)) => t.nearest(q).0.sqrt(),
                        (None, None) => f32::INFINITY,
                    }
                })
                .collect::<Vec<f32>>()
        })
        .collect::<Vec<_>>()
        .concat();
    let beyond = to_patch.iter().filter(|&&d| d > 2.0 * spacing).count();
    let share = beyond as f64 / to_patch.len() as f64;
    let cloud_tree = PointTree::build(&cloud.positions)?;
    let mut to_cloud: Vec<f32> = nodes
        .par_chunks(CHUNK)
        .map(|chunk| {
            chunk
                .iter()
                .map(|&q| cloud_tree.nearest(q - shift).0.sqrt())
                .collect::<Vec<f32>>()
        })
        .collect::<Vec<_>>()
        .concat();
    Ok(CloudErrorReport {
        cloud_to_patch: CloudToPatch {
            distance: DistanceStats::from_distances(&mut to_patch, diagonal),
            share_beyond_2x_spacing: share,
        },
        node_to_cloud: DistanceStats::from_distances(&mut to_cloud, diagonal),
        spacing: f64::from(spacing),
        diagonal,
        seconds: started.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let p = closest_on_triangle(Vec3::new(0.2, 0.2, 1.0), a, b, c);
        assert!((p - Vec3::new(0.2, 0.2, 0.0)).length() < 1e-6);
        assert_eq!(closest_on_triangle(Vec3::new(-1.0, -1.0, 0.0), a, b, c), a);
        assert_eq!(
            closest_on_triangle(Vec3::new(0.5, -1.0, 0.0), a, b, c),
            Vec3::new(0.5, 0.0, 0.0)
        );
        let p = closest_on_triangle(Vec3::new(1.0, 1.0, 0.0), a, b, c);
        assert!((p - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-6);
        // Degenerate triangle.
        assert_eq!(closest_on_triangle(Vec3::new(3.0, 0.0, 0.0), a, b, b), b);
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
