//! A PLY header with a 4 × 3 `range_grid` (a raw range scan's layout), then any bytes as the
//! body (ASCII vertices, then the grid's lists): the loader gives a mesh or an error, never a
//! panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

/// Twelve vertices and a 4 × 3 grid, so fuzzed bodies reach the grid code quickly.
const HEADER: &[u8] = b"ply\nformat ascii 1.0\nobj_info num_cols 4\nobj_info num_rows 3\n\
element vertex 12\nproperty float x\nproperty float y\nproperty float z\n\
element range_grid 12\nproperty list uchar int vertex_indices\nend_header\n";

fuzz_target!(|data: &[u8]| {
    spatch_fuzz::load_mesh_after(HEADER, data, "input.ply");
});
