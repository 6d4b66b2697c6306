//! Preparation, once per scene and reused by every frame: what does not
//! depend on the view. In use order (each uses only those above it): the
//! eight-lane vectors of its kernels, normal reconstruction and the slots
//! of node differences, the normal buffer, the corner fill and the level-1
//! cells drawn by quarters, the mip pyramid, how far a level strays from
//! the one below, the normal cone, a level's shading inputs, the prepared
//! patch, the openings as portals, overlap trimming, the prepared scene.

pub(crate) mod coarse_fit;
pub(crate) mod cone;
pub(crate) mod corner_fill;
pub(crate) mod level_shading;
pub(crate) mod mip;
#[cfg(test)]
mod mip_tests;
pub(crate) mod normal_buffer;
pub(crate) mod normals;
pub(crate) mod overlap;
pub(crate) mod patch;
#[cfg(test)]
mod patch_tests;
pub(crate) mod portals;
pub(crate) mod quarters;
pub(crate) mod scene;
pub(crate) mod wide;
