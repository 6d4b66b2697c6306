//! One glTF primitive read into a [`Piece`]: its accessors checked and read (positions into
//! world space, indices, normals, texture coordinates with the material's
//! `KHR_texture_transform`, vertex colours to sRGB) and its strips and fans turned into
//! counter-clockwise triangles. Part of the glTF reader ([`super::gltf`]).
//!
//! Cost: O(vertices + indices) per primitive.

use std::path::Path;

use glam::{DMat3, DMat4, DVec3, Vec2, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::gltf_accessor::{read_accessor, AccessorValues};
use super::gltf_buffers::Views;
use crate::error::{Element, GltfAttribute, GltfProblem};
use crate::material::linear_to_srgb;
use crate::MeshError;

/// Geometry of one primitive instance, in world space.
pub(super) struct Piece {
    pub(super) positions: Vec<DVec3>,
    pub(super) triangles: Vec<[u32; 3]>,
    pub(super) normals: Option<Vec<Vec3>>,
    pub(super) uvs: Option<Vec<Vec2>>,
    pub(super) colours: Option<Vec<[u8; 4]>>,
    pub(super) material: Option<usize>,
}

/// `KHR_texture_transform` of a material's base colour texture.
#[derive(Clone, Copy)]
pub(super) struct UvTransform {
    pub(super) offset: [f32; 2],
    pub(super) rotation: f32,
    pub(super) scale: [f32; 2],
}

impl UvTransform {
    pub(super) const IDENTITY: UvTransform = UvTransform {
        offset: [0.0; 2],
        rotation: 0.0,
        scale: [1.0; 2],
    };

    /// Applies the transform in glTF UV space (v down), as the extension defines:
    /// translate * rotate * scale.
    fn apply(&self, uv: Vec2) -> Vec2 {
        let s = Vec2::new(uv.x * self.scale[0], uv.y * self.scale[1]);
        let (sin, cos) = self.rotation.sin_cos();
        let r = Vec2::new(cos * s.x + sin * s.y, -sin * s.x + cos * s.y);
        r + Vec2::from_array(self.offset)
    }
}

/// Reads an accessor if it has one of the allowed shapes, a non-zero count and a byte range
/// inside its view.
fn read_checked(
    accessor: &gltf::Accessor,
    dimensions: &[Dimensions],
    types: &[DataType],
    views: &Views,
) -> Option<AccessorValues> {
    if !dimensions.contains(&accessor.dimensions())
        || !types.contains(&accessor.data_type())
        || accessor.count() == 0
    {
        return None;
    }
    read_accessor(accessor, views)
}

/// Component types a position may have: `FLOAT`, or any 8/16-bit integer
/// (`KHR_mesh_quantization`).
const POSITION_TYPES: &[DataType] = &[
    DataType::F32,
    DataType::I8,
    DataType::U8,
    DataType::I16,
    DataType::U16,
];
/// Component types a normal may have (`FLOAT`, or normalized signed 8/16-bit).
const NORMAL_TYPES: &[DataType] = &[DataType::F32, DataType::I8, DataType::I16];
/// Component types a texture coordinate may have.
const TEXCOORD_TYPES: &[DataType] = POSITION_TYPES;
/// Component types a colour may have.
const COLOUR_TYPES: &[DataType] = &[DataType::F32, DataType::U8, DataType::U16];
/// Component types an index may have.
const INDEX_TYPES: &[DataType] = &[DataType::U8, DataType::U16, DataType::U32];

/// Triangles of a primitive's index list in its mode, counter-clockwise after `mirrored`.
fn assemble_triangles(mode: Mode, indices: &[u32], mirrored: bool) -> Vec<[u32; 3]> {
    let mut triangles = Vec::with_capacity(indices.len() / 3);
    let mut push = |a: u32, b: u32, c: u32| {
        triangles.push(if mirrored { [a, c, b] } else { [a, b, c] });
    };
    match mode {
        Mode::Triangles => {
            for t in indices.chunks_exact(3) {
                push(t[0], t[1], t[2]);
            }
        }
        Mode::TriangleStrip => {
            for i in 0..indices.len().saturating_sub(2) {
                let (a, b, c) = (indices[i], indices[i + 1], indices[i + 2]);
                if i % 2 == 0 {
                    push(a, b, c);
                } else {
                    push(b, a, c);
                }
            }
        }
        _ => {
            for i in 1..indices.len().saturating_sub(1) {
                push(indices[0], indices[i], indices[i + 1]);
            }
        }
    }
    triangles
}

/// What reading one primitive needs: where it is (for errors), the
/// file's buffers and the node's world transform.
pub(super) struct PrimitiveAt<'a, 'b> {
    pub(super) path: &'a Path,
    pub(super) mesh: usize,
    pub(super) primitive: usize,
    pub(super) views: &'a Views<'b>,
    pub(super) world: &'a DMat4,
}

impl PrimitiveAt<'_, '_> {
    /// An error of this primitive.
    fn fail(&self, problem: GltfProblem) -> MeshError {
        MeshError::GltfPrimitive {
            path: self.path.to_path_buf(),
            mesh: self.mesh,
            primitive: self.primitive,
            problem,
        }
    }

    /// The error of an accessor of `attribute` that cannot be read.
    fn bad(&self, attribute: GltfAttribute) -> MeshError {
        self.fail(GltfProblem::BadAccessor { attribute })
    }

    /// A non-finite `element`.
    fn non_finite(&self, element: Element) -> MeshError {
        MeshError::NonFinite {
            path: self.path.to_path_buf(),
            element,
        }
    }

    /// Checks that `attribute` has one value per vertex (`n`).
    fn check_count(
        &self,
        attribute: GltfAttribute,
        count: usize,
        n: usize,
    ) -> Result<(), MeshError> {
        if count == n {
            return Ok(());
        }
        Err(self.fail(GltfProblem::AttributeCountMismatch {
            attribute,
            count,
            expected: n,
        }))
    }
}

/// A primitive's triangles as a [`Piece`] in world space (`None` for
/// points and lines), its texture coordinates from the set and transform
/// its material names (`material_uv_set`, `material_uv_transform`, by
/// material index).
pub(super) fn read_primitive(
    at: &PrimitiveAt<'_, '_>,
    primitive: &gltf::Primitive,
    (material_uv_set, material_uv_transform): (&[u32], &[UvTransform]),
) -> Result<Option<Piece>, MeshError> {
    let mode = primitive.mode();
    if !matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    ) {
        return Ok(None);
    }
    let positions = read_positions(at, primitive)?;
    let n = positions.len();
    let indices = read_indices(at, primitive, n)?;
    let mirrored = DMat3::from_mat4(*at.world).determinant() < 0.0;
    let triangles = assemble_triangles(mode, &indices, mirrored);
    let material = primitive.material().index();
    let set = material.map_or(0, |m| material_uv_set.get(m).copied().unwrap_or(0));
    let transform = material
        .and_then(|m| material_uv_transform.get(m).copied())
        .unwrap_or(UvTransform::IDENTITY);
    Ok(Some(Piece {
        positions,
        triangles,
        normals: read_normals(at, primitive, n)?,
        uvs: read_uvs(at, primitive, n, (set, transform))?,
        colours: read_colours(at, primitive, n)?,
        material,
    }))
}

