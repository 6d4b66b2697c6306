//! One mesh tile read from a PLY or OBJ file without loading the mesh: memory follows the
//! tile, plus one byte per vertex of the file.
//!
//! Three streamed passes:
//! 1. vertices: each gets a one-byte **side code** against the tile's buffered box (per
//!    axis a bit for below `min` and one for above `max`), from its position as the part
//!    will hold it (the plan's anchor plus an f32 offset);
//! 2. polygons: a polygon touches the box unless all its corners share a side bit (the
//!    closed-box test on its bounding box); those that touch are kept, with their vertex
//!    indices;
//! 3. vertices again: the positions (and PLY colours and normals) of the vertices the kept
//!    polygons use.
//!
//! The kept polygons are split into triangles as the mesh loader splits them
//! (`spatch_mesh::triangulate_polygon` on the file's positions), and the part's origin is
//! the plan's anchor, so every tile holding a face computes the same world centroid for it
//! (the ownership rule of `mesh_tiles.rs`). What stays O(input): the side codes (one byte
//! per vertex) and the time of three passes over the file.

use std::path::Path;

use glam::{DVec3, Vec3};
use spatch_mesh::{triangulate_polygon, TriangleMesh};

use crate::obj_stream::{obj_is_plain, stream_obj, ObjVisitor};
use crate::plan::WorldBox;
use crate::ply_faces::stream_ply_faces;
use crate::ply_stream::stream_ply;
use crate::stream::PointChunk;
use crate::TilingError;

/// The two streamed mesh formats.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Format {
    Ply,
    Obj,
}

/// Whether [`read_mesh_tile`] streams `path`: a PLY, or an OBJ of plain geometry (no
/// materials, no texture coordinates; reading the file once to find out).
pub fn can_stream_mesh(path: &Path) -> Result<bool, TilingError> {
    Ok(match format_of(path) {
        Some(Format::Ply) => true,
        Some(Format::Obj) => obj_is_plain(path)?,
        None => false,
    })
}

pub(crate) fn format_of(path: &Path) -> Option<Format> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    match ext.as_str() {
        "ply" => Some(Format::Ply),
        "obj" => Some(Format::Obj),
        _ => None,
    }
}

/// The faces of the mesh at `path` whose box touches `area`, as a mesh at origin `anchor`
/// (PLY vertex colours and normals kept), read in three streamed passes (see the module
/// docs). Errors: [`TilingError::UnsupportedFormat`] for a file [`can_stream_mesh`] refuses,
/// the readers' I/O and format errors, a corner naming no vertex.
pub fn read_mesh_tile(
    path: &Path,
    anchor: DVec3,
    area: &WorldBox,
) -> Result<TriangleMesh, TilingError> {
    let format = format_of(path).ok_or_else(|| TilingError::UnsupportedFormat {
        path: path.to_path_buf(),
    })?;
    let (min, max) = (DVec3::from_array(area.min), DVec3::from_array(area.max));
    let mut codes = Vec::new();
    each_vertex(path, format, &mut |p, _, _| {
        codes.push(side_code(
            anchor + (p - anchor).as_vec3().as_dvec3(),
            min,
            max,
        ));
        Ok(())
    })?;
    let (polygons, needed) = touching_polygons(path, format, &codes)?;
    drop(codes);
    let part = needed_vertices(path, format, &needed)?;
    Ok(assemble(anchor, &part, &polygons, &needed))
}

/// The per-axis below/above bits of `p` against the closed box `[min, max]`.
fn side_code(p: DVec3, min: DVec3, max: DVec3) -> u8 {
    (0..3).fold(0, |code, k| {
        code | (u8::from(p[k] < min[k]) << (2 * k)) | (u8::from(p[k] > max[k]) << (2 * k + 1))
    })
}

/// Visits every vertex of the file in order: position, then colour and normal when the
/// file has them.
pub(crate) fn each_vertex(
    path: &Path,
    format: Format,
    visit: &mut dyn FnMut(DVec3, Option<[u8; 4]>, Option<Vec3>) -> Result<(), TilingError>,
) -> Result<u64, TilingError> {
    match format {
        Format::Ply => stream_ply(path, &mut |chunk: &PointChunk| {
            for (i, &p) in chunk.positions.iter().enumerate() {
                let colour = chunk.colours.as_ref().map(|c| c[i]);
                visit(p, colour, chunk.normals.as_ref().map(|n| n[i]))?;
            }
            Ok(())
        }),
        Format::Obj => stream_obj(
            path,
            &mut ObjVisitor {
                vertex: &mut |p| visit(p, None, None),
                polygon: None,
            },
        ),
    }
}

