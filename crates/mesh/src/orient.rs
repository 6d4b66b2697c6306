//! Face orientation: consistent winding across shared edges, and outward per piece.
//!
//! Back-face culling, and the renderer's rule for what an opening lets the eye see (the
//! converter's sides pass, `spatch_convert::find_mesh_sides`), assume that each connected
//! piece of the surface is wound consistently and that its front faces *out*: away from the
//! volume the piece encloses, or would enclose once its openings were capped. Meshes from the
//! wild break both: a scan triangulated in the scanner's image order can face into the
//! object, an exporter can flip a whole model or a few faces. Drawn with culling, such a
//! model shows its inside.
//!
//! [`orient_faces`] repairs both, in three steps per connected piece:
//!
//! 1. **Consistent winding.** A breadth-first walk from the piece's lowest face crosses every
//!    edge with exactly two faces and flips the next face when both faces run along the edge
//!    the same way. Edges with three or more faces are not crossed (which way is "opposite"
//!    is undefined there), so they separate pieces. Where the walk meets a face already
//!    placed the other way (a Möbius band, a badly glued seam), the edge is counted as
//!    *conflicting* and left.
//! 2. **Outward.** The piece's signed volume is taken about the mean `o` of its open edges'
//!    endpoints (edges with one face, or with three or more), or of all its edges' when it
//!    is closed: `Σ det(a − o, b − o, c − o) / 6`. It is the volume of the piece closed by
//!    the cone from `o` over its open edges (the cone's triangles contain `o` and add
//!    nothing), so positive means out. A negative piece is turned over.
//! 3. **Flat pieces.** A piece whose volume is below [`FLAT_VOLUME`] times `area^1.5` (a flat
//!    sheet, a saddle, a lone triangle beside a non-manifold edge) has no inside: it keeps the
//!    winding most of its area had in the input, unless most of the area of the decided
//!    pieces faced in. The file is then wound inward by its maker, and its flat pieces are
//!    turned over with the rest.
//!
//! Turning a face over swaps its last two corners (and their UVs); vertex data is not
//! touched. A consistently wound input comes out unchanged; a whole mesh wound inward
//! comes out as the same mesh wound outward, face for face. The report counts the pieces the
//! file wound inward (most of their area turned over) and says whether most of the whole
//! surface was: such a file may be a room made to be seen from inside, which a caller may
//! rather draw from both sides (the converter does).
//!
//! Cost: one walk over faces and edges, O(F + E), and one pass of 3×3 determinants.
//!
//! Based on: the orientation propagation of Botsch et al., *Polygon Mesh Processing* (2010),
//! chapter 3 (consistent orientation of a manifold triangle soup), and the signed volume by
//! the divergence theorem used to orient closed meshes outward.

use std::collections::VecDeque;

use glam::DVec3;

use crate::{FaceAdjacency, FaceId, TriangleMesh};

/// Below this fraction of `area^1.5`, a piece's signed volume does not decide its side.
pub const FLAT_VOLUME: f64 = 1e-4;

/// What [`orient_faces`] changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OrientReport {
    /// Connected pieces (joined across edges with exactly two faces).
    pub pieces: usize,
    /// Faces whose last two corners were swapped.
    pub flipped_faces: usize,
    /// Pieces the file wound inward: most of their area turned over (to face out or, when
    /// flat, as step 3 says). A piece with a few faces wound wrong is not one.
    pub inward_pieces: usize,
    /// Whether the file wound most of its surface inward (more than half of all the area
    /// turned over): an object exported inside out, or a room made to be seen from inside.
    pub wound_inward: bool,
    /// Edges with two faces that no choice of winding makes opposite (non-orientable).
    pub conflicting_edges: usize,
}

