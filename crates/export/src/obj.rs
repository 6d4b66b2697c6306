//! Wavefront OBJ writing of patch meshes or points.
//!
//! Text, so positions keep f64 precision: each `v` line holds
//! `world - origin` printed as the shortest decimal that reads back as the
//! same f64. Colours use the common `v x y z r g b` extension (values in
//! 0..=1, sRGB as stored) that MeshLab, Blender and trimesh read; normals are
//! `vn` lines with the same index as their vertex. Each patch with faces is
//! an `o patch_<index>` object whose faces are `f a//a b//b c//c`; points
//! are `v`/`vn` lines only (how point clouds travel in OBJ). A non-zero
//! origin is recorded in a `# origin X Y Z` comment.
//!
//! Cost: one pass over the vertices and one over the triangles; about 80
//! bytes of text per vertex.

use std::fmt::Write;

use glam::DVec3;

use crate::PatchMesh;

/// `meshes` as OBJ text (faces when `faces` is set, points otherwise),
/// positions minus `origin`.
pub fn write_obj(meshes: &[PatchMesh], origin: DVec3, faces: bool) -> Vec<u8> {
    let mut out = format!("# written by spatch {}\n", env!("CARGO_PKG_VERSION"));
    if origin != DVec3::ZERO {
        // Writing to a String cannot fail.
        let _ = writeln!(
            out,
            "# origin {} {} {} (model position = written position + origin)",
            origin.x, origin.y, origin.z
        );
    }
    let mut first = 1usize;
    for mesh in meshes {
        if faces {
            let _ = writeln!(out, "o patch_{}", mesh.patch);
        }
        for (k, n) in mesh.normals.iter().enumerate() {
            let p = mesh.world_position(k) - origin;
            let _ = write!(out, "v {} {} {}", p.x, p.y, p.z);
            if let Some(colours) = &mesh.colours {
                let [r, g, b, _] = colours[k].map(|c| f32::from(c) / 255.0);
                let _ = write!(out, " {r} {g} {b}");
            }
            let _ = writeln!(out, "\nvn {} {} {}", n.x, n.y, n.z);
        }
        if faces {
            for t in &mesh.triangles {
                let [a, b, c] = t.map(|v| first + v as usize);
                let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
            }
        }
        first += mesh.positions.len();
    }
    out.into_bytes()
}
