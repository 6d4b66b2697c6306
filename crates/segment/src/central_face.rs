//! The central face of every region: the face farthest from the region's border.
//!
//! Input: face centroids, the face adjacency and a region per face. Output: one face per
//! region.
//!
//! A face is on the border of its region when one of its edges is a mesh boundary, a
//! non-manifold edge, or is shared with a face of another region. A multi-source Dijkstra
//! search starts from every border face at distance 0 and walks only between faces of the same
//! region, with steps as long as the distance between centroids; the central face of a region
//! is the one reached last (largest distance; ties to the lowest face index). A region without
//! any border (a closed surface in one region) gets its lowest face.
//!
//! Invariant: the central face belongs to its region; the result depends only on the
//! partition and the geometry.
//!
//! Cost: O(n log n) time (one binary heap over all faces), O(n) memory.
//!
//! Based on: Dijkstra, *A note on two problems in connexion with graphs* (1959); the
//! distance-to-border centre is the discrete analogue of the medial-axis "innermost point".

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use spatch_mesh::{FaceAdjacency, FaceId};

use crate::face_geometry::FaceGeometry;
use crate::priority::{priority_key, priority_value};
use crate::RegionId;

/// The central face of each of `region_count` regions (see the module docs). Faces of region
/// `ignore`, if given, are not searched (its entry in the result is then its lowest face).
pub(crate) fn find_central_faces(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    face_region: &[RegionId],
    region_count: usize,
    ignore: Option<RegionId>,
) -> Vec<FaceId> {
    let distance = border_distances(geometry, adjacency, face_region, ignore);
    farthest_faces(&distance, face_region, region_count)
}

/// Whether `face` (of `region`) lies on its region's border: one of its edges is a boundary,
/// non-manifold or shared with another region, or one of its neighbours is of another region.
fn on_region_border(
    adjacency: &FaceAdjacency,
    face_region: &[RegionId],
    face: FaceId,
    region: RegionId,
) -> bool {
    adjacency.face_edges(face).iter().any(|&e| {
        e.is_valid() && {
            let faces = adjacency.edge(e).faces;
            faces.len() != 2 || faces.iter().any(|g| face_region[g.index()] != region)
        }
    }) || adjacency
        .neighbours(face)
        .iter()
        .any(|g| face_region[g.index()] != region)
}

/// Each face's distance from its region's border, along centroid-to-centroid steps between
/// neighbours of the same region (Dijkstra from every border face); infinite for faces of
/// `ignore` and of regions without a border.
fn border_distances(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    face_region: &[RegionId],
    ignore: Option<RegionId>,
) -> Vec<f32> {
    let mut distance = vec![f32::INFINITY; face_region.len()];
    let mut heap: BinaryHeap<Reverse<(u32, u32)>> = BinaryHeap::new();
    for (f, &region) in face_region.iter().enumerate() {
        if Some(region) != ignore
            && on_region_border(adjacency, face_region, FaceId(f as u32), region)
        {
            distance[f] = 0.0;
            heap.push(Reverse((0, f as u32)));
        }
    }
    while let Some(Reverse((key, f))) = heap.pop() {
        let d = priority_value(key);
        if d > distance[f as usize] {
            continue;
        }
        let region = face_region[f as usize];
        let centre = geometry.centroids[f as usize];
        for &g in adjacency.neighbours(FaceId(f)) {
            if face_region[g.index()] != region {
                continue;
            }
            let next = d + centre.distance(geometry.centroids[g.index()]);
            if next < distance[g.index()] {
                distance[g.index()] = next;
                heap.push(Reverse((priority_key(next), g.0)));
            }
        }
    }
    distance
}

/// Per region: the face of the largest finite `distance`, ties to the lowest face (faces
/// scanned in ascending order, replaced only on a strictly larger distance); else the lowest
/// face.
fn farthest_faces(distance: &[f32], face_region: &[RegionId], region_count: usize) -> Vec<FaceId> {
    let mut best: Vec<(FaceId, f32)> = vec![(FaceId::INVALID, -1.0); region_count];
    for (f, &region) in face_region.iter().enumerate() {
        let slot = &mut best[region.index()];
        let d = distance[f];
        let d = if d.is_finite() { d } else { -0.5 };
        if !slot.0.is_valid() || d > slot.1 {
            *slot = (FaceId(f as u32), d);
        }
    }
    best.into_iter().map(|(f, _)| f).collect()
}
