//! Atomic writes.

use spatch_format::{read_scene, write_file_atomically, write_scene, WriteOptions};

use crate::scenes::minimal_scene;

#[test]
fn a_written_scene_reads_back_and_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.spatch");
    write_scene(&path, &minimal_scene(), &WriteOptions::default()).unwrap();
    assert_eq!(read_scene(&path).unwrap(), minimal_scene());
    let names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}");
}

#[test]
fn a_failed_write_leaves_the_old_file_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.bin");
    std::fs::write(&path, b"old").unwrap();
    // The target is a directory that does not exist: the write fails.
    let missing = dir.path().join("no/such/folder/out.bin");
    assert!(write_file_atomically(&missing, b"new").is_err());
    assert!(!missing.exists());
    // Overwriting works and is complete.
    write_file_atomically(&path, b"new").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"new");
}
