//! Any bytes in a `.pts` or `.xyz` text cloud give a cloud or an error, never a panic: with
//! the column rules, and with a 9-column `--columns` layout.
#![no_main]

use libfuzzer_sys::fuzz_target;
use spatch_scan::{load_scans, parse_columns, ScanOptions};

fuzz_target!(|data: &[u8]| {
    let mut layout = ScanOptions::default();
    layout.columns = Some(parse_columns("x,y,z,nx,ny,nz,r,g,b").expect("a valid layout"));
    for name in ["input.pts", "input.xyz"] {
        let path = spatch_fuzz::scratch_file(name);
        std::fs::write(&path, data).expect("scratch write");
        let _ = load_scans(&[path.clone()], &ScanOptions::default());
        let _ = load_scans(&[path], &layout);
    }
});
