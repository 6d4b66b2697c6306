//! Edge patches: the crease polylines cut into pieces, each covered by one patch seen along
//! the bisector of its two faces' normals.
//!
//! Input: the chains of [`SharpEdges`] joined into runs (`chain_runs`), the surface node spacing `s`, the options. Output:
//! one [`NodeLattice`] per piece (cast into a patch by `lattice_cast`), with the faces its
//! rays may hit.
//!
//! **Pieces.** Each chain is walked segment by segment (segments longer than a piece are cut
//! into equal parts first). A piece grows while its length plus its overlaps stays within
//! `(max_cols − 1) × s_e`, every vertex of its crease stays within `max_stray × s_e` of its
//! chord (a fifth of that where a face is seen obliquely, [`STEEP_STRAY`]; so the row of
//! nodes along the chord stays near the crease), the faces' bisector
//! turns at most `max_turn_deg` from the piece's first segment, and every face normal stays
//! more than about 78° from that first bisector (both faces keep facing the patch). Knife
//! creases (faces folded flat onto each other) end a piece and are left uncovered: no
//! direction sees both faces. A chord rule rather than a turn rule lets a gently curved
//! crease run on for a whole patch (fandisk: 108 pieces where 8° turns made 173).
//!
//! **Frame.** x runs along the piece's chord; z is the length-weighted mean of the segments'
//! bisectors `normalize(n₁ + n₂)`, made orthogonal to x; y = z × x. Seen along z both faces
//! face the patch whenever the crease is not a knife (each normal is half the dihedral angle
//! away from the bisector, less than 90°).
//!
//! **Strip and resolution rule.** The patch covers the piece plus a strip of width
//! `w = strip_width × s` measured on each face, perpendicular to the edge, and reaches
//! `s_e + w / 2` beyond both ends so consecutive pieces overlap even on the outer side of a
//! turn. Its node spacing is
//! `s_e = s / resolution` along x, and `s_e × c` along y, where `c` is the smallest
//! foreshortening `|d · y|` of the strip directions `d` (in each face, perpendicular to the
//! edge), clamped to `[0.1, 1]`: a face tilted away by half the dihedral angle φ/2 is
//! foreshortened by `cos(φ/2)`, so rows are denser in the plane and nodes stay `s_e` apart on
//! the face. The patch thus has about `2 w / s_e + 1 = 2 × strip_width × resolution + 1`
//! rows whatever the crease angle. The rows are offset so that one runs along the crease
//! (its mean offset from the chord): where the piece is straight, that row's nodes land on
//! the crease itself and no cell cuts off the fold's tip, which would shrink the silhouette
//! (on the sweep frustums, 0.13 % of the pixels without the offset, 0.016 % with it and
//! 8° pieces; docs/algorithms/edges.md).
//!
//! **Faces.** Rays may hit the faces connected to the piece's creases whose bounding box
//! meets the strip's box, so a layer of the model behind or in front of the strip is never
//! taken.
//!
//! Cost: O(chain segments) to cut pieces; per piece O(faces near the strip) to gather faces.
//!
//! Based on: the sharp-edge patches proposed as the cure for rim gaps in the original spatial
//! patch work (a patch of higher resolution oriented between the two faces), and the
//! bisector view direction used for crease sampling in Botsch and Kobbelt, *Feature
//! Sensitive Surface Extraction from Volume Data* (SIGGRAPH 2001).

use glam::Vec3;
use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh};

use crate::lattice_cast::{faces_near, NodeLattice};
use crate::sharp_edges::{CreaseChain, SharpEdges};

/// Smallest foreshortening used to space rows (a face nearly edge-on to the patch).
pub(crate) const MIN_FORESHORTENING: f32 = 0.1;

/// One straight piece of a segment of a chain.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Segment {
    pub(crate) a: Vec3,
    pub(crate) b: Vec3,
    /// Index of its crease in [`SharpEdges::creases`].
    pub(crate) crease: u32,
}

/// Consecutive segments covered by one edge patch.
#[derive(Debug, Clone)]
pub(crate) struct EdgePiece {
    pub(crate) segments: Vec<Segment>,
}

/// How far a piece may grow (see the module docs).
#[derive(Debug, Clone, Copy)]
pub(crate) struct PieceLimits {
    /// Largest length of a piece along the crease.
    pub(crate) max_len: f32,
    /// Cosine of the largest turn of the faces' bisector from the piece's first segment.
    pub(crate) cos_turn: f32,
    /// Cosine of the largest turn while every face of the piece is seen squarely (within
    /// [`SQUARE_FACE_DOT`] of the first bisector): [`WIDE_TURN`] times the turn.
    pub(crate) cos_wide_turn: f32,
    /// Largest distance of the crease from the piece's chord.
    pub(crate) max_stray: f32,
}

