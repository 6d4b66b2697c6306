//! Edge pieces the other patches already close: on low-poly models, a short piece between
//! two others is often covered by their overlaps and by the surface patches around it, and
//! its own patch only adds a frame and its nodes.
//!
//! After every piece is cast, the pieces are probed as the creases were (`coverage`), but
//! against the surface patches *and the other edge patches*: points on both faces of each of
//! the piece's segments, every half surface spacing along it, at [`PROBE_OFFSETS`] surface
//! spacings across, each within the crease's tolerance (soft or not) of a drawable cell of a
//! patch facing its face. The patch of the piece under test is left out of its own probes.
//!
//! **Greedy, shortest first.** Pieces are tried in order of length (ties by index); a
//! covered piece is dropped at once, so a later piece may no longer count on it. Dropping
//! one piece may uncover another that was dropped earlier (two pieces that each covered the
//! other's stretch), so the dropped pieces are probed again against what is kept, and any
//! that is no longer covered is taken back, until a whole pass takes none back. Taking a
//! piece back only adds coverage, so the loop ends, and at its end every dropped piece is
//! covered by the surface patches and the kept edge patches together.
//!
//! Cost: O(pieces × probes per piece × patches per index cell), plus the passes that take
//! pieces back (rarely more than one). Deterministic: no parallelism, a total order.

use glam::Vec3;
use spatch_format::Patch;
use spatch_mesh::TriangleMesh;

use crate::coverage::{crease_tolerance, span_probes, SurfaceCoverage, COVER_TOLERANCE};
use crate::edge_patch::EdgePiece;
use crate::sharp_edges::SharpEdges;
use crate::PROBE_OFFSETS;

/// Distances of a piece's probes from its crease, in surface node spacings: the crease
/// probes' ([`PROBE_OFFSETS`]) and the crease itself, whose tip a patch that runs past the
/// end of its own piece may cut.
const PIECE_PROBE_OFFSETS: [f32; 4] = [0.0, PROBE_OFFSETS[0], PROBE_OFFSETS[1], PROBE_OFFSETS[2]];

/// For each of `made` (a piece and its cast patch, in order), whether it is dropped: covered
/// by `surface` and the kept ones of `made` (see the module docs). `spacing` is the surface
/// node spacing the creases were probed at; creases under `soft_crease_deg` are soft.
pub(crate) fn covered_pieces(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    surface: &[Patch],
    made: &[(EdgePiece, Patch)],
    spacing: f32,
    soft_crease_deg: f32,
) -> Vec<bool> {
    let all = surface.iter().chain(made.iter().map(|(_, patch)| patch));
    let mut coverage = SurfaceCoverage::new(all, spacing);
    let first = surface.len();
    let covered = |coverage: &SurfaceCoverage<'_>, piece: &EdgePiece| {
        let covers = |p, n, tolerance| coverage.covers(p, n, tolerance);
        piece_covered(mesh, sharp, piece, spacing, soft_crease_deg, &covers)
    };
    let mut order: Vec<usize> = (0..made.len()).collect();
    let length = |k: usize| -> f32 { made[k].0.segments.iter().map(|s| s.a.distance(s.b)).sum() };
    order.sort_by(|&i, &j| length(i).total_cmp(&length(j)).then(i.cmp(&j)));

    let mut dropped = vec![false; made.len()];
    for &k in &order {
        coverage.set_enabled(first + k, false);
        if covered(&coverage, &made[k].0) {
            dropped[k] = true;
        } else {
            coverage.set_enabled(first + k, true);
        }
    }
    loop {
        let mut taken_back = false;
        for &k in &order {
            if dropped[k] && !covered(&coverage, &made[k].0) {
                dropped[k] = false;
                coverage.set_enabled(first + k, true);
                taken_back = true;
            }
        }
        if !taken_back {
            return dropped;
        }
    }
}

/// Whether `covers` (a point, its face's unit normal, a tolerance in cells) holds for every
/// probe of `piece`: both faces of each segment, every half `spacing` along it and at both
/// ends, on the crease and at [`PROBE_OFFSETS`] spacings across, within the crease's
/// tolerance and never more than [`COVER_TOLERANCE`] cells.
pub(crate) fn piece_covered(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    piece: &EdgePiece,
    spacing: f32,
    soft_crease_deg: f32,
    covers: &dyn Fn(Vec3, Vec3, f32) -> bool,
) -> bool {
    piece.segments.iter().all(|s| {
        let crease = &sharp.creases[s.crease as usize];
        let tolerance = crease_tolerance(crease, soft_crease_deg).min(COVER_TOLERANCE);
        span_probes(
            mesh,
            crease,
            [s.a, s.b],
            spacing,
            &PIECE_PROBE_OFFSETS,
            true,
        )
        .all(|(p, n)| covers(p, n, tolerance))
    })
}

#[cfg(test)]
mod tests {
    use spatch_mesh::build_face_adjacency;

    use super::*;
    use crate::edge_patch::{piece_lattice, Segment};
    use crate::lattice_cast::{cast_lattice, CastJob};
    use crate::sharp_edges::detect_sharp_edges;

    /// Two unit squares folded 90° along the x axis: one crease.
    fn fold() -> TriangleMesh {
        TriangleMesh::new(
            vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::Y,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::Z,
                Vec3::new(1.0, 0.0, 1.0),
            ],
            vec![[0, 1, 2], [2, 1, 3], [1, 0, 4], [1, 4, 5]],
        )
        .unwrap()
    }

    #[test]
    fn of_two_pieces_covering_each_other_one_is_kept() {
        let mesh = fold();
        let adjacency = build_face_adjacency(&mesh);
        let sharp = detect_sharp_edges(&mesh, &adjacency, 25.0);
        assert_eq!(sharp.creases.len(), 1);
        let crease = &sharp.creases[0];
        let (a, b) = (
            mesh.positions[crease.v0.index()],
            mesh.positions[crease.v1.index()],
        );
        // The middle of the crease: near the mesh's border no patch has a drawable cell.
        let piece = EdgePiece {
            segments: vec![Segment {
                a: a.lerp(b, 0.25),
                b: a.lerp(b, 0.75),
                crease: 0,
            }],
        };
        let spacing = 0.1;
        let (lattice, faces) =
            piece_lattice(&mesh, &adjacency, &sharp, &piece, spacing, 0.8 * spacing).unwrap();
        let job = CastJob {
            mesh: &mesh,
            spacing,
            max_step_error: 0.1,
            with_colour: false,
        };
        let patch = cast_lattice(&job, &lattice, &faces, 0).unwrap().unwrap();

        // Alone, nothing else covers the crease: kept.
        let one = [(piece.clone(), patch.clone())];
        assert_eq!(
            covered_pieces(&mesh, &sharp, &[], &one, spacing, 50.0),
            [false]
        );
        // Twice over, either covers the other: one is dropped, never both.
        let two = [
            (piece.clone(), patch.clone()),
            (piece.clone(), patch.clone()),
        ];
        assert_eq!(
            covered_pieces(&mesh, &sharp, &[], &two, spacing, 50.0),
            [true, false]
        );
        // A patch that covers the stretch as a surface patch does also lets it go.
        let surface = [patch];
        assert_eq!(
            covered_pieces(&mesh, &sharp, &surface, &one, spacing, 50.0),
            [true]
        );
    }
}
