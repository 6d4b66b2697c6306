//! Converting the part of a mesh one tile owns, with its neighbours' faces as context.
//!
//! A tile of a large mesh reads its own faces and those of a buffer around it. Every face is
//! owned by exactly one tile (the one whose box holds the face's centroid, decided by a
//! [`PartOwner`]), so segmenting only the owned faces gives every region exactly one owner:
//! regions never cross a tile border, whatever each tile reads. The buffer's faces are
//! still in the mesh the fitter sees, so a patch at the border reaches across it into the
//! neighbour's surface exactly as it reaches across a region border inside one tile (the
//! fitter's overlap), and joined tiles leave no crack along the cut.
//!
//! Sharp-edge patches follow crease chains, which the buffer cuts at different places in
//! different tiles; so each crease is made by the tile owning its midpoint, and each corner
//! by the tile owning its position (`spatch_edges::generate_part_edge_patches`), by the
//! same [`PartOwner::owns_point`].

use glam::DVec3;
use spatch_mesh::{build_face_adjacency, FaceId, TriangleMesh};
use spatch_segment::{segment, Region, SegmentError, SegmentOptions};

/// Which faces, creases and corners of a mesh part belong to the tile being converted.
pub trait PartOwner: Sync {
    /// Whether the tile owns the world point `world`: a face's centroid (the f64 mean of its
    /// three world corners: the face is segmented by the tile), a crease's midpoint (the f64
    /// mean of its two world corners: its edge patches are made by the tile) or a corner's
    /// world position (its corner patch). Every tile must answer alike for a point it reads,
    /// and exactly one tile must answer `true`.
    fn owns_point(&self, world: DVec3) -> bool;
}

/// The world centroid of `face`: the f64 mean of its corners' world positions, so that two
/// parts holding the same corners at the same origin compute the same value bit for bit.
pub fn world_centroid(mesh: &TriangleMesh, face: FaceId) -> DVec3 {
    let [a, b, c] = mesh.face_vertex_ids(face).map(|v| mesh.world_position(v));
    (a + b + c) / 3.0
}

/// Segments the faces of `mesh` that `owner` owns (the others are in no region), returning
/// regions that name faces of `mesh`.
pub(crate) fn segment_owned(
    mesh: &TriangleMesh,
    owner: &dyn PartOwner,
    options: &SegmentOptions,
) -> Result<Vec<Region>, SegmentError> {
    let owned: Vec<FaceId> = mesh
        .faces()
        .filter(|&f| owner.owns_point(world_centroid(mesh, f)))
        .collect();
    if owned.is_empty() {
        return Ok(Vec::new());
    }
    let part = TriangleMesh {
        origin: mesh.origin,
        positions: mesh.positions.clone(),
        triangles: owned.iter().map(|f| mesh.triangles[f.index()]).collect(),
        ..TriangleMesh::default()
    };
    let adjacency = build_face_adjacency(&part);
    let (segmentation, _) = segment(&part, &adjacency, options)?;
    let mut regions = segmentation.regions;
    for region in &mut regions {
        for face in &mut region.faces {
            *face = owned[face.index()];
        }
        region.seed = owned[region.seed.index()];
    }
    Ok(regions)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Owns the points with x below `cut`.
    struct LeftOf(f64);

    impl PartOwner for LeftOf {
        fn owns_point(&self, world: DVec3) -> bool {
            world.x < self.0
        }
    }

    /// A flat strip of `n` unit squares along x, two triangles each.
    fn strip(n: u32) -> TriangleMesh {
        let mut positions = Vec::new();
        for i in 0..=n {
            positions.push(Vec3::new(i as f32, 0.0, 0.0));
            positions.push(Vec3::new(i as f32, 1.0, 0.0));
        }
        let triangles = (0..n)
            .flat_map(|i| {
                let (a, b, c, d) = (2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3);
                [[a, c, b], [b, c, d]]
            })
            .collect();
        TriangleMesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn regions_hold_only_owned_faces_by_their_ids_in_the_whole_part() {
        let mesh = strip(8);
        let regions = segment_owned(&mesh, &LeftOf(3.0), &SegmentOptions::default()).unwrap();
        let mut faces: Vec<u32> = regions
            .iter()
            .flat_map(|r| r.faces.iter().map(|f| f.0))
            .collect();
        faces.sort_unstable();
        // Squares 0, 1 and 2 (faces 0..6) have centroids left of x = 3.
        assert_eq!(faces, (0..6).collect::<Vec<u32>>());
        assert!(regions.iter().all(|r| r.faces.contains(&r.seed)));
    }

    #[test]
    fn a_part_owning_nothing_has_no_region() {
        let mesh = strip(2);
        let regions = segment_owned(&mesh, &LeftOf(-1.0), &SegmentOptions::default()).unwrap();
        assert!(regions.is_empty());
    }
}
