//! The generator's driver: detect, cut, cast, in a deterministic order.
//!
//! 1. sharp edges and their chains (`sharp_edges`);
//! 2. with [`EdgeOptions::only_gaps`], the creases the surface patches already cover
//!    (`coverage`; soft creases, under [`EdgeOptions::soft_crease_deg`], within a looser
//!    tolerance);
//! 3. the chains joined through corners where they run on straight (`chain_runs`) and cut
//!    into pieces around the covered creases, one lattice per piece (`edge_patch`);
//! 4. every piece's lattice cast against the source and quantized into a patch
//!    (`lattice_cast`);
//! 5. with [`EdgeOptions::only_gaps`] and [`EdgeOptions::join_pieces`], pieces that meet at
//!    a crease vertex joined into one patch wherever it covers them all (`joined_pieces`);
//! 6. with [`EdgeOptions::only_gaps`] and [`EdgeOptions::drop_covered_pieces`], the pieces
//!    that the surface patches and the other edge patches already cover dropped
//!    (`covered_pieces`);
//! 7. when [`EdgeOptions::corners`] is on, one lattice per corner that an uncovered crease
//!    reaches and (with `only_gaps`) that the surface and edge patches leave open
//!    (`corner_patch`), cast the same way.
//!
//! Casting runs in parallel and is collected in order (pieces by chain, then corners by
//! vertex id), so the output never depends on the thread count.
//!
//! Cost: O(E) for detection, O(creases × probes) for coverage, O(faces near each strip +
//! its nodes) for the casts; memory O(creases + the largest lattice).

use rayon::prelude::*;
use serde::Serialize;
use spatch_format::Patch;
use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh, VertexId};

use crate::chain_runs::chain_runs;
use crate::corner_patch::corner_lattice;
use crate::coverage::{covered_corner, covered_creases, SurfaceCoverage};
use crate::covered_pieces::covered_pieces;
use crate::edge_patch::{cut_pieces, piece_lattice, EdgePiece, PieceLimits, WIDE_TURN};
use crate::joined_pieces::{join_pieces, JoinJob};
use crate::lattice_cast::{cast_lattice, CastJob, NodeLattice};
use crate::part::{drop_unowned_corners, skip_unowned, OwnsPoint};
use crate::sharp_edges::{detect_sharp_edges, SharpEdges};
use crate::{EdgeError, EdgeOptions};

/// Counts gathered while generating edge patches.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct EdgeStats {
    /// Sharp edges found.
    pub creases: usize,
    /// Polylines they form.
    pub chains: usize,
    /// Of which closed loops.
    pub closed_chains: usize,
    /// Vertices where three or more creases meet.
    pub corners: usize,
    /// Vertices where a single crease ends.
    pub ends: usize,
    /// Creases whose faces fold onto each other; no patch covers them.
    pub knife_edges: usize,
    /// Creases the surface patches already cover, left without an edge patch.
    pub covered_creases: usize,
    /// Edges with three or more faces, not tested.
    pub non_manifold_edges: usize,
    /// Pieces the chains were cut into.
    pub pieces: usize,
    /// Pieces joined into another piece's patch ([`EdgeOptions::join_pieces`]).
    pub joined_pieces: usize,
    /// Of their patches, those dropped because the surface patches and the other edge
    /// patches already cover their piece ([`EdgeOptions::drop_covered_pieces`]).
    pub covered_pieces: usize,
    /// Patches along edges (pieces whose rays hit something).
    pub edge_patches: usize,
    /// Patches at corners.
    pub corner_patches: usize,
    /// Grid nodes of all edge and corner patches, filled or not.
    pub nodes: usize,
    /// Filled nodes of those patches.
    pub filled_nodes: usize,
    /// Node spacing of the edge patches along the edge (model units).
    pub spacing: f32,
}

