//! Error per patch, and the quantization-only bound beside it.
//!
//! Input: the node distances in patch-then-node order (as
//! [`node_to_surface_distances`](crate::geometric::node_to_surface_distances) gives them) and,
//! for every source sample (or cloud point), its distance to the patch surface and the patch
//! that nearest point belongs to ([`nearest_patch_cells`](crate::nearest_patch_cells)).
//! Output: one [`PatchError`] per patch, so the worst patch can be found, and a
//! [`QuantizationBound`] summary.
//!
//! The quantization-only bound of a patch is `|az| / 2`: a node whose ray hit the source
//! exactly is stored at most half a displacement step away from it. Nodes are placed on the
//! source, so a patch whose nodes are farther than that (beyond f32 slack,
//! [`BOUND_SLACK_REL`] of the diagonal) was fitted wrongly, not just quantized.
//!
//! A source sample is attributed to the patch whose cell is nearest to it, so a hole shows on
//! the patches at its rim.
//!
//! Cost: O(nodes + samples).

use serde::Serialize;
use spatch_format::Scene;

use crate::geometric::NO_PATCH;

/// Slack (fraction of the diagonal) over `|az| / 2` before a patch counts as beyond its
/// quantization bound: f32 rounding of frames and positions.
pub const BOUND_SLACK_REL: f64 = 2e-6;

/// The error of one patch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PatchError {
    /// Index of the patch in the scene.
    pub patch: usize,
    /// Nodes per row.
    pub cols: u16,
    /// Rows of nodes.
    pub rows: u16,
    /// Non-empty nodes.
    pub filled_nodes: usize,
    /// Bits per stored displacement (8 or 16).
    pub bits: u8,
    /// The displacement step `|az|` (model units).
    pub step: f64,
    /// The quantization-only bound `|az| / 2` (model units).
    pub quantization_bound: f64,
    /// Largest distance from a node of this patch to the source.
    pub node_max: f64,
    /// RMS distance from the nodes of this patch to the source.
    pub node_rms: f64,
    /// Source samples whose nearest patch point is on this patch.
    pub source_samples: usize,
    /// Largest distance of those samples.
    pub source_max: f64,
    /// RMS distance of those samples.
    pub source_rms: f64,
}

/// The quantization-only bound over the scene, beside the measured node error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct QuantizationBound {
    /// Largest `|az| / 2` of any patch (model units).
    pub max: f64,
    /// `max` over the diagonal.
    pub max_rel: f64,
    /// `|az| / 2` averaged over filled nodes (model units).
    pub mean: f64,
    /// `mean` over the diagonal.
    pub mean_rel: f64,
    /// Patches whose largest node distance exceeds their own `|az| / 2` (plus
    /// [`BOUND_SLACK_REL`] of the diagonal); `None` when the node distances are not to a
    /// surface (to a point cloud's nearest point, which a node between points exceeds).
    pub patches_beyond: Option<usize>,
}

fn rms(sum_sq: f64, n: usize) -> f64 {
    if n == 0 {
        0.0
    } else {
        (sum_sq / n as f64).sqrt()
    }
}

/// One row per patch of `scene` (see the module docs). `node_distances` has one entry per
/// filled node in scene order; `sample_distances[k]` belongs to patch `sample_patches[k]`.
pub fn per_patch_errors(
    scene: &Scene,
    node_distances: &[f32],
    sample_distances: &[f32],
    sample_patches: &[u32],
) -> Vec<PatchError> {
    let mut rows: Vec<PatchError> = Vec::with_capacity(scene.patches().len());
    let mut at = 0;
    for (k, patch) in scene.patches().iter().enumerate() {
        let n = patch.filled_count();
        let nodes = node_distances.get(at..at + n).unwrap_or(&[]);
        at += n;
        let node_max = nodes.iter().copied().fold(0.0f32, f32::max);
        let node_sq: f64 = nodes.iter().map(|&d| f64::from(d) * f64::from(d)).sum();
        let step = f64::from(patch.frame().lengths()[2]);
        rows.push(PatchError {
            patch: k,
            cols: patch.grid().cols(),
            rows: patch.grid().rows(),
            filled_nodes: n,
            bits: patch.displacement_width().bits(),
            step,
            quantization_bound: step / 2.0,
            node_max: f64::from(node_max),
            node_rms: rms(node_sq, nodes.len()),
            source_samples: 0,
            source_max: 0.0,
            source_rms: 0.0,
        });
    }
    let mut sums = vec![0.0f64; rows.len()];
    for (&d, &p) in sample_distances.iter().zip(sample_patches) {
        if p == NO_PATCH {
            continue;
        }
        if let Some(row) = rows.get_mut(p as usize) {
            let d = f64::from(d);
            row.source_samples += 1;
            row.source_max = row.source_max.max(d);
            sums[p as usize] += d * d;
        }
    }
    for (row, sum) in rows.iter_mut().zip(sums) {
        row.source_rms = rms(sum, row.source_samples);
    }
    rows
}