/// Winds every piece of `mesh` consistently and outward (see the module docs); `adjacency`
/// is [`build_face_adjacency`](crate::build_face_adjacency) of `mesh`, and stays so (a face
/// turned over keeps its edges, listed from its new corners).
pub fn orient_faces(mesh: &mut TriangleMesh, adjacency: &mut FaceAdjacency) -> OrientReport {
    let faces = mesh.face_count();
    let mut walk = Walk {
        flip: vec![false; faces],
        piece_of: vec![u32::MAX; faces],
        conflicting_edges: 0,
    };
    let mut report = OrientReport::default();
    let mut pieces = Vec::new();
    for seed in 0..faces {
        if walk.piece_of[seed] == u32::MAX {
            let members = walk.piece(mesh, adjacency, seed, pieces.len() as u32);
            pieces.push(measure_piece(mesh, adjacency, &members, &walk.flip));
        }
    }
    let turn = piece_turns(&pieces);
    report.pieces = pieces.len();
    report.inward_pieces = pieces
        .iter()
        .zip(&turn)
        .filter(|(p, &t)| p.wound_inward(t))
        .count();
    let flipped_area: f64 = pieces
        .iter()
        .zip(&turn)
        .map(|(p, &t)| p.flipped_area(t))
        .sum();
    report.wound_inward = flipped_area > pieces.iter().map(|p| p.area).sum::<f64>() / 2.0;
    for (flip, &piece) in walk.flip.iter_mut().zip(&walk.piece_of) {
        *flip ^= turn[piece as usize];
    }
    report.conflicting_edges = walk.conflicting_edges;
    for (f, _) in walk.flip.iter().enumerate().filter(|&(_, &turn)| turn) {
        report.flipped_faces += 1;
        mesh.triangles[f].swap(1, 2);
        adjacency.swap_last_corners(FaceId(f as u32));
        if let Some(uvs) = &mut mesh.face_uvs {
            uvs[f].swap(1, 2);
        }
    }
    report
}

/// Step 1's state: per face, whether it is flipped and which piece holds it (`u32::MAX`
/// before the walk reaches it).
struct Walk {
    flip: Vec<bool>,
    piece_of: Vec<u32>,
    conflicting_edges: usize,
}

impl Walk {
    /// The faces of `seed`'s piece in walk order, each marked with `piece` and flipped
    /// where it must be to agree with the seed.
    fn piece(
        &mut self,
        mesh: &TriangleMesh,
        adjacency: &FaceAdjacency,
        seed: usize,
        piece: u32,
    ) -> Vec<usize> {
        let mut members = vec![seed];
        self.piece_of[seed] = piece;
        let mut queue = VecDeque::from([seed]);
        while let Some(f) = queue.pop_front() {
            for edge in adjacency.face_edges(FaceId(f as u32)) {
                if !edge.is_valid() {
                    continue;
                }
                let e = adjacency.edge(edge);
                let &[g, h] = e.faces else { continue };
                let other = if g.index() == f { h.index() } else { g.index() };
                let same_way = runs_forward(mesh, f, e.v0.0, e.v1.0)
                    == runs_forward(mesh, other, e.v0.0, e.v1.0);
                // After flipping, the two faces must run along the edge opposite ways.
                let wanted = self.flip[f] ^ same_way;
                if self.piece_of[other] == u32::MAX {
                    self.piece_of[other] = piece;
                    self.flip[other] = wanted;
                    members.push(other);
                    queue.push_back(other);
                } else if self.flip[other] != wanted && f < other {
                    self.conflicting_edges += 1;
                }
            }
        }
        members
    }
}

/// Whether face `f` runs from vertex `a` to vertex `b` (they are consecutive corners).
fn runs_forward(mesh: &TriangleMesh, f: usize, a: u32, b: u32) -> bool {
    let t = mesh.triangles[f];
    (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b)
}

/// A piece as steps 2 and 3 measure it, wound as the walk left it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PieceMeasure {
    /// Whether its volume is negative, or `None` when it is flat (step 3).
    faces_in: Option<bool>,
    /// Its area.
    area: f64,
    /// The area of its faces the walk left as the file has them.
    kept_area: f64,
}

impl PieceMeasure {
    /// Whether the piece turns over, given whether most of the decided area of the file
    /// faced in (see [`piece_turns`]).
    fn turns(&self, file_inward: bool) -> bool {
        self.faces_in
            .unwrap_or((self.kept_area < self.area / 2.0) ^ file_inward)
    }

    /// The area of the piece's faces turned over, when the piece turns as `turn` says.
    fn flipped_area(&self, turn: bool) -> f64 {
        if turn {
            self.kept_area
        } else {
            self.area - self.kept_area
        }
    }

    /// Whether the file wound the piece inward: turned as `turn` says, most of its area
    /// ends up turned over.
    fn wound_inward(&self, turn: bool) -> bool {
        self.flipped_area(turn) > self.area / 2.0
    }
}

/// Steps 2 and 3 for the piece `members`, wound as `flip` says.
fn measure_piece(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    members: &[usize],
    flip: &[bool],
) -> PieceMeasure {
    let o = volume_centre(mesh, adjacency, members);
    let (mut volume, mut area, mut kept_area) = (0.0f64, 0.0f64, 0.0f64);
    for &f in members {
        let [a, b, c] = mesh.triangles[f].map(|v| mesh.positions[v as usize].as_dvec3() - o);
        let det = a.dot(b.cross(c));
        volume += if flip[f] { -det } else { det } / 6.0;
        let face_area = (b - a).cross(c - a).length() / 2.0;
        area += face_area;
        kept_area += if flip[f] { 0.0 } else { face_area };
    }
    let decided = volume.abs() > FLAT_VOLUME * area.powf(1.5);
    PieceMeasure {
        faces_in: decided.then_some(volume < 0.0),
        area,
        kept_area,
    }
}

