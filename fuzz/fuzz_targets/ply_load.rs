//! Any bytes in a `.ply` file give a mesh, a point cloud or an error from
//! the loaders, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = spatch_fuzz::scratch_file("input.ply");
    std::fs::write(&path, data).expect("scratch write");
    let _ = spatch_mesh::load_mesh(&path);
    let _ = spatch_mesh::load_point_cloud(&path);
});
