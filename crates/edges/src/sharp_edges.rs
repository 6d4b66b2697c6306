//! Sharp-edge detection by dihedral angle, and chaining of the sharp edges into polylines.
//!
//! Input: a mesh and its face adjacency, a crease angle θ. Output: [`SharpEdges`]:
//!
//! - **creases**: every edge with exactly two faces whose normals differ by at least θ. The
//!   angle is taken between the normals as the faces are *consistently* oriented: when the
//!   two faces walk the shared edge in the same direction (one of them is wound the other
//!   way), the second normal is flipped first, so a winding error never reads as a 180°
//!   crease. Edges whose normals differ by more than [`KNIFE_ANGLE_DEG`] (faces folded onto
//!   each other) are creases with no usable bisector and are counted as knife edges.
//!   Edges with one face (boundary) are not creases; edges with three or more faces
//!   (non-manifold) are counted and left alone.
//! - **corners**: vertices where three or more creases meet; **ends**: vertices with exactly
//!   one crease (a crease fading into a smooth surface, or an open boundary of creases).
//! - **chains**: the creases joined end to end through vertices with exactly two creases.
//!   Chains start and stop at corners and ends, so a polyline never turns through a corner;
//!   the creases left after that form closed loops (a cylinder's rims).
//!
//! Invariants: every crease is in exactly one chain; consecutive vertices of a chain share a
//! crease; a closed chain repeats its first vertex at the end. The output is deterministic:
//! creases follow the adjacency's sorted edge order, chains start at the lowest vertex id.
//!
//! Cost: one pass over the edges, one sort of `2 × creases` vertex records, one walk over the
//! creases; memory O(creases).
//!
//! Based on: the dihedral-angle crease test of Hoppe et al., *Piecewise Smooth Surface
//! Reconstruction* (SIGGRAPH 1994), and the feature-line chaining common to mesh
//! simplification (Garland and Heckbert, *Surface Simplification Using Quadric Error
//! Metrics*, SIGGRAPH 1997, boundary/feature edges).

use glam::Vec3;
use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh, VertexId};

/// Normals further apart than this (degrees) fold the two faces onto each other: the
/// crease has no bisector to look from.
pub const KNIFE_ANGLE_DEG: f32 = 179.0;

/// One sharp edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crease {
    /// The smaller vertex id of the edge.
    pub v0: VertexId,
    /// The larger vertex id.
    pub v1: VertexId,
    /// The two faces on the edge, by id.
    pub faces: [FaceId; 2],
    /// Unit normals of the two faces, the second flipped when the faces are wound
    /// inconsistently (so both point to the same side of the surface).
    pub normals: [Vec3; 2],
    /// Angle between the normals, degrees (0 = flat).
    pub angle_deg: f32,
}

impl Crease {
    /// Whether the faces fold onto each other (angle beyond [`KNIFE_ANGLE_DEG`]).
    pub fn is_knife(&self) -> bool {
        self.angle_deg > KNIFE_ANGLE_DEG
    }

    /// The other end of the crease from `v` (which must be one of its ends).
    pub fn other(&self, v: VertexId) -> VertexId {
        if v == self.v0 {
            self.v1
        } else {
            self.v0
        }
    }
}

/// A polyline of creases.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CreaseChain {
    /// The vertices in order; for a closed chain the last equals the first.
    pub vertices: Vec<VertexId>,
    /// Index (into [`SharpEdges::creases`]) of the crease joining `vertices[k]` and
    /// `vertices[k + 1]`; one fewer than the vertices.
    pub creases: Vec<u32>,
    /// Whether the chain is a closed loop.
    pub closed: bool,
}

/// What [`detect_sharp_edges`] finds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SharpEdges {
    /// The creases, in the adjacency's edge order.
    pub creases: Vec<Crease>,
    /// The creases joined into polylines.
    pub chains: Vec<CreaseChain>,
    /// Vertices with three or more creases, by id.
    pub corners: Vec<VertexId>,
    /// Vertices with exactly one crease, by id.
    pub ends: Vec<VertexId>,
    /// Edges with three or more faces (not tested for sharpness).
    pub non_manifold_edges: usize,
}

impl SharpEdges {
    /// Creases whose faces fold onto each other (no bisector; no edge patch covers them).
    pub fn knife_count(&self) -> usize {
        self.creases.iter().filter(|c| c.is_knife()).count()
    }
}

