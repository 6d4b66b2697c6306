//! Edge pieces that meet at a vertex joined into one patch where one height field holds
//! them all: on low-poly models most pieces are single facet creases between crease ends
//! and corners (fuze's base: up to five pieces around one vertex), each paying a frame of
//! its own for a few nodes.
//!
//! Input: the cast pieces (piece and patch, in order), the surface patches, the edge
//! spacing and strip width. Output: groups of pieces, each with one patch.
//!
//! **Joined lattice.** A group's patch is seen along the length-weighted mean of its
//! segments' bisectors; x runs between the two crease vertices farthest apart in that view.
//! It covers the strips of every piece of the group (`w` on each face, `s_e + w / 2` past
//! every end, as the pieces' own lattices) and its node spacing along each axis is `s_e`
//! times the smallest foreshortening of the group's faces along that axis (so nodes stay
//! within `s_e` of each other on every face), and at most [`FOLD_CELL`] `× s_e / k` for the
//! sharpest fold (`k`: how much its faces' gradients differ in the patch's view), clamped to
//! `[0.1, 1] × s_e`. No row follows a crease, as a piece's does, so its cells must be fine
//! enough not to cut a fold's tip. Nodes farther than `w + s_e` (in the view) from every
//! segment of the group stay empty, as they were for the pieces' own patches: the rest of the
//! box lies on faces away from the creases or bridges over the silhouette.
//!
//! **Accepted only when nothing is lost.** Two groups that share a crease vertex are joined
//! when the joined patch, with the surface patches and every other group's patch (the two
//! groups' own left out), covers every probe of both groups' pieces that the two patches
//! covered: the probes of `covered_pieces` (both faces, every half surface spacing along,
//! the crease line itself and both ends, within the crease's tolerance and never more than
//! 0.2 cells). A joined patch with more than [`MAX_NODE_RATIO`] times the two patches' nodes
//! is refused. Pairs are tried in order of
//! the angle between the groups' view directions (then by index), repeatedly until a pass
//! joins none; a pair that failed is tried again only after one of its groups changed.
//!
//! Cost: per tried pair one cast (O(faces near the strips + nodes near the segments), the
//! node mask built segment by segment over its own box) and the groups' probes;
//! a pass is O(pairs), and there are at most as many successful joins as pieces. Memory O(the
//! patches). Deterministic: no parallelism, a total order.

use std::collections::HashSet;

use glam::{Vec2, Vec3};
use spatch_format::Patch;
use spatch_mesh::{FaceAdjacency, FaceId, VertexId};

use crate::coverage::{SurfaceCoverage, MAX_FACING_ANGLE_DEG};
use crate::covered_pieces::piece_covered;
use crate::edge_patch::{frame_and_model_bounds, nodes_over, EdgePiece, MIN_FORESHORTENING};
use crate::lattice_cast::{cast_lattice_within, faces_near, CastJob, NodeLattice};
use crate::sharp_edges::SharpEdges;
use crate::EdgeError;

/// Largest node count of a joined patch (cropped to its filled nodes), in multiples of the
/// two patches' it replaces. The edge pieces' own patches are a few rows of nodes; a joined
/// patch covers the area between their strips too, and finer cells across its folds
/// ([`FOLD_CELL`]). On fuze.obj 8 joins 18 of 66 pieces for 2.5 times the edge nodes
/// (6 joins 16, 4 joins 11: docs/algorithms/edges.md).
pub(crate) const MAX_NODE_RATIO: usize = 8;

/// Node spacing of a joined patch across its sharpest fold, in edge spacings over `k`, the
/// difference of the fold's two face gradients seen along the patch's z: a cell straddling
/// the fold cuts its tip by up to about `spacing × k / 4` along z, a quarter of an edge
/// spacing here. The probes then decide: the joins whose cells cut a fold deeper than the
/// pieces' own patches did are refused. 0.8 joins 4 more pieces of fuze.obj for 1.6 times
/// the nodes, 1.5 joins 8 fewer.
pub(crate) const FOLD_CELL: f32 = 1.0;

