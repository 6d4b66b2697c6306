//! Binary PLY writing of nodes and cells.
//!
//! Positions are `offset + local` computed in f64 and stored as f32 (the
//! PLY `float` type most tools expect). Cost: one pass over the nodes.

use spatch_format::{ColourChannel, Patch, Scene};

fn header(scene: &Scene, vertices: usize, faces: Option<usize>) -> String {
    let mut h = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by spatch {}\nelement vertex {vertices}\n\
         property float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\n",
        env!("CARGO_PKG_VERSION")
    );
    if scene.channel() != ColourChannel::None {
        h.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
    }
    if let Some(faces) = faces {
        h.push_str(&format!(
            "element face {faces}\nproperty list uchar int vertex_indices\n"
        ));
    }
    h.push_str("end_header\n");
    h
}

/// Appends one vertex record for node `(i, j)` of `patch`; returns false
/// (writing nothing) when the node is empty.
fn push_node(out: &mut Vec<u8>, scene: &Scene, patch: &Patch, i: usize, j: usize) -> bool {
    let (Some(local), Some(normal)) = (patch.node_position(i, j), patch.node_normal(i, j)) else {
        return false;
    };
    let world = scene.offset() + local.as_dvec3();
    for v in [
        world.x as f32,
        world.y as f32,
        world.z as f32,
        normal.x,
        normal.y,
        normal.z,
    ] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    if let Some(colours) = patch.colours() {
        out.extend_from_slice(&colours[patch.grid().index(i, j)][..3]);
    }
    true
}

/// The non-empty nodes of `scene` as a binary PLY point cloud.
pub fn export_nodes_ply(scene: &Scene) -> Vec<u8> {
    let mut body = Vec::new();
    let mut count = 0;
    for patch in scene.patches() {
        let (cols, rows) = (
            usize::from(patch.grid().cols()),
            usize::from(patch.grid().rows()),
        );
        for j in 0..rows {
            for i in 0..cols {
                count += usize::from(push_node(&mut body, scene, patch, i, j));
            }
        }
    }
    let mut out = header(scene, count, None).into_bytes();
    out.extend_from_slice(&body);
    out
}

/// The drawable cells of `scene` as a binary PLY triangle mesh.
pub fn export_cells_ply(scene: &Scene) -> Vec<u8> {
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    let mut vertex_count: u32 = 0;
    let mut face_count = 0usize;
    let mut index_of = Vec::new();
    for patch in scene.patches() {
        let (cols, rows) = (
            usize::from(patch.grid().cols()),
            usize::from(patch.grid().rows()),
        );
        index_of.clear();
        for j in 0..rows {
            for i in 0..cols {
                if push_node(&mut vertices, scene, patch, i, j) {
                    index_of.push(vertex_count);
                    vertex_count += 1;
                } else {
                    index_of.push(u32::MAX);
                }
            }
        }
        for j in 0..rows - 1 {
            for i in 0..cols - 1 {
                if !patch.cell_is_drawable(i, j) {
                    continue;
                }
                let at = |a: usize, b: usize| index_of[b * cols + a];
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                // Counter-clockwise seen from +z (the outward side).
                for tri in [[a, b, c], [a, c, d]] {
                    faces.push(3u8);
                    for v in tri {
                        faces.extend_from_slice(&(v as i32).to_le_bytes());
                    }
                    face_count += 1;
                }
            }
        }
    }
    let mut out = header(scene, vertex_count as usize, Some(face_count)).into_bytes();
    out.extend_from_slice(&vertices);
    out.extend_from_slice(&faces);
    out
}