/// Kept polygons, flat: their vertex indices and where each polygon ends.
#[derive(Debug, Default)]
struct Polygons {
    corners: Vec<u32>,
    ends: Vec<usize>,
}

/// The polygons whose corners' codes share no side bit, and the sorted distinct vertices
/// they use.
fn touching_polygons(
    path: &Path,
    format: Format,
    codes: &[u8],
) -> Result<(Polygons, Vec<u32>), TilingError> {
    let mut kept = Polygons::default();
    let mut keep = |polygon: &[u32]| -> Result<(), TilingError> {
        let mut shared = u8::MAX;
        for &v in polygon {
            let code = codes.get(v as usize).ok_or_else(|| {
                let n = codes.len();
                TilingError::malformed(path, format!("a face names vertex {v} (from 0) of {n}"))
            })?;
            shared &= code;
        }
        if polygon.len() >= 3 && shared == 0 {
            kept.corners.extend_from_slice(polygon);
            kept.ends.push(kept.corners.len());
        }
        Ok(())
    };
    each_polygon(path, format, &mut keep)?;
    let mut needed = kept.corners.clone();
    needed.sort_unstable();
    needed.dedup();
    Ok((kept, needed))
}

/// Visits every polygon of the file in order, as its 0-based vertex indices.
pub(crate) fn each_polygon(
    path: &Path,
    format: Format,
    visit: &mut dyn FnMut(&[u32]) -> Result<(), TilingError>,
) -> Result<(), TilingError> {
    match format {
        Format::Ply => {
            stream_ply_faces(path, visit)?;
        }
        Format::Obj => {
            stream_obj(
                path,
                &mut ObjVisitor {
                    vertex: &mut |_| Ok(()),
                    polygon: Some(visit),
                },
            )?;
        }
    }
    Ok(())
}

/// The needed vertices' file positions, colours and normals, in `needed` order.
#[derive(Debug, Default)]
struct PartVertices {
    positions: Vec<DVec3>,
    colours: Option<Vec<[u8; 4]>>,
    normals: Option<Vec<Vec3>>,
}

/// Reads the vertices `needed` (sorted) from the file.
fn needed_vertices(
    path: &Path,
    format: Format,
    needed: &[u32],
) -> Result<PartVertices, TilingError> {
    let mut part = PartVertices::default();
    let (mut index, mut next) = (0u32, 0usize);
    each_vertex(path, format, &mut |p, colour, normal| {
        if needed.get(next) == Some(&index) {
            part.positions.push(p);
            if let Some(c) = colour {
                part.colours.get_or_insert_with(Vec::new).push(c);
            }
            if let Some(n) = normal {
                part.normals.get_or_insert_with(Vec::new).push(n);
            }
            next += 1;
        }
        index += 1;
        Ok(())
    })?;
    Ok(part)
}

/// The part mesh: the kept polygons split into triangles over the needed vertices.
fn assemble(
    anchor: DVec3,
    part: &PartVertices,
    polygons: &Polygons,
    needed: &[u32],
) -> TriangleMesh {
    let local = |v: u32| needed.binary_search(&v).unwrap_or(0) as u32;
    let (mut triangles, mut split, mut points) = (Vec::new(), Vec::new(), Vec::new());
    let mut start = 0;
    for &end in &polygons.ends {
        let corners = &polygons.corners[start..end];
        start = end;
        if let [a, b, c] = *corners {
            triangles.push([local(a), local(b), local(c)]);
            continue;
        }
        points.clear();
        points.extend(corners.iter().map(|&v| part.positions[local(v) as usize]));
        split.clear();
        triangulate_polygon(&points, &mut split);
        triangles.extend(split.iter().map(|t| t.map(|k| local(corners[k as usize]))));
    }
    TriangleMesh {
        origin: anchor,
        positions: part
            .positions
            .iter()
            .map(|&p| (p - anchor).as_vec3())
            .collect(),
        triangles,
        vertex_colours: part.colours.clone(),
        vertex_normals: part.normals.clone(),
        ..TriangleMesh::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn side_codes_share_a_bit_only_when_the_box_is_missed() {
        let (min, max) = (DVec3::ZERO, DVec3::ONE);
        let code = |x, y, z| side_code(DVec3::new(x, y, z), min, max);
        assert_eq!(code(0.5, 0.5, 0.5), 0);
        assert_eq!(code(1.0, 0.0, 1.0), 0, "the box is closed");
        // Both left of the box: missed.
        assert_ne!(code(-1.0, 0.5, 0.5) & code(-2.0, 3.0, 0.5), 0);
        // On both sides of it: may cross it, kept.
        assert_eq!(code(-1.0, 0.5, 0.5) & code(2.0, 0.5, 0.5), 0);
    }
}