/// What joining needs besides the pieces.
pub(crate) struct JoinJob<'a> {
    pub(crate) cast: &'a CastJob<'a>,
    pub(crate) adjacency: &'a FaceAdjacency,
    pub(crate) sharp: &'a SharpEdges,
    /// The surface patches, which cover the pieces' probes too.
    pub(crate) surface: &'a [Patch],
    /// Surface node spacing (probe spacing, smallest tolerance cell).
    pub(crate) spacing: f32,
    /// Edge node spacing.
    pub(crate) edge_spacing: f32,
    /// Strip width on each face.
    pub(crate) strip: f32,
    /// Creases under this angle are soft (`coverage`).
    pub(crate) soft_crease_deg: f32,
}

/// One group of joined pieces: its segments as one piece, its patch and its crease vertices
/// (sorted).
struct Group {
    piece: EdgePiece,
    patch: Patch,
    vertices: Vec<VertexId>,
    /// Bumped whenever the group absorbs another, so failed pairs are tried again.
    version: u32,
    live: bool,
}

/// Joins the pieces of `made` (each piece with its cast patch, in order) that meet at a
/// crease vertex wherever one patch covers them (see the module docs). Returns the groups
/// (each as one piece with its patch, in the order of their first piece) and the number of
/// pieces absorbed into another's group.
pub(crate) fn join_pieces(
    job: &JoinJob<'_>,
    made: Vec<(&EdgePiece, Patch)>,
) -> Result<(Vec<(EdgePiece, Patch)>, usize), EdgeError> {
    let mut groups: Vec<Group> = made
        .into_iter()
        .map(|(piece, patch)| Group {
            vertices: piece_vertices(job.sharp, piece),
            piece: piece.clone(),
            patch,
            version: 0,
            live: true,
        })
        .collect();
    let mut failed: HashSet<(usize, u32, usize, u32)> = HashSet::new();
    let mut joined = 0;
    while let Some((a, b, patch)) = next_join(job, &groups, &mut failed)? {
        let segments = std::mem::take(&mut groups[b].piece.segments);
        let b_vertices = std::mem::take(&mut groups[b].vertices);
        groups[b].live = false;
        let group = &mut groups[a];
        group.piece.segments.extend(segments);
        group.vertices.extend(b_vertices);
        group.vertices.sort_unstable();
        group.vertices.dedup();
        group.patch = patch;
        group.version += 1;
        joined += 1;
    }
    let kept = groups
        .into_iter()
        .filter(|g| g.live)
        .map(|g| (g.piece, g.patch))
        .collect();
    Ok((kept, joined))
}

/// The first pair of live groups (in the order of the module docs) whose joined patch
/// covers both, with that patch; pairs that fail are recorded in `failed`.
fn next_join(
    job: &JoinJob<'_>,
    groups: &[Group],
    failed: &mut HashSet<(usize, u32, usize, u32)>,
) -> Result<Option<(usize, usize, Patch)>, EdgeError> {
    let pairs = untried_pairs(job, groups, failed);
    if pairs.is_empty() {
        return Ok(None);
    }
    let mut coverage = live_coverage(job, groups);
    for (a, b) in pairs {
        let nodes = groups[a].patch.grid().node_count() + groups[b].patch.grid().node_count();
        let candidate = join_patch(job, &groups[a].piece, &groups[b].piece, nodes)?;
        let covered = candidate
            .as_ref()
            .is_some_and(|patch| join_covers(job, groups, &mut coverage, (a, b), patch));
        match candidate {
            Some(patch) if covered => return Ok(Some((a, b, patch))),
            _ => {
                failed.insert((a, groups[a].version, b, groups[b].version));
            }
        }
    }
    Ok(None)
}

