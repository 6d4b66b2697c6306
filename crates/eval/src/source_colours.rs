//! The source mesh as the triangle rasterizer draws it in colour: per-corner
//! colours from [`TriangleMesh::colour_at`] (material colour × texture ×
//! vertex colour), on triangles subdivided finely enough that the
//! rasterizer's interpolation between corners follows the texture.
//!
//! Input: a source mesh. Output: a `ColouredSource` (positions relative
//! to the mesh origin, triangles, one colour per corner) and how it was
//! drawn ([`SourceDrawing`]); a mesh without colour gives `None` and is
//! drawn grey as before.
//!
//! A textured triangle whose longest edge spans `L` texels (in the larger
//! texture dimension) is split into `n²` similar triangles, `n =
//! ceil(L / TEXELS_PER_EDGE)`, at most [`MAX_SPLIT`]; the split is lowered
//! for the whole mesh until the triangle count stays within
//! [`MAX_TRIANGLES`]. The new vertices lie on the flat triangle, so the
//! geometry is unchanged; each sub-triangle corner gets the colour at its
//! barycentric point. Untextured meshes (vertex or material colours) are
//! not split: interpolating corner colours is exact for them up to the
//! rasterizer's linear (not perspective) colour interpolation.
//!
//! Cost: O(output triangles) texture samples; memory 12 bytes per vertex and
//! 24 per triangle.

use glam::{Vec2, Vec3};
use serde::Serialize;
use spatch_mesh::{FaceId, TriangleMesh};

/// The texel span a subdivided edge may cover.
pub const TEXELS_PER_EDGE: f32 = 2.0;
/// The largest split `n` of one triangle (`n²` sub-triangles).
pub const MAX_SPLIT: u32 = 64;
/// The largest triangle count after subdivision.
pub const MAX_TRIANGLES: usize = 4_000_000;

/// What the source was drawn with in the image error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum SourceDrawing {
    /// No colour: the lighting's base colour (the mesh has none, or the
    /// scene has none so colour would only add error).
    Grey,
    /// Per-corner colours from vertex colours and material colours.
    Colours,
    /// Per-corner colours sampled from the texture (with vertex and material
    /// colours) on triangles subdivided to about 2 texels per edge.
    Texture,
}

/// A coloured copy of the source for the rasterizer.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ColouredSource {
    /// Positions relative to the mesh origin.
    pub(crate) positions: Vec<Vec3>,
    /// Counter-clockwise triangles.
    pub(crate) triangles: Vec<[u32; 3]>,
    /// One sRGB colour per triangle corner (`3 × triangles`).
    pub(crate) corner_colours: Vec<[u8; 4]>,
    /// Textured or not.
    pub(crate) drawing: SourceDrawing,
}

/// `mesh` with per-corner colours, or `None` when it has no colour.
pub(crate) fn colour_source(mesh: &TriangleMesh) -> Option<ColouredSource> {
    if !mesh.has_colour() {
        return None;
    }
    let splits = triangle_splits(mesh);
    let mut out = ColouredSource {
        positions: Vec::new(),
        triangles: Vec::new(),
        corner_colours: Vec::new(),
        drawing: if has_texture(mesh) {
            SourceDrawing::Texture
        } else {
            SourceDrawing::Colours
        },
    };
    for (face, &n) in mesh.faces().zip(&splits) {
        push_split_triangle(&mut out, mesh, face, n);
    }
    Some(out)
}

fn has_texture(mesh: &TriangleMesh) -> bool {
    mesh.face_uvs.is_some() && mesh.materials.iter().any(|m| m.texture.is_some())
}

/// Per face, the split `n` (1 = unsplit), lowered together until the total
/// stays within [`MAX_TRIANGLES`].
fn triangle_splits(mesh: &TriangleMesh) -> Vec<u32> {
    let wanted: Vec<u32> = mesh.faces().map(|f| wanted_split(mesh, f)).collect();
    let mut cap = MAX_SPLIT;
    loop {
        let total: usize = wanted.iter().map(|&n| (n.min(cap) as usize).pow(2)).sum();
        if total <= MAX_TRIANGLES || cap == 1 {
            return wanted.iter().map(|&n| n.min(cap)).collect();
        }
        cap = (cap * 3 / 4).max(1);
    }
}

/// The split that brings `face`'s longest edge to [`TEXELS_PER_EDGE`]
/// texels of its material's texture (1 without a texture or UVs).
fn wanted_split(mesh: &TriangleMesh, face: FaceId) -> u32 {
    let Some((texture, [a, b, c])) = mesh.face_texture(face) else {
        return 1;
    };
    let size = Vec2::new(texture.width as f32, texture.height as f32);
    let longest = [(a, b), (b, c), (c, a)]
        .iter()
        .map(|&(p, q)| ((q - p) * size).length())
        .fold(0.0, f32::max);
    if !longest.is_finite() {
        return 1;
    }
    ((longest / TEXELS_PER_EDGE).ceil() as u32).clamp(1, MAX_SPLIT)
}

