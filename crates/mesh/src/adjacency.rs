//! Face adjacency across shared edges, in compressed sparse row (CSR) form.
//!
//! Computes, for a [`TriangleMesh`], the list of edges (unordered vertex pairs) with the
//! faces on each, the three edges of each face, and for each face the faces that share an
//! edge with it.
//!
//! Invariants kept:
//! - edges are matched by their **unordered** vertex pair, so inconsistent winding between
//!   neighbours does not break adjacency;
//! - an edge with three or more faces (non-manifold) links every pair of its faces, up to
//!   [`FULL_LINK_LIMIT`] faces; beyond that the faces are linked as a chain (each to the next
//!   by face index), which keeps them connected while keeping memory linear in the input;
//! - a degenerate edge (both ends the same vertex) is not an edge: it gets
//!   [`EdgeId::INVALID`] and links nothing;
//! - every list is sorted (edges by vertex pair, faces and neighbours by id), so the result
//!   is deterministic and binary-searchable; neighbours hold no duplicates and never the face
//!   itself.
//!
//! Cost: one sort of `3F` edge records (`O(F log F)`), then linear passes; memory about
//! `3F * 16` bytes transient and `~40 bytes * F` kept.
//!
//! Based on: the half-edge-free CSR adjacency of meshoptimizer (Kapoulkine,
//! `meshopt_generateAdjacencyIndexBuffer`-style edge sorting), and the usual
//! "sort the edge list" construction from Botsch et al., *Polygon Mesh Processing* (2010),
//! chapter 2.

use crate::{EdgeId, FaceId, TriangleMesh, VertexId};

/// Edges with at most this many faces link every pair of their faces; larger fans are linked
/// as a chain so a hostile input (thousands of faces on one edge) cannot need quadratic memory.
pub const FULL_LINK_LIMIT: usize = 64;

/// Face-to-face and edge-to-face adjacency of a triangle mesh (see the module docs).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceAdjacency {
    neighbour_offsets: Vec<u32>,
    neighbours: Vec<FaceId>,
    edge_vertices: Vec<[VertexId; 2]>,
    edge_offsets: Vec<u32>,
    edge_faces: Vec<FaceId>,
    face_edges: Vec<[EdgeId; 3]>,
}

/// One edge with the faces that contain it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Edge<'a> {
    /// The smaller vertex index of the edge.
    pub v0: VertexId,
    /// The larger vertex index.
    pub v1: VertexId,
    /// Faces containing the edge, sorted by id (one: boundary, two: manifold, more:
    /// non-manifold).
    pub faces: &'a [FaceId],
}

impl FaceAdjacency {
    /// Number of faces the adjacency was built for.
    pub fn face_count(&self) -> usize {
        self.face_edges.len()
    }

    /// Faces sharing an edge with `face`, sorted by id, without duplicates or `face` itself.
    ///
    /// # Panics
    /// When `face` is not a face of the mesh the adjacency was built from.
    #[inline]
    pub fn neighbours(&self, face: FaceId) -> &[FaceId] {
        let i = face.index();
        let (a, b) = (self.neighbour_offsets[i], self.neighbour_offsets[i + 1]);
        &self.neighbours[a as usize..b as usize]
    }

    /// Number of distinct edges.
    pub fn edge_count(&self) -> usize {
        self.edge_vertices.len()
    }

    /// One edge.
    ///
    /// # Panics
    /// When `edge` is out of range.
    #[inline]
    pub fn edge(&self, edge: EdgeId) -> Edge<'_> {
        let i = edge.index();
        let [v0, v1] = self.edge_vertices[i];
        let (a, b) = (self.edge_offsets[i], self.edge_offsets[i + 1]);
        Edge {
            v0,
            v1,
            faces: &self.edge_faces[a as usize..b as usize],
        }
    }

    /// Every edge as `(v0, v1, faces)` with `v0 < v1`, in order of `(v0, v1)`.
    pub fn edges(&self) -> impl ExactSizeIterator<Item = (VertexId, VertexId, &[FaceId])> + '_ {
        (0..self.edge_vertices.len()).map(move |i| {
            let e = self.edge(EdgeId(i as u32));
            (e.v0, e.v1, e.faces)
        })
    }

    /// The edges of `face`: entry `k` is the edge from corner `k` to corner `(k + 1) % 3`, or
    /// [`EdgeId::INVALID`] when those corners are the same vertex.
    #[inline]
    pub fn face_edges(&self, face: FaceId) -> [EdgeId; 3] {
        self.face_edges[face.index()]
    }

    /// Keeps [`face_edges`](Self::face_edges) in step when `face`'s last two corners are
    /// swapped (corners `a b c` become `a c b`): its edges then run `a→c`, `c→b`, `b→a`.
    pub(crate) fn swap_last_corners(&mut self, face: FaceId) {
        self.face_edges[face.index()].swap(0, 2);
    }

    /// Number of edges with exactly one face.
    pub fn boundary_edge_count(&self) -> usize {
        self.edge_offsets
            .windows(2)
            .filter(|w| w[1] - w[0] == 1)
            .count()
    }

    /// Number of edges with three or more faces.
    pub fn non_manifold_edge_count(&self) -> usize {
        self.edge_offsets
            .windows(2)
            .filter(|w| w[1] - w[0] > 2)
            .count()
    }
}

