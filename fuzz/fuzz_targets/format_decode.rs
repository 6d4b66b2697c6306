//! Any bytes given to the container decoder give a scene or an error, never
//! a panic, a hang or a huge allocation.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = spatch_format::decode_scene(data);
});