/// Per piece, whether it turns over: a decided piece when it faces in; a flat one when it
/// must to keep its input's winding, or else when most of the decided area faced in (the
/// file is wound inward, so its flat pieces are too).
fn piece_turns(pieces: &[PieceMeasure]) -> Vec<bool> {
    let (mut inward, mut outward) = (0.0, 0.0);
    for piece in pieces {
        match piece.faces_in {
            Some(true) => inward += piece.area,
            Some(false) => outward += piece.area,
            None => {}
        }
    }
    pieces.iter().map(|p| p.turns(inward > outward)).collect()
}

/// The point the volume of `members` is taken about: the mean of its open edges' endpoints
/// (edges of one face, or three or more; each edge as often as its faces in `members` list
/// it), or of all its edges' when it has none.
fn volume_centre(mesh: &TriangleMesh, adjacency: &FaceAdjacency, members: &[usize]) -> DVec3 {
    let (mut open, mut open_n, mut all, mut all_n) = (DVec3::ZERO, 0u64, DVec3::ZERO, 0u64);
    for &f in members {
        for edge in adjacency.face_edges(FaceId(f as u32)) {
            if !edge.is_valid() {
                continue;
            }
            let e = adjacency.edge(edge);
            let p = mesh.positions[e.v0.index()].as_dvec3();
            let q = mesh.positions[e.v1.index()].as_dvec3();
            if e.faces.len() != 2 {
                open += p + q;
                open_n += 2;
            }
            all += p + q;
            all_n += 2;
        }
    }
    if open_n > 0 {
        open / open_n as f64
    } else {
        all / all_n.max(1) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build_face_adjacency;
    use glam::{Vec2, Vec3};

    /// An octahedron (closed, wound outward) with its six vertices on the axes.
    fn octahedron() -> TriangleMesh {
        let p = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
        let t = vec![
            [0, 2, 4],
            [2, 1, 4],
            [1, 3, 4],
            [3, 0, 4],
            [2, 0, 5],
            [1, 2, 5],
            [3, 1, 5],
            [0, 3, 5],
        ];
        TriangleMesh::new(p, t).unwrap()
    }

    fn signed_volume(mesh: &TriangleMesh) -> f64 {
        mesh.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    fn oriented(mut mesh: TriangleMesh) -> (TriangleMesh, OrientReport) {
        let mut adjacency = build_face_adjacency(&mesh);
        let report = orient_faces(&mut mesh, &mut adjacency);
        assert_eq!(adjacency, build_face_adjacency(&mesh));
        (mesh, report)
    }

    #[test]
    fn an_outward_mesh_is_left_as_it_is() {
        let (mesh, report) = oriented(octahedron());
        assert_eq!(mesh.triangles, octahedron().triangles);
        assert_eq!((report.pieces, report.flipped_faces), (1, 0));
        assert!(signed_volume(&mesh) > 1.3);
    }

    #[test]
    fn an_inward_mesh_and_scattered_flips_come_out_outward() {
        let outward = octahedron();
        for pattern in [0b1111_1111u32, 0b0000_0001, 0b1010_0110, 0b0111_1111] {
            let mut mesh = octahedron();
            for (f, t) in mesh.triangles.iter_mut().enumerate() {
                if pattern >> f & 1 == 1 {
                    t.swap(0, 1);
                }
            }
            let (mesh, report) = oriented(mesh);
            assert_eq!(report.conflicting_edges, 0);
            assert_eq!(report.flipped_faces, pattern.count_ones() as usize);
            // Wound inward only when most of it was (four of eight is not most).
            let most = pattern.count_ones() > 4;
            assert_eq!(report.inward_pieces, usize::from(most), "{pattern:b}");
            assert_eq!(report.wound_inward, most, "{pattern:b}");
            // Same faces, each wound as the outward original (up to a rotation of corners).
            for (got, want) in mesh.triangles.iter().zip(&outward.triangles) {
                let turned = [
                    [got[0], got[1], got[2]],
                    [got[1], got[2], got[0]],
                    [got[2], got[0], got[1]],
                ];
                assert!(turned.contains(want), "{got:?} against {want:?}");
            }
            assert!((signed_volume(&mesh) - 4.0 / 3.0).abs() < 1e-9);
        }
    }

    #[test]
    fn an_open_bowl_faces_away_from_its_cap_and_uvs_follow_their_corners() {
        // The octahedron's lower half (z <= 0) wound into the bowl: the volume closed by
        // its rim is negative, so every face turns over.
        let full = octahedron();
        let mut bowl =
            TriangleMesh::new(full.positions.clone(), full.triangles[4..].to_vec()).unwrap();
        for t in &mut bowl.triangles {
            t.swap(1, 2);
        }
        let uvs: Vec<[Vec2; 3]> = (0..4)
            .map(|f| [Vec2::ZERO, Vec2::X * f as f32, Vec2::Y])
            .collect();
        bowl.face_uvs = Some(uvs.clone());
        let (bowl, report) = oriented(bowl);
        assert_eq!((report.inward_pieces, report.flipped_faces), (1, 4));
        assert_eq!(bowl.triangles, full.triangles[4..]);
        for (got, was) in bowl.face_uvs.unwrap().iter().zip(&uvs) {
            assert_eq!(*got, [was[0], was[2], was[1]]);
        }
    }

    #[test]
    fn a_flat_sheet_keeps_the_winding_of_most_of_its_area() {
        // Four triangles in z = 0; the larger two face +z, one small one was flipped.
        let p = vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(1.0, 3.0, 0.0),
        ];
        let t = vec![[0, 1, 2], [0, 2, 3], [3, 4, 2]];
        let (mesh, report) = oriented(TriangleMesh::new(p, t).unwrap());
        assert_eq!(report.flipped_faces, 1);
        assert_eq!(mesh.triangles[2], [3, 2, 4]);
        assert!(mesh.faces().all(|f| mesh.face_normal(f).z > 0.99));
    }

    #[test]
    fn a_flat_piece_turns_with_a_file_wound_inward() {
        // An octahedron and a lone triangle, both as the outward file has them, then both
        // turned over: the triangle has no inside, but follows the octahedron either way.
        let one = octahedron();
        let mut p = one.positions.clone();
        p.extend([
            Vec3::new(3.0, 0.0, 0.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(3.0, 1.0, 0.0),
        ]);
        let mut t = one.triangles.clone();
        t.push([6, 7, 8]);
        let outward = TriangleMesh::new(p, t).unwrap();
        let (kept, report) = oriented(outward.clone());
        assert_eq!((report.pieces, report.flipped_faces), (2, 0));
        let mut inward = outward;
        for t in &mut inward.triangles {
            t.swap(0, 1);
        }
        let (turned, report) = oriented(inward);
        assert_eq!((report.inward_pieces, report.flipped_faces), (2, 9));
        assert_eq!(turned.triangles.last(), Some(&[7, 8, 6]));
        assert_eq!(turned.face_normal(FaceId(8)), kept.face_normal(FaceId(8)));
    }

    #[test]
    fn a_moebius_band_counts_its_conflicting_edge() {
        // Six quads around a loop with a half twist, as twelve triangles.
        let n = 6;
        let mut p = Vec::new();
        for k in 0..n {
            let a = std::f32::consts::TAU * k as f32 / n as f32;
            let twist = a / 2.0;
            let (dr, dz) = (0.3 * twist.cos(), 0.3 * twist.sin());
            let (c, s) = (a.cos(), a.sin());
            p.push(Vec3::new((1.0 - dr) * c, (1.0 - dr) * s, -dz));
            p.push(Vec3::new((1.0 + dr) * c, (1.0 + dr) * s, dz));
        }
        let mut t = Vec::new();
        for k in 0..n as u32 {
            let (a, b) = (2 * k, 2 * k + 1);
            // The last quad joins the first rung the other way round.
            let (c, d) = if k + 1 == n as u32 {
                (1, 0)
            } else {
                (2 * k + 2, 2 * k + 3)
            };
            t.push([a, c, b]);
            t.push([b, c, d]);
        }
        let (_, report) = oriented(TriangleMesh::new(p, t).unwrap());
        assert_eq!(report.pieces, 1);
        assert_eq!(report.conflicting_edges, 1);
    }

    #[test]
    fn pieces_are_oriented_apart() {
        // Two octahedra, the second shifted and wound inward: only it turns over.
        let one = octahedron();
        let mut p = one.positions.clone();
        p.extend(one.positions.iter().map(|v| *v + Vec3::new(5.0, 0.0, 0.0)));
        let mut t = one.triangles.clone();
        t.extend(one.triangles.iter().map(|t| [t[0] + 6, t[2] + 6, t[1] + 6]));
        let (mesh, report) = oriented(TriangleMesh::new(p, t).unwrap());
        assert_eq!(
            (report.pieces, report.inward_pieces, report.flipped_faces),
            (2, 1, 8)
        );
        assert!((signed_volume(&mesh) - 8.0 / 3.0).abs() < 1e-9);
    }
}
