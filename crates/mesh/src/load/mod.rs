//! Loading meshes and point clouds from files.
//!
//! [`load_mesh`] and [`load_point_cloud`] pick the reader by file extension
//! (case-insensitive):
//!
//! | extension | meshes | point clouds |
//! |---|---|---|
//! | `.obj` (+ `.mtl`, textures) | [`obj`] | — |
//! | `.gltf`, `.glb` | [`gltf`] | — |
//! | `.ply` (ASCII, binary LE/BE) | [`ply`] | [`ply`] (the vertices of any PLY) |
//! | `.off` (ASCII) | [`off`] | — |
//! | `.stl` (binary, ASCII) | [`stl`] | — |
//! | `.xyz`, `.txt`, `.pts` | — | [`xyz`] |
//!
//! Rules every reader keeps:
//! - positions are read as f64 and stored relative to the f64 centre of their bounding box
//!   ([`TriangleMesh::origin`]);
//! - a NaN or infinite coordinate, normal or UV in a mesh file is refused with
//!   [`MeshError::NonFinite`] naming the file and the element (`vertex 17`); point clouds drop
//!   such points and count them instead;
//! - an index past the vertex list is refused with [`MeshError::IndexOutOfRange`];
//! - a model spanning more than [`MAX_EXTENT`] from its centre is refused with
//!   [`MeshError::ExtentTooLarge`] naming the farthest vertex;
//! - a UTF-8 byte-order mark before the first line of a text format is skipped;
//! - files a model refers to (glTF buffers and images, OBJ material libraries and textures)
//!   are read only from the model's folder or below (no absolute paths, no `..`);
//! - polygons are split into triangles by [`triangulate_polygon`](crate::triangulate_polygon)
//!   (a fan from the first corner when convex, as always; ear clipping otherwise), counted in
//!   [`LoadWarning::PolygonsTriangulated`] and [`LoadWarning::PolygonsNotSimple`];
//! - problems that leave a usable mesh (a missing texture or material library, ignored
//!   options) become [`LoadWarning`]s, never errors and never prints;
//! - no input bytes make a reader panic; counts read from a file never size an allocation
//!   beyond what the file's length can back.

use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};

use crate::error::ElementKind;
use crate::mesh::world_bounds_centre;
use crate::{LoadWarning, Material, MaterialId, MeshError, PointCloud, TriangleMesh};

pub use ply_scalar::PlyScalar;

pub mod gltf;
mod gltf_accessor;
mod gltf_buffers;
mod gltf_primitive;
mod local_reference;
mod mtl;
pub mod obj;
pub mod off;
pub mod ply;
mod ply_fast;
mod ply_scalar;
mod range_grid;
pub mod stl;
mod texture;
mod tristrips;
pub mod xyz;

/// A mesh read from a file, with the warnings the reader collected.
#[derive(Clone, Debug)]
pub struct LoadedMesh {
    /// The mesh (validated; not yet welded or cleaned: see [`prepare_mesh`](crate::prepare_mesh)).
    pub mesh: TriangleMesh,
    /// What the reader worked around.
    pub warnings: Vec<LoadWarning>,
}

/// A point cloud read from a file.
#[derive(Clone, Debug)]
pub struct LoadedPointCloud {
    /// The finite points.
    pub cloud: PointCloud,
    /// Points dropped because a coordinate or normal was NaN or infinite.
    pub dropped_non_finite: u64,
    /// What the reader worked around.
    pub warnings: Vec<LoadWarning>,
}

/// A file format this crate reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FileFormat {
    /// Wavefront OBJ.
    Obj,
    /// glTF 2.0, JSON (`.gltf`) or binary (`.glb`).
    Gltf,
    /// Stanford PLY.
    Ply,
    /// Object File Format (ASCII).
    Off,
    /// STL, binary or ASCII.
    Stl,
    /// Plain point text (`.xyz`, `.txt`).
    Xyz,
    /// Leica-style point text (`.pts`): an optional count line, then `x y z [i] [r g b]`.
    Pts,
}