/// Builds the [`FaceAdjacency`] of `mesh` (see the module docs for the rules).
pub fn build_face_adjacency(mesh: &TriangleMesh) -> FaceAdjacency {
    let face_count = mesh.triangles.len();
    let records = corner_edge_records(mesh);
    let edges = group_edges(&records, face_count);
    let mut pairs = edges.pairs;
    pairs.sort_unstable();
    pairs.dedup();
    let (neighbour_offsets, neighbours) = neighbour_lists(&pairs, face_count);

    FaceAdjacency {
        neighbour_offsets,
        neighbours,
        edge_vertices: edges.edge_vertices,
        edge_offsets: edges.edge_offsets,
        edge_faces: edges.edge_faces,
        face_edges: edges.face_edges,
    }
}

/// One record per non-degenerate corner edge of `mesh`: (lo, hi, face, corner), sorted;
/// sorting the tuples orders by edge, then face, so the output never depends on the input
/// order of equal keys.
fn corner_edge_records(mesh: &TriangleMesh) -> Vec<(u32, u32, u32, u8)> {
    let mut records: Vec<(u32, u32, u32, u8)> = Vec::with_capacity(mesh.triangles.len() * 3);
    for (f, t) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a != b {
                records.push((a.min(b), a.max(b), f as u32, k as u8));
            }
        }
    }
    records.sort_unstable();
    records
}

/// The edges found in the sorted corner-edge records, and the face pairs they link.
struct EdgeGroups {
    /// Per face, its edge per corner (see [`FaceAdjacency::face_edges`]).
    face_edges: Vec<[EdgeId; 3]>,
    /// The two vertices of each edge, lower first.
    edge_vertices: Vec<[VertexId; 2]>,
    /// Where each edge's faces start in `edge_faces` (one more entry than edges).
    edge_offsets: Vec<u32>,
    /// The faces of every edge, edge after edge.
    edge_faces: Vec<FaceId>,
    /// Ordered face pairs linked by an edge, with repeats.
    pairs: Vec<(u32, u32)>,
}

/// Groups the sorted `records` into edges (on `face_count` faces), listing each edge's faces
/// and the face pairs it links.
fn group_edges(records: &[(u32, u32, u32, u8)], face_count: usize) -> EdgeGroups {
    let mut groups = EdgeGroups {
        face_edges: vec![[EdgeId::INVALID; 3]; face_count],
        edge_vertices: Vec::new(),
        edge_offsets: vec![0u32],
        edge_faces: Vec::with_capacity(records.len()),
        pairs: Vec::with_capacity(records.len() * 2),
    };
    let mut start = 0;
    while start < records.len() {
        let (lo, hi) = (records[start].0, records[start].1);
        let mut end = start;
        let first_face = groups.edge_faces.len();
        let edge = EdgeId(groups.edge_vertices.len() as u32);
        while end < records.len() && records[end].0 == lo && records[end].1 == hi {
            let (_, _, f, k) = records[end];
            groups.face_edges[f as usize][k as usize] = edge;
            // A face holding the same edge twice ([a, b, a]) is listed once.
            if groups.edge_faces.last() != Some(&FaceId(f)) || groups.edge_faces.len() == first_face
            {
                groups.edge_faces.push(FaceId(f));
            }
            end += 1;
        }
        link_faces(&groups.edge_faces[first_face..], &mut groups.pairs);
        groups.edge_vertices.push([VertexId(lo), VertexId(hi)]);
        groups.edge_offsets.push(groups.edge_faces.len() as u32);
        start = end;
    }
    groups
}

