//! The triangle mesh type shared by every spatch stage, and its axis-aligned box.
//!
//! Positions are `f32` relative to an `f64` [`TriangleMesh::origin`]; loaders put the origin
//! at the f64 centre of the model's bounding box, so a model a million units from the world
//! origin keeps full f32 precision (about 6e-8 of its own size) in every later stage.

use glam::{DVec3, Vec2, Vec3};

use crate::error::{Element, MeshArray, MeshProblem};
use crate::material::{linear_to_srgb, srgb_to_linear, srgb_unit_to_linear};
use crate::{FaceId, Material, MaterialId, MeshError, Texture, VertexId};

/// An axis-aligned bounding box in mesh coordinates (relative to the mesh origin).
///
/// The empty box has `min = +inf`, `max = -inf`, so extending it by a point gives that point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The box containing nothing.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The smallest box containing all `points` (empty for no points).
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Aabb {
        let mut b = Aabb::EMPTY;
        for p in points {
            b.extend(p);
        }
        b
    }

    /// Grows the box to contain `p`.
    #[inline]
    pub fn extend(&mut self, p: Vec3) {
        self.min = self.min.min(p);
        self.max = self.max.max(p);
    }

    /// The smallest box containing both boxes.
    #[inline]
    pub fn union(self, other: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Whether the box contains no point.
    #[inline]
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    /// Centre point (NaN for the empty box).
    #[inline]
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// Edge lengths (zero for the empty box).
    #[inline]
    pub fn size(&self) -> Vec3 {
        if self.is_empty() {
            Vec3::ZERO
        } else {
            self.max - self.min
        }
    }

    /// Length of the diagonal (zero for the empty box).
    #[inline]
    pub fn diagonal(&self) -> f32 {
        self.size().length()
    }

    /// Whether `p` lies inside or on the box.
    #[inline]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Squared distance from `p` to the box (zero inside).
    #[inline]
    pub fn distance_squared(&self, p: Vec3) -> f32 {
        let d = (self.min - p).max(p - self.max).max(Vec3::ZERO);
        d.length_squared()
    }
}

/// A triangle mesh with optional per-corner UVs, vertex colours, vertex normals and materials.
///
/// # Guarantees
///
/// A mesh returned by a loader, by [`TriangleMesh::new`] or by
/// [`prepare_mesh`](crate::prepare_mesh) has passed [`TriangleMesh::validate`]: every index is
/// below `positions.len()`, every position, normal and UV is finite, and every optional array
/// has its documented length. Code that builds a mesh by hand through the public fields should
/// call `validate` before handing it on; methods taking a [`FaceId`] panic when the id is out
/// of range (a caller bug), never on data.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Model-space offset of every position (f64, so models far from the world origin stay
    /// precise). World position of vertex `v` is `origin + positions[v]` in f64.
    pub origin: DVec3,
    /// Vertex positions relative to `origin`.
    pub positions: Vec<Vec3>,
    /// Triangles as vertex indices, counter-clockwise seen from the front.
    pub triangles: Vec<[u32; 3]>,
    /// Texture coordinates per face corner (`len == triangles.len()`), so UV seams need no
    /// vertex split. `v` is up (see [`crate::material`] conventions).
    pub face_uvs: Option<Vec<[Vec2; 3]>>,
    /// sRGB RGBA8 colour per vertex (`len == positions.len()`).
    pub vertex_colours: Option<Vec<[u8; 4]>>,
    /// Unit (or zero) normal per vertex as given by the file (`len == positions.len()`).
    pub vertex_normals: Option<Vec<Vec3>>,
    /// Material per face (`len == triangles.len()`), or empty when there are no materials.
    pub face_materials: Vec<MaterialId>,
    /// Materials named by `face_materials`.
    pub materials: Vec<Material>,
}

