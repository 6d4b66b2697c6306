//! Integration tests of spatch-render (one binary; one module per area).
//!
//! - `sphere`: the perfect sphere from a known camera — silhouette against
//!   the analytic circle, no holes at 250² to 2000², centre depth.
//! - `near_plane`: camera inside the sphere, near plane cutting patches,
//!   nothing drawn from behind the eye.
//! - `modes`: triangle mode against patch mode, 1 against N threads,
//!   projection / cell / shading / mip / supersampling variants.
//! - `mesh`: the public triangle rasterizer on plain meshes.
//! - `big_cells`: cells large on screen — the triangle path reads colour
//!   grids, magnified cells at a slant lie at their exact depth.
//! - `camera`: degenerate cameras and options refused.
//! - `crease`: a patch bent over a crease keeps its front lit with
//!   back-face culling (issue 21 item 3).
//! - `level_one`: level 1 past the mip limit keeps level 0's outline.
//! - `layers`: the modules of `src/` form one layered order without
//!   import circles (reads the sources).

mod big_cells;
mod camera;
mod common;
mod crease;
mod layers;
mod level_one;
mod mesh;
mod modes;
mod near_plane;
mod sphere;