/// Adds to `pairs` the face pairs one edge's `faces` link: every ordered pair up to
/// [`FULL_LINK_LIMIT`] faces, else each face with the next and previous in the list.
#[inline]
fn link_faces(faces: &[FaceId], pairs: &mut Vec<(u32, u32)>) {
    if faces.len() <= FULL_LINK_LIMIT {
        for &a in faces {
            for &b in faces {
                if a != b {
                    pairs.push((a.0, b.0));
                }
            }
        }
    } else {
        for w in faces.windows(2) {
            pairs.push((w[0].0, w[1].0));
            pairs.push((w[1].0, w[0].0));
        }
    }
}

/// The neighbour lists of `face_count` faces in offset-and-list form, from the sorted,
/// deduplicated ordered face `pairs`.
fn neighbour_lists(pairs: &[(u32, u32)], face_count: usize) -> (Vec<u32>, Vec<FaceId>) {
    let mut neighbour_offsets = vec![0u32; face_count + 1];
    for &(a, _) in pairs {
        neighbour_offsets[a as usize + 1] += 1;
    }
    for i in 0..face_count {
        neighbour_offsets[i + 1] += neighbour_offsets[i];
    }
    let neighbours = pairs.iter().map(|&(_, b)| FaceId(b)).collect();
    (neighbour_offsets, neighbours)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn mesh(positions: usize, triangles: Vec<[u32; 3]>) -> TriangleMesh {
        TriangleMesh::new(vec![Vec3::ZERO; positions], triangles).unwrap()
    }

    #[test]
    fn two_triangles_share_one_edge() {
        let adj = build_face_adjacency(&mesh(4, vec![[0, 1, 2], [2, 1, 3]]));
        assert_eq!(adj.neighbours(FaceId(0)), &[FaceId(1)]);
        assert_eq!(adj.neighbours(FaceId(1)), &[FaceId(0)]);
        assert_eq!(adj.edge_count(), 5);
        assert_eq!(adj.boundary_edge_count(), 4);
        let shared: Vec<_> = adj.edges().filter(|e| e.2.len() == 2).collect();
        assert_eq!(
            shared,
            vec![(VertexId(1), VertexId(2), &[FaceId(0), FaceId(1)][..])]
        );
        let e = adj.face_edges(FaceId(0))[1];
        assert_eq!(adj.edge(e).faces, &[FaceId(0), FaceId(1)]);
    }

    #[test]
    fn inconsistent_winding_still_links() {
        // Both faces traverse edge 1->2 in the same direction.
        let adj = build_face_adjacency(&mesh(4, vec![[0, 1, 2], [1, 2, 3]]));
        assert_eq!(adj.neighbours(FaceId(0)), &[FaceId(1)]);
    }

    #[test]
    fn degenerate_edges_link_nothing() {
        let adj = build_face_adjacency(&mesh(3, vec![[0, 0, 1], [0, 1, 2]]));
        assert_eq!(adj.face_edges(FaceId(0))[0], EdgeId::INVALID);
        assert_eq!(adj.neighbours(FaceId(0)), &[FaceId(1)]);
        // The face [0, 0, 1] has edge {0, 1} twice but is listed once on it.
        let e = adj.face_edges(FaceId(0))[1];
        assert_eq!(adj.edge(e).faces, &[FaceId(0), FaceId(1)]);
    }

    #[test]
    fn huge_fans_are_chained() {
        let n = FULL_LINK_LIMIT as u32 + 10;
        let tris = (0..n).map(|k| [0, 1, k + 2]).collect();
        let adj = build_face_adjacency(&mesh(n as usize + 2, tris));
        assert_eq!(adj.non_manifold_edge_count(), 1);
        assert_eq!(adj.neighbours(FaceId(0)), &[FaceId(1)]);
        assert_eq!(adj.neighbours(FaceId(5)), &[FaceId(4), FaceId(6)]);
    }

    #[test]
    fn empty_mesh() {
        let adj = build_face_adjacency(&TriangleMesh::default());
        assert_eq!(adj.face_count(), 0);
        assert_eq!(adj.edges().count(), 0);
    }
}
