//! Any bytes in a `.glb`/`.gltf` file give a mesh or an error from the loader, never a panic
//! (JSON, accessors, quantized attributes, meshopt-compressed views).
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let name = if data.starts_with(b"glTF") {
        "input.glb"
    } else {
        "input.gltf"
    };
    let path = spatch_fuzz::scratch_file(name);
    std::fs::write(&path, data).expect("scratch write");
    let _ = spatch_mesh::load_mesh(&path);
});