impl TriangleMesh {
    /// A plain mesh (no UVs, colours, normals or materials) with origin zero, validated.
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<TriangleMesh, MeshError> {
        let mesh = TriangleMesh {
            positions,
            triangles,
            ..TriangleMesh::default()
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// A plain mesh from f64 world positions: the origin is put at the f64 centre of their
    /// bounding box and positions are stored relative to it. Validated.
    pub fn from_world_positions(
        world: &[DVec3],
        triangles: Vec<[u32; 3]>,
    ) -> Result<TriangleMesh, MeshError> {
        let origin = world_bounds_centre(world);
        let positions = world.iter().map(|&p| (p - origin).as_vec3()).collect();
        let mesh = TriangleMesh {
            origin,
            positions,
            triangles,
            ..TriangleMesh::default()
        };
        mesh.validate()?;
        Ok(mesh)
    }

    /// Checks the invariants listed under `# Guarantees`.
    pub fn validate(&self) -> Result<(), MeshError> {
        self.check_geometry()?;
        self.check_attributes()?;
        self.check_materials()
    }

    /// The size limits, finite origin and positions, and in-range vertex indices.
    fn check_geometry(&self) -> Result<(), MeshError> {
        let n = self.positions.len();
        if n >= u32::MAX as usize || self.triangles.len() >= u32::MAX as usize {
            return invalid(MeshProblem::TooLarge);
        }
        if !self.origin.is_finite() {
            return invalid(MeshProblem::NonFinite {
                element: Element::Vertex(0),
            });
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return invalid(MeshProblem::NonFinite {
                element: Element::Vertex(i as u64),
            });
        }
        for (f, t) in self.triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= n) {
                return invalid(MeshProblem::IndexOutOfRange {
                    face: f as u32,
                    index,
                    vertex_count: n,
                });
            }
        }
        Ok(())
    }

    /// The lengths and finite values of the face UVs, vertex colours and vertex normals.
    fn check_attributes(&self) -> Result<(), MeshError> {
        let n = self.positions.len();
        if let Some(uvs) = &self.face_uvs {
            check_len(MeshArray::FaceUvs, uvs.len(), self.triangles.len())?;
            if let Some(f) = uvs.iter().position(|c| c.iter().any(|uv| !uv.is_finite())) {
                return invalid(MeshProblem::NonFinite {
                    element: Element::TexCoord(f as u64),
                });
            }
        }
        if let Some(colours) = &self.vertex_colours {
            check_len(MeshArray::VertexColours, colours.len(), n)?;
        }
        if let Some(normals) = &self.vertex_normals {
            check_len(MeshArray::VertexNormals, normals.len(), n)?;
            if let Some(i) = normals.iter().position(|v| !v.is_finite()) {
                return invalid(MeshProblem::NonFinite {
                    element: Element::Normal(i as u64),
                });
            }
        }
        Ok(())
    }

    /// The length of the face materials and their in-range material ids (when any).
    fn check_materials(&self) -> Result<(), MeshError> {
        if self.face_materials.is_empty() {
            return Ok(());
        }
        check_len(
            MeshArray::FaceMaterials,
            self.face_materials.len(),
            self.triangles.len(),
        )?;
        let m = self.materials.len();
        if let Some(f) = self.face_materials.iter().position(|id| id.index() >= m) {
            return invalid(MeshProblem::MaterialOutOfRange {
                face: f as u32,
                material: self.face_materials[f].0,
            });
        }
        Ok(())
    }

    /// Number of triangles.
    #[inline]
    pub fn face_count(&self) -> usize {
        self.triangles.len()
    }