impl PieceLimits {
    /// The largest distance of the crease from the chord of a piece whose faces are all seen
    /// squarely (`squarely`), or not ([`STEEP_STRAY`]).
    fn stray(&self, squarely: bool) -> f32 {
        if squarely {
            self.max_stray
        } else {
            self.max_stray * STEEP_STRAY
        }
    }
}

/// Smallest `n · b` of a face normal `n` of a piece against its first bisector `b`: below it
/// the face would be seen too obliquely (or from behind) by the patch.
const MIN_FACE_DOT: f32 = 0.2;

/// Smallest `n · b` of every face normal of a piece for it to take the wider turn
/// [`WIDE_TURN`]: faces within 50° of the first bisector (creases up to 100°, fandisk's
/// 80-90° ones), which a turn of the view by a few degrees more still sees squarely. Steeper
/// rims (the crease sweep's 110-150° ones, faces 55-75° from the bisector) open holes past
/// 10° and keep the plain turn.
pub(crate) const SQUARE_FACE_DOT: f32 = 0.64;

/// The turn allowed while every face is seen squarely, in multiples of
/// [`crate::EdgeOptions::max_turn_deg`].
pub(crate) const WIDE_TURN: f32 = 1.5;

/// The stray allowed while some face is not seen squarely (beyond [`SQUARE_FACE_DOT`] from
/// the first bisector), in multiples of [`crate::EdgeOptions::max_stray`]. Why: seen that
/// obliquely, a row of nodes that strays from a curved rim cuts more of its tip on screen;
/// the crease sweep's 110° rims left 0.0657 % of the pixels open over 14 views at 500² with
/// the plain stray and 0.0335 % with a fifth of it (40 → 48 patches on those two frustums,
/// the other five unchanged; fandisk unchanged, fuze 46 → 45 patches; a half or a third
/// changed nothing: the turn still ended those pieces first).
pub(crate) const STEEP_STRAY: f32 = 0.2;

/// Cuts every run of chains (`chain_runs`; creases of `sharp`) into pieces (see the module
/// docs), leaving out the creases `skip` marks
/// (those the surface patches already cover). Returns the pieces and the number of knife
/// creases skipped.
pub(crate) fn cut_pieces(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    runs: &[CreaseChain],
    skip: &[bool],
    limits: &PieceLimits,
) -> (Vec<EdgePiece>, usize) {
    let mut pieces = Vec::new();
    let mut knives = 0;
    for chain in runs {
        let mut cut = PieceCut::default();
        for (k, &ci) in chain.creases.iter().enumerate() {
            let crease = &sharp.creases[ci as usize];
            let knife = crease.is_knife();
            if knife || skip[ci as usize] {
                knives += usize::from(knife);
                flush(&mut pieces, &mut cut.current);
                continue;
            }
            let a = mesh.positions[chain.vertices[k].index()];
            let b = mesh.positions[chain.vertices[k + 1].index()];
            let seg_len = (b - a).length();
            let parts = (seg_len / limits.max_len).ceil().max(1.0) as usize;
            for p in 0..parts {
                let segment = Segment {
                    a: a.lerp(b, p as f32 / parts as f32),
                    b: a.lerp(b, (p + 1) as f32 / parts as f32),
                    crease: ci,
                };
                let part = (segment, seg_len / parts as f32);
                cut.extend(&mut pieces, part, crease.normals, limits);
            }
        }
        flush(&mut pieces, &mut cut.current);
    }
    (pieces, knives)
}

/// The piece being cut along a chain: its segments, their length, the bisector of its first
/// crease (`b0`) and whether every face of it is within [`SQUARE_FACE_DOT`] of `b0`.
#[derive(Default)]
struct PieceCut {
    current: Vec<Segment>,
    length: f32,
    b0: Vec3,
    square: bool,
}

impl PieceCut {
    /// Adds a `(segment, its length)` of a crease whose faces have `normals`, first ending
    /// the piece into `pieces` when the segment does not fit it (too long, turned too far,
    /// a face too steep, or straying from the chord).
    fn extend(
        &mut self,
        pieces: &mut Vec<EdgePiece>,
        (segment, part_len): (Segment, f32),
        normals: [Vec3; 2],
        limits: &PieceLimits,
    ) {
        let bisector = (normals[0] + normals[1]).normalize_or_zero();
        let b0 = self.b0;
        let turn = bisector.dot(b0);
        let squarely = self.square && normals.iter().all(|n| n.dot(b0) >= SQUARE_FACE_DOT);
        let fits = self.length + part_len <= limits.max_len
            && (turn >= limits.cos_turn || (squarely && turn >= limits.cos_wide_turn))
            && normals.iter().all(|n| n.dot(b0) >= MIN_FACE_DOT)
            && stays_near_chord(&self.current, segment.b, b0, limits.stray(squarely));
        if !fits {
            flush(pieces, &mut self.current);
        }
        if self.current.is_empty() {
            self.length = 0.0;
            self.b0 = bisector;
            self.square = normals.iter().all(|n| n.dot(bisector) >= SQUARE_FACE_DOT);
        } else {
            self.square = squarely;
        }
        self.current.push(segment);
        self.length += part_len;
    }
}