/// Finds the sharp edges of `mesh` and covers them with edge patches (see the crate docs).
///
/// `adjacency` must be the face adjacency of `mesh`; `surface` are the surface patches (in
/// `mesh`'s coordinates), whose gaps the edge patches close; `surface_spacing` is their node
/// spacing, from which the edge spacing and strip width follow. The patches use
/// `mesh`'s coordinates (relative to `mesh.origin`), as the fitter's do, and carry colours
/// exactly when the mesh has colour and [`EdgeOptions::colour`] is on.
pub fn generate_edge_patches(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    surface: &[Patch],
    surface_spacing: f32,
    options: &EdgeOptions,
) -> Result<(Vec<Patch>, EdgeStats), EdgeError> {
    generate_part_edge_patches(mesh, adjacency, surface, surface_spacing, options, &|_| {
        true
    })
}

/// [`generate_edge_patches`] for one part of a tiled mesh: only the creases whose world
/// midpoint and the corners whose world position `owns` answers `true` for get patches
/// (`part.rs`: when the parts' answers partition space, each crease and corner is made by
/// exactly one part). The other creases end the pieces as covered ones do; the stats count
/// what was found in all of `mesh`.
pub fn generate_part_edge_patches(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    surface: &[Patch],
    surface_spacing: f32,
    options: &EdgeOptions,
    owns: OwnsPoint<'_>,
) -> Result<(Vec<Patch>, EdgeStats), EdgeError> {
    check_inputs(mesh, adjacency, surface_spacing, options)?;
    let sharp = detect_sharp_edges(mesh, adjacency, options.crease_angle_deg);
    let edge_spacing = surface_spacing / options.resolution;
    let mut stats = found_stats(&sharp, edge_spacing);
    if sharp.creases.is_empty() {
        return Ok((Vec::new(), stats));
    }
    let covered = if options.only_gaps {
        let coverage = SurfaceCoverage::new(surface, surface_spacing);
        let soft = options.soft_crease_deg;
        covered_creases(mesh, &sharp, &coverage, surface_spacing, soft)
    } else {
        vec![false; sharp.creases.len()]
    };
    stats.covered_creases = covered.iter().filter(|&&c| c).count();
    let job = CastJob {
        mesh,
        spacing: edge_spacing,
        max_step_error: options.max_step_error,
        with_colour: options.colour && mesh.has_colour(),
    };
    let found = Found {
        adjacency,
        sharp: &sharp,
        covered: &covered,
        surface,
        surface_spacing,
        strip: options.strip_width * surface_spacing,
        owns,
    };
    let (mut patches, lattice_count) = crease_patches(&job, &found, options, &mut stats)?;
    if options.corners && !sharp.corners.is_empty() {
        let corner_patches = corner_patches(&job, &found, options, &patches, lattice_count)?;
        stats.corner_patches = corner_patches.len();
        patches.extend(corner_patches);
    }
    for patch in &patches {
        stats.nodes += patch.grid().node_count();
        stats.filled_nodes += patch.filled_count();
    }
    Ok((patches, stats))
}

/// Refuses options, a spacing or an adjacency the generator cannot use.
fn check_inputs(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    surface_spacing: f32,
    options: &EdgeOptions,
) -> Result<(), EdgeError> {
    options.validate()?;
    if !(surface_spacing.is_finite() && surface_spacing > 0.0) {
        return Err(EdgeError::InvalidSpacing {
            spacing: surface_spacing,
        });
    }
    if adjacency.face_count() != mesh.face_count() {
        return Err(EdgeError::AdjacencyMismatch {
            adjacency_faces: adjacency.face_count(),
            mesh_faces: mesh.face_count(),
        });
    }
    Ok(())
}

/// The counts of what `sharp` found, the patches' spacing beside them.
fn found_stats(sharp: &SharpEdges, edge_spacing: f32) -> EdgeStats {
    EdgeStats {
        creases: sharp.creases.len(),
        chains: sharp.chains.len(),
        closed_chains: sharp.chains.iter().filter(|c| c.closed).count(),
        corners: sharp.corners.len(),
        ends: sharp.ends.len(),
        knife_edges: sharp.knife_count(),
        non_manifold_edges: sharp.non_manifold_edges,
        spacing: edge_spacing,
        ..EdgeStats::default()
    }
}

