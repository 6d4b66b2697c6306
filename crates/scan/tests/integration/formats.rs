//! Every format round-trips through `load_scans`: positions, colours (or intensity as grey)
//! and E57 poses; malformed files give one clear error naming the file.

use std::path::PathBuf;

use glam::{DQuat, DVec3};
use spatch_scan::{load_scans, parse_columns, ScanError, ScanOptions, ScanWarning};

use crate::writers::{test_points, write_e57, write_las, E57Scan, TestPoint};

/// Loads one file with default options.
fn load(path: &std::path::Path) -> spatch_scan::LoadedScans {
    load_scans(&[path.to_path_buf()], &ScanOptions::default()).unwrap()
}

/// Asserts that the merged cloud holds `points` in order (within `tolerance`).
fn assert_positions(loaded: &spatch_scan::LoadedScans, points: &[TestPoint], tolerance: f64) {
    assert_eq!(loaded.cloud.len(), points.len());
    for (i, p) in points.iter().enumerate() {
        let got = loaded.cloud.world_position(i);
        let d = (got - DVec3::from(p.position)).length();
        assert!(d <= tolerance, "point {i}: {got} vs {:?}", p.position);
    }
}

#[test]
fn las_versions_and_laz_round_trip_with_colours() {
    let dir = tempfile::tempdir().unwrap();
    let points = test_points(2000, [500_100.0, 4_000_200.0, 30.0]);
    for (name, version, format) in [
        ("v12.las", (1, 2), 2),
        ("v13.las", (1, 3), 3),
        ("v14.las", (1, 4), 7),
        ("v14.laz", (1, 4), 7),
        ("v12.laz", (1, 2), 3),
    ] {
        let path = dir.path().join(name);
        write_las(&path, &points, version, format);
        let loaded = load(&path);
        // f32 offsets from a centre within 2 m: well under the 1 mm LAS step.
        assert_positions(&loaded, &points, 1e-5);
        let colours = loaded
            .cloud
            .colours
            .as_ref()
            .expect("RGB formats have colours");
        for (c, p) in colours.iter().zip(&points) {
            assert_eq!(&c[..3], &p.colour, "{name}");
        }
        assert!(loaded.warnings.is_empty(), "{name}: {:?}", loaded.warnings);
    }
}

#[test]
fn las_without_rgb_shows_intensity_as_grey() {
    let dir = tempfile::tempdir().unwrap();
    let points = test_points(500, [0.0; 3]);
    let path = dir.path().join("grey.laz");
    write_las(&path, &points, (1, 4), 6);
    let loaded = load(&path);
    assert_positions(&loaded, &points, 1e-6);
    let colours = loaded.cloud.colours.as_ref().unwrap();
    let max = points.iter().map(|p| p.intensity).max().unwrap() as f64;
    for (c, p) in colours.iter().zip(&points) {
        let expected = (p.intensity as f64 * 255.0 / max).round() as u8;
        assert_eq!(c[0].abs_diff(expected), 0, "{} -> {c:?}", p.intensity);
        assert!(c[0] == c[1] && c[1] == c[2]);
    }
    assert!(matches!(
        loaded.warnings.as_slice(),
        [ScanWarning::IntensityAsGrey { .. }]
    ));
}

