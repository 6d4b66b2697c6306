//! The three stages in a row, timed: [`segment`].
//!
//! Input: a mesh, its face adjacency and [`SegmentOptions`]. Output: the final
//! [`Segmentation`] and [`SegmentStats`] (region counts after each stage and wall time of each
//! stage). Face geometry is computed once and shared by the stages.
//!
//! Cost: the sum of the stages, O(n log n); single-threaded, so the result and its timing do
//! not depend on a thread pool.
//!
//! Based on: the three-stage segmenter of the spatial-patch work this project reproduces.

use std::time::Instant;

use spatch_mesh::{FaceAdjacency, TriangleMesh};

use crate::cone_growing::grow_cones_with;
use crate::face_geometry::compute_face_geometry;
use crate::merge::merge_regions_with;
use crate::secondary_growth::grow_secondary_with;
use crate::{SegmentError, SegmentOptions, Segmentation};

/// What [`segment`] did: region counts after each stage and seconds spent in each.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentStats {
    /// Regions after cone-growing (stage 1).
    pub preliminary_regions: usize,
    /// Regions after secondary growth (stage 2).
    pub after_secondary: usize,
    /// Regions after merging (stage 3): the final count.
    pub after_merge: usize,
    /// Wall time of each stage in seconds, named `"cone_growing"`, `"secondary_growth"` and
    /// `"merge"` (the shared face-geometry pass is counted in the first).
    pub seconds_per_stage: [(&'static str, f64); 3],
}

/// Checks what every stage relies on: valid options and an adjacency built for this mesh.
pub(crate) fn check_inputs(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    options: &SegmentOptions,
) -> Result<(), SegmentError> {
    options.validate()?;
    if adjacency.face_count() != mesh.face_count() {
        return Err(SegmentError::AdjacencyMismatch {
            mesh_faces: mesh.face_count(),
            adjacency_faces: adjacency.face_count(),
        });
    }
    Ok(())
}

/// Segments `mesh` into regions by the three stages: [`grow_cones`](crate::grow_cones),
/// [`grow_secondary`](crate::grow_secondary) and [`merge_regions`](crate::merge_regions).
///
/// Every face lands in exactly one region; every region is connected through `adjacency`
/// and its normals fit in a cone of half-angle at most θ3 (θ1 for regions the merge stage left
/// alone). Errors only for invalid options or an adjacency of another mesh.
pub fn segment(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    options: &SegmentOptions,
) -> Result<(Segmentation, SegmentStats), SegmentError> {
    check_inputs(mesh, adjacency, options)?;
    let start = Instant::now();
    let geometry = compute_face_geometry(mesh);
    let preliminary = grow_cones_with(&geometry, adjacency, options)?;
    let t1 = Instant::now();
    let secondary = grow_secondary_with(&geometry, adjacency, &preliminary, options)?;
    let t2 = Instant::now();
    let merged = merge_regions_with(mesh, &geometry, adjacency, &secondary, options)?;
    let t3 = Instant::now();
    let stats = SegmentStats {
        preliminary_regions: preliminary.len(),
        after_secondary: secondary.len(),
        after_merge: merged.len(),
        seconds_per_stage: [
            ("cone_growing", (t1 - start).as_secs_f64()),
            ("secondary_growth", (t2 - t1).as_secs_f64()),
            ("merge", (t3 - t2).as_secs_f64()),
        ],
    };
    Ok((merged, stats))
}