/// What the generator found on the mesh and is told about the surface:
/// the sharp edges, which creases the surface patches cover, and which
/// points this part owns.
struct Found<'a> {
    adjacency: &'a FaceAdjacency,
    sharp: &'a SharpEdges,
    covered: &'a [bool],
    surface: &'a [Patch],
    surface_spacing: f32,
    /// The width of the patches' strips across the edge (model units).
    strip: f32,
    owns: OwnsPoint<'a>,
}

/// The patches along the creases: the chains cut into pieces, each piece's
/// lattice cast, pieces joined and those already covered dropped (as
/// `options` asks). Gives the number of lattices cast (the corners'
/// indices follow them).
fn crease_patches(
    job: &CastJob<'_>,
    found: &Found<'_>,
    options: &EdgeOptions,
    stats: &mut EdgeStats,
) -> Result<(Vec<Patch>, usize), EdgeError> {
    let (mesh, sharp) = (job.mesh, found.sharp);
    let limits = piece_limits(options, job.spacing, found.strip);
    let runs = chain_runs(mesh, sharp, limits.cos_turn);
    let skip = skip_unowned(mesh, sharp, found.covered, found.owns);
    let (pieces, _) = cut_pieces(mesh, sharp, &runs, &skip, &limits);
    stats.pieces = pieces.len();
    let (made, lattice_count) = cast_pieces(job, found, &pieces)?;
    let made = if options.only_gaps && options.join_pieces {
        let join = JoinJob {
            cast: job,
            adjacency: found.adjacency,
            sharp,
            surface: found.surface,
            spacing: found.surface_spacing,
            edge_spacing: job.spacing,
            strip: found.strip,
            soft_crease_deg: options.soft_crease_deg,
        };
        let (groups, joined) = join_pieces(&join, made)?;
        stats.joined_pieces = joined;
        groups
    } else {
        made.into_iter()
            .map(|(piece, patch)| (piece.clone(), patch))
            .collect()
    };
    let patches = uncovered_patches(mesh, found, options, made, stats);
    stats.edge_patches = patches.len();
    Ok((patches, lattice_count))
}

/// How far a piece may grow, from the options, the edge spacing and the strip width.
fn piece_limits(options: &EdgeOptions, edge_spacing: f32, strip: f32) -> PieceLimits {
    // A piece plus its overlap at both ends (`edge_patch`) must fit `max_cols` nodes.
    let overlap = edge_spacing + 0.5 * strip;
    let max_len = ((options.max_cols - 1) as f32 * edge_spacing - 2.0 * overlap).max(edge_spacing);
    PieceLimits {
        max_len,
        cos_turn: options.max_turn_deg.to_radians().cos(),
        cos_wide_turn: (options.max_turn_deg * WIDE_TURN)
            .min(90.0)
            .to_radians()
            .cos(),
        max_stray: options.max_stray * edge_spacing,
    }
}

/// A piece whose lattice's rays hit something, with its patch.
type CastPiece<'p> = (&'p EdgePiece, Patch);

/// Every piece's lattice cast: the pieces whose rays hit something with their patches (in
/// order), and the number of lattices cast.
fn cast_pieces<'p>(
    job: &CastJob<'_>,
    found: &Found<'_>,
    pieces: &'p [EdgePiece],
) -> Result<(Vec<CastPiece<'p>>, usize), EdgeError> {
    let (lattices, of_piece): (Vec<(NodeLattice, Vec<FaceId>)>, Vec<&EdgePiece>) = pieces
        .par_iter()
        .filter_map(|piece| {
            piece_lattice(
                job.mesh,
                found.adjacency,
                found.sharp,
                piece,
                job.spacing,
                found.strip,
            )
            .map(|lattice| (lattice, piece))
        })
        .unzip();
    let made = of_piece
        .into_iter()
        .zip(cast_each(job, &lattices, 0)?)
        .filter_map(|(piece, patch)| patch.map(|patch| (piece, patch)))
        .collect();
    Ok((made, lattices.len()))
}

