//! Any bytes in an `.stl` file give a mesh or an error from the loader, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let path = spatch_fuzz::scratch_file("input.stl");
    std::fs::write(&path, data).expect("scratch write");
    let _ = spatch_mesh::load_mesh(&path);
});