/// Appends `face` split into `n²` triangles, corners coloured at their
/// barycentric points.
fn push_split_triangle(out: &mut ColouredSource, mesh: &TriangleMesh, face: FaceId, n: u32) {
    let [ia, ib, ic] = mesh.triangles[face.index()];
    let [pa, pb, pc] = [ia, ib, ic].map(|i| mesh.positions[i as usize]);
    let first = out.positions.len() as u32;
    let nf = n as f32;
    // Lattice point (r, s): barycentric (1 - r/n - s/n, r/n, s/n), r + s <= n;
    // row r holds n + 1 - r points.
    let index = |r: u32, s: u32| first + r * (n + 1) - r * r.saturating_sub(1) / 2 + s;
    let mut bary = Vec::new();
    for r in 0..=n {
        for s in 0..=n - r {
            let w = Vec3::new((n - r - s) as f32 / nf, r as f32 / nf, s as f32 / nf);
            out.positions.push(pa * w.x + pb * w.y + pc * w.z);
            bary.push(w);
        }
    }
    let colour = |v: u32| {
        mesh.colour_at(face, bary[(v - first) as usize])
            .unwrap_or([255; 4])
    };
    for r in 0..n {
        for s in 0..n - r {
            let upright = [index(r, s), index(r + 1, s), index(r, s + 1)];
            push_triangle(out, upright, &colour);
            if s + 1 < n - r {
                let inverted = [index(r + 1, s), index(r + 1, s + 1), index(r, s + 1)];
                push_triangle(out, inverted, &colour);
            }
        }
    }
}

fn push_triangle(out: &mut ColouredSource, t: [u32; 3], colour: &impl Fn(u32) -> [u8; 4]) {
    out.triangles.push(t);
    out.corner_colours.extend(t.map(colour));
}

#[cfg(test)]
mod tests {
    use super::*;
    use spatch_mesh::{Material, MaterialId, Texture};

    /// One triangle with a 64 × 64 texture (red left half, blue right half)
    /// spread over it.
    fn textured() -> TriangleMesh {
        let mut mesh =
            TriangleMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
        let rgba = (0..64 * 64)
            .flat_map(|k| {
                if k % 64 < 32 {
                    [255, 0, 0, 255]
                } else {
                    [0, 0, 255, 255]
                }
            })
            .collect();
        let mut material = Material::white("t");
        material.texture = Some(Texture::new(64, 64, rgba).unwrap());
        mesh.materials = vec![material];
        mesh.face_materials = vec![MaterialId(0)];
        mesh.face_uvs = Some(vec![[Vec2::ZERO, Vec2::X, Vec2::Y]]);
        mesh
    }

    #[test]
    fn a_textured_triangle_is_split_and_keeps_its_shape() {
        let mesh = textured();
        let c = colour_source(&mesh).unwrap();
        assert_eq!(c.drawing, SourceDrawing::Texture);
        // Longest edge: the diagonal, 64·√2 ≈ 90.5 texels → n = 46.
        assert_eq!(c.triangles.len(), 46 * 46);
        assert_eq!(c.corner_colours.len(), 3 * c.triangles.len());
        let area: f32 = c
            .triangles
            .iter()
            .map(|t| {
                let [a, b, d] = t.map(|v| c.positions[v as usize]);
                (b - a).cross(d - a).z * 0.5
            })
            .sum();
        assert!((area - 0.5).abs() < 1e-4, "{area}");
        assert!(c
            .triangles
            .iter()
            .flatten()
            .all(|&v| (v as usize) < c.positions.len()));
        // Both halves of the texture show up.
        assert!(c.corner_colours.iter().any(|k| k[0] > 200 && k[2] < 50));
        assert!(c.corner_colours.iter().any(|k| k[2] > 200 && k[0] < 50));
    }

    #[test]
    fn a_mesh_without_colour_is_left_grey() {
        let mesh = TriangleMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
        assert!(colour_source(&mesh).is_none());
    }

    #[test]
    fn vertex_colours_are_not_split() {
        let mut mesh =
            TriangleMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::Y], vec![[0, 1, 2]]).unwrap();
        mesh.vertex_colours = Some(vec![[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255]]);
        let c = colour_source(&mesh).unwrap();
        assert_eq!(c.drawing, SourceDrawing::Colours);
        assert_eq!(c.triangles.len(), 1);
        let corners = c.triangles[0].map(|v| c.positions[v as usize]);
        assert_eq!(corners, [Vec3::ZERO, Vec3::X, Vec3::Y]);
        assert_eq!(c.corner_colours[1], [0, 255, 0, 255]);
    }
}
