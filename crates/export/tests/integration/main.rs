//! Integration tests of the exports.
//!
//! - `gltf_read_back`: `.gltf` and `.glb` exports read by the `gltf` crate
//!   (one mesh per patch, counts, accessor bounds, colours, placement).
//! - `far_precision`: scenes 1e4 to 1e7 from the origin (alone and merged)
//!   export within 1e-6 of their extent in PLY (double), OBJ and glTF, and
//!   with an explicit origin.

mod far_precision;
mod gltf_read_back;
mod scenes;
