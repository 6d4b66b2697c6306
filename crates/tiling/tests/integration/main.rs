//! Integration tests of spatch-tiling: the streamed readers against each other, plans,
//! and per-tile conversion joining into the untiled conversion.

mod join;
mod mesh_owners;
mod mesh_plan;
mod mesh_stream;
mod plan_json;
mod readers;
mod scan_sets;
mod spill;

use std::path::Path;

use spatch_fixtures::Cityscape;

/// Writes `city` as binary little-endian PLY (float xyz, uchar rgb).
pub(crate) fn write_city_ply(city: &Cityscape, path: &Path) {
    city.write_binary_ply(path, false).unwrap();
}
