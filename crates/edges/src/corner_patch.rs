//! Corner patches: one patch at each vertex where three or more creases meet.
//!
//! Input: a corner vertex, the faces around it, the edge spacing `s_e` and strip width `w`.
//! Output: a [`NodeLattice`] centred on the corner and the faces its rays may hit.
//!
//! Edge patches end at corners, where the surface turns in three or more directions at once:
//! their last cells may miss the corner itself. A corner patch is seen along the mean normal
//! of the faces around the corner (each face weighted by its angle at the corner, so the
//! result does not depend on how the faces are cut into triangles), from which every face of
//! a convex corner (a cube's, say) is visible. It covers a square of half-side `w` around the
//! corner in its plane, with nodes `s_e × c` apart, `c` the smallest `n · z` of the faces
//! seen (clamped to `[0.25, 1]`), so nodes stay about `s_e` apart on the most tilted face.
//! Faces around a saddle corner that face away from the mean normal are left to the edge
//! patches.
//!
//! Cost: O(faces around the corner + faces near the square).
//!
//! Based on: the vertex-normal by incident angles of Thürmer and Wüthrich, *Computing Vertex
//! Normals from Polygonal Facets* (JGT 1998).

use glam::Vec3;
use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh, VertexId};

use crate::edge_patch::nodes_over;
use crate::lattice_cast::{faces_near, NodeLattice, MIN_FACING};

/// Smallest `n · z` used to space a corner patch's nodes.
const MIN_CORNER_FACING: f32 = 0.25;

/// The lattice of the corner patch at `corner` (whose faces are `around`) and the faces its
/// rays may hit, or `None` when the faces' normals cancel.
pub(crate) fn corner_lattice(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    corner: VertexId,
    around: &[FaceId],
    edge_spacing: f32,
    strip: f32,
) -> Option<(NodeLattice, Vec<FaceId>)> {
    let p = mesh.positions[corner.index()];
    let mut sum = Vec3::ZERO;
    for &f in around {
        let t = mesh.triangles[f.index()];
        let k = t.iter().position(|&v| v == corner.0)?;
        let a = mesh.positions[t[(k + 1) % 3] as usize] - p;
        let b = mesh.positions[t[(k + 2) % 3] as usize] - p;
        sum += mesh.face_normal(f) * a.angle_between(b);
    }
    let z = sum.normalize_or_zero();
    if z == Vec3::ZERO || !z.is_finite() {
        return None;
    }
    let helper = [Vec3::X, Vec3::Y, Vec3::Z]
        .into_iter()
        .min_by(|a, b| a.dot(z).abs().total_cmp(&b.dot(z).abs()))
        .unwrap_or(Vec3::X);
    let x = (helper - z * helper.dot(z)).normalize_or_zero();
    if x == Vec3::ZERO {
        return None;
    }
    let y = z.cross(x);
    let c = around
        .iter()
        .map(|&f| mesh.face_normal(f).dot(z))
        .filter(|&d| d > MIN_FACING)
        .fold(1.0f32, f32::min)
        .clamp(MIN_CORNER_FACING, 1.0);
    let (n, s) = nodes_over(2.0 * strip, edge_spacing * c);
    let centre = Vec3::new(p.dot(x), p.dot(y), p.dot(z));
    // Faces tilted down to n · z = c drop by up to w × tan(acos c) ≤ 3.9 w within the square.
    let drop = strip * (1.0 - c * c).sqrt() / c + edge_spacing;
    let lattice = NodeLattice {
        x,
        y,
        z,
        start: [centre.x - strip, centre.y - strip],
        spacing: [s, s],
        cols: n,
        rows: n,
        heights: [centre.z - drop, centre.z + drop],
    };
    let reach = Vec3::splat(strip * 1.5 + edge_spacing);
    let faces = faces_near(mesh, adjacency, around, p - reach, p + reach);
    Some((lattice, faces))
}