impl FileFormat {
    /// The format named by `path`'s extension, if any.
    pub fn from_path(path: &Path) -> Option<FileFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "obj" => FileFormat::Obj,
            "gltf" | "glb" => FileFormat::Gltf,
            "ply" => FileFormat::Ply,
            "off" => FileFormat::Off,
            "stl" => FileFormat::Stl,
            "xyz" | "txt" => FileFormat::Xyz,
            "pts" => FileFormat::Pts,
            _ => return None,
        })
    }
}

/// Loads a triangle mesh, choosing the reader by extension (`.obj`, `.gltf`, `.glb`, `.ply`,
/// `.off`, `.stl`).
pub fn load_mesh(path: impl AsRef<Path>) -> Result<LoadedMesh, MeshError> {
    let path = path.as_ref();
    match FileFormat::from_path(path) {
        Some(FileFormat::Obj) => obj::load_obj(path),
        Some(FileFormat::Gltf) => gltf::load_gltf(path),
        Some(FileFormat::Ply) => ply::load_ply_mesh(path),
        Some(FileFormat::Off) => off::load_off(path),
        Some(FileFormat::Stl) => stl::load_stl(path),
        _ => Err(MeshError::UnsupportedFormat {
            path: path.to_path_buf(),
        }),
    }
}

/// Loads a point cloud, choosing the reader by extension: `.ply` (the vertex element of any
/// PLY, faces ignored; the common layout of `float x y z [nx ny nz] [uchar colours]`, binary
/// little-endian or ASCII, is decoded directly and in parallel, anything else by
/// [`ply::load_ply_points`]),
/// `.xyz`/`.txt` and `.pts` (see [`xyz`] for the column rules).
pub fn load_point_cloud(path: impl AsRef<Path>) -> Result<LoadedPointCloud, MeshError> {
    let path = path.as_ref();
    match FileFormat::from_path(path) {
        Some(FileFormat::Ply) => {
            if let Some(loaded) = ply_fast::read_simple_ply_file(path) {
                return Ok(loaded);
            }
            ply::load_ply_points(path)
        }
        Some(FileFormat::Xyz) => xyz::load_xyz(path, false),
        Some(FileFormat::Pts) => xyz::load_xyz(path, true),
        _ => Err(MeshError::UnsupportedFormat {
            path: path.to_path_buf(),
        }),
    }
}

/// Reads a whole file, mapping failure to [`MeshError::Io`] and an empty file to
/// [`MeshError::EmptyFile`].
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(MeshError::EmptyFile {
            path: path.to_path_buf(),
        });
    }
    Ok(bytes)
}

/// Mesh data as loaders collect it (f64 positions), turned into a [`TriangleMesh`] by
/// [`MeshBuilder::finish`].
#[derive(Default)]
pub(crate) struct MeshBuilder {
    pub(crate) positions: Vec<DVec3>,
    pub(crate) triangles: Vec<[u32; 3]>,
    pub(crate) face_uvs: Option<Vec<[Vec2; 3]>>,
    pub(crate) vertex_colours: Option<Vec<[u8; 4]>>,
    pub(crate) vertex_normals: Option<Vec<Vec3>>,
    pub(crate) face_materials: Vec<MaterialId>,
    pub(crate) materials: Vec<Material>,
}

impl MeshBuilder {
    /// Centres the positions on their f64 bounding-box centre and validates the result.
    pub(crate) fn finish(self, path: &Path) -> Result<TriangleMesh, MeshError> {
        if self.positions.len() >= u32::MAX as usize {
            return Err(MeshError::TooManyElements {
                path: path.to_path_buf(),
                kind: ElementKind::Vertices,
                count: self.positions.len() as u64,
            });
        }
        if self.triangles.len() >= u32::MAX as usize {
            return Err(MeshError::TooManyElements {
                path: path.to_path_buf(),
                kind: ElementKind::Triangles,
                count: self.triangles.len() as u64,
            });
        }
        if self.triangles.is_empty() {
            return Err(MeshError::NoFaces {
                path: path.to_path_buf(),
            });
        }
        let origin = world_bounds_centre(&self.positions);
        check_extent(path, &self.positions, origin)?;
        let mesh = TriangleMesh {
            origin,
            positions: self
                .positions
                .iter()
                .map(|&p| (p - origin).as_vec3())
                .collect(),
            triangles: self.triangles,
            face_uvs: self.face_uvs,
            vertex_colours: self.vertex_colours,
            vertex_normals: self.vertex_normals,
            face_materials: self.face_materials,
            materials: self.materials,
        };
        // Loaders check every value with its file index before this point, so a failure here
        // is a bug in the loader, reported with the broken invariant.
        mesh.validate()?;
        Ok(mesh)
    }
}