/// `POSITION`, in world space.
fn read_positions(
    at: &PrimitiveAt<'_, '_>,
    primitive: &gltf::Primitive,
) -> Result<Vec<DVec3>, MeshError> {
    let accessor = primitive
        .get(&gltf::Semantic::Positions)
        .ok_or_else(|| at.fail(GltfProblem::NoPositions))?;
    let local = read_checked(&accessor, &[Dimensions::Vec3], POSITION_TYPES, at.views)
        .ok_or_else(|| at.bad(GltfAttribute::Position))?;
    let mut positions = Vec::with_capacity(local.len());
    for i in 0..local.len() {
        let p = DVec3::from_array(local.get::<3>(i));
        if !p.is_finite() {
            return Err(at.non_finite(Element::Vertex(i as u64)));
        }
        positions.push(at.world.transform_point3(p));
    }
    Ok(positions)
}

/// The indices (every vertex in order when there are none), each below
/// the `n` vertices.
fn read_indices(
    at: &PrimitiveAt<'_, '_>,
    primitive: &gltf::Primitive,
    n: usize,
) -> Result<Vec<u32>, MeshError> {
    let indices: Vec<u32> = match primitive.indices() {
        Some(accessor) => read_checked(&accessor, &[Dimensions::Scalar], INDEX_TYPES, at.views)
            .ok_or_else(|| at.bad(GltfAttribute::Indices))?
            .values
            .iter()
            .map(|&i| i as u32)
            .collect(),
        None => (0..n as u32).collect(),
    };
    if let Some(&index) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(at.fail(GltfProblem::IndexOutOfRange {
            index,
            vertex_count: n,
        }));
    }
    Ok(indices)
}

