//! Golden files: committed bytes that must decode forever.
//!
//! To regenerate after a deliberate format change (a new version!), run
//! `SPATCH_BLESS=1 cargo test -p spatch-format golden` and update the hex
//! walk-through in docs/format.md.

use std::path::PathBuf;

use spatch_format::{decode_scene, encode_scene, WriteOptions};

use crate::scenes::minimal_scene;

fn testdata(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/format")
        .join(name)
}

#[test]
fn v1_minimal_decodes_to_the_documented_scene() {
    let path = testdata("v1_minimal.spatch");
    let encoded = encode_scene(&minimal_scene(), &WriteOptions::default()).unwrap();
    if std::env::var_os("SPATCH_BLESS").is_some() {
        std::fs::write(&path, &encoded).unwrap();
    }
    let bytes = std::fs::read(&path).expect("testdata/format/v1_minimal.spatch is committed");
    assert_eq!(
        bytes.len(),
        197,
        "the walk-through in docs/format.md covers 197 bytes"
    );
    assert_eq!(decode_scene(&bytes).unwrap(), minimal_scene());
    assert_eq!(
        encoded, bytes,
        "the writer no longer produces the golden bytes"
    );
}
