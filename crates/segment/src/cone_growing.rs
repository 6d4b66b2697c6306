//! Stage 1, cone-growing: preliminary regions whose normals fit a cone of half-angle θ1.
//!
//! Input: a mesh, its face adjacency and θ1 ([`SegmentOptions::cone_angle_deg`]). Output: a
//! [`Segmentation`] whose every region is connected and has all normals within θ1 of its axis.
//!
//! Method: take the lowest unassigned face as a seed. Keep the region's bounding
//! [`NormalCone`] and a binary heap of the unassigned faces adjacent to the region, keyed by
//! the angle between their normal and the cone's axis (how far they deviate from the set).
//! Pop the least deviating face: if its normal is inside the cone, or the smallest cone
//! holding the cone and the normal ([`NormalCone::including`]) still has a half-angle of at
//! most θ1, add it, grow the cone and push its unassigned neighbours; otherwise refuse it for
//! this region. The region ends when the heap is empty, that is when no adjacent face keeps
//! every normal inside a cone of half-angle θ1. Repeat from the next unassigned face.
//!
//! Keys go stale as the cone's axis moves; a popped face whose deviation grew by more than
//! [`REKEY_TOLERANCE`] since it was pushed is pushed again with its current key (lazy
//! re-keying), so the face added is always within that tolerance of the least deviating one.
//! A refusal is final for the region: the half-angle after adding a direction never shrinks
//! as the cone grows (see [`crate::cone`]).
//!
//! Degenerate faces (no normal, see [`crate::face_geometry`]) fit any cone: they join the
//! first region that reaches them (key 0, so before any real deviation); a region seeded by a
//! degenerate face takes its cone from the first normal it reaches.
//!
//! Invariants: every face ends in exactly one region; regions are connected; the result
//! depends only on the mesh (ties broken by face index).
//!
//! Cost: O(n log n) time; each face is pushed at most once per adjacent face added, plus the
//! rare re-keys; O(n) memory.
//!
//! Based on: the cone-growing stage of the spatial-patch segmenter this project reproduces;
//! region growing on normal cones as in Sander et al., *Texture mapping progressive meshes*
//! (SIGGRAPH 2001) and Cohen-Steiner et al., *Variational shape approximation* (2004).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh};

use crate::cone::{angle_between, NormalCone};
use crate::face_geometry::{compute_face_geometry, FaceGeometry};
use crate::priority::{priority_key, priority_value};
use crate::region::{build_segmentation, UNLABELLED};
use crate::{check_inputs, SegmentError, SegmentOptions, Segmentation};

/// A popped face whose deviation grew by more than this (radians, about 0.06°) since it was
/// pushed is re-keyed instead of added.
pub const REKEY_TOLERANCE: f32 = 1e-3;

/// Stage 1: grows preliminary regions with normals inside a cone of half-angle
/// [`SegmentOptions::cone_angle_deg`] (see the module docs).
pub fn grow_cones(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    options: &SegmentOptions,
) -> Result<Segmentation, SegmentError> {
    check_inputs(mesh, adjacency, options)?;
    let geometry = compute_face_geometry(mesh);
    grow_cones_with(&geometry, adjacency, options)
}

/// [`grow_cones`] on precomputed face geometry.
pub(crate) fn grow_cones_with(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    options: &SegmentOptions,
) -> Result<Segmentation, SegmentError> {
    let mut labels = vec![UNLABELLED; geometry.face_count()];
    let mut cones = Vec::new();
    grow_cone_regions(
        geometry,
        adjacency,
        options.cone_angle(),
        &mut labels,
        &mut cones,
    );
    build_segmentation(geometry, adjacency, &labels, &cones)
}

/// Grows cone regions over every face still [`UNLABELLED`] in `labels`, numbering them from
/// `cones.len()` and pushing each region's cone (`None` when it holds no normal) to `cones`.
/// Faces already labelled are left alone and never joined.
pub(crate) fn grow_cone_regions(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    max_half_angle: f32,
    labels: &mut [u32],
    cones: &mut Vec<Option<NormalCone>>,
) {
    // `refused[f] == label` when region `label` refused face `f` (a stamp, so the array is
    // never cleared).
    let mut refused = vec![UNLABELLED; labels.len()];
    let mut heap: BinaryHeap<Reverse<(u32, u32)>> = BinaryHeap::new();
    for seed in 0..labels.len() {
        if labels[seed] != UNLABELLED {
            continue;
        }
        let label = cones.len() as u32;
        let mut cone = geometry.normals[seed].map(NormalCone::around);
        labels[seed] = label;
        heap.clear();
        push_neighbours(
            geometry, adjacency, labels, &refused, label, cone, seed, &mut heap,
        );
        while let Some(Reverse((key, f))) = heap.pop() {
            let fi = f as usize;
            if labels[fi] != UNLABELLED || refused[fi] == label {
                continue;
            }
            if let (Some(n), Some(c)) = (geometry.normals[fi], cone) {
                let deviation = angle_between(c.axis, n);
                if deviation > c.half_angle {
                    if deviation > priority_value(key) + REKEY_TOLERANCE {
                        heap.push(Reverse((priority_key(deviation), f)));
                        continue;
                    }
                    let grown = c.including(n);
                    if grown.half_angle > max_half_angle {
                        refused[fi] = label;
                        continue;
                    }
                    cone = Some(grown);
                }
            } else if cone.is_none() {
                cone = geometry.normals[fi].map(NormalCone::around);
            }
            labels[fi] = label;
            push_neighbours(
                geometry, adjacency, labels, &refused, label, cone, fi, &mut heap,
            );
        }
        cones.push(cone);
    }
}

/// Pushes the unassigned, not-refused neighbours of `face` with their deviation from `cone`.
#[allow(clippy::too_many_arguments)] // the growth loop's state, passed by parts to borrow it
fn push_neighbours(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    labels: &[u32],
    refused: &[u32],
    label: u32,
    cone: Option<NormalCone>,
    face: usize,
    heap: &mut BinaryHeap<Reverse<(u32, u32)>>,
) {
    for &g in adjacency.neighbours(FaceId(face as u32)) {
        let gi = g.index();
        if labels[gi] != UNLABELLED || refused[gi] == label {
            continue;
        }
        let deviation = match (geometry.normals[gi], cone) {
            (Some(n), Some(c)) => angle_between(c.axis, n),
            _ => 0.0,
        };
        heap.push(Reverse((priority_key(deviation), g.0)));
    }
}