    /// Number of vertices (including any not referenced by a face).
    #[inline]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// All face ids in order.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = FaceId> + '_ {
        (0..self.triangles.len() as u32).map(FaceId)
    }

    /// The three vertex ids of a face.
    #[inline]
    pub fn face_vertex_ids(&self, face: FaceId) -> [VertexId; 3] {
        self.triangles[face.index()].map(VertexId)
    }

    /// The three corner positions of a face (relative to the origin).
    #[inline]
    pub fn face_positions(&self, face: FaceId) -> [Vec3; 3] {
        self.triangles[face.index()].map(|i| self.positions[i as usize])
    }

    /// World (f64) position of a vertex: `origin + positions[v]`.
    #[inline]
    pub fn world_position(&self, vertex: VertexId) -> DVec3 {
        self.origin + self.positions[vertex.index()].as_dvec3()
    }

    /// Unit normal of a face by the right-hand rule over its corners (counter-clockwise =
    /// front), or zero for a degenerate (zero-area) face.
    #[inline]
    pub fn face_normal(&self, face: FaceId) -> Vec3 {
        let [a, b, c] = self.face_positions(face);
        let n = (b - a).cross(c - a);
        let unit = n.normalize_or_zero();
        if unit != Vec3::ZERO || n == Vec3::ZERO {
            return unit;
        }
        // The f32 length over- or underflowed (edges beyond ~1e9 or below ~1e-19): f64.
        self.face_cross_f64(face).normalize_or_zero().as_vec3()
    }

    /// The face's edge cross product `(b - a) x (c - a)` in f64 (never overflows for f32
    /// positions).
    fn face_cross_f64(&self, face: FaceId) -> DVec3 {
        let [a, b, c] = self.face_positions(face).map(Vec3::as_dvec3);
        (b - a).cross(c - a)
    }

    /// Area of a face.
    #[inline]
    pub fn face_area(&self, face: FaceId) -> f32 {
        let [a, b, c] = self.face_positions(face);
        let area = 0.5 * (b - a).cross(c - a).length();
        if area.is_finite() {
            return area;
        }
        // The f32 squared length overflowed (edges beyond ~1e9): f64.
        (0.5 * self.face_cross_f64(face).length()) as f32
    }

    /// Centroid (mean of the corners) of a face.
    #[inline]
    pub fn face_centroid(&self, face: FaceId) -> Vec3 {
        let [a, b, c] = self.face_positions(face);
        (a + b + c) * (1.0 / 3.0)
    }

    /// The point of a face at barycentric coordinates `(w0, w1, w2)` (weights of its corners).
    #[inline]
    pub fn point_at(&self, face: FaceId, barycentric: Vec3) -> Vec3 {
        let [a, b, c] = self.face_positions(face);
        a * barycentric.x + b * barycentric.y + c * barycentric.z
    }

    /// Bounding box of all positions (relative to the origin).
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }

    /// Length of the bounding-box diagonal: the scale every relative tolerance refers to.
    pub fn diagonal(&self) -> f32 {
        self.bounds().diagonal()
    }

    /// The material of a face, if the mesh has materials.
    #[inline]
    pub fn material_of(&self, face: FaceId) -> Option<&Material> {
        let id = self.face_materials.get(face.index())?;
        self.materials.get(id.index())
    }

    /// The texture of a face's material and the face's corner UVs, when the material has a
    /// texture and the mesh has UVs.
    #[inline]
    pub fn face_texture(&self, face: FaceId) -> Option<(&Texture, [Vec2; 3])> {
        let texture = self.material_of(face)?.texture.as_ref()?;
        let uvs = self.face_uvs.as_ref()?;
        Some((texture, uvs[face.index()]))
    }

    /// Whether the surface has colour worth storing.
    ///
    /// The rule: true when the mesh has vertex colours, or when any material has a texture or
    /// a base colour whose RGB is not exactly white. A mesh whose only material is white and
    /// untextured (common in OBJ exports) has no colour.
    pub fn has_colour(&self) -> bool {
        self.vertex_colours.is_some() || self.materials.iter().any(Material::has_colour)
    }

    /// The colour (sRGB RGBA8) at barycentric coordinates `barycentric` on `face`, or `None`
    /// when the mesh [has no colour](TriangleMesh::has_colour).
    ///
    /// The colour is the product, in linear space, of the face material's base colour, its
    /// texture sampled bilinearly at the interpolated UV (when the material has a texture and
    /// the mesh has UVs) and the interpolated vertex colour (when present), encoded back to
    /// sRGB. A lone texture or vertex colour with a white factor comes back unchanged.
    pub fn colour_at(&self, face: FaceId, barycentric: Vec3) -> Option<[u8; 4]> {
        if !self.has_colour() {
            return None;
        }
        let w = barycentric;
        let material = self.material_of(face);
        let mut linear = material.map_or([1.0; 4], |m| m.base_colour);
        if let Some((texture, [a, b, c])) = self.face_texture(face) {
            let s = texture.sample_bilinear(a * w.x + b * w.y + c * w.z);
            for k in 0..3 {
                linear[k] *= srgb_unit_to_linear(s[k]);
            }
            linear[3] *= s[3];
        }
        if let Some(colours) = &self.vertex_colours {
            let t = self.triangles[face.index()];
            let cs = t.map(|i| colours[i as usize]);
            for k in 0..3 {
                linear[k] *= srgb_to_linear(cs[0][k]) * w.x
                    + srgb_to_linear(cs[1][k]) * w.y
                    + srgb_to_linear(cs[2][k]) * w.z;
            }
            linear[3] *=
                (f32::from(cs[0][3]) * w.x + f32::from(cs[1][3]) * w.y + f32::from(cs[2][3]) * w.z)
                    / 255.0;
        }
        let alpha = (linear[3].clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
        Some([
            linear_to_srgb(linear[0]),
            linear_to_srgb(linear[1]),
            linear_to_srgb(linear[2]),
            alpha,
        ])
    }
}