#[test]
fn e57_scans_come_with_their_poses() {
    let dir = tempfile::tempdir().unwrap();
    let a = test_points(400, [0.0; 3]);
    let b = test_points(300, [0.5, 0.0, 0.0]);
    // A quarter turn about z (w x y z) and a shift.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let path = dir.path().join("two.e57");
    write_e57(
        &path,
        &[
            E57Scan {
                points: &a,
                rotation: [1.0, 0.0, 0.0, 0.0],
                translation: [0.0; 3],
                colour: true,
            },
            E57Scan {
                points: &b,
                rotation: [h, 0.0, 0.0, h],
                translation: [10.0, 0.0, 1.0],
                colour: false,
            },
        ],
    );
    let loaded = load(&path);
    assert_eq!(loaded.scans.len(), 2);
    assert_eq!(loaded.scans[1].points, 400..700);
    let turn = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    let expected: Vec<TestPoint> = a
        .iter()
        .copied()
        .chain(b.iter().map(|p| TestPoint {
            position: (turn * DVec3::from(p.position) + DVec3::new(10.0, 0.0, 1.0)).to_array(),
            ..*p
        }))
        .collect();
    assert_positions(&loaded, &expected, 1e-5);
    // The same positions as the e57 crate's own pose application.
    let mut reader = e57::E57Reader::from_file(&path).unwrap();
    let second = reader.pointclouds()[1].clone();
    let own: Vec<DVec3> = reader
        .pointcloud_simple(&second)
        .unwrap()
        .map(|p| match p.unwrap().cartesian {
            e57::CartesianCoordinate::Valid { x, y, z } => DVec3::new(x, y, z),
            other => panic!("{other:?}"),
        })
        .collect();
    for (k, p) in own.iter().enumerate() {
        assert!((loaded.cloud.world_position(400 + k) - *p).length() < 1e-5);
    }
    // Colours from the first scan, intensity as grey from the second.
    let colours = loaded.cloud.colours.as_ref().unwrap();
    assert_eq!(&colours[7][..3], &a[7].colour);
    assert!(colours[450][0] == colours[450][1]);
    assert!(loaded
        .warnings
        .iter()
        .any(|w| matches!(w, ScanWarning::IntensityAsGrey { .. })));
}

#[test]
fn leica_pts_with_its_count_line() {
    let dir = tempfile::tempdir().unwrap();
    let points = test_points(50, [0.0; 3]);
    let mut text = format!("{}\n", points.len());
    for p in &points {
        let [x, y, z] = p.position;
        let [r, g, b] = p.colour;
        text.push_str(&format!(
            "{x} {y} {z} {} {r} {g} {b}\n",
            p.intensity as i32 - 2048
        ));
    }
    let path = dir.path().join("scan.pts");
    std::fs::write(&path, text).unwrap();
    let loaded = load(&path);
    assert_positions(&loaded, &points, 1e-6);
    let colours = loaded.cloud.colours.as_ref().unwrap();
    assert_eq!(&colours[9][..3], &points[9].colour);
}

#[test]
fn xyz_nine_columns_normals_then_colours() {
    let dir = tempfile::tempdir().unwrap();
    let lines = "0 0 0 0 0 1 255 128 0\n1 0 0 0.6 0.8 0 10 20 30\n0 1 0 1 0 0 0 0 255\n";
    let path = dir.path().join("nine.xyz");
    std::fs::write(&path, lines).unwrap();
    let loaded = load(&path);
    let normals = loaded.cloud.normals.as_ref().unwrap();
    assert_eq!(normals[1].to_array(), [0.6, 0.8, 0.0]);
    assert_eq!(
        loaded.cloud.colours.as_ref().unwrap()[0],
        [255, 128, 0, 255]
    );
    // The same values with colours first are still read as colours first.
    let swapped = "0 0 0 255 128 0 0 0 1\n1 0 0 10 20 30 0.6 0.8 0\n";
    let path = dir.path().join("swapped.xyz");
    std::fs::write(&path, swapped).unwrap();
    let loaded = load(&path);
    assert_eq!(
        loaded.cloud.normals.as_ref().unwrap()[1].to_array(),
        [0.6, 0.8, 0.0]
    );
    assert_eq!(loaded.cloud.colours.as_ref().unwrap()[1], [10, 20, 30, 255]);
}

#[test]
fn xyz_header_and_columns_option() {
    let dir = tempfile::tempdir().unwrap();
    // CloudCompare: colours as 0..1 floats, a scalar field, normals last.
    let text =
        "//X Y Z Rf Gf Bf Scalar_field Nx Ny Nz\n0 0 0 1 0.5 0 7 0 0 1\n1 0 0 0 0 1 8 1 0 0\n";
    let path = dir.path().join("cc.txt");
    std::fs::write(&path, text).unwrap();
    let loaded = load(&path);
    assert_eq!(
        loaded.cloud.colours.as_ref().unwrap()[0],
        [255, 128, 0, 255]
    );
    assert_eq!(
        loaded.cloud.normals.as_ref().unwrap()[1].to_array(),
        [1.0, 0.0, 0.0]
    );
    // --columns overrides the count rules: an intensity column shown as grey, one skipped.
    let text = "0 0 0 5 100\n1 0 0 9 300\n2 0 0 9 200\n";
    let path = dir.path().join("cols.xyz");
    std::fs::write(&path, text).unwrap();
    let mut options = ScanOptions::default();
    options.columns = Some(parse_columns("x,y,z,skip,intensity").unwrap());
    let loaded = load_scans(std::slice::from_ref(&path), &options).unwrap();
    let grey: Vec<u8> = loaded.cloud.colours.unwrap().iter().map(|c| c[0]).collect();
    assert_eq!(&grey[..2], &[0, 255]);
    assert!(grey[2].abs_diff(128) <= 1, "{grey:?}");
    // A layout of the wrong width names the line.
    options.columns = Some(parse_columns("x,y,z").unwrap());
    let message = load_scans(&[path], &options).unwrap_err().to_string();
    assert!(
        message.contains("cols.xyz: line 1: expected 3 values, found 5"),
        "{message}"
    );
}