/// `NORMAL`, in world space (the inverse transpose of the transform),
/// unit or zero.
fn read_normals(
    at: &PrimitiveAt<'_, '_>,
    primitive: &gltf::Primitive,
    n: usize,
) -> Result<Option<Vec<Vec3>>, MeshError> {
    let Some(accessor) = primitive.get(&gltf::Semantic::Normals) else {
        return Ok(None);
    };
    let values = read_checked(&accessor, &[Dimensions::Vec3], NORMAL_TYPES, at.views)
        .ok_or_else(|| at.bad(GltfAttribute::Normal))?;
    at.check_count(GltfAttribute::Normal, values.len(), n)?;
    let normal_matrix = DMat3::from_mat4(*at.world).inverse().transpose();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let v = DVec3::from_array(values.get::<3>(i));
        if !v.is_finite() {
            return Err(at.non_finite(Element::Normal(i as u64)));
        }
        let t = (normal_matrix * v).normalize_or_zero();
        out.push(if t.is_finite() {
            t.as_vec3()
        } else {
            Vec3::ZERO
        });
    }
    Ok(Some(out))
}

/// `TEXCOORD_<set>` through the material's `transform`, `v` flipped to
/// the project's convention.
fn read_uvs(
    at: &PrimitiveAt<'_, '_>,
    primitive: &gltf::Primitive,
    n: usize,
    (set, transform): (u32, UvTransform),
) -> Result<Option<Vec<Vec2>>, MeshError> {
    let Some(accessor) = primitive.get(&gltf::Semantic::TexCoords(set)) else {
        return Ok(None);
    };
    let values = read_checked(&accessor, &[Dimensions::Vec2], TEXCOORD_TYPES, at.views)
        .ok_or_else(|| at.bad(GltfAttribute::TexCoord))?;
    at.check_count(GltfAttribute::TexCoord, values.len(), n)?;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let [u, v] = values.get::<2>(i);
        let uv = transform.apply(Vec2::new(u as f32, v as f32));
        if !uv.is_finite() {
            return Err(at.non_finite(Element::TexCoord(i as u64)));
        }
        out.push(Vec2::new(uv.x, 1.0 - uv.y));
    }
    Ok(Some(out))
}

/// `COLOR_0` as sRGB bytes.
fn read_colours(
    at: &PrimitiveAt<'_, '_>,
    primitive: &gltf::Primitive,
    n: usize,
) -> Result<Option<Vec<[u8; 4]>>, MeshError> {
    let Some(accessor) = primitive.get(&gltf::Semantic::Colors(0)) else {
        return Ok(None);
    };
    let dimensions = [Dimensions::Vec3, Dimensions::Vec4];
    let values = read_checked(&accessor, &dimensions, COLOUR_TYPES, at.views)
        .ok_or_else(|| at.bad(GltfAttribute::Colour))?;
    at.check_count(GltfAttribute::Colour, values.len(), n)?;
    Ok(Some(
        (0..n).map(|i| linear_colour_to_srgb(&values, i)).collect(),
    ))
}

/// `COLOR_0` element `i` (linear, RGB or RGBA) as sRGB bytes with alpha.
fn linear_colour_to_srgb(values: &AccessorValues, i: usize) -> [u8; 4] {
    let at = i * values.components;
    let c = &values.values[at..at + values.components];
    let a = match c.get(3) {
        Some(a) if !a.is_nan() => a.clamp(0.0, 1.0),
        _ => 1.0,
    };
    [
        linear_to_srgb(c[0] as f32),
        linear_to_srgb(c[1] as f32),
        linear_to_srgb(c[2] as f32),
        (a * 255.0 + 0.5) as u8,
    ]
}
