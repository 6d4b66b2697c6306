//! Runs: crease chains joined through the corners where one continues another nearly
//! straight, so that an edge piece may run on through a corner instead of ending there.
//!
//! Chains stop at every corner (a vertex of three or more creases, `sharp_edges`). On
//! low-poly models many corners are where a side crease meets a long one that runs straight
//! on; cut per chain, the long crease becomes two short pieces there. Here the chain ends
//! meeting at each corner are paired, straightest pair first: two ends pair when their
//! directions from the corner are within `max_turn` of opposite and their first creases'
//! bisectors within `max_turn` of each other. Each end pairs at most once, so a run still
//! never turns into a third crease. The pieces (`edge_patch`) then cut runs as they cut
//! chains, with the same limits; the corner patch is still made when its probes find a gap.
//!
//! Deterministic: pairs sorted by straightness, then by corner and chain index; runs start at
//! the lowest chain index of each run (a run closing on itself starts there too).
//!
//! Cost: O(chain ends × ends per corner) to pair, O(creases) to walk.

use glam::Vec3;
use spatch_mesh::{TriangleMesh, VertexId};

use crate::sharp_edges::{CreaseChain, SharpEdges};

/// One end of a chain at a corner.
#[derive(Debug, Clone, Copy)]
struct ChainEnd {
    chain: usize,
    /// Whether it is the chain's first vertex (else its last).
    at_start: bool,
    /// Unit direction from the corner along the chain.
    direction: Vec3,
    /// Unit bisector of the faces of the chain's crease at the corner.
    bisector: Vec3,
}

/// The chains of `sharp` joined into runs (see the module docs); `cos_turn` is the cosine of
/// the largest turn allowed through a corner. A run is a [`CreaseChain`] in the same form.
pub(crate) fn chain_runs(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    cos_turn: f32,
) -> Vec<CreaseChain> {
    let links = pair_ends(mesh, sharp, cos_turn);
    let count = sharp.chains.len();
    let mut used = vec![false; count];
    let mut runs = Vec::with_capacity(count);
    for first in 0..count {
        if used[first] {
            continue;
        }
        // Walk back to the run's first chain (or around a closed run to its lowest index).
        let (mut chain, mut forward) = (first, true);
        let mut lowest = (first, true);
        loop {
            let entry = if forward { 0 } else { 1 };
            let Some((prev, prev_at_start)) = links[chain][entry] else {
                break;
            };
            // Entering `prev` through its start means walking it backwards.
            let prev_forward = !prev_at_start;
            if prev == first {
                (chain, forward) = lowest;
                break;
            }
            (chain, forward) = (prev, prev_forward);
            if chain < lowest.0 {
                lowest = (chain, forward);
            }
        }
        runs.push(walk_run(sharp, &links, &mut used, chain, forward));
    }
    runs
}

/// Follows the links from `chain` (walked forward or not) and concatenates the run.
fn walk_run(
    sharp: &SharpEdges,
    links: &[[Option<(usize, bool)>; 2]],
    used: &mut [bool],
    mut chain: usize,
    mut forward: bool,
) -> CreaseChain {
    let mut run = CreaseChain {
        vertices: Vec::new(),
        creases: Vec::new(),
        closed: false,
    };
    while !used[chain] {
        used[chain] = true;
        let c = &sharp.chains[chain];
        let (mut vertices, mut creases) = (c.vertices.clone(), c.creases.clone());
        if !forward {
            vertices.reverse();
            creases.reverse();
        }
        if !run.vertices.is_empty() {
            vertices.remove(0);
        }
        run.vertices.extend(vertices);
        run.creases.extend(creases);
        run.closed = c.closed;
        let exit = if forward { 1 } else { 0 };
        let Some((next, next_at_start)) = links[chain][exit] else {
            break;
        };
        (chain, forward) = (next, next_at_start);
    }
    if run.vertices.len() > 1 && run.vertices.first() == run.vertices.last() {
        run.closed = true;
    }
    run
}

/// For each chain, the chain end its start ([0]) and end ([1]) are joined to, if any.
fn pair_ends(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    cos_turn: f32,
) -> Vec<[Option<(usize, bool)>; 2]> {
    let at_corner = ends_at_corners(mesh, sharp);
    let mut links = vec![[None; 2]; sharp.chains.len()];
    let mut taken = vec![false; at_corner.len()];
    for (_, i, j) in straightest_pairs(&at_corner, cos_turn) {
        if taken[i] || taken[j] {
            continue;
        }
        taken[i] = true;
        taken[j] = true;
        let (a, b) = (at_corner[i].1, at_corner[j].1);
        links[a.chain][usize::from(!a.at_start)] = Some((b.chain, b.at_start));
        links[b.chain][usize::from(!b.at_start)] = Some((a.chain, a.at_start));
    }
    links
}

/// The ends of open chains that lie on a corner vertex, with the
/// direction the chain leaves in and its crease's bisector, sorted by
/// vertex (then chain, start first).
fn ends_at_corners(mesh: &TriangleMesh, sharp: &SharpEdges) -> Vec<(VertexId, ChainEnd)> {
    let mut at_corner: Vec<(VertexId, ChainEnd)> = Vec::new();
    for (k, chain) in sharp.chains.iter().enumerate() {
        if chain.closed || chain.creases.is_empty() {
            continue;
        }
        let n = chain.vertices.len();
        for (at_start, v, next, crease) in [
            (true, chain.vertices[0], chain.vertices[1], chain.creases[0]),
            (
                false,
                chain.vertices[n - 1],
                chain.vertices[n - 2],
                chain.creases[n - 2],
            ),
        ] {
            if sharp.corners.binary_search(&v).is_err() {
                continue;
            }
            let c = &sharp.creases[crease as usize];
            let direction =
                (mesh.positions[next.index()] - mesh.positions[v.index()]).normalize_or_zero();
            let bisector = (c.normals[0] + c.normals[1]).normalize_or_zero();
            let end = ChainEnd {
                chain: k,
                at_start,
                direction,
                bisector,
            };
            at_corner.push((v, end));
        }
    }
    at_corner.sort_by_key(|(v, e)| (*v, e.chain, !e.at_start));
    at_corner
}

/// Every pair `(straightness, i, j)` of ends of different chains at one
/// corner of `at_corner` that continue each other within `cos_turn` (in
/// direction and in crease bisector), straightest first.
fn straightest_pairs(
    at_corner: &[(VertexId, ChainEnd)],
    cos_turn: f32,
) -> Vec<(f32, usize, usize)> {
    let mut pairs: Vec<(f32, usize, usize)> = Vec::new();
    let mut lo = 0;
    while lo < at_corner.len() {
        let v = at_corner[lo].0;
        let hi = lo + at_corner[lo..].partition_point(|(w, _)| *w == v);
        for i in lo..hi {
            for j in i + 1..hi {
                let (a, b) = (&at_corner[i].1, &at_corner[j].1);
                let straight = -a.direction.dot(b.direction);
                if a.chain != b.chain
                    && straight >= cos_turn
                    && a.bisector.dot(b.bisector) >= cos_turn
                {
                    pairs.push((straight, i, j));
                }
            }
        }
        lo = hi;
    }
    pairs.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    pairs
}
