//! The first hit of every node ray of a lattice, found by projecting the allowed faces onto
//! the lattice (a z-buffer) rather than by casting one ray per node.
//!
//! Input: a [`NodeLattice`] and the faces its rays may hit (each with its normal · z above
//! [`MIN_FACING`]). Output: for each node (row-major), the hit of the ray from `heights[1]`
//! along −z, stopping at `heights[0]`: the allowed face with the largest height there, ties
//! to the smaller face id, with its barycentric coordinates. This is what a ray cast against
//! the same faces returns; the projection along z keeps barycentric coordinates, so the 2D
//! coordinates of a node in the projected triangle are those of the hit on the 3D triangle.
//!
//! Each face is scanned row by row over the nodes its projection covers (the span where the
//! row's line crosses the triangle), and a node is inside when its barycentric coordinates
//! are at least `-EDGE_TOLERANCE` (as the ray test accepts), so a node on an edge two faces
//! share is hit by both and keeps the higher (or, level, the smaller id).
//!
//! Cost: O(allowed faces + nodes they cover + rows they span); no tree walk per node. On
//! fandisk this took the edges stage from 61 ms to a few ms (docs/algorithms/edges.md), as
//! the model's long sliver triangles make each ray of a tree walk visit many boxes.

use glam::{Vec2, Vec3};
use spatch_mesh::{FaceId, TriangleMesh};

use crate::lattice_cast::{NodeLattice, MIN_FACING};

/// How far outside a triangle (in barycentric terms) a node still counts as inside, as the
/// ray test of `spatch-mesh` accepts.
const EDGE_TOLERANCE: f32 = 1e-6;

/// Where a node's ray first meets an allowed face.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeHit {
    /// Height of the hit along z.
    pub(crate) height: f32,
    /// The face hit.
    pub(crate) face: FaceId,
    /// Barycentric coordinates of the hit on the face.
    pub(crate) bary: Vec3,
}

/// The first hit of each node's ray of `lattice` (row-major) among `allowed` (see the module
/// docs); faces facing away from z (normal · z at most [`MIN_FACING`]) are never hit. With
/// `mask` (row-major, one flag a node), only the nodes whose flag is set are tested; the
/// others stay empty.
pub(crate) fn raster_hits(
    mesh: &TriangleMesh,
    lattice: &NodeLattice,
    allowed: &[FaceId],
    mask: Option<&[bool]>,
) -> Vec<Option<NodeHit>> {
    let mut hits: Vec<Option<NodeHit>> = vec![None; lattice.cols * lattice.rows];
    for &face in allowed {
        if mesh.face_normal(face).dot(lattice.z) > MIN_FACING {
            raster_face(mesh, lattice, face, mask, &mut hits);
        }
    }
    hits
}

/// Writes `face` into `hits` where it is above what is there (see the module docs).
fn raster_face(
    mesh: &TriangleMesh,
    lattice: &NodeLattice,
    face: FaceId,
    mask: Option<&[bool]>,
    hits: &mut [Option<NodeHit>],
) {
    let corners = mesh.face_positions(face);
    // Node-index coordinates of the corners, and their heights.
    let grid = corners.map(|p| {
        Vec2::new(
            (p.dot(lattice.x) - lattice.start[0]) / lattice.spacing[0],
            (p.dot(lattice.y) - lattice.start[1]) / lattice.spacing[1],
        )
    });
    let heights = corners.map(|p| p.dot(lattice.z));
    let [a, b, c] = grid;
    let area = (b - a).perp_dot(c - a);
    let floor = f32::EPSILON * (b - a).length() * (c - a).length();
    if area.is_nan() || area.abs() <= floor {
        return;
    }
    let Some((j0, j1)) = index_range(a.y.min(b.y).min(c.y), a.y.max(b.y).max(c.y), lattice.rows)
    else {
        return;
    };
    for j in j0..=j1 {
        let y = j as f32;
        let Some((x0, x1)) = row_span(&grid, y) else {
            continue;
        };
        let Some((i0, i1)) = index_range(x0, x1, lattice.cols) else {
            continue;
        };
        for i in i0..=i1 {
            if mask.is_some_and(|m| !m[j * lattice.cols + i]) {
                continue;
            }
            let p = Vec2::new(i as f32, y);
            if let Some((height, bary)) = face_at_node(p, (&grid, area), heights, lattice) {
                keep_higher(
                    &mut hits[j * lattice.cols + i],
                    NodeHit { height, face, bary },
                );
            }
        }
    }
}

/// The height and clamped barycentric weights of the face (corners `grid` in node-index
/// coordinates, signed `area`, corner `heights`) at the node `p`, or `None` when `p` lies
/// outside the face by more than [`EDGE_TOLERANCE`] or the height outside the lattice's range.
fn face_at_node(
    p: Vec2,
    (grid, area): (&[Vec2; 3], f32),
    heights: [f32; 3],
    lattice: &NodeLattice,
) -> Option<(f32, Vec3)> {
    let [a, b, c] = *grid;
    let w1 = (p - a).perp_dot(c - a) / area;
    let w2 = (b - a).perp_dot(p - a) / area;
    let w0 = 1.0 - w1 - w2;
    if w0 < -EDGE_TOLERANCE || w1 < -EDGE_TOLERANCE || w2 < -EDGE_TOLERANCE {
        return None;
    }
    let bary = clamp_bary(w0, w1, w2);
    let height = bary.dot(Vec3::from(heights));
    (lattice.heights[0]..=lattice.heights[1])
        .contains(&height)
        .then_some((height, bary))
}

