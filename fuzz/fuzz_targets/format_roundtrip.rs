//! Whatever decodes must encode again, and re-decode to the same scene, with
//! and without compression.
#![no_main]

use libfuzzer_sys::fuzz_target;
use spatch_format::{decode_scene, encode_scene, Compression, WriteOptions};

fuzz_target!(|data: &[u8]| {
    let Ok(scene) = decode_scene(data) else {
        return;
    };
    for compression in [Compression::None, Compression::Predictive] {
        let bytes = encode_scene(&scene, &WriteOptions::with_compression(compression))
            .expect("a decoded scene encodes");
        assert_eq!(decode_scene(&bytes).expect("re-decodes"), scene);
    }
});
