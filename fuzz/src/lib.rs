//! Shared pieces of the fuzz targets.

use std::path::{Path, PathBuf};

/// A file path in a folder private to this fuzzing process (in memory under
/// /dev/shm when it exists): the mesh loaders read paths, so each input is
/// written there first.
pub fn scratch_file(name: &str) -> PathBuf {
    let base = if Path::new("/dev/shm").is_dir() {
        PathBuf::from("/dev/shm")
    } else {
        std::env::temp_dir()
    };
    let dir = base.join(format!("spatch-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    dir.join(name)
}

/// Loads `header` followed by `body` as a mesh from a scratch file named `name` (the
/// targets that fuzz a PLY body after a fixed header); the result is dropped, so only a
/// panic fails.
pub fn load_mesh_after(header: &[u8], body: &[u8], name: &str) {
    let path = scratch_file(name);
    let mut bytes = header.to_vec();
    bytes.extend_from_slice(body);
    std::fs::write(&path, bytes).expect("scratch write");
    let _ = spatch_mesh::load_mesh(&path);
}
