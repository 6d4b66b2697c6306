//! Node colour from the source surface.
//!
//! Each filled node remembers the face and barycentric coordinates of its ray hit; its colour
//! is the source's colour there ([`TriangleMesh::colour_at`]): the material's texture sampled
//! bilinearly at the interpolated UV, times the interpolated vertex colour and the material's
//! base colour. A source with no colour gets no colour channel at all.
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