/// The largest distance (per axis) of a vertex from its mesh's centre: positions are stored
/// in f32 relative to that centre, and the geometry computed from them (squared lengths,
/// cross products) must stay finite in f32. A model spanning more is refused, naming its
/// farthest vertex.
pub const MAX_EXTENT: f64 = 1e15;

/// Refuses positions farther than [`MAX_EXTENT`] from `origin` on any axis.
fn check_extent(path: &Path, positions: &[DVec3], origin: DVec3) -> Result<(), MeshError> {
    let far = positions
        .iter()
        .enumerate()
        .map(|(i, &p)| (i, (p - origin).abs().max_element()))
        .max_by(|a, b| a.1.total_cmp(&b.1));
    match far {
        Some((vertex, distance)) if distance > MAX_EXTENT => Err(MeshError::ExtentTooLarge {
            path: path.to_path_buf(),
            vertex: vertex as u64,
            distance,
        }),
        _ => Ok(()),
    }
}

/// The text of a file with a leading UTF-8 byte-order mark removed (editors on Windows write
/// one; left in place it would hide the first keyword).
pub(crate) fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// Builds a cloud from f64 points, dropping the non-finite ones (and their colour and normal).
pub(crate) fn build_point_cloud(
    path: &Path,
    positions: Vec<DVec3>,
    colours: Option<Vec<[u8; 4]>>,
    normals: Option<Vec<Vec3>>,
    warnings: Vec<LoadWarning>,
) -> Result<LoadedPointCloud, MeshError> {
    let keep: Vec<bool> = positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            p.is_finite()
                && normals
                    .as_ref()
                    .is_none_or(|n| n.get(i).is_some_and(|n| n.is_finite()))
        })
        .collect();
    let kept = keep.iter().filter(|&&k| k).count();
    let dropped_non_finite = (positions.len() - kept) as u64;
    if kept == 0 {
        return Err(MeshError::NoPoints {
            path: path.to_path_buf(),
        });
    }
    let filter = |i: usize| keep[i];
    let world: Vec<DVec3> = positions
        .into_iter()
        .enumerate()
        .filter(|&(i, _)| filter(i))
        .map(|(_, p)| p)
        .collect();
    // The centre of the bulk, so a far outlier does not cost the real points their precision.
    let origin = crate::robust_centre(world.len(), |k| world[k]);
    let colours = colours.map(|c| {
        c.into_iter()
            .enumerate()
            .filter(|&(i, _)| filter(i))
            .map(|(_, c)| c)
            .collect()
    });
    let normals = normals.map(|n| {
        n.into_iter()
            .enumerate()
            .filter(|&(i, _)| filter(i))
            .map(|(_, n)| n)
            .collect()
    });
    Ok(LoadedPointCloud {
        cloud: PointCloud {
            origin,
            positions: world.iter().map(|&p| (p - origin).as_vec3()).collect(),
            colours,
            normals,
        },
        dropped_non_finite,
        warnings,
    })
}

/// Converts a colour channel in `0..=1` (or wider, clamped) to a byte.
#[inline]
pub(crate) fn unit_to_byte(v: f64) -> u8 {
    if v.is_nan() {
        0
    } else {
        (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
    }
}

/// Path for diagnostics and relative lookups: the directory holding `path`.
pub(crate) fn parent_dir(path: &Path) -> PathBuf {
    path.parent().map(Path::to_path_buf).unwrap_or_default()
}
