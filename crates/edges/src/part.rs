//! Edge patches of one part of a tiled mesh: the creases and corners the part owns.
//!
//! A tile of a large mesh reads its own faces and a buffer of its neighbours'. Tiles cut
//! the crease chains at different places, so pieces made by each tile from all it reads
//! differ from tile to tile, and no rule on the finished patches can keep every stretch of
//! crease exactly once. Ownership is therefore decided per crease, before the chains are
//! cut: a crease belongs to the part that owns its **midpoint** (the f64 mean of its two
//! world corners), a corner to the part that owns the corner's world position. A part
//! cuts its pieces from the creases it owns only (the others end a piece, as covered
//! creases do), and makes only the corner patches of the corners it owns.
//!
//! When the owner's answers partition space (each world point owned by exactly one part)
//! and every part computes world positions alike (the same origin, the same f32 offsets),
//! every crease and corner has exactly one part making its patches. The owning part holds
//! both faces of its creases and every face around its corners (they contain the owned
//! point, so they touch the part's own box), so it detects them as a whole conversion does.

use glam::DVec3;
use spatch_mesh::TriangleMesh;

use crate::sharp_edges::{Crease, SharpEdges};

/// Whether a part owns a world point (a crease's midpoint, a corner).
pub type OwnsPoint<'a> = &'a (dyn Fn(DVec3) -> bool + Sync);

/// The world midpoint of `crease`: the f64 mean of its two world corners.
pub(crate) fn crease_midpoint(mesh: &TriangleMesh, crease: &Crease) -> DVec3 {
    (mesh.world_position(crease.v0) + mesh.world_position(crease.v1)) * 0.5
}

/// Per crease of `sharp`: left out of the pieces, because it is `covered` or because
/// `owns` does not own its midpoint.
pub(crate) fn skip_unowned(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    covered: &[bool],
    owns: OwnsPoint<'_>,
) -> Vec<bool> {
    sharp
        .creases
        .iter()
        .zip(covered)
        .map(|(crease, &covered)| covered || !owns(crease_midpoint(mesh, crease)))
        .collect()
}

/// Clears `open[k]` for each corner of `sharp` whose world position `owns` does not own.
pub(crate) fn drop_unowned_corners(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    open: &mut [bool],
    owns: OwnsPoint<'_>,
) {
    for (open, &v) in open.iter_mut().zip(&sharp.corners) {
        *open &= owns(mesh.world_position(v));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detect_sharp_edges;
    use spatch_mesh::build_face_adjacency;

    /// A unit cube centred at `origin`, far from the world origin.
    fn far_cube() -> TriangleMesh {
        let shape = spatch_fixtures::shapes::cube(1.0);
        let positions = shape.positions.iter().map(|p| glam::Vec3::from(*p));
        let mut mesh = TriangleMesh::new(positions.collect(), shape.triangles).unwrap();
        mesh.origin = DVec3::new(6.4e6, -3.0e5, 12.0);
        mesh
    }

    #[test]
    fn every_crease_and_corner_has_one_owner_among_the_parts() {
        let mesh = far_cube();
        let adjacency = build_face_adjacency(&mesh);
        let sharp = detect_sharp_edges(&mesh, &adjacency, 25.0);
        assert_eq!(sharp.creases.len(), 12, "a cube's edges");
        assert_eq!(sharp.corners.len(), 8);
        // Two parts split at the cube's middle plane (its creases along y and z lie on
        // either side; those along x cross it and go by their midpoint, on the plane).
        let cut = mesh.origin.x;
        let left = |w: DVec3| w.x < cut;
        let right = |w: DVec3| w.x >= cut;
        let covered = vec![false; sharp.creases.len()];
        let made: Vec<Vec<bool>> = [&left as OwnsPoint<'_>, &right]
            .iter()
            .map(|owns| {
                skip_unowned(&mesh, &sharp, &covered, *owns)
                    .into_iter()
                    .map(|skip| !skip)
                    .collect()
            })
            .collect();
        for (k, (a, b)) in made[0].iter().zip(&made[1]).enumerate() {
            assert_eq!(usize::from(*a) + usize::from(*b), 1, "crease {k}");
        }
        let mut corners = [vec![true; 8], vec![true; 8]];
        drop_unowned_corners(&mesh, &sharp, &mut corners[0], &left);
        drop_unowned_corners(&mesh, &sharp, &mut corners[1], &right);
        for (k, (a, b)) in corners[0].iter().zip(&corners[1]).enumerate() {
            assert!(a ^ b, "corner {k}");
        }
        // A covered crease is skipped by every part.
        let all_covered = vec![true; sharp.creases.len()];
        assert!(skip_unowned(&mesh, &sharp, &all_covered, &left)
            .iter()
            .all(|&s| s));
    }
}
