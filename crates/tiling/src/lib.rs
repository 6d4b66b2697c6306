//! Scale-out conversion of large point clouds: streamed readers, tile plans, one tile's
//! points, and tiled scene indexes.
//!
//! A plan ([`make_plan`], `spatch plan`) fixes a grid and the options every tile shares;
//! each tile is then converted on its own ([`read_tile_points`] gives its points and its
//! buffer's, the cloud pipeline with `tile_grid` and `only_tile` keeps the patches it
//! owns), on one machine or many (a local run spills every tile's points in one pass:
//! [`spill_tiles`]); [`build_index`] lists the tile files as a tiled scene that a viewer
//! opens tile by tile ([`ViewPyramid`] decides which), with a coarse level of the whole
//! scene in one file ([`coarse_scene`]). The readers ([`stream_points`]) hand out
//! chunks and never load a whole input; a `.conf` scan set or an E57 file streams its
//! scans, each chunk moved by its scan's pose and numbered by its scan, so that each tile
//! knows its points' scanners and the scans are aligned once for every tile
//! ([`spilled_scan_shifts`], kept in the plan).
//!
//! Meshes are tiled by face ([`make_mesh_plan`], or [`census_mesh_file`] streamed from a
//! PLY or plain OBJ; [`mesh_tile`], [`read_mesh_tile`]; a tile segments the faces
//! whose centroid it owns and makes the edge patches of the creases whose midpoint it owns:
//! [`TileOwner`]).
//!
//! Running at scale, the JSON schemas and measured figures: `docs/scale.md`.
#![forbid(unsafe_code)]

mod coarse;
mod error;
mod index;
mod las_stream;
mod mesh_plan;
mod mesh_stream;
mod mesh_tiles;
mod obj_stream;
mod plan;
mod ply_faces;
mod ply_stream;
mod scan_align;
mod scan_stream;
mod select;
mod spill;
mod stream;
mod view;
mod xyz_stream;

pub use coarse::{coarse_patch, coarse_scene, COARSE_FILE, COARSE_STEP};
pub use error::TilingError;
pub use index::{
    build_index, is_index_file, tile_file_name, CoarseLevel, IndexTile, SceneIndex, INDEX_VERSION,
};
pub use mesh_plan::{census_mesh, census_mesh_file, make_mesh_plan, MeshCensus};
pub use mesh_stream::{can_stream_mesh, read_mesh_tile};
pub use mesh_tiles::{mesh_tile, owns, patch_anchor, TileOwner};
pub use plan::{make_plan, Plan, PlanGrid, PlanOptions, PlanTile, WorldBox, PLAN_VERSION};
pub use scan_align::{spilled_scan_shifts, tile_scanners};
pub use select::{is_member, read_tile, read_tile_points, TileCloud};
pub use spill::{read_spilled_tile, spill_tiles, Spill, SpillLayout, SpilledTile, SPILL_BUDGET};
pub use stream::{stream_points, PointChunk, Visit, CHUNK_POINTS};
pub use view::ViewPyramid;
