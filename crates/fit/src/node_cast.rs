//! Node heights by casting rays along −z onto the region and its neighbourhood.
//!
//! Every needed node casts a ray from above the region along −ẑ. Only the faces of the region
//! and of its neighbourhood (see `overlap`) may be hit; the first such hit gives the node its
//! height, its face and its barycentric coordinates (for colour). A node with no accepted hit
//! stays empty.
//!
//! Because the set of acceptable faces is known before casting, the casts are done face-first,
//! as a z-buffer: each acceptable triangle is projected on the lattice and, for every needed
//! node inside it, the hit height is interpolated and kept when it is the highest so far. This
//! gives exactly the answer of a BVH cast filtered to those faces (the highest accepted hit on
//! a −z ray is its first), at O(nodes covered) per face instead of a tree walk per node.
//!
//! Region faces take precedence: a node under the region's own surface takes that surface even
//! when a neighbouring face lies above it, so a fold of the neighbourhood cannot hide the
//! region from its own patch.
//!
//! Inside-tests use edge functions in f64 with a tolerance of 1e-6 of the triangle's doubled
//! area plus [`EDGE_SLACK`] cells of distance past each edge, so a node on an edge shared by
//! two faces is hit by both (never by neither), and a node on a region's straight border
//! hits its faces even where f32 rounding leaves the border a few millionths of a cell off
//! straight; faces whose projection has no area (edge-on) are never hit, as a ray would
//! graze them.
//!
//! Cost: O(Σ nodes in each face's footprint); memory one [`Hit`] per lattice node.

use glam::{DVec2, Vec3};
use spatch_mesh::{FaceId, TriangleMesh};

use crate::lattice::Lattice;

/// The accepted hit of one node's ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Hit {
    /// Height along ẑ (mesh coordinates); `-inf` when the node has no hit.
    pub(crate) height: f32,
    /// The face hit.
    pub(crate) face: FaceId,
    /// Barycentric coordinates of the hit on that face.
    pub(crate) bary: [f32; 3],
}

impl Hit {
    /// No hit.
    pub(crate) const NONE: Hit = Hit {
        height: f32::NEG_INFINITY,
        face: FaceId::INVALID,
        bary: [0.0; 3],
    };

    /// Whether the node was hit.
    #[inline]
    pub(crate) fn is_hit(&self) -> bool {
        self.face.is_valid()
    }
}

/// How far outside a face, in cells, a node still hits it. The faces' corners carry f32
/// rounding of a few millionths of a cell (more on a part turned away from the axes, whose
/// straight edges are no longer exactly straight in f32), so a node on a straight crease
/// that bounds its region lies just outside some of the faces along it; without the slack
/// it hits none of them and the region's patch loses its last row along the crease.
pub(crate) const EDGE_SLACK: f64 = 1e-4;

/// Casts the needed nodes of `lattice` onto `faces`, keeping the highest hit per node in
/// `hits`. Nodes where `locked` is true (already hit by a face of higher precedence) are left
/// alone.
pub(crate) fn cast_nodes(
    mesh: &TriangleMesh,
    faces: &[FaceId],
    lattice: &Lattice,
    needed: &[bool],
    locked: Option<&[bool]>,
    hits: &mut [Hit],
) {
    for &face in faces {
        let g = mesh.face_positions(face).map(|p| lattice.grid_point(p));
        let reach = FaceReach {
            past_edge: [EDGE_SLACK; 3],
            extend_plane: false,
        };
        cast_face(face, g, reach, lattice, needed, locked, hits);
    }
}

/// How far past each edge of a face its nodes reach, and how they get their height there.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FaceReach {
    /// Entry `c`: cells of distance past the edge opposite corner `c` that still hit.
    pub(crate) past_edge: [f64; 3],
    /// Heights past an edge from the face's plane extended (else from the nearest point of
    /// the face: the weights are clamped).
    pub(crate) extend_plane: bool,
}