#[test]
fn several_files_merge_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let a = test_points(100, [0.0; 3]);
    let b = test_points(80, [3.0, 0.0, 0.0]);
    let las = dir.path().join("a.las");
    write_las(&las, &a, (1, 2), 0);
    let xyz = dir.path().join("b.xyz");
    let text: String = b
        .iter()
        .map(|p| format!("{} {} {}\n", p.position[0], p.position[1], p.position[2]))
        .collect();
    std::fs::write(&xyz, text).unwrap();
    let loaded = load_scans(&[las, xyz], &ScanOptions::default()).unwrap();
    let all: Vec<TestPoint> = a.iter().chain(&b).copied().collect();
    assert_positions(&loaded, &all, 1e-6);
    assert_eq!(loaded.scans[1].points, 100..180);
}

#[test]
fn malformed_files_name_the_file_and_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let points = test_points(3000, [0.0; 3]);
    let good_las = dir.path().join("good.las");
    write_las(&good_las, &points, (1, 4), 2);
    let good_laz = dir.path().join("good.laz");
    write_las(&good_laz, &points, (1, 4), 2);
    let good_e57 = dir.path().join("good.e57");
    write_e57(
        &good_e57,
        &[E57Scan {
            points: &points,
            rotation: [1.0, 0.0, 0.0, 0.0],
            translation: [0.0; 3],
            colour: true,
        }],
    );
    let mut cases: Vec<(PathBuf, &str)> = Vec::new();
    let mut put = |name: &str, bytes: &[u8], expected: &'static str| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        cases.push((path, expected));
    };
    let las = std::fs::read(&good_las).unwrap();
    let laz = std::fs::read(&good_laz).unwrap();
    let e57 = std::fs::read(&good_e57).unwrap();
    put("short.las", &las[..las.len() - 100], "truncated");
    put("header.las", &las[..50], "not a readable LAS/LAZ file");
    put(
        "sig.las",
        b"LASX and then some bytes that are not a header at all",
        "not a readable LAS/LAZ file",
    );
    put("short.laz", &laz[..laz.len() / 2], "LAS/LAZ");
    put(
        "short.e57",
        &e57[..e57.len() / 2],
        "not a readable E57 file",
    );
    put(
        "junk.e57",
        b"ASTM-E57 but nothing else",
        "not a readable E57 file",
    );
    put("empty.las", b"", "LAS/LAZ");
    put(
        "words.pts",
        b"3\n1 2 3\n4 five 6\n",
        "line 3: value 2 is not a number",
    );
    put(
        "ragged.xyz",
        b"1 2 3\n4 5\n",
        "line 2: expected 3 values, found 2",
    );
    put(
        "a.conf",
        b"bmesh missing.ply 0 0 0 0 0 0 1\n",
        "missing.ply: cannot read",
    );
    put(
        "nested.conf",
        b"bmesh a.conf 0 0 0 0 0 0 1\n",
        "cannot list another scan set",
    );
    put("what.dat", b"1 2 3\n", "unknown point cloud type");
    for (path, expected) in cases {
        let err: ScanError =
            load_scans(std::slice::from_ref(&path), &ScanOptions::default()).unwrap_err();
        let message = err.to_string();
        let name = path.file_name().unwrap().to_str().unwrap();
        assert!(!message.contains('\n'), "{name}: {message}");
        assert!(message.contains(expected), "{name}: {message}");
        if name != "a.conf" {
            assert!(message.contains(name), "{name}: {message}");
        }
    }
}