/// Keeps `hit` in `slot` when it is higher than what is there (equal heights: the lower
/// face id, so the result does not depend on the faces' order).
fn keep_higher(slot: &mut Option<NodeHit>, hit: NodeHit) {
    let better = match slot {
        None => true,
        Some(h) => hit.height > h.height || (hit.height == h.height && hit.face < h.face),
    };
    if better {
        *slot = Some(hit);
    }
}

/// Node indices `0..count` within `[lo, hi]` widened by a hair, or `None` when there are none.
fn index_range(lo: f32, hi: f32, count: usize) -> Option<(usize, usize)> {
    let slack = 1e-4;
    let first = ceil(lo - slack).max(0.0);
    let last = floor(hi + slack).min(count as f32 - 1.0);
    (first.is_finite() && last.is_finite() && first <= last)
        .then_some((first as usize, last as usize))
}

/// `x.ceil()`, exactly (but for the sign of a zero), without the software rounding the
/// baseline x86-64 target falls back to: it runs twice per row of every face cast.
fn ceil(x: f32) -> f32 {
    // Beyond 2^23 every f32 is an integer (and NaN, infinities pass through).
    if x.abs() >= 8_388_608.0 || x.is_nan() {
        return x;
    }
    let t = x as i32 as f32;
    if t < x {
        t + 1.0
    } else {
        t
    }
}

/// `x.floor()`, exactly (but for the sign of a zero); see [`ceil`].
fn floor(x: f32) -> f32 {
    if x.abs() >= 8_388_608.0 || x.is_nan() {
        return x;
    }
    let t = x as i32 as f32;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// The x interval where the line at `y` crosses the triangle `t`, or `None` when it misses.
fn row_span(t: &[Vec2; 3], y: f32) -> Option<(f32, f32)> {
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    for k in 0..3 {
        let (p, q) = (t[k], t[(k + 1) % 3]);
        if (p.y - y) * (q.y - y) > 0.0 {
            continue;
        }
        if p.y == q.y {
            lo = lo.min(p.x.min(q.x));
            hi = hi.max(p.x.max(q.x));
        } else {
            let x = p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y);
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    (lo <= hi).then_some((lo, hi))
}

/// Barycentric coordinates clamped onto the triangle (a node a hair outside an edge).
fn clamp_bary(w0: f32, w1: f32, w2: f32) -> Vec3 {
    let w = Vec3::new(w0, w1, w2).max(Vec3::ZERO);
    w / w.element_sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5 × 5 lattice over [0, 4]² seen from +z, searching heights [-10, 10].
    fn lattice() -> NodeLattice {
        NodeLattice {
            x: Vec3::X,
            y: Vec3::Y,
            z: Vec3::Z,
            start: [0.0, 0.0],
            spacing: [1.0, 1.0],
            cols: 5,
            rows: 5,
            heights: [-10.0, 10.0],
        }
    }

    #[test]
    fn the_higher_face_wins_and_edges_are_inside() {
        // Two stacked squares over [0, 4]², at z = 1 (faces 0, 1) and z = 2 (faces 2, 3); the
        // upper one covers only x ≤ 2.
        let mesh = TriangleMesh::new(
            vec![
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(4.0, 0.0, 1.0),
                Vec3::new(4.0, 4.0, 1.0),
                Vec3::new(0.0, 4.0, 1.0),
                Vec3::new(0.0, 0.0, 2.0),
                Vec3::new(2.0, 0.0, 2.0),
                Vec3::new(2.0, 4.0, 2.0),
                Vec3::new(0.0, 4.0, 2.0),
            ],
            vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]],
        )
        .unwrap();
        let faces: Vec<FaceId> = mesh.faces().collect();
        let hits = raster_hits(&mesh, &lattice(), &faces, None);
        for (k, hit) in hits.iter().enumerate() {
            let (i, j) = (k % 5, k / 5);
            let hit = hit.expect("every node is over the lower square");
            let expected = if i <= 2 { 2.0 } else { 1.0 };
            assert!((hit.height - expected).abs() < 1e-5, "node ({i}, {j})");
            let p = mesh.face_positions(hit.face);
            let on = p[0] * hit.bary.x + p[1] * hit.bary.y + p[2] * hit.bary.z;
            assert!((on - Vec3::new(i as f32, j as f32, expected)).length() < 1e-4);
        }
        // Out of the searched heights: nothing.
        let mut high = lattice();
        high.heights = [5.0, 10.0];
        assert!(raster_hits(&mesh, &high, &faces, None)
            .iter()
            .all(Option::is_none));
    }

    #[test]
    fn rounding_matches_the_standard_library() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            1e-4,
            -1e-4,
            2.999_999_8,
            -2.999_999_8,
            8_388_607.5,
            -8_388_607.5,
            8_388_608.0,
            1e20,
            -1e20,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        values.extend((-4000..4000).map(|k| k as f32 * 0.013_7));
        for x in values {
            assert_eq!(ceil(x), x.ceil(), "ceil {x}");
            assert_eq!(floor(x), x.floor(), "floor {x}");
        }
        assert!(ceil(f32::NAN).is_nan() && floor(f32::NAN).is_nan());
    }

    #[test]
    fn faces_seen_edge_on_or_from_behind_are_skipped() {
        let mesh = TriangleMesh::new(
            vec![
                Vec3::ZERO,
                Vec3::new(0.0, 4.0, 0.0),
                Vec3::new(4.0, 0.0, 0.0),
            ],
            vec![[0, 1, 2]],
        )
        .unwrap();
        let faces: Vec<FaceId> = mesh.faces().collect();
        assert!(mesh.face_normal(faces[0]).z < 0.0);
        assert!(raster_hits(&mesh, &lattice(), &faces, None)
            .iter()
            .all(Option::is_none));
    }
}