/// The adjacent pairs of live groups not already `failed` as they are, most alike view
/// directions first (then by index).
fn untried_pairs(
    job: &JoinJob<'_>,
    groups: &[Group],
    failed: &HashSet<(usize, u32, usize, u32)>,
) -> Vec<(usize, usize)> {
    let mut pairs = adjacent_pairs(groups);
    let views: Vec<Vec3> = groups
        .iter()
        .map(|g| view_of(job.sharp, &g.piece))
        .collect();
    pairs.retain(|&(a, b)| !failed.contains(&(a, groups[a].version, b, groups[b].version)));
    pairs.sort_by(|&(a, b), &(c, d)| {
        let (p, q) = (views[a].dot(views[b]), views[c].dot(views[d]));
        q.total_cmp(&p).then((a, b).cmp(&(c, d)))
    });
    pairs
}

/// The coverage of the surface patches and of the live groups' patches (the groups'
/// patches follow the surface's, in group order).
fn live_coverage<'a>(job: &JoinJob<'a>, groups: &'a [Group]) -> SurfaceCoverage<'a> {
    let mut coverage = SurfaceCoverage::new(
        job.surface.iter().chain(groups.iter().map(|g| &g.patch)),
        job.spacing,
    );
    let first = job.surface.len();
    for (k, g) in groups.iter().enumerate() {
        coverage.set_enabled(first + k, g.live);
    }
    coverage
}

/// Whether the joined `patch` of groups `a` and `b`, with `coverage` (of [`live_coverage`])
/// less their own patches, covers every probe of their pieces that their two patches
/// covered. Leaves `coverage` as it found it.
fn join_covers(
    job: &JoinJob<'_>,
    groups: &[Group],
    coverage: &mut SurfaceCoverage<'_>,
    (a, b): (usize, usize),
    patch: &Patch,
) -> bool {
    let first = job.surface.len();
    coverage.set_enabled(first + a, false);
    coverage.set_enabled(first + b, false);
    let own = SurfaceCoverage::new([patch], job.spacing);
    let before = SurfaceCoverage::new([&groups[a].patch, &groups[b].patch], job.spacing);
    // Every probe the two patches covered (beyond what the others cover) is covered
    // by the joined one. The small indexes are asked first: most probes end there.
    let covers = |p: Vec3, n: Vec3, tolerance: f32| {
        !before.covers(p, n, tolerance)
            || own.covers(p, n, tolerance)
            || coverage.covers(p, n, tolerance)
    };
    let ok = [&groups[a].piece, &groups[b].piece]
        .into_iter()
        .all(|piece| {
            piece_covered(
                job.cast.mesh,
                job.sharp,
                piece,
                job.spacing,
                job.soft_crease_deg,
                &covers,
            )
        });
    coverage.set_enabled(first + a, true);
    coverage.set_enabled(first + b, true);
    ok
}

