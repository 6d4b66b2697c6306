//! Binary little-endian PLY writing of patch meshes or points.
//!
//! Vertices carry `x y z` (`float`, or `double` when
//! [`crate::precision::needs_f64`] says f32 would lose precision),
//! `nx ny nz` (float) and `red green blue` (uchar) when the scene has
//! colour; meshes add a `face` element of `vertex_indices` (uchar count,
//! int indices). Patches follow each other in the vertex list; a patch's
//! triangles index its own vertices only. Positions are `world - origin`
//! computed in f64; a non-zero origin is recorded in a `comment origin X Y Z`
//! header line (full f64 precision), so `world = written + origin`.
//!
//! Cost: one pass over the vertices and one over the triangles.

use glam::DVec3;

use crate::PatchMesh;

fn header(
    meshes: &[PatchMesh],
    coloured: bool,
    doubles: bool,
    origin: DVec3,
    faces: bool,
) -> String {
    let vertices: usize = meshes.iter().map(|m| m.positions.len()).sum();
    let number = if doubles { "double" } else { "float" };
    let mut h = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by spatch {}\n",
        env!("CARGO_PKG_VERSION")
    );
    if origin != DVec3::ZERO {
        h.push_str(&format!(
            "comment origin {} {} {} (model position = written position + origin)\n",
            origin.x, origin.y, origin.z
        ));
    }
    h.push_str(&format!(
        "element vertex {vertices}\nproperty {number} x\nproperty {number} y\nproperty {number} z\n\
         property float nx\nproperty float ny\nproperty float nz\n"
    ));
    if coloured {
        h.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
    }
    if faces {
        let count: usize = meshes.iter().map(|m| m.triangles.len()).sum();
        h.push_str(&format!(
            "element face {count}\nproperty list uchar int vertex_indices\n"
        ));
    }
    h.push_str("end_header\n");
    h
}

/// `meshes` as one binary PLY file: points only, or with faces when
/// `faces` is set. `coloured` adds the colour properties (every mesh must
/// then have colours); positions are written minus `origin`, as f64 when
/// `doubles` is set.
pub fn write_ply(
    meshes: &[PatchMesh],
    coloured: bool,
    doubles: bool,
    origin: DVec3,
    faces: bool,
) -> Vec<u8> {
    let mut out = header(meshes, coloured, doubles, origin, faces).into_bytes();
    for mesh in meshes {
        for (k, normal) in mesh.normals.iter().enumerate() {
            let p = mesh.world_position(k) - origin;
            if doubles {
                for v in p.to_array() {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            } else {
                for v in p.as_vec3().to_array() {
                    out.extend_from_slice(&v.to_le_bytes());
                }
            }
            for v in normal.to_array() {
                out.extend_from_slice(&v.to_le_bytes());
            }
            if coloured {
                let c = mesh.colours.as_ref().map_or([255; 4], |c| c[k]);
                out.extend_from_slice(&c[..3]);
            }
        }
    }
    if faces {
        let mut first = 0u32;
        for mesh in meshes {
            for triangle in &mesh.triangles {
                out.push(3);
                for v in triangle {
                    out.extend_from_slice(&((first + v) as i32).to_le_bytes());
                }
            }
            first += mesh.positions.len() as u32;
        }
    }
    out
}
