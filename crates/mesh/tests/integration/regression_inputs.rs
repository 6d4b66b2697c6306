//! Inputs of the STL, glTF, tristrips and range-grid fuzz targets kept under `testdata/regression/`
//! (seeds and corpus samples that reach the readers' error paths): each loads or fails with
//! a one-line error, never a panic.

use std::path::PathBuf;

/// The files of `testdata/regression/<target>`, sorted.
fn inputs(target: &str) -> Vec<PathBuf> {
    spatch_fixtures::regression_inputs(target)
}

/// Loads every input of `target` as its fuzz target does (`prefix` before the bytes, the
/// extension `extension`); returns how many loaded.
fn replay(target: &str, prefix: &[u8], extension: &str) -> usize {
    let dir = tempfile::tempdir().unwrap();
    let scratch = dir.path().join(format!("input.{extension}"));
    let mut loaded = 0;
    for path in inputs(target) {
        let mut bytes = prefix.to_vec();
        bytes.extend_from_slice(&std::fs::read(&path).unwrap());
        std::fs::write(&scratch, bytes).unwrap();
        match spatch_mesh::load_mesh(&scratch) {
            Ok(_) => loaded += 1,
            Err(e) => assert!(!e.to_string().contains('\n'), "{}: {e}", path.display()),
        }
    }
    loaded
}

#[test]
fn stl_load_inputs() {
    assert!(replay("stl_load", b"", "stl") > 0);
}

#[test]
fn gltf_load_inputs() {
    replay("gltf_load", b"", "glb");
}

#[test]
fn ply_tristrips_load_inputs() {
    // The target's header: eight vertices, two strip lists.
    let header = b"ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\n\
property float y\nproperty float z\nelement tristrips 2\n\
property list int int vertex_indices\nend_header\n";
    assert!(replay("ply_tristrips_load", header, "ply") > 0);
}

#[test]
fn ply_range_grid_load_inputs() {
    // The target's header: twelve vertices, a 4 × 3 grid.
    let header = b"ply\nformat ascii 1.0\nobj_info num_cols 4\nobj_info num_rows 3\n\
element vertex 12\nproperty float x\nproperty float y\nproperty float z\n\
element range_grid 12\nproperty list uchar int vertex_indices\nend_header\n";
    // The seeds load (whole, with holes, with a depth jump) or fail on one line (a bad
    // index, a list of two, a short grid).
    assert!(replay("ply_range_grid_load", header, "ply") >= 3);
}
