//! Planning, once per frame and patch: everything decided before any
//! pixel is touched, into flat per-chunk work for the bands. In use order:
//! culling, which backs to cull (the portal test), splitting, lane
//! conversions, the node positions' scratch, projection, cell measurement,
//! the level-1 cells drawn by quarters, subdivision, counters, the chunk's
//! work and the per-patch context, the mip level, attributes, cells as
//! triangles, the drawer of a piece, the piece, the chunk, meshes.

pub(crate) mod attributes;
pub(crate) mod cell_triangles;
pub(crate) mod chunk;
pub(crate) mod counters;
pub(crate) mod cull;
pub(crate) mod drawer;
pub(crate) mod lanes;
pub(crate) mod level_choice;
pub(crate) mod measure;
#[cfg(test)]
mod measure_tests;
pub(crate) mod mesh;
pub(crate) mod node_xy;
pub(crate) mod open_sides;
pub(crate) mod piece;
pub(crate) mod project;
pub(crate) mod quartered;
pub(crate) mod sides;
pub(crate) mod split;
pub(crate) mod subdivision;
pub(crate) mod work;
