//! A rectangular node lattice in a given frame, cast against the source and turned into a
//! patch: the step edge patches and corner patches share.
//!
//! Input: a [`NodeLattice`] (orthonormal basis, origin of node (0, 0) in the plane, node
//! spacings, node counts, the height interval to search) and the faces the rays may hit.
//! Output: one [`Patch`], or `None` when no cell has four filled corners.
//!
//! Steps, as the fitter does them (`spatch-fit`):
//! 1. every node casts a ray along −z from above the searched interval; the first hit on an
//!    allowed face that faces the patch (normal · z above [`MIN_FACING`]) gives the node its
//!    height, face and barycentric coordinates; a node with no such hit is empty;
//! 2. the heights get one quantizer ([`spatch_fit::choose_quantizer`]: 8-bit codes over the
//!    patch's height range, 16-bit only beyond the error budget);
//! 3. the lattice is cropped to its filled nodes, codes are rebased to the smallest, colours
//!    are sampled at the hits ([`spatch_fit::sample_colour`]).
//!
//! The rays are answered by projecting the allowed faces onto the lattice (`lattice_raster`),
//! not by a tree walk per node: the allowed faces are the few near the strip, and long sliver
//! triangles (CAD tessellations) make each walk through the whole mesh's BVH visit many boxes.
//!
//! Invariant: a node's reconstructed point lies on the ray through it, within half a
//! displacement step of the source surface.
//!
//! Cost: O(allowed faces + nodes); memory O(nodes).

use glam::Vec3;
use spatch_fit::{choose_quantizer, quantize_height, sample_colour};
use spatch_format::{Frame, GridSize, Patch, EMPTY};
use spatch_mesh::{FaceId, TriangleMesh};

use crate::lattice_raster::{raster_hits, NodeHit};
use crate::EdgeError;

/// Faces whose normal · z is at most this are edge-on or facing away and never hit.
pub(crate) const MIN_FACING: f32 = 0.02;

/// A lattice of nodes in a frame, with the interval its rays search.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeLattice {
    /// Unit x axis.
    pub(crate) x: Vec3,
    /// Unit y axis.
    pub(crate) y: Vec3,
    /// Unit z axis (`x × y`): the direction the patch is seen from.
    pub(crate) z: Vec3,
    /// Coordinates of node (0, 0) along x and y (mesh coordinates projected).
    pub(crate) start: [f32; 2],
    /// Node spacing along x and y.
    pub(crate) spacing: [f32; 2],
    /// Nodes along x and y (each 2..=257).
    pub(crate) cols: usize,
    /// Nodes along y.
    pub(crate) rows: usize,
    /// The heights (along z) to search: rays start at `heights[1]` and stop at `heights[0]`.
    pub(crate) heights: [f32; 2],
}

/// What casting needs besides the lattice.
pub(crate) struct CastJob<'a> {
    pub(crate) mesh: &'a TriangleMesh,
    /// Edge node spacing (for the quantizer's budget).
    pub(crate) spacing: f32,
    /// Half-step budget as a fraction of `spacing`.
    pub(crate) max_step_error: f32,
    pub(crate) with_colour: bool,
}

/// Casts `lattice` against the faces in `allowed` (sorted) and builds its patch (see the
/// module docs). `index` names the patch in errors.
pub(crate) fn cast_lattice(
    job: &CastJob<'_>,
    lattice: &NodeLattice,
    allowed: &[FaceId],
    index: usize,
) -> Result<Option<Patch>, EdgeError> {
    cast_lattice_within(job, lattice, allowed, None, index)
}

/// [`cast_lattice`] casting only the nodes whose flag in `within` (row-major, one a node) is
/// set; the others stay empty.
pub(crate) fn cast_lattice_within(
    job: &CastJob<'_>,
    lattice: &NodeLattice,
    allowed: &[FaceId],
    within: Option<&[bool]>,
    index: usize,
) -> Result<Option<Patch>, EdgeError> {
    let hits = raster_hits(job.mesh, lattice, allowed, within);
    let Some((h_min, h_max)) = height_range(&hits) else {
        return Ok(None);
    };
    let quantizer = choose_quantizer(h_max - h_min, job.spacing, job.max_step_error * job.spacing)
        .map_err(|source| EdgeError::Quantize {
            patch: index,
            source,
        })?;
    let codes: Vec<u16> = hits
        .iter()
        .map(|h| match h {
            Some(h) => quantize_height(&quantizer, h_min, h.height),
            None => EMPTY,
        })
        .collect();
    let Some(crop) = Crop::of_filled(&codes, lattice) else {
        return Ok(None);
    };
    let nodes = crop.nodes(job, &hits, &codes);
    let build = |source| EdgeError::PatchBuild {
        patch: index,
        source,
    };
    let height = f64::from(h_min) + f64::from(nodes.base) * f64::from(quantizer.step());
    let origin = lattice.x * (lattice.start[0] + crop.i0 as f32 * lattice.spacing[0])
        + lattice.y * (lattice.start[1] + crop.j0 as f32 * lattice.spacing[1])
        + lattice.z * height as f32;
    let frame = Frame::new(
        origin,
        lattice.x * lattice.spacing[0],
        lattice.y * lattice.spacing[1],
        lattice.z * quantizer.step(),
    )
    .map_err(build)?;
    let grid = GridSize::new(crop.cols() as u32, crop.rows() as u32).map_err(build)?;
    Patch::new(frame, grid, nodes.displacements, nodes.colours)
        .map(Some)
        .map_err(build)
}

