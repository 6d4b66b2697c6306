//! Tiling a mesh by face: plans, one tile's faces, and the patches a tile owns.
//!
//! A face is counted by every tile its bounding box touches; a tile's conversion reads the
//! faces whose box touches its buffered box (its own box grown by the buffer), so the
//! surface near its border is fitted with the context a whole-mesh conversion would see.
//! Each face is **owned** by the one tile whose box holds its centroid ([`TileOwner`]):
//! a tile segments only the faces it owns and fits them with every face it read
//! (`spatch_convert::convert_part`), so every region, hence every surface patch, is made
//! by exactly one tile, and the patches reach across the border as they reach across
//! region borders inside one conversion. Likewise each crease is covered by the tile owning
//! its midpoint and each corner by the tile owning it, so every sharp-edge and corner patch
//! is made by exactly one tile.

use glam::DVec3;
use spatch_convert::PartOwner;
use spatch_format::Patch;
use spatch_mesh::TriangleMesh;

use crate::plan::WorldBox;

/// World bounds of face `f` of `mesh`.
fn face_box(mesh: &TriangleMesh, f: usize) -> (DVec3, DVec3) {
    let [a, b, c] = mesh.triangles[f].map(|v| mesh.origin + mesh.positions[v as usize].as_dvec3());
    (a.min(b).min(c), a.max(b).max(c))
}

/// Whether the closed boxes `(lo, hi)` and `(min, max)` overlap.
fn touches((lo, hi): (DVec3, DVec3), min: DVec3, max: DVec3) -> bool {
    lo.cmple(max).all() && hi.cmpge(min).all()
}

/// The faces of `mesh` whose box touches `area`, as a mesh of their own (the same origin;
/// UVs, colours, normals and materials kept).
pub fn mesh_tile(mesh: &TriangleMesh, area: &WorldBox) -> TriangleMesh {
    let (min, max) = (DVec3::from_array(area.min), DVec3::from_array(area.max));
    let faces: Vec<usize> = (0..mesh.triangles.len())
        .filter(|&f| touches(face_box(mesh, f), min, max))
        .collect();
    sub_mesh(mesh, &faces)
}

/// The faces `faces` of `mesh` as a mesh of their own.
fn sub_mesh(mesh: &TriangleMesh, faces: &[usize]) -> TriangleMesh {
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut kept: Vec<u32> = Vec::new();
    let triangles = faces
        .iter()
        .map(|&f| {
            mesh.triangles[f].map(|v| {
                let slot = &mut remap[v as usize];
                if *slot == u32::MAX {
                    *slot = kept.len() as u32;
                    kept.push(v);
                }
                *slot
            })
        })
        .collect();
    TriangleMesh {
        origin: mesh.origin,
        positions: pick(&mesh.positions, &kept),
        triangles,
        face_uvs: mesh
            .face_uvs
            .as_ref()
            .map(|uv| faces.iter().map(|&f| uv[f]).collect()),
        vertex_colours: mesh.vertex_colours.as_ref().map(|c| pick(c, &kept)),
        vertex_normals: mesh.vertex_normals.as_ref().map(|n| pick(n, &kept)),
        face_materials: if mesh.face_materials.is_empty() {
            Vec::new()
        } else {
            faces.iter().map(|&f| mesh.face_materials[f]).collect()
        },
        materials: mesh.materials.clone(),
    }
}

/// The values of the vertices `kept`, in that order.
fn pick<T: Copy>(values: &[T], kept: &[u32]) -> Vec<T> {
    kept.iter().map(|&v| values[v as usize]).collect()
}

/// The anchor of `patch` in a scene at `offset`: the world position of its filled node
/// nearest its grid's centre (ties: the first in node order), or `None` when it has no
/// filled node.
pub fn patch_anchor(patch: &Patch, offset: DVec3) -> Option<DVec3> {
    let (cols, rows) = (
        usize::from(patch.grid().cols()),
        usize::from(patch.grid().rows()),
    );
    let centre =
        |i: usize, j: usize| (2 * i).abs_diff(cols - 1).pow(2) + (2 * j).abs_diff(rows - 1).pow(2);
    let (i, j, _) = patch.filled_nodes().min_by_key(|&(i, j, _)| centre(i, j))?;
    patch.model_position(offset, i, j)
}

/// Whether `w` lies in `bounds`, `[min, max)` per axis.
pub fn owns(bounds: &WorldBox, w: DVec3) -> bool {
    (0..3).all(|k| w[k] >= bounds.min[k] && w[k] < bounds.max[k])
}

/// What one tile of a mesh plan owns: the faces whose world centroid, the creases whose
/// world midpoint and the corners whose world position lies in its box (`[min, max)` per
/// axis). The tiles' boxes partition space, so every face, crease and corner has exactly
/// one owner tile, and that tile reads it (a face's box holds its centroid; both faces of
/// a crease hold its midpoint; every face around a corner holds the corner).
#[derive(Debug, Clone, Copy)]
pub struct TileOwner<'a> {
    /// The tile's own box (the plan's `tiles[].bounds`).
    pub bounds: &'a WorldBox,
}

impl PartOwner for TileOwner<'_> {
    fn owns_point(&self, world: DVec3) -> bool {
        owns(self.bounds, world)
    }
}