/// The scene-wide [`QuantizationBound`] of `rows`; `nodes_to_surface` says whether the rows'
/// node distances are to a surface (then patches beyond their bound are counted).
pub fn quantization_bound(
    rows: &[PatchError],
    diagonal: f64,
    nodes_to_surface: bool,
) -> QuantizationBound {
    let rel = |v: f64| if diagonal > 0.0 { v / diagonal } else { 0.0 };
    let max = rows
        .iter()
        .map(|r| r.quantization_bound)
        .fold(0.0, f64::max);
    let nodes: usize = rows.iter().map(|r| r.filled_nodes).sum();
    let weighted: f64 = rows
        .iter()
        .map(|r| r.quantization_bound * r.filled_nodes as f64)
        .sum();
    let mean = if nodes == 0 {
        0.0
    } else {
        weighted / nodes as f64
    };
    let slack = BOUND_SLACK_REL * diagonal;
    QuantizationBound {
        max,
        max_rel: rel(max),
        mean,
        mean_rel: rel(mean),
        patches_beyond: nodes_to_surface.then(|| {
            rows.iter()
                .filter(|r| r.node_max > r.quantization_bound + slack)
                .count()
        }),
    }
}

/// The rows as CSV with a header line; `*_rel` columns divide by `diagonal`.
pub fn per_patch_csv(rows: &[PatchError], diagonal: f64) -> String {
    let rel = |v: f64| if diagonal > 0.0 { v / diagonal } else { 0.0 };
    let mut out = String::from(
        "patch,cols,rows,filled_nodes,bits,step,quantization_bound,node_max,node_rms,\
         node_max_rel,source_samples,source_max,source_rms,source_max_rel\n",
    );
    for r in rows {
        out.push_str(&format!(
            "{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{},{:e},{:e},{:e}\n",
            r.patch,
            r.cols,
            r.rows,
            r.filled_nodes,
            r.bits,
            r.step,
            r.quantization_bound,
            r.node_max,
            r.node_rms,
            rel(r.node_max),
            r.source_samples,
            r.source_max,
            r.source_rms,
            rel(r.source_max),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};
    use spatch_format::{ColourChannel, Frame, GridSize, Patch, EMPTY};

    fn two_patches() -> Scene {
        let frame = |z: f32, step: f32| {
            Frame::new(Vec3::new(0.0, 0.0, z), Vec3::X, Vec3::Y, Vec3::Z * step).unwrap()
        };
        let grid = GridSize::new(2, 2).unwrap();
        let a = Patch::new(frame(0.0, 0.1), grid, vec![0, 0, 0, EMPTY], None).unwrap();
        let b = Patch::new(frame(1.0, 0.5), grid, vec![0; 4], None).unwrap();
        Scene::new(DVec3::ZERO, ColourChannel::None, vec![a, b]).unwrap()
    }

    #[test]
    fn distances_are_split_by_patch() {
        let scene = two_patches();
        // Patch 0 has 3 filled nodes, patch 1 has 4.
        let nodes = [0.01, 0.02, 0.04, 0.2, 0.0, 0.0, 0.0];
        let samples = [0.5, 1.5, 0.25, 9.0];
        let owners = [1, 1, 0, NO_PATCH];
        let rows = per_patch_errors(&scene, &nodes, &samples, &owners);
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].filled_nodes, 3);
        assert!((rows[0].node_max - 0.04).abs() < 1e-7);
        assert!((rows[1].node_max - 0.2).abs() < 1e-7);
        assert_eq!(rows[0].source_samples, 1);
        assert_eq!(rows[1].source_samples, 2);
        assert_eq!(rows[1].source_max, 1.5);
        assert!((rows[1].source_rms - ((0.25 + 2.25) / 2.0f64).sqrt()).abs() < 1e-12);
        assert!((rows[0].quantization_bound - 0.05).abs() < 1e-7);
        let bound = quantization_bound(&rows, 10.0, true);
        assert!((bound.max - 0.25).abs() < 1e-7);
        // Patch 1's 0.2 is within 0.25; patch 0's 0.04 is within 0.05: none beyond.
        assert_eq!(bound.patches_beyond, Some(0));
        assert_eq!(quantization_bound(&rows, 10.0, false).patches_beyond, None);
        let csv = per_patch_csv(&rows, 10.0);
        assert_eq!(csv.lines().count(), 3);
        assert!(csv.starts_with("patch,cols,rows,"));
    }

    #[test]
    fn a_node_beyond_half_a_step_is_counted() {
        let scene = two_patches();
        let nodes = [0.01, 0.02, 0.06, 0.0, 0.0, 0.0, 0.0];
        let rows = per_patch_errors(&scene, &nodes, &[], &[]);
        assert_eq!(
            quantization_bound(&rows, 10.0, true).patches_beyond,
            Some(1)
        );
    }
}
