//! Any bytes in a `.las` or `.laz` file give a cloud or an error from the scan reader, never
//! a panic, a hang or a huge allocation (a header's point count is not trusted).
#![no_main]

use libfuzzer_sys::fuzz_target;
use spatch_scan::{load_scans, ScanOptions};

fuzz_target!(|data: &[u8]| {
    for name in ["input.las", "input.laz"] {
        let path = spatch_fuzz::scratch_file(name);
        std::fs::write(&path, data).expect("scratch write");
        let _ = load_scans(&[path], &ScanOptions::default());
    }
});
