//! Structured scans say where their scanner was: a PLY with a `range_grid` written by hand
//! and an E57 scan with row and column indices (written by the `e57` crate) are read back
//! with sight lines (unit vectors toward the scanner, from each scan's posed viewpoint), also
//! after a pose turns the scan over; the grids can be ignored; unstructured scans get none.

use std::path::{Path, PathBuf};

use e57::{E57Writer, Record, RecordDataType, RecordName, RecordValue};
use glam::DVec3;
use spatch_scan::{load_scans, LoadedScans, ScanOptions};

/// The plane `z = 0.3 x − 0.2 y` sampled on a `rows × cols` grid of 1 mm steps, with the
/// cells of `hole` empty: an ASCII PLY in the Stanford raw-scan layout (vertices, then one
/// `vertex_indices` list of 0 or 1 index per cell, row-major).
fn write_plane_scan(path: &Path, rows: usize, cols: usize, hole: impl Fn(usize, usize) -> bool) {
    let mut vertices = String::new();
    let mut cells = String::new();
    let mut count = 0;
    for r in 0..rows {
        for c in 0..cols {
            if hole(r, c) {
                cells.push_str("0\n");
                continue;
            }
            let (x, y) = (c as f64 * 0.001, r as f64 * 0.001);
            vertices.push_str(&format!("{x} {y} {}\n", 0.3 * x - 0.2 * y));
            cells.push_str(&format!("1 {count}\n"));
            count += 1;
        }
    }
    let header = format!(
        "ply\nformat ascii 1.0\nobj_info is_cyberware_data 1\nobj_info num_cols {cols}\n\
         obj_info num_rows {rows}\nelement vertex {count}\nproperty float x\n\
         property float y\nproperty float z\nelement range_grid {}\n\
         property list uchar int vertex_indices\nend_header\n",
        rows * cols
    );
    std::fs::write(path, header + &vertices + &cells).unwrap();
}

fn load(paths: &[PathBuf], ignore_range_grids: bool) -> LoadedScans {
    let mut options = ScanOptions::default();
    options.ignore_range_grids = ignore_range_grids;
    load_scans(paths, &options).unwrap()
}

/// Asserts every sight line of `loaded` is the unit vector `expected` (and no normals are
/// stored per point).
fn assert_sight_lines(loaded: &LoadedScans, expected: DVec3) {
    assert!(loaded.sight_lines);
    assert!(loaded.cloud.normals.is_none());
    for i in 0..loaded.cloud.len() {
        let n = loaded.sight_line(i).expect("a sight line");
        assert!(
            (n - expected).length() < 1e-6,
            "point {i}: {n} vs {expected}"
        );
    }
}

#[test]
fn a_ply_range_grid_gives_sight_lines_toward_the_scanner() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plane.ply");
    write_plane_scan(&path, 12, 15, |r, c| (r * 7 + c * 3) % 11 == 0);
    let loaded = load(std::slice::from_ref(&path), false);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    // The Stanford raw scans' scanner looks down −z of the scan's frame.
    assert_sight_lines(&loaded, DVec3::Z);

    // The same scan turned over by its pose (a half turn about x): the scanner now looks
    // up the common frame's +z, and the sight lines turn with it.
    let conf = dir.path().join("flipped.conf");
    std::fs::write(&conf, "bmesh plane.ply 0 0 0 1 0 0 0\n").unwrap();
    assert_sight_lines(&load(&[conf], false), -DVec3::Z);

    let ignored = load(std::slice::from_ref(&path), true);
    assert!(ignored.cloud.normals.is_none());
    assert!(!ignored.sight_lines);
    assert_eq!(ignored.sight_line(0), None);

    // A scan without a grid beside it: no sight lines for any scan of the set.
    let plain = dir.path().join("plain.xyz");
    std::fs::write(&plain, "0 0 0\n1 0 0\n0 1 0\n").unwrap();
    let mixed = load(&[path, plain], false);
    assert!(!mixed.sight_lines);
    assert!(mixed.cloud.normals.is_none());
    assert_eq!(mixed.sight_line(mixed.cloud.len() - 1), None);
}

/// An index record of the E57 prototype.
fn index_record(name: RecordName, max: i64) -> Record {
    Record {
        name,
        data_type: RecordDataType::Integer { min: 0, max },
    }
}

#[test]
fn an_e57_structured_scan_gives_sight_lines_toward_its_scanner() {
    // A spherical scan of the inside of a sphere of radius 5 m around the scanner, every
    // point with its row and column, and a pose that moves the scanner to (100, 0, 0).
    // (E57 scans without row and column indices get no sight lines: the round trips of
    // `formats.rs` load them without normals.)
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("room.e57");
    let (rows, cols) = (30usize, 60usize);
    let mut writer = E57Writer::from_file(&path, "grid-guid").unwrap();
    let prototype = vec![
        Record::CARTESIAN_X_F64,
        Record::CARTESIAN_Y_F64,
        Record::CARTESIAN_Z_F64,
        index_record(RecordName::RowIndex, rows as i64),
        index_record(RecordName::ColumnIndex, cols as i64),
    ];
    let mut pc = writer.add_pointcloud("scan-0", prototype).unwrap();
    pc.set_transform(Some(e57::Transform {
        rotation: e57::Quaternion {
            w: 1.0,
            x: 0.0,
            y: 0.0,
            z: 0.0,
        },
        translation: e57::Translation {
            x: 100.0,
            y: 0.0,
            z: 0.0,
        },
    }));
    for k in 0..rows * cols {
        let cell = (k * 7) % (rows * cols);
        let (r, c) = (cell / cols, cell % cols);
        let (theta, phi) = (0.6 + r as f64 * 0.01, c as f64 * 0.01);
        let p = 5.0
            * DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
        let mut values: Vec<RecordValue> =
            p.to_array().into_iter().map(RecordValue::Double).collect();
        values.extend([r, c].map(|v| RecordValue::Integer(v as i64)));
        pc.add_point(values).unwrap();
    }
    pc.finalize().unwrap();
    writer.finalize().unwrap();

    let loaded = load(std::slice::from_ref(&path), false);
    assert!(loaded.sight_lines);
    assert!(loaded.cloud.normals.is_none());
    let scanner = DVec3::new(100.0, 0.0, 0.0);
    for i in 0..loaded.cloud.len() {
        let n = loaded.sight_line(i).expect("a sight line");
        let toward = (scanner - loaded.cloud.world_position(i)).normalize();
        assert!((n - toward).length() < 1e-5, "point {i}: {n} vs {toward}");
    }
    let ignored = load(&[path], true);
    assert!(!ignored.sight_lines && ignored.sight_line(0).is_none());
}
