//! Node colour from the source surface.
//!
//! Each filled node remembers the face and barycentric coordinates of its ray hit; its colour
//! is the source's colour there ([`TriangleMesh::colour_at`]): the material's texture sampled
//! bilinearly at the interpolated UV, times the interpolated vertex colour and the material's
//! base colour. A source with no colour gets no colour channel at all.
//!
//! A node of a textured face covers a cell of texture, not a point: it takes the mean of
//! [`FOOTPRINT_SAMPLES`]² samples spread over its cell (`±spacing/3` along the lattice axes,
//! carried along the patch axis onto the hit face's plane, kept inside the face so that no
//! sample reaches into another part of a texture atlas). The bilinear cells the renderer
//! draws between nodes then show the texture's local mean instead of aliasing it when the
//! spacing is coarser than a texel. Untextured colour is sampled at the hit alone, and so is
//! every colour when texture-aware fitting is off (`texels_per_node` 0).
//!
//! The scene's channel is RGBA8 when some node is not fully opaque, RGB8 otherwise.

use glam::Vec3;
use spatch_format::{ColourChannel, Patch};
use spatch_mesh::{FaceId, TriangleMesh};

/// The colour of a hit, or opaque black when the mesh has no colour there.
///
/// Public so that other producers (the sharp-edge patches of `spatch-edges`) colour nodes
/// exactly as the fitter does.
#[inline]
pub fn sample_colour(mesh: &TriangleMesh, face: FaceId, bary: [f32; 3]) -> [u8; 4] {
    mesh.colour_at(face, Vec3::from(bary))
        .unwrap_or([0, 0, 0, 255])
}

/// Samples per side of a textured node's footprint.
pub(crate) const FOOTPRINT_SAMPLES: usize = 3;

/// A node's cell on the lattice: its two spacing vectors and the patch axis (model space).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Footprint {
    pub(crate) ax: Vec3,
    pub(crate) ay: Vec3,
    pub(crate) axis: Vec3,
}

/// The colour of a node hitting `face` at `bary`: [`sample_colour`] for untextured faces or
/// without a footprint, the mean over the node's footprint on textured ones (module docs).
pub(crate) fn node_colour(
    mesh: &TriangleMesh,
    face: FaceId,
    bary: [f32; 3],
    footprint: Option<&Footprint>,
) -> [u8; 4] {
    let Some(footprint) = footprint else {
        return sample_colour(mesh, face, bary);
    };
    let textured =
        mesh.face_uvs.is_some() && mesh.material_of(face).is_some_and(|m| m.texture.is_some());
    if !textured {
        return sample_colour(mesh, face, bary);
    }
    let [a, b, c] = mesh.face_positions(face);
    let (e1, e2) = (b - a, c - a);
    let n = e1.cross(e2).normalize_or_zero();
    let facing = n.dot(footprint.axis);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    if facing.abs() < 1e-3 || !(det.is_finite() && det > 0.0) {
        return sample_colour(mesh, face, bary);
    }
    let w = Vec3::from(bary);
    let mut sum = [0u32; 4];
    let k = FOOTPRINT_SAMPLES as i32;
    for j in 0..k {
        for i in 0..k {
            let (u, v) = (offset(i, k), offset(j, k));
            let o = footprint.ax * u + footprint.ay * v;
            // Along the axis onto the face's plane, then into barycentric deltas.
            let d = o - footprint.axis * (o.dot(n) / facing);
            let (p, q) = (d.dot(e1), d.dot(e2));
            let beta = (g22 * p - g12 * q) / det;
            let gamma = (g11 * q - g12 * p) / det;
            let moved = (Vec3::new(w.x - beta - gamma, w.y + beta, w.z + gamma)).max(Vec3::ZERO);
            let total = moved.x + moved.y + moved.z;
            let at = if total > 0.0 { moved / total } else { w };
            let colour = mesh.colour_at(face, at).unwrap_or([0, 0, 0, 255]);
            for (s, c) in sum.iter_mut().zip(colour) {
                *s += u32::from(c);
            }
        }
    }
    let count = (FOOTPRINT_SAMPLES * FOOTPRINT_SAMPLES) as u32;
    sum.map(|s| ((s + count / 2) / count) as u8)
}

/// The offset, in cells, of sample `i` of `k` evenly spread over a cell centred on its
/// node (`-1/3, 0, 1/3` for `k = 3`).
fn offset(i: i32, k: i32) -> f32 {
    (2 * i - (k - 1)) as f32 / (2 * k) as f32
}

/// The narrowest colour channel that holds the colours of `patches`.
pub fn choose_channel(patches: &[Patch]) -> ColourChannel {
    let mut any = false;
    for patch in patches {
        let Some(colours) = patch.colours() else {
            continue;
        };
        any = true;
        for (c, &d) in colours.iter().zip(patch.displacements()) {
            if d != spatch_format::EMPTY && c[3] != 255 {
                return ColourChannel::Rgba8;
            }
        }
    }
    if any {
        ColourChannel::Rgb8
    } else {
        ColourChannel::None
    }
}