/// The patches of `made` left once those whose piece the surface patches and the other
/// edge patches already cover are dropped (with `only_gaps` and `drop_covered_pieces`);
/// counts the dropped ones in `stats`.
fn uncovered_patches(
    mesh: &TriangleMesh,
    found: &Found<'_>,
    options: &EdgeOptions,
    made: Vec<(EdgePiece, Patch)>,
    stats: &mut EdgeStats,
) -> Vec<Patch> {
    let dropped = if options.only_gaps && options.drop_covered_pieces {
        let soft = options.soft_crease_deg;
        covered_pieces(
            mesh,
            found.sharp,
            found.surface,
            &made,
            found.surface_spacing,
            soft,
        )
    } else {
        vec![false; made.len()]
    };
    stats.covered_pieces = dropped.iter().filter(|&&d| d).count();
    made.into_iter()
        .zip(dropped)
        .filter(|(_, dropped)| !dropped)
        .map(|((_, patch), _)| patch)
        .collect()
}

/// The patches at the corners this part owns that the surface and the
/// crease patches (`edge_patches`) leave open; `first` is the index of
/// their first lattice (for error messages).
fn corner_patches(
    job: &CastJob<'_>,
    found: &Found<'_>,
    options: &EdgeOptions,
    edge_patches: &[Patch],
    first: usize,
) -> Result<Vec<Patch>, EdgeError> {
    let (mesh, sharp, spacing) = (job.mesh, found.sharp, found.surface_spacing);
    let around = faces_around(mesh, sharp);
    let mut open = corners_with_gaps(sharp, found.covered);
    drop_unowned_corners(mesh, sharp, &mut open, found.owns);
    if options.only_gaps {
        // The surface and edge patches often close a corner between them already.
        let seen = SurfaceCoverage::new(found.surface.iter().chain(edge_patches), spacing);
        open.par_iter_mut()
            .zip(sharp.corners.par_iter().zip(around.par_iter()))
            .filter(|(open, _)| **open)
            .for_each(|(open, (&v, faces))| {
                *open = !covered_corner(mesh, v, faces, &seen, spacing);
            });
    }
    let corners: Vec<(NodeLattice, Vec<FaceId>)> = sharp
        .corners
        .par_iter()
        .zip(around.par_iter())
        .zip(open.par_iter())
        .filter(|(_, &open)| open)
        .filter_map(|((&v, faces), _)| {
            corner_lattice(mesh, found.adjacency, v, faces, job.spacing, found.strip)
        })
        .collect();
    cast_all(job, &corners, first)
}

/// Casts `lattices` in parallel and keeps, in order, those whose rays hit something; `first`
/// is the index of the first lattice (for error messages).
fn cast_all(
    job: &CastJob<'_>,
    lattices: &[(NodeLattice, Vec<FaceId>)],
    first: usize,
) -> Result<Vec<Patch>, EdgeError> {
    Ok(cast_each(job, lattices, first)?
        .into_iter()
        .flatten()
        .collect())
}

/// Casts `lattices` in parallel: per lattice, in order, its patch, or `None` when its rays
/// hit nothing; `first` is the index of the first lattice (for error messages).
fn cast_each(
    job: &CastJob<'_>,
    lattices: &[(NodeLattice, Vec<FaceId>)],
    first: usize,
) -> Result<Vec<Option<Patch>>, EdgeError> {
    lattices
        .par_iter()
        .enumerate()
        .map(|(k, (lattice, faces))| cast_lattice(job, lattice, faces, first + k))
        .collect()
}

/// For each corner of `sharp` (in order), whether a crease ending there is not covered.
fn corners_with_gaps(sharp: &SharpEdges, covered: &[bool]) -> Vec<bool> {
    let mut open = vec![false; sharp.corners.len()];
    for (crease, _) in sharp.creases.iter().zip(covered).filter(|(_, &c)| !c) {
        for v in [crease.v0, crease.v1] {
            if let Ok(k) = sharp.corners.binary_search(&v) {
                open[k] = true;
            }
        }
    }
    open
}

/// For each corner of `sharp` (in order), the faces that contain it, by id.
fn faces_around(mesh: &TriangleMesh, sharp: &SharpEdges) -> Vec<Vec<FaceId>> {
    let mut around = vec![Vec::new(); sharp.corners.len()];
    for face in mesh.faces() {
        for v in mesh.triangles[face.index()] {
            if let Ok(k) = sharp.corners.binary_search(&VertexId(v)) {
                around[k].push(face);
            }
        }
    }
    around
}
