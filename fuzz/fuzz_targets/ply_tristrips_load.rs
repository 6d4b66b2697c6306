//! A PLY header with a `tristrips` element, then any bytes as the body (ASCII): the loader
//! gives a mesh or an error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

/// Eight vertices and two strip lists, so fuzzed bodies reach the strip code quickly.
const HEADER: &[u8] = b"ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\n\
property float y\nproperty float z\nelement tristrips 2\n\
property list int int vertex_indices\nend_header\n";

fuzz_target!(|data: &[u8]| {
    spatch_fuzz::load_mesh_after(HEADER, data, "input.ply");
});