/// Ends the piece being built, if any.
fn flush(pieces: &mut Vec<EdgePiece>, current: &mut Vec<Segment>) {
    if !current.is_empty() {
        pieces.push(EdgePiece {
            segments: std::mem::take(current),
        });
    }
}

/// Whether every vertex of `segments` stays within `max_stray` of the chord from their
/// start to `end`, measured across the chord in the plane seen along `bisector` (the
/// piece's first bisector): a piece ending at `end` keeps its crease near its row of nodes.
/// A stray along the bisector only changes heights, which the patch records. False for no
/// segments (nothing to extend).
fn stays_near_chord(segments: &[Segment], end: Vec3, bisector: Vec3, max_stray: f32) -> bool {
    let Some(first) = segments.first() else {
        return false;
    };
    let chord = (end - first.a).normalize_or_zero();
    let across = bisector.cross(chord).normalize_or_zero();
    if across == Vec3::ZERO {
        return false;
    }
    segments
        .iter()
        .all(|s| (s.b - first.a).dot(across).abs() <= max_stray)
}

/// The lattice of one piece and the faces its rays may hit, or `None` when the piece has no
/// usable frame (its bisectors cancel along its chord).
pub(crate) fn piece_lattice(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    sharp: &SharpEdges,
    piece: &EdgePiece,
    edge_spacing: f32,
    strip: f32,
) -> Option<(NodeLattice, Vec<FaceId>)> {
    let [x, y, z] = piece_frame(sharp, piece)?;
    let outline = StripOutline::of_piece(mesh, sharp, piece, y, strip);
    let ([lo, hi], [box_lo, box_hi]) = frame_and_model_bounds(&outline.points, [x, y, z]);
    // Beyond each end so neighbouring pieces overlap: one column, plus the wedge that opens on
    // the outer side of a turn between two pieces' rectangles (half the strip covers the
    // default 15° turn with room to spare).
    let reach = edge_spacing + 0.5 * strip;
    let (u0, u1) = (lo.x - reach, hi.x + reach);
    let (cols, sx) = nodes_over(u1 - u0, edge_spacing);
    let row_spacing = edge_spacing * outline.foreshortening;
    let (rows, y0) = rows_along_crease(piece, y, [lo.y, hi.y], row_spacing);
    let margin = 0.5 * strip + edge_spacing;
    let lattice = NodeLattice {
        x,
        y,
        z,
        start: [u0, y0],
        spacing: [sx, row_spacing],
        cols,
        rows,
        heights: [lo.z - margin, hi.z + margin],
    };
    let pad = Vec3::splat(edge_spacing);
    let faces = faces_near(mesh, adjacency, &outline.seeds, box_lo - pad, box_hi + pad);
    Some((lattice, faces))
}

/// The frame `[x, y, z]` of a piece (see the module docs): x along its chord (or its first
/// segment when the chord is zero), z the length-weighted mean bisector made orthogonal to
/// x, y = z × x; `None` when x or z is zero.
fn piece_frame(sharp: &SharpEdges, piece: &EdgePiece) -> Option<[Vec3; 3]> {
    let first = piece.segments.first()?;
    let last = piece.segments.last()?;
    let mut x = (last.b - first.a).normalize_or_zero();
    if x == Vec3::ZERO {
        x = (first.b - first.a).normalize_or_zero();
    }
    let mut z0 = Vec3::ZERO;
    for s in &piece.segments {
        let c = &sharp.creases[s.crease as usize];
        z0 += (c.normals[0] + c.normals[1]).normalize_or_zero() * (s.b - s.a).length();
    }
    let z = (z0 - x * z0.dot(x)).normalize_or_zero();
    if x == Vec3::ZERO || z == Vec3::ZERO {
        return None;
    }
    Some([x, z.cross(x), z])
}

/// The strip a piece's patch covers on its faces.
struct StripOutline {
    /// The segments' ends and those ends moved `strip` into each face.
    points: Vec<Vec3>,
    /// The smallest foreshortening of the strip directions along y, clamped to
    /// `[MIN_FORESHORTENING, 1]`.
    foreshortening: f32,
    /// The faces of the piece's creases (two a segment, in order).
    seeds: Vec<FaceId>,
}