/// f64 centre of the bounding box of `points` (zero for no points or non-finite input).
pub(crate) fn world_bounds_centre(points: &[DVec3]) -> DVec3 {
    if points.is_empty() {
        return DVec3::ZERO;
    }
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for &p in points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    let c = (lo + hi) * 0.5;
    if c.is_finite() {
        c
    } else {
        DVec3::ZERO
    }
}

/// The invalid-mesh error for `problem`.
fn invalid(problem: MeshProblem) -> Result<(), MeshError> {
    Err(MeshError::InvalidMesh { problem })
}

/// Checks that `array` holds `expected` entries (it holds `len`).
fn check_len(array: MeshArray, len: usize, expected: usize) -> Result<(), MeshError> {
    if len == expected {
        Ok(())
    } else {
        invalid(MeshProblem::LengthMismatch {
            array,
            len,
            expected,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Texture;

    fn quad() -> TriangleMesh {
        TriangleMesh::new(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 2.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        )
        .unwrap()
    }

    #[test]
    fn face_geometry() {
        let m = quad();
        assert_eq!(m.face_normal(FaceId(0)), Vec3::Z);
        assert_eq!(m.face_area(FaceId(1)), 2.0);
        assert_eq!(
            m.face_centroid(FaceId(0)),
            Vec3::new(4.0 / 3.0, 2.0 / 3.0, 0.0)
        );
        assert!((m.diagonal() - 8.0f32.sqrt()).abs() < 1e-6);
        let degenerate = TriangleMesh::new(vec![Vec3::ZERO; 3], vec![[0, 1, 2]]).unwrap();
        assert_eq!(degenerate.face_normal(FaceId(0)), Vec3::ZERO);
    }

    #[test]
    fn validate_catches_each_broken_invariant() {
        assert!(TriangleMesh::new(vec![Vec3::ZERO; 2], vec![[0, 1, 2]]).is_err());
        assert!(TriangleMesh::new(vec![Vec3::NAN; 3], vec![[0, 1, 2]]).is_err());
        let mut m = quad();
        m.face_uvs = Some(vec![[Vec2::ZERO; 3]]);
        assert!(matches!(
            m.validate(),
            Err(MeshError::InvalidMesh {
                problem: MeshProblem::LengthMismatch { .. }
            })
        ));
        let mut m = quad();
        m.face_materials = vec![MaterialId(0), MaterialId(1)];
        m.materials = vec![Material::white("a")];
        assert!(m.validate().is_err());
    }

    #[test]
    fn far_from_origin_positions_keep_their_precision() {
        let world = [
            DVec3::new(1e6, 1e6, 1e6),
            DVec3::new(1e6 + 1e-3, 1e6, 1e6),
            DVec3::new(1e6, 1e6 + 1e-3, 1e6),
        ];
        let m = TriangleMesh::from_world_positions(&world, vec![[0, 1, 2]]).unwrap();
        assert!((m.face_area(FaceId(0)) - 0.5e-6).abs() < 1e-9);
        let back = m.world_position(VertexId(1));
        assert!((back - world[1]).length() < 1e-9);
    }

    #[test]
    fn colour_rules() {
        let mut m = quad();
        assert!(!m.has_colour());
        assert_eq!(m.colour_at(FaceId(0), Vec3::splat(1.0 / 3.0)), None);
        m.materials = vec![Material::white("white")];
        m.face_materials = vec![MaterialId(0); 2];
        assert!(!m.has_colour(), "a white untextured material is no colour");
        m.vertex_colours = Some(vec![[200, 10, 10, 255], [10, 200, 10, 255], [0; 4], [0; 4]]);
        assert!(m.has_colour());
        assert_eq!(m.colour_at(FaceId(0), Vec3::X), Some([200, 10, 10, 255]));
        m.vertex_colours = None;
        m.materials[0].texture = Some(Texture::new(1, 1, vec![40, 80, 120, 255]).unwrap());
        m.face_uvs = Some(vec![[Vec2::ZERO; 3]; 2]);
        assert_eq!(m.colour_at(FaceId(1), Vec3::Y), Some([40, 80, 120, 255]));
        // A factor of 0.5 halves the linear value.
        m.materials[0].base_colour = [0.5, 1.0, 1.0, 1.0];
        let c = m.colour_at(FaceId(1), Vec3::Y).unwrap();
        let expected = linear_to_srgb(srgb_to_linear(40) * 0.5);
        assert_eq!(c, [expected, 80, 120, 255]);
    }
}