/// Pairs `(a, b)`, `a < b`, of live groups that share a crease vertex.
fn adjacent_pairs(groups: &[Group]) -> Vec<(usize, usize)> {
    let mut at: Vec<(VertexId, usize)> = groups
        .iter()
        .enumerate()
        .filter(|(_, g)| g.live)
        .flat_map(|(k, g)| g.vertices.iter().map(move |&v| (v, k)))
        .collect();
    at.sort_unstable();
    let mut pairs = Vec::new();
    for run in at.chunk_by(|x, y| x.0 == y.0) {
        for (i, &(_, a)) in run.iter().enumerate() {
            for &(_, b) in &run[i + 1..] {
                pairs.push((a.min(b), a.max(b)));
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// The crease vertices of `piece`, sorted.
fn piece_vertices(sharp: &SharpEdges, piece: &EdgePiece) -> Vec<VertexId> {
    let mut vertices: Vec<VertexId> = piece
        .segments
        .iter()
        .flat_map(|s| {
            let c = &sharp.creases[s.crease as usize];
            [c.v0, c.v1]
        })
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    vertices
}

/// The length-weighted mean of the bisectors of `piece`'s segments (unit, or zero when
/// they cancel).
fn view_of(sharp: &SharpEdges, piece: &EdgePiece) -> Vec3 {
    piece
        .segments
        .iter()
        .map(|s| {
            let c = &sharp.creases[s.crease as usize];
            (c.normals[0] + c.normals[1]).normalize_or_zero() * s.a.distance(s.b)
        })
        .sum::<Vec3>()
        .normalize_or_zero()
}

/// The patch covering both `a` and `b` (see the module docs), or `None` when no view sees
/// all their faces within the probes' facing angle, when it would have more than
/// [`MAX_NODE_RATIO`] × `nodes` nodes, or when its rays hit nothing.
fn join_patch(
    job: &JoinJob<'_>,
    a: &EdgePiece,
    b: &EdgePiece,
    nodes: usize,
) -> Result<Option<Patch>, EdgeError> {
    let segments: Vec<_> = a.segments.iter().chain(&b.segments).copied().collect();
    let piece = EdgePiece { segments };
    let Some((lattice, faces)) = joined_lattice(job, &piece) else {
        return Ok(None);
    };
    // The lattice is cropped to its filled nodes after casting; one far larger is not cast.
    if lattice.cols * lattice.rows > 4 * MAX_NODE_RATIO * nodes {
        return Ok(None);
    }
    // Only the nodes near the pieces, as their own patches had: the rest of the box may lie
    // on faces far from any crease, or bridge over the model's silhouette.
    let reach = job.strip + job.edge_spacing;
    let flat: Vec<[Vec2; 2]> = piece
        .segments
        .iter()
        .map(|s| [s.a, s.b].map(|p| Vec2::new(p.dot(lattice.x), p.dot(lattice.y))))
        .collect();
    let within = nodes_near(&lattice, &flat, reach);
    let patch = cast_lattice_within(job.cast, &lattice, &faces, Some(&within), 0)?;
    Ok(patch.filter(|p| p.grid().node_count() <= MAX_NODE_RATIO * nodes))
}

/// The lattice of a group's `piece` (its segments need not be consecutive) and the faces its
/// rays may hit, or `None` when a face of it is seen beyond the probes' facing angle.
fn joined_lattice(job: &JoinJob<'_>, piece: &EdgePiece) -> Option<(NodeLattice, Vec<FaceId>)> {
    let mesh = job.cast.mesh;
    let z = view_of(job.sharp, piece);
    let min_facing = MAX_FACING_ANGLE_DEG.to_radians().cos();
    let (seeds, points) = joined_outline(job, piece, z, min_facing)?;
    let x = widest_direction(&points, z)?;
    let y = z.cross(x);
    let shrink = joined_shrink(job, piece, &seeds, [x, y, z], min_facing);
    let reach = job.edge_spacing + 0.5 * job.strip;
    let ([lo, hi], [box_lo, box_hi]) = frame_and_model_bounds(&points, [x, y, z]);
    let (cols, sx) = nodes_over(hi.x - lo.x + 2.0 * reach, job.edge_spacing * shrink[0]);
    let (rows, sy) = nodes_over(hi.y - lo.y + 2.0 * reach, job.edge_spacing * shrink[1]);
    let pad = Vec3::splat(reach);
    let faces = faces_near(mesh, job.adjacency, &seeds, box_lo - pad, box_hi + pad);
    // Rays search every height the allowed faces reach.
    let (h_lo, h_hi) = faces
        .iter()
        .flat_map(|&f| mesh.face_positions(f))
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), p| {
            (l.min(p.dot(z)), h.max(p.dot(z)))
        });
    let margin = job.edge_spacing;
    let lattice = NodeLattice {
        x,
        y,
        z,
        start: [lo.x - reach, lo.y - reach],
        spacing: [sx, sy],
        cols,
        rows,
        heights: [h_lo - margin, h_hi + margin],
    };
    Some((lattice, faces))
}

/// The faces of `piece`'s creases (two a segment, in order) and the outline of its strips
/// (each segment's ends, and those ends moved `job.strip` into each face), or `None` when a
/// face's normal is within `min_facing` (a cosine) of being seen edge-on along `z`.
fn joined_outline(
    job: &JoinJob<'_>,
    piece: &EdgePiece,
    z: Vec3,
    min_facing: f32,
) -> Option<(Vec<FaceId>, Vec<Vec3>)> {
    let (mesh, sharp, strip) = (job.cast.mesh, job.sharp, job.strip);
    let mut seeds = Vec::new();
    let mut points = Vec::new();
    for s in &piece.segments {
        let c = &sharp.creases[s.crease as usize];
        let t = (s.b - s.a).normalize_or_zero();
        points.extend([s.a, s.b]);
        for (face, n) in c.faces.iter().zip(c.normals) {
            if n.dot(z) < min_facing {
                return None;
            }
            seeds.push(*face);
            let mut d = n.cross(t).normalize_or_zero();
            if (mesh.face_centroid(*face) - s.a).dot(d) < 0.0 {
                d = -d;
            }
            points.extend([s.a + d * strip, s.b + d * strip]);
        }
    }
    Some((seeds, points))
}

/// The node spacing of a joined lattice along x and y, in edge spacings (see the module
/// docs): the smallest foreshortening of the `seeds` faces along each axis of the frame
/// `[x, y, z]`, at most [`FOLD_CELL`] over the sharpest fold, clamped to
/// `[MIN_FORESHORTENING, 1]`.
fn joined_shrink(
    job: &JoinJob<'_>,
    piece: &EdgePiece,
    seeds: &[FaceId],
    [x, y, z]: [Vec3; 3],
    min_facing: f32,
) -> [f32; 2] {
    // Foreshortening of each face along x and y: a step along the axis climbs its slope.
    let mut shrink = [1.0f32; 2];
    for &f in seeds {
        let n = job.cast.mesh.face_normal(f);
        let nz = n.dot(z);
        for (k, axis) in [x, y].into_iter().enumerate() {
            let along = n.dot(axis);
            shrink[k] = shrink[k].min(nz / (nz * nz + along * along).sqrt());
        }
    }
    let shrink = shrink.map(|c| c.clamp(MIN_FORESHORTENING, 1.0));
    let kink = piece
        .segments
        .iter()
        .map(|s| {
            let c = &job.sharp.creases[s.crease as usize];
            let g = c.normals.map(|n| {
                let nz = n.dot(z).max(min_facing);
                Vec2::new(n.dot(x), n.dot(y)) / nz
            });
            (g[0] - g[1]).length()
        })
        .fold(0.0f32, f32::max);
    let fold = (FOLD_CELL / kink.max(1e-3)).min(1.0);
    shrink.map(|c| c.min(fold).max(MIN_FORESHORTENING))
}

/// The unit direction, across `z`, between the two of `points` farthest apart seen along
/// `z`; `None` when they all project onto one point.
fn widest_direction(points: &[Vec3], z: Vec3) -> Option<Vec3> {
    let flat: Vec<Vec3> = points.iter().map(|&p| p - z * p.dot(z)).collect();
    let x =
        farthest_pair(&flat).map_or(Vec3::ZERO, |(i, j)| (flat[j] - flat[i]).normalize_or_zero());
    (x != Vec3::ZERO && z != Vec3::ZERO).then_some(x)
}

/// The first pair `(i, j)`, `i < j`, of `points` (in lexicographic order) at the largest
/// positive squared distance, or `None` when all coincide: what scanning every pair in
/// order and keeping a strictly farther one finds, without scanning every pair. A point `i`
/// can be in the farthest pair only if `(|p_i − c| + R)²` (triangle inequality through the
/// box centre `c`, `R` the largest radius), widened far beyond rounding, reaches a distance
/// some pair already has; the others are left out of the scan.
fn farthest_pair(points: &[Vec3]) -> Option<(usize, usize)> {
    let (lo, hi) = points
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(l, h), &p| {
            (l.min(p), h.max(p))
        });
    let centre = (lo + hi) * 0.5;
    let radii: Vec<f32> = points.iter().map(|p| p.distance(centre)).collect();
    let (outer, big) =
        radii.iter().enumerate().fold(
            (0, 0.0f32),
            |(k, r), (i, &q)| if q > r { (i, q) } else { (k, r) },
        );
    // A distance some pair has: from the outermost point to the farthest from it.
    let known = points
        .iter()
        .map(|p| p.distance_squared(points[outer]))
        .fold(0.0f32, f32::max);
    let kept: Vec<usize> = (0..points.len())
        .filter(|&i| {
            // NaN or infinite points stay: they are scanned as every pair would.
            let bound = (radii[i] + big).powi(2) * 1.001;
            bound >= known || bound.is_nan()
        })
        .collect();
    let mut best = (0.0f32, None);
    for (n, &i) in kept.iter().enumerate() {
        for &j in &kept[n + 1..] {
            let d = points[i].distance_squared(points[j]);
            if d > best.0 {
                best = (d, Some((i, j)));
            }
        }
    }
    best.1
}

/// The nodes of `lattice` (row-major) within `reach` of a segment of `flat` (in the lattice's
/// plane). Each segment tests only the nodes of its box widened by `reach` and one node, so
/// the cost is O(nodes near the segments), not O(nodes × segments).
fn nodes_near(lattice: &NodeLattice, flat: &[[Vec2; 2]], reach: f32) -> Vec<bool> {
    let (cols, rows) = (lattice.cols, lattice.rows);
    let mut near = vec![false; cols * rows];
    let node = |i: usize, j: usize| {
        Vec2::new(
            lattice.start[0] + i as f32 * lattice.spacing[0],
            lattice.start[1] + j as f32 * lattice.spacing[1],
        )
    };
    for &[a, b] in flat {
        let (lo, hi) = (a.min(b) - Vec2::splat(reach), a.max(b) + Vec2::splat(reach));
        let span = |k: usize, count: usize| {
            let first = ((lo[k] - lattice.start[k]) / lattice.spacing[k]).floor() - 1.0;
            let last = ((hi[k] - lattice.start[k]) / lattice.spacing[k]).ceil() + 1.0;
            // `as` saturates: below zero (or NaN) is 0.
            (
                first.max(0.0) as usize,
                (last.max(0.0) as usize).min(count - 1),
            )
        };
        let ((i0, i1), (j0, j1)) = (span(0, cols), span(1, rows));
        for j in j0..=j1 {
            for i in i0..=i1 {
                let k = j * cols + i;
                if !near[k] && distance_to_segment(node(i, j), a, b) <= reach {
                    near[k] = true;
                }
            }
        }
    }
    near
}

/// Distance from `q` to the segment from `a` to `b`.
fn distance_to_segment(q: Vec2, a: Vec2, b: Vec2) -> f32 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((q - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    q.distance(a + ab * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pair in order, keeping a strictly farther one.
    fn every_pair(points: &[Vec3]) -> Option<(usize, usize)> {
        let mut best = (0.0f32, None);
        for i in 0..points.len() {
            for j in i + 1..points.len() {
                let d = points[i].distance_squared(points[j]);
                if d > best.0 {
                    best = (d, Some((i, j)));
                }
            }
        }
        best.1
    }

    #[test]
    fn the_farthest_pair_is_the_one_every_pair_finds() {
        // Pseudo-random clouds, and grids (many pairs tie at the largest distance).
        let mut state = 12345u32;
        let mut next = || {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (state >> 8) as f32 / (1u32 << 24) as f32 - 0.5
        };
        for n in [0, 1, 2, 3, 7, 40, 120] {
            let cloud: Vec<Vec3> = (0..n)
                .map(|_| Vec3::new(next() * 10.0, next(), next() * 0.1))
                .collect();
            assert_eq!(farthest_pair(&cloud), every_pair(&cloud), "cloud of {n}");
        }
        let grid: Vec<Vec3> = (0..64)
            .map(|k| Vec3::new((k % 8) as f32, (k / 8) as f32, 0.0))
            .collect();
        assert_eq!(farthest_pair(&grid), every_pair(&grid));
        let same = vec![Vec3::ONE; 5];
        assert_eq!(farthest_pair(&same), None);
    }
}