impl StripOutline {
    /// The outline of `piece`'s strip of width `strip` on each face, seen with the frame's
    /// y axis `y`.
    fn of_piece(
        mesh: &TriangleMesh,
        sharp: &SharpEdges,
        piece: &EdgePiece,
        y: Vec3,
        strip: f32,
    ) -> Self {
        let mut points = Vec::with_capacity(piece.segments.len() * 6);
        let mut foreshortening = 1.0f32;
        let mut seeds = Vec::with_capacity(piece.segments.len() * 2);
        for s in &piece.segments {
            let c = &sharp.creases[s.crease as usize];
            let t = (s.b - s.a).normalize_or_zero();
            points.push(s.a);
            points.push(s.b);
            for (face, n) in c.faces.iter().zip(c.normals) {
                seeds.push(*face);
                let mut d = n.cross(t).normalize_or_zero();
                if (mesh.face_centroid(*face) - s.a).dot(d) < 0.0 {
                    d = -d;
                }
                foreshortening = foreshortening.min(d.dot(y).abs());
                points.push(s.a + d * strip);
                points.push(s.b + d * strip);
            }
        }
        Self {
            points,
            foreshortening: foreshortening.clamp(MIN_FORESHORTENING, 1.0),
            seeds,
        }
    }
}

/// The rows (2..=257) spanning `[low, high]` along `y` at `row_spacing`, and the y of the
/// first, placed so that one row runs along the crease (its mean offset across the piece):
/// the nodes of that row land on the crease itself, so no cell cuts the fold's tip where
/// the piece is straight.
fn rows_along_crease(
    piece: &EdgePiece,
    y: Vec3,
    [low, high]: [f32; 2],
    row_spacing: f32,
) -> (usize, f32) {
    let crease_y = piece
        .segments
        .iter()
        .map(|s| (s.a + s.b).dot(y) * 0.5)
        .sum::<f32>()
        / piece.segments.len() as f32;
    let below = ((crease_y - low) / row_spacing).ceil().max(0.0);
    let above = ((high - crease_y) / row_spacing).ceil().max(0.0);
    let rows = ((below + above) as usize + 1).clamp(2, 257);
    (rows, crease_y - below * row_spacing)
}

/// Nodes (2..=257) spanning `length` at spacing at most `target` (wider only when 257 nodes
/// cannot reach), and the spacing used.
pub(crate) fn nodes_over(length: f32, target: f32) -> (usize, f32) {
    let cells = (length / target).ceil();
    let cells = if cells.is_finite() {
        cells.clamp(1.0, 256.0) as usize
    } else {
        1
    };
    let spacing = if length > 0.0 {
        length / cells as f32
    } else {
        target
    };
    (cells + 1, spacing)
}

/// The bounds of `points` in the frame with axes `x, y, z` (frame coordinates) and in model
/// space, each as `[low, high]`.
pub(crate) fn frame_and_model_bounds(
    points: &[Vec3],
    [x, y, z]: [Vec3; 3],
) -> ([Vec3; 2], [Vec3; 2]) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    let (mut box_lo, mut box_hi) = (lo, hi);
    for &p in points {
        let q = Vec3::new(p.dot(x), p.dot(y), p.dot(z));
        lo = lo.min(q);
        hi = hi.max(q);
        box_lo = box_lo.min(p);
        box_hi = box_hi.max(p);
    }
    ([lo, hi], [box_lo, box_hi])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn segment(a: Vec3, b: Vec3) -> Segment {
        Segment { a, b, crease: 0 }
    }

    #[test]
    fn a_piece_grows_while_its_crease_stays_near_the_chord() {
        // Two unit segments turning by 2 × atan(0.1) ≈ 11.4°: the middle vertex is 0.1 from
        // the chord of the piece they would form.
        let first = segment(Vec3::ZERO, Vec3::new(1.0, 0.1, 0.0));
        let end = Vec3::new(2.0, 0.0, 0.0);
        assert!(stays_near_chord(&[first], end, Vec3::Z, 0.11));
        assert!(!stays_near_chord(&[first], end, Vec3::Z, 0.09));
        assert!(
            stays_near_chord(&[first], end, Vec3::Y, 0.01),
            "a stray along the bisector is a height"
        );
        assert!(
            !stays_near_chord(&[], end, Vec3::Z, 1.0),
            "nothing to extend"
        );
    }

    #[test]
    fn nodes_over_never_exceeds_the_target_spacing() {
        let (n, s) = nodes_over(1.0, 0.3);
        assert_eq!(n, 5);
        assert!(s <= 0.3);
        assert_eq!(nodes_over(0.0, 0.3), (2, 0.3));
        let (n, s) = nodes_over(1000.0, 0.1);
        assert_eq!(n, 257);
        assert!((s - 1000.0 / 256.0).abs() < 1e-3);
    }
}
