//! Stage 2, secondary growth: compact regions grown simultaneously from the preliminary
//! regions' central faces.
//!
//! Input: a mesh, its face adjacency, the preliminary [`Segmentation`] of stage 1 and θ1
//! ([`SegmentOptions::cone_angle_deg`]). Output: a [`Segmentation`] whose regions are
//! connected, compact, and have all normals within θ1 of their axis.
//!
//! Method: every preliminary region's central face (its [`Region::seed`](crate::Region::seed),
//! the face farthest from its border) seeds a new region. All regions grow at once by a
//! multi-source Dijkstra search over the face adjacency, with steps as long as the distance
//! between face centroids: the frontier face nearest (along the surface) to its seed is taken
//! next, by the region that reached it, provided its normal keeps the region's cone within θ1.
//! A face refused by one region stays available to the others. Growing by distance instead of
//! by normal deviation gives each region the shape of a geodesic Voronoi cell around its
//! centre, compact rather than a long strip following a ridge.
//!
//! Only preliminary regions of at least [`SegmentOptions::min_region_faces`] faces seed: on
//! scanned meshes most preliminary regions are one or two faces with noisy normals, and a
//! seed in each would give as many competing regions. Faces no region could take (between
//! regions on a strongly curved stretch, around noise) are grown again the same way, seeded
//! by the central faces of their own cone-growing, for up to [`LEFTOVER_ROUNDS`] rounds; what
//! still remains is grouped by plain cone-growing.
//!
//! Invariants: every face ends in exactly one region; regions are connected (a face is only
//! reached from a face of its region); every cone is within θ1; deterministic (ties by
//! distance, then face index, then region index).
//!
//! Cost: O(n log n) time per round (each face pushes its neighbours once, when taken; a round
//! only visits the faces left by the previous one), O(n) memory.
//!
//! Based on: the secondary-growth stage of the spatial-patch segmenter this project
//! reproduces; the region-growing step of Lloyd relaxation in Cohen-Steiner et al.,
//! *Variational shape approximation* (SIGGRAPH 2004).

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh};

use crate::central_face::find_central_faces;
use crate::cone::NormalCone;
use crate::cone_growing::grow_cone_regions;
use crate::face_geometry::{compute_face_geometry, FaceGeometry};
use crate::priority::{priority_key, priority_value};
use crate::region::{build_segmentation, UNLABELLED};
use crate::{check_inputs, RegionId, SegmentError, SegmentOptions, Segmentation};

/// Stage 2: regrows compact regions from the central faces of `preliminary` (see the module
/// docs).
pub fn grow_secondary(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    preliminary: &Segmentation,
    options: &SegmentOptions,
) -> Result<Segmentation, SegmentError> {
    check_inputs(mesh, adjacency, options)?;
    preliminary.check_fits(mesh.face_count())?;
    let geometry = compute_face_geometry(mesh);
    grow_secondary_with(&geometry, adjacency, preliminary, options)
}

/// Rounds of re-seeded growth over the faces every region refused, before the last
/// leftovers are grouped by plain cone-growing.
pub const LEFTOVER_ROUNDS: usize = 3;

/// [`grow_secondary`] on precomputed face geometry.
pub(crate) fn grow_secondary_with(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    preliminary: &Segmentation,
    options: &SegmentOptions,
) -> Result<Segmentation, SegmentError> {
    let max_half_angle = options.cone_angle();
    let mut labels = vec![UNLABELLED; geometry.face_count()];
    let mut cones: Vec<Option<NormalCone>> = Vec::new();
    let seeds: Vec<FaceId> = preliminary
        .regions
        .iter()
        .filter(|r| r.faces.len() >= options.min_region_faces)
        .map(|r| r.seed)
        .collect();
    grow_from_seeds(
        geometry,
        adjacency,
        max_half_angle,
        &seeds,
        &mut labels,
        &mut cones,
    );
    for _ in 0..LEFTOVER_ROUNDS {
        let seeds = leftover_seeds(geometry, adjacency, max_half_angle, &labels);
        if seeds.is_empty() {
            break;
        }
        grow_from_seeds(
            geometry,
            adjacency,
            max_half_angle,
            &seeds,
            &mut labels,
            &mut cones,
        );
    }
    grow_cone_regions(geometry, adjacency, max_half_angle, &mut labels, &mut cones);
    build_segmentation(geometry, adjacency, &labels, &cones)
}

/// Grows one region per seed, all at once by surface distance, over the faces still
/// [`UNLABELLED`]; new labels start at `cones.len()` and each region's cone is pushed to
/// `cones`.
fn grow_from_seeds(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    max_half_angle: f32,
    seeds: &[FaceId],
    labels: &mut [u32],
    cones: &mut Vec<Option<NormalCone>>,
) {
    let first = cones.len();
    cones.resize(first + seeds.len(), None);
    // (distance key, face, label)
    let mut heap: BinaryHeap<Reverse<(u32, u32, u32)>> = BinaryHeap::new();
    for (k, seed) in seeds.iter().enumerate() {
        heap.push(Reverse((0, seed.0, (first + k) as u32)));
    }
    while let Some(Reverse((key, f, r))) = heap.pop() {
        let fi = f as usize;
        if labels[fi] != UNLABELLED {
            continue;
        }
        let cone = &mut cones[r as usize];
        if let Some(n) = geometry.normals[fi] {
            match cone {
                None => *cone = Some(NormalCone::around(n)),
                Some(c) => {
                    if !c.contains(n) {
                        let grown = c.including(n);
                        if grown.half_angle > max_half_angle {
                            continue;
                        }
                        *c = grown;
                    }
                }
            }
        }
        labels[fi] = r;
        let distance = priority_value(key);
        let centre = geometry.centroids[fi];
        for &g in adjacency.neighbours(FaceId(f)) {
            if labels[g.index()] == UNLABELLED {
                let step = centre.distance(geometry.centroids[g.index()]);
                heap.push(Reverse((priority_key(distance + step), g.0, r)));
            }
        }
    }
}

/// Seeds for the faces still [`UNLABELLED`]: cone-grow them (apart from everything else) and
/// take each resulting region's central face.
fn leftover_seeds(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    max_half_angle: f32,
    labels: &[u32],
) -> Vec<FaceId> {
    // Labelled faces get one shared label so they neither join nor seed a region.
    let done = 0u32;
    let mut scratch: Vec<u32> = labels
        .iter()
        .map(|&l| if l == UNLABELLED { UNLABELLED } else { done })
        .collect();
    let mut cones = vec![None];
    grow_cone_regions(
        geometry,
        adjacency,
        max_half_angle,
        &mut scratch,
        &mut cones,
    );
    if cones.len() == 1 {
        return Vec::new();
    }
    let face_region: Vec<RegionId> = scratch.iter().map(|&l| RegionId(l)).collect();
    let centres = find_central_faces(
        geometry,
        adjacency,
        &face_region,
        cones.len(),
        Some(RegionId(done)),
    );
    centres[1..].to_vec()
}
