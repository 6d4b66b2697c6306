//! The generator's driver: detect, cut, cast, in a deterministic order.
//!
//! 1. sharp edges and their chains (`sharp_edges`);
//! 2. chains cut into pieces, one lattice per piece (`edge_patch`);
//! 3. one lattice per corner when [`EdgeOptions::corners`] is on (`corner_patch`);
//! 4. every lattice cast against the source and quantized into a patch (`lattice_cast`), in
//!    parallel, collected in order (pieces by chain, then corners by vertex id), so the
//!    output never depends on the thread count.
//!
//! Cost: O(E) for detection plus O(F log F) for the BVH plus O(edge nodes × log F) for the
//! casts; memory O(F) for the BVH.

use rayon::prelude::*;
use serde::Serialize;
use spatch_format::Patch;
use spatch_mesh::{Bvh, FaceAdjacency, FaceId, TriangleMesh, VertexId};

use crate::corner_patch::corner_lattice;
use crate::edge_patch::{cut_pieces, piece_lattice};
use crate::lattice_cast::{cast_lattice, CastJob, NodeLattice};
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
    /// Edges with three or more faces, not tested.
    pub non_manifold_edges: usize,
    /// Pieces the chains were cut into.
    pub pieces: usize,
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
/// `adjacency` must be the face adjacency of `mesh`; `surface_spacing` is the node spacing of
/// the surface patches, from which the edge spacing and strip width follow. The patches use
/// `mesh`'s coordinates (relative to `mesh.origin`), as the fitter's do, and carry colours
/// exactly when the mesh has colour and [`EdgeOptions::colour`] is on.
pub fn generate_edge_patches(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    surface_spacing: f32,
    options: &EdgeOptions,
) -> Result<(Vec<Patch>, EdgeStats), EdgeError> {
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
    let sharp = detect_sharp_edges(mesh, adjacency, options.crease_angle_deg);
    let edge_spacing = surface_spacing / options.resolution;
    let strip = options.strip_width * surface_spacing;
    let mut stats = EdgeStats {
        creases: sharp.creases.len(),
        chains: sharp.chains.len(),
        closed_chains: sharp.chains.iter().filter(|c| c.closed).count(),
        corners: sharp.corners.len(),
        ends: sharp.ends.len(),
        knife_edges: sharp.knife_count(),
        non_manifold_edges: sharp.non_manifold_edges,
        spacing: edge_spacing,
        ..EdgeStats::default()
    };
    if sharp.creases.is_empty() {
        return Ok((Vec::new(), stats));
    }

    // A piece plus its overlap at both ends (`edge_patch`) must fit `max_cols` nodes.
    let overlap = edge_spacing + 0.5 * strip;
    let max_len = ((options.max_cols - 1) as f32 * edge_spacing - 2.0 * overlap).max(edge_spacing);
    let (pieces, _) = cut_pieces(mesh, &sharp, max_len, options.max_turn_deg);
    stats.pieces = pieces.len();
    let mut lattices: Vec<(NodeLattice, Vec<FaceId>)> = pieces
        .par_iter()
        .filter_map(|piece| piece_lattice(mesh, adjacency, &sharp, piece, edge_spacing, strip))
        .collect();
    let edge_lattices = lattices.len();
    if options.corners && !sharp.corners.is_empty() {
        let around = faces_around(mesh, &sharp);
        let corners: Vec<(NodeLattice, Vec<FaceId>)> = sharp
            .corners
            .par_iter()
            .zip(around.par_iter())
            .filter_map(|(&v, faces)| {
                corner_lattice(mesh, adjacency, v, faces, edge_spacing, strip)
            })
            .collect();
        lattices.extend(corners);
    }

    let bvh = Bvh::new(mesh);
    let job = CastJob {
        mesh,
        bvh: &bvh,
        spacing: edge_spacing,
        max_step_error: options.max_step_error,
        with_colour: options.colour && mesh.has_colour(),
    };
    let cast: Vec<Option<Patch>> = lattices
        .par_iter()
        .enumerate()
        .map(|(index, (lattice, faces))| cast_lattice(&job, lattice, faces, index))
        .collect::<Result<_, _>>()?;
    let mut patches = Vec::with_capacity(cast.len());
    for (index, patch) in cast.into_iter().enumerate() {
        let Some(patch) = patch else { continue };
        if index < edge_lattices {
            stats.edge_patches += 1;
        } else {
            stats.corner_patches += 1;
        }
        stats.nodes += patch.grid().node_count();
        stats.filled_nodes += patch.filled_count();
        patches.push(patch);
    }
    Ok((patches, stats))
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
