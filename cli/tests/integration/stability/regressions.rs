//! Every input under `testdata/regression/` goes through its reader without a panic.

use std::path::PathBuf;

/// The files of `testdata/regression/<target>`, sorted.
fn inputs(target: &str) -> Vec<PathBuf> {
    spatch_fixtures::regression_inputs(target)
}

/// Bytes through the container decoder (as the `format_decode` target): a scene or an
/// error, never a panic; a decoded scene encodes again.
#[test]
fn format_decode_inputs() {
    for path in inputs("format_decode") {
        let bytes = std::fs::read(&path).unwrap();
        if let Ok(scene) = spatch_format::decode_scene(&bytes) {
            spatch_format::encode_scene(&scene, &spatch_format::WriteOptions::default())
                .unwrap_or_else(|e| panic!("{}: decoded but cannot encode: {e}", path.display()));
        }
    }
}

/// A file through the mesh and point-cloud loaders under the extension its target gives it.
fn load_as(target: &str, extension: &str) {
    let dir = tempfile::tempdir().unwrap();
    let scratch = dir.path().join(format!("input.{extension}"));
    for path in inputs(target) {
        std::fs::copy(&path, &scratch).unwrap();
        let _ = spatch_mesh::load_mesh(&scratch);
        let _ = spatch_mesh::load_point_cloud(&scratch);
    }
}

/// PLY inputs (as the `ply_load` target).
#[test]
fn ply_load_inputs() {
    load_as("ply_load", "ply");
}

/// OBJ inputs (as the `obj_load` target).
#[test]
fn obj_load_inputs() {
    load_as("obj_load", "obj");
}

/// LAS/LAZ inputs (as the `las_load` target) through the scan reader: a cloud or an error,
/// never a panic, and no allocation the file's bytes do not justify (the `oom-*` input
/// declares 58 KB records and made one chunk allocate 3.8 GB).
#[test]
fn las_load_inputs() {
    let dir = tempfile::tempdir().unwrap();
    for path in inputs("las_load") {
        for name in ["input.las", "input.laz"] {
            let scratch = dir.path().join(name);
            std::fs::copy(&path, &scratch).unwrap();
            let _ = spatch_scan::load_scans(&[scratch], &spatch_scan::ScanOptions::default());
        }
    }
}