/// Finds the creases of `mesh` at `crease_angle_deg` and chains them (see the module docs).
///
/// `adjacency` must be the face adjacency of `mesh`.
pub fn detect_sharp_edges(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    crease_angle_deg: f32,
) -> SharpEdges {
    let cos_limit = crease_angle_deg.to_radians().cos();
    let mut out = SharpEdges::default();
    for (v0, v1, faces) in adjacency.edges() {
        match faces.len() {
            2 => {}
            0 | 1 => continue,
            _ => {
                out.non_manifold_edges += 1;
                continue;
            }
        }
        let (fa, fb) = (faces[0], faces[1]);
        let na = mesh.face_normal(fa);
        let mut nb = mesh.face_normal(fb);
        if na == Vec3::ZERO || nb == Vec3::ZERO {
            continue;
        }
        if walks_forward(mesh, fa, v0, v1) == walks_forward(mesh, fb, v0, v1) {
            nb = -nb;
        }
        let cos = na.dot(nb).clamp(-1.0, 1.0);
        if cos > cos_limit {
            continue;
        }
        out.creases.push(Crease {
            v0,
            v1,
            faces: [fa, fb],
            normals: [na, nb],
            angle_deg: cos.acos().to_degrees(),
        });
    }
    chain_creases(&mut out);
    out
}

/// Whether `face` walks from `a` to `b` (in its winding order).
fn walks_forward(mesh: &TriangleMesh, face: FaceId, a: VertexId, b: VertexId) -> bool {
    let t = mesh.triangles[face.index()];
    (0..3).any(|k| t[k] == a.0 && t[(k + 1) % 3] == b.0)
}

/// Fills `chains`, `corners` and `ends` from `creases`.
fn chain_creases(out: &mut SharpEdges) {
    // CSR of creases per vertex, sorted by (vertex, crease).
    let mut incidence: Vec<(u32, u32)> = Vec::with_capacity(out.creases.len() * 2);
    for (k, c) in out.creases.iter().enumerate() {
        incidence.push((c.v0.0, k as u32));
        incidence.push((c.v1.0, k as u32));
    }
    incidence.sort_unstable();
    let at = |v: u32| -> &[(u32, u32)] {
        let lo = incidence.partition_point(|&(x, _)| x < v);
        let hi = incidence.partition_point(|&(x, _)| x <= v);
        &incidence[lo..hi]
    };
    let mut vertices: Vec<u32> = incidence.iter().map(|&(v, _)| v).collect();
    vertices.dedup();
    let mut visited = vec![false; out.creases.len()];
    for &v in &vertices {
        match at(v).len() {
            1 => out.ends.push(VertexId(v)),
            2 => {}
            _ => out.corners.push(VertexId(v)),
        }
    }
    // Open chains from every corner and end.
    for &v in &vertices {
        if at(v).len() == 2 {
            continue;
        }
        for &(_, k) in at(v) {
            if !visited[k as usize] {
                let chain = walk(&out.creases, &at, &mut visited, VertexId(v), k);
                out.chains.push(chain);
            }
        }
    }
    // What is left are closed loops through vertices of two creases.
    for k in 0..out.creases.len() {
        if !visited[k] {
            let start = out.creases[k].v0;
            let chain = walk(&out.creases, &at, &mut visited, start, k as u32);
            out.chains.push(chain);
        }
    }
}

/// Walks from `start` along crease `first` until a vertex without exactly two creases, or
/// until the next crease was already walked.
fn walk<'a>(
    creases: &[Crease],
    at: &impl Fn(u32) -> &'a [(u32, u32)],
    visited: &mut [bool],
    start: VertexId,
    first: u32,
) -> CreaseChain {
    let mut chain = CreaseChain {
        vertices: vec![start],
        creases: Vec::new(),
        closed: false,
    };
    let mut current = first;
    let mut v = start;
    loop {
        visited[current as usize] = true;
        chain.creases.push(current);
        v = creases[current as usize].other(v);
        chain.vertices.push(v);
        let around = at(v.0);
        if around.len() != 2 {
            break;
        }
        let next = if around[0].1 == current {
            around[1].1
        } else {
            around[0].1
        };
        if visited[next as usize] {
            chain.closed = v == start;
            break;
        }
        current = next;
    }
    chain
}

#[cfg(test)]
mod tests {
    use super::*;
    use spatch_mesh::build_face_adjacency;

    #[test]
    fn a_flipped_face_is_not_a_crease() {
        // Two coplanar triangles, the second wound the other way.
        let mesh = TriangleMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
            vec![[0, 1, 2], [1, 2, 3]],
        )
        .unwrap();
        let adjacency = build_face_adjacency(&mesh);
        let sharp = detect_sharp_edges(&mesh, &adjacency, 10.0);
        assert!(sharp.creases.is_empty());
    }

    #[test]
    fn a_folded_sheet_has_one_open_chain() {
        // Two triangles folded 90° along the edge (0,0,0)-(1,0,0).
        let mesh = TriangleMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            vec![[0, 1, 2], [1, 0, 3]],
        )
        .unwrap();
        let adjacency = build_face_adjacency(&mesh);
        let sharp = detect_sharp_edges(&mesh, &adjacency, 30.0);
        assert_eq!(sharp.creases.len(), 1);
        assert!((sharp.creases[0].angle_deg - 90.0).abs() < 1e-3);
        assert_eq!(sharp.chains.len(), 1);
        assert!(!sharp.chains[0].closed);
        assert_eq!(sharp.ends.len(), 2);
        assert!(detect_sharp_edges(&mesh, &adjacency, 95.0)
            .creases
            .is_empty());
    }
}
