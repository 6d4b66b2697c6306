//! Extraction of one welded mesh (or point set) per patch, the common input
//! of every writer.
//!
//! Input: a [`Scene`] and what to export. Output: one [`PatchMesh`] per
//! patch that has something to export, in scene order. Each node becomes
//! at most one vertex, shared by every cell that uses it (the mesh is
//! welded within its patch); vertices are placed relative to the patch's
//! own model-space origin, kept in f64, so precision does not depend on how
//! far the patch is from the model origin or from the scene offset.
//!
//! Cells become two triangles each, split along the `(i, j)`–`(i+1, j+1)`
//! diagonal and wound counter-clockwise seen from the frame's +z side (the
//! outward side). In cell meshes only nodes used by a drawable cell are
//! kept; in point sets every filled node is.
//!
//! Cost: one pass over the nodes and one over the cells of each patch;
//! memory: the output (36 bytes per vertex and 12 per triangle, plus 4 per
//! vertex for colours).

use glam::{DVec3, Vec3};
use spatch_format::{Patch, Scene};

/// What is exported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Content {
    /// Every filled node as a point (with its normal and colour).
    #[default]
    Nodes,
    /// The drawable cells as triangles, one welded mesh per patch.
    Cells,
}

/// One patch's vertices (and triangles for [`Content::Cells`]).
///
/// # Guarantees
/// `normals` (and `colours` when present) have one entry per position;
/// every triangle index is below `positions.len()`; normals are unit length.
#[derive(Debug, Clone, PartialEq)]
pub struct PatchMesh {
    /// Index of the patch in the scene.
    pub patch: usize,
    /// Model-space position of the patch origin (scene offset included), f64.
    pub origin: DVec3,
    /// Vertex positions relative to [`Self::origin`].
    pub positions: Vec<Vec3>,
    /// Unit vertex normals ([`Patch::node_normal`]).
    pub normals: Vec<Vec3>,
    /// sRGB colours with straight alpha, when the scene has colour.
    pub colours: Option<Vec<[u8; 4]>>,
    /// Counter-clockwise triangles (empty for points).
    pub triangles: Vec<[u32; 3]>,
}

impl PatchMesh {
    /// Model-space position of vertex `k` in f64.
    pub fn world_position(&self, k: usize) -> DVec3 {
        self.origin + self.positions[k].as_dvec3()
    }
}

/// The meshes (or point sets) of every patch of `scene` with at least one
/// vertex to export.
pub fn extract_patch_meshes(scene: &Scene, content: Content) -> Vec<PatchMesh> {
    scene
        .patches()
        .iter()
        .enumerate()
        .filter_map(|(k, patch)| {
            let origin = scene.offset() + patch.frame().precise_origin();
            let mesh = match content {
                Content::Nodes => extract_points(patch, k, origin),
                Content::Cells => extract_cells(patch, k, origin),
            };
            (!mesh.positions.is_empty()).then_some(mesh)
        })
        .collect()
}

/// An empty mesh of patch `k`, with colours when the patch has them.
fn empty_mesh(patch: &Patch, k: usize, origin: DVec3) -> PatchMesh {
    PatchMesh {
        patch: k,
        origin,
        positions: Vec::new(),
        normals: Vec::new(),
        colours: patch.colours().map(|_| Vec::new()),
        triangles: Vec::new(),
    }
}

/// Appends node `(i, j)` as a vertex (the node must be filled).
fn push_vertex(mesh: &mut PatchMesh, patch: &Patch, i: usize, j: usize) {
    let (Some(local), Some(normal)) = (patch.node_local(i, j), patch.node_normal(i, j)) else {
        return;
    };
    mesh.positions.push(local);
    mesh.normals.push(normal);
    if let (Some(out), Some(colours)) = (mesh.colours.as_mut(), patch.colours()) {
        out.push(colours[patch.grid().index(i, j)]);
    }
}

fn extract_points(patch: &Patch, k: usize, origin: DVec3) -> PatchMesh {
    let mut mesh = empty_mesh(patch, k, origin);
    for (i, j, _) in patch.filled_nodes() {
        push_vertex(&mut mesh, patch, i, j);
    }
    mesh
}

fn extract_cells(patch: &Patch, k: usize, origin: DVec3) -> PatchMesh {
    let mut mesh = empty_mesh(patch, k, origin);
    let (cols, rows) = (
        usize::from(patch.grid().cols()),
        usize::from(patch.grid().rows()),
    );
    let mut index_of = vec![u32::MAX; cols * rows];
    for j in 0..rows - 1 {
        for i in 0..cols - 1 {
            if !patch.cell_is_drawable(i, j) {
                continue;
            }
            let mut corner = |a: usize, b: usize| {
                let slot = &mut index_of[b * cols + a];
                if *slot == u32::MAX {
                    *slot = mesh.positions.len() as u32;
                    push_vertex(&mut mesh, patch, a, b);
                }
                *slot
            };
            let (a, b, c, d) = (
                corner(i, j),
                corner(i + 1, j),
                corner(i + 1, j + 1),
                corner(i, j + 1),
            );
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use spatch_format::{ColourChannel, Frame, GridSize, EMPTY};

    fn scene(offset: DVec3, displacements: Vec<u16>) -> Scene {
        let frame = Frame::new(Vec3::new(1.0, 0.0, 0.0), Vec3::X, Vec3::Y, Vec3::Z * 0.1).unwrap();
        let patch = Patch::new(frame, GridSize::new(3, 3).unwrap(), displacements, None).unwrap();
        Scene::new(offset, ColourChannel::None, vec![patch]).unwrap()
    }

    #[test]
    fn cells_share_their_corner_vertices() {
        let s = scene(DVec3::ZERO, vec![0; 9]);
        let m = &extract_patch_meshes(&s, Content::Cells)[0];
        assert_eq!(m.positions.len(), 9);
        assert_eq!(m.triangles.len(), 8);
        assert_eq!(m.origin, DVec3::new(1.0, 0.0, 0.0));
        // Counter-clockwise from +z.
        for t in &m.triangles {
            let [a, b, c] = t.map(|v| m.positions[v as usize]);
            assert!((b - a).cross(c - a).z > 0.0);
        }
    }

    #[test]
    fn a_node_outside_every_cell_is_a_point_but_not_a_mesh_vertex() {
        // Only the cell (0, 0) is drawable; node (2, 2) is alone.
        let e = EMPTY;
        let s = scene(DVec3::new(1e7, 0.0, 0.0), vec![0, 0, e, 0, 0, e, e, e, 5]);
        let cells = &extract_patch_meshes(&s, Content::Cells)[0];
        assert_eq!((cells.positions.len(), cells.triangles.len()), (4, 2));
        let points = &extract_patch_meshes(&s, Content::Nodes)[0];
        assert_eq!(points.positions.len(), 5);
        assert!(points.triangles.is_empty());
        let last = points.world_position(4);
        assert!(
            (last - DVec3::new(1e7 + 3.0, 2.0, 0.5)).length() < 1e-6,
            "{last}"
        );
    }

    #[test]
    fn an_empty_patch_exports_nothing() {
        let s = scene(DVec3::ZERO, vec![EMPTY; 9]);
        assert!(extract_patch_meshes(&s, Content::Nodes).is_empty());
        assert!(extract_patch_meshes(&s, Content::Cells).is_empty());
    }
}