/// The lowest and highest height of the nodes that hit, or `None` when none did.
fn height_range(hits: &[Option<NodeHit>]) -> Option<(f32, f32)> {
    let (mut h_min, mut h_max) = (f32::INFINITY, f32::NEG_INFINITY);
    for h in hits.iter().flatten() {
        h_min = h_min.min(h.height);
        h_max = h_max.max(h.height);
    }
    (h_min <= h_max).then_some((h_min, h_max))
}

/// The nodes of a lattice kept in its patch: columns `i0..=i1`, rows `j0..=j1`.
struct Crop {
    /// Nodes along x of the whole lattice (the stride of its rows).
    stride: usize,
    i0: usize,
    i1: usize,
    j0: usize,
    j1: usize,
}

/// A cropped patch's node data: displacements rebased to `base`, and colours when asked.
struct CroppedNodes {
    /// The smallest filled code, subtracted from every filled one.
    base: u16,
    displacements: Vec<u16>,
    colours: Option<Vec<[u8; 4]>>,
}

impl Crop {
    /// The box of the filled nodes of `codes` (row-major over `lattice`), or `None` when it
    /// is not at least one cell wide and high or no cell in it has four filled corners.
    fn of_filled(codes: &[u16], lattice: &NodeLattice) -> Option<Self> {
        let at = |i: usize, j: usize| j * lattice.cols + i;
        let (mut i0, mut i1, mut j0, mut j1) = (usize::MAX, 0, usize::MAX, 0);
        for j in 0..lattice.rows {
            for i in 0..lattice.cols {
                if codes[at(i, j)] != EMPTY {
                    i0 = i0.min(i);
                    i1 = i1.max(i);
                    j0 = j0.min(j);
                    j1 = j1.max(j);
                }
            }
        }
        if i1 <= i0 || j1 <= j0 {
            return None;
        }
        let drawable = (j0..j1).any(|j| {
            (i0..i1).any(|i| {
                [at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]
                    .iter()
                    .all(|&k| codes[k] != EMPTY)
            })
        });
        drawable.then_some(Self {
            stride: lattice.cols,
            i0,
            i1,
            j0,
            j1,
        })
    }

    /// Kept nodes along x.
    fn cols(&self) -> usize {
        self.i1 - self.i0 + 1
    }

    /// Kept nodes along y.
    fn rows(&self) -> usize {
        self.j1 - self.j0 + 1
    }

    /// Index of node `(i, j)` in the whole lattice.
    fn at(&self, i: usize, j: usize) -> usize {
        j * self.stride + i
    }

    /// The kept nodes' displacements (rebased to the smallest filled code) and, with
    /// `job.with_colour`, their colours sampled at the hits.
    fn nodes(&self, job: &CastJob<'_>, hits: &[Option<NodeHit>], codes: &[u16]) -> CroppedNodes {
        let (i0, i1, j0, j1) = (self.i0, self.i1, self.j0, self.j1);
        let base = (j0..=j1)
            .flat_map(|j| (i0..=i1).map(move |i| (i, j)))
            .map(|(i, j)| codes[self.at(i, j)])
            .filter(|&c| c != EMPTY)
            .min()
            .unwrap_or(0);
        let (cols, rows) = (self.cols(), self.rows());
        let mut displacements = Vec::with_capacity(cols * rows);
        let mut colours = job.with_colour.then(|| Vec::with_capacity(cols * rows));
        for j in j0..=j1 {
            for i in i0..=i1 {
                let k = self.at(i, j);
                let c = codes[k];
                displacements.push(if c == EMPTY { EMPTY } else { c - base });
                if let Some(colours) = colours.as_mut() {
                    colours.push(match &hits[k] {
                        Some(h) if c != EMPTY => sample_colour(job.mesh, h.face, h.bary.to_array()),
                        _ => [0; 4],
                    });
                }
            }
        }
        CroppedNodes {
            base,
            displacements,
            colours,
        }
    }
}

/// The faces reachable from `seeds` across shared edges whose bounding box meets the box
/// `[lo, hi]`, sorted by id. Seeds are always included.
pub(crate) fn faces_near(
    mesh: &TriangleMesh,
    adjacency: &spatch_mesh::FaceAdjacency,
    seeds: &[FaceId],
    lo: Vec3,
    hi: Vec3,
) -> Vec<FaceId> {
    let mut found: Vec<FaceId> = seeds.to_vec();
    found.sort_unstable();
    found.dedup();
    let mut stack = found.clone();
    while let Some(f) = stack.pop() {
        for &n in adjacency.neighbours(f) {
            if found.binary_search(&n).is_ok() {
                continue;
            }
            let [a, b, c] = mesh.face_positions(n);
            let (flo, fhi) = (a.min(b).min(c), a.max(b).max(c));
            if flo.cmple(hi).all() && fhi.cmpge(lo).all() {
                let at = found.partition_point(|&x| x < n);
                found.insert(at, n);
                stack.push(n);
            }
        }
    }
    found
}
