//! Integration tests of spatch-edges (one binary, as the workspace's test layout asks).
//!
//! - `surface`: the surface patches of a mesh, fitted as `spatch convert` does (helper);
//! - `detection`: sharp edges, chains and corners of a cube, a cylinder and a sphere;
//! - `patches`: edge patches lie on the source and cover both faces of a crease;
//! - `crease_sweep`: frustums whose rim angle runs from 30° to 150° keep no holes;
//! - `cad_targets`: the targets on the shared CAD parts (skipped when missing);
//! - `covered_pieces`: pieces the other patches cover lose their patch, holes unchanged;
//! - `joined_pieces`: pieces meeting at a crease vertex share a patch, holes unchanged;
//! - `determinism`: same input, same patches, whatever the thread count;
//! - `turned_cube`: a meshed cube turned about random axes needs no more crease patches and
//!   leaves no more holes than the axis-aligned one.

mod cad_targets;
mod coverage;
mod covered_pieces;
mod crease_sweep;
mod detection;
mod determinism;
mod joined_pieces;
mod patches;
mod surface;
mod turned_cube;