/// One face of [`cast_nodes`]; `g` holds its corners as `(grid x, grid y, height)`.
pub(crate) fn cast_face(
    face: FaceId,
    g: [Vec3; 3],
    reach: FaceReach,
    lattice: &Lattice,
    needed: &[bool],
    locked: Option<&[bool]>,
    hits: &mut [Hit],
) {
    let Some((p, area2)) = projected_corners(g) else {
        return;
    };
    let inv = 1.0 / area2;
    // Weight of corner c at distance d (grid units) outside the opposite edge: -d·|edge|/|area2|.
    let opposite = [(2, 1), (0, 2), (1, 0)];
    let tol: [f64; 3] = std::array::from_fn(|c| {
        let (a, b) = opposite[c];
        -1e-6 - reach.past_edge[c] * (p[a] - p[b]).length() / area2.abs()
    });
    let Some(((i0, i1), (j0, j1))) = node_window(g, reach.past_edge, lattice) else {
        return;
    };
    for j in j0..=j1 {
        for i in i0..=i1 {
            let k = lattice.index(i, j);
            if !needed[k] || locked.is_some_and(|l| l[k]) {
                continue;
            }
            let q = DVec2::new(i as f64, j as f64);
            // Barycentric weight of corner c is the signed area opposite it over the total.
            let w0 = (p[2] - p[1]).perp_dot(q - p[1]) * inv;
            let w1 = (p[0] - p[2]).perp_dot(q - p[2]) * inv;
            let w2 = 1.0 - w0 - w1;
            if w0 < tol[0] || w1 < tol[1] || w2 < tol[2] {
                continue;
            }
            let plane = [w0 as f32, w1 as f32, w2 as f32];
            let (w0, w1, w2) = (w0.max(0.0), w1.max(0.0), w2.max(0.0));
            let sum = w0 + w1 + w2;
            let w = [(w0 / sum) as f32, (w1 / sum) as f32, (w2 / sum) as f32];
            let at = if reach.extend_plane { plane } else { w };
            let height = g[0].z * at[0] + g[1].z * at[1] + g[2].z * at[2];
            if height > hits[k].height {
                hits[k] = Hit {
                    height,
                    face,
                    bary: w,
                };
            }
        }
    }
}

/// The corners `g` of a face projected on the grid plane, with twice its signed area there;
/// `None` when the projection is edge-on (a ray would graze it).
#[inline(always)] // Sets up the node loop of `cast_face`, once per face.
fn projected_corners(g: [Vec3; 3]) -> Option<([DVec2; 3], f64)> {
    let p = g.map(|v| DVec2::new(f64::from(v.x), f64::from(v.y)));
    let area2 = (p[1] - p[0]).perp_dot(p[2] - p[0]);
    let scale = (p[1] - p[0])
        .length_squared()
        .max((p[2] - p[0]).length_squared())
        .max((p[2] - p[1]).length_squared());
    // Edge-on in projection: a ray would graze it.
    if area2.abs() <= 1e-9 * scale || !area2.is_finite() {
        return None;
    }
    Some((p, area2))
}

/// The lattice nodes `((i0, i1), (j0, j1))` (inclusive) that may hit the face of corners
/// `g`: its box widened by the largest reach `past_edge`; `None` when it misses the lattice.
#[inline(always)] // Sets up the node loop of `cast_face`, once per face.
fn node_window(
    g: [Vec3; 3],
    past_edge: [f64; 3],
    lattice: &Lattice,
) -> Option<((usize, usize), (usize, usize))> {
    // The box widened by the reach, so a node just past the face's extreme corner is tested.
    let widen = past_edge.iter().copied().fold(0.0, f64::max) as f32;
    let lo = g[0].min(g[1]).min(g[2]) - Vec3::splat(widen);
    let hi = g[0].max(g[1]).max(g[2]) + Vec3::splat(widen);
    let columns = Lattice::node_range(lo.x, hi.x, lattice.cols)?;
    let rows = Lattice::node_range(lo.y, hi.y, lattice.rows)?;
    Some((columns, rows))
}
