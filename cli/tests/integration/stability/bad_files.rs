//! Non-finite numbers, empty files and too little data: one clear line naming the file, exit
//! code 2, no output. Point clouds are the documented exception for NaN: a scan may carry a
//! few invalid points, which are dropped and counted (issue #6), not fatal.

use super::assert_refused;
use crate::test_command::TestCommand;

const PLY_HEADER: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n\
property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n\
end_header\n";

/// Three vertices (the second with `bad` as its y) and one face, as binary little-endian PLY.
fn binary_ply(bad: f32) -> Vec<u8> {
    let mut bytes = PLY_HEADER
        .replace("ascii", "binary_little_endian")
        .into_bytes();
    for v in [0.0f32, 0.0, 0.0, 1.0, bad, 0.0, 0.0, 1.0, 0.0] {
        bytes.extend(v.to_le_bytes());
    }
    bytes.push(3);
    for i in [0i32, 1, 2] {
        bytes.extend(i.to_le_bytes());
    }
    bytes
}

/// A glTF with one triangle whose third vertex has `bad` as its z, the buffer embedded.
fn gltf(bad: f32) -> String {
    let mut raw = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, bad] {
        raw.extend(v.to_le_bytes());
    }
    const DIGITS: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut b64 = String::new();
    for chunk in raw.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (k, &b)| n | u32::from(b) << (16 - 8 * k));
        for k in 0..4 {
            if k <= chunk.len() {
                b64.push(DIGITS[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                b64.push('=');
            }
        }
    }
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
"buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{b64}"}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,1]}}]}}"#
    )
}

/// NaN or infinity in a mesh vertex, in every mesh format: refused, naming the file and the
/// vertex by its 0-based index (or, for ASCII PLY, whose reader cannot parse `inf`, the
/// line and its text).
#[test]
fn nan_and_infinity_in_every_mesh_format() {
    let t = TestCommand::new();
    let cases: Vec<(&str, Vec<u8>, &[&str])> = vec![
        (
            "nan.obj",
            b"v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n".to_vec(),
            &["vertex 2", "not finite"],
        ),
        (
            "inf.obj",
            b"v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n".to_vec(),
            &["vertex 1", "not finite"],
        ),
        (
            "nan.off",
            b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n".to_vec(),
            &["vertex", "not finite"],
        ),
        ("nan.ply", binary_ply(f32::NAN), &["vertex 1", "not finite"]),
        (
            "inf.ply",
            binary_ply(f32::INFINITY),
            &["vertex", "not finite"],
        ),
        (
            "inf_ascii.ply",
            format!("{PLY_HEADER}0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n").into_bytes(),
            &["Line 11", "1 inf 0"],
        ),
        (
            "nan.gltf",
            gltf(f32::NAN).into_bytes(),
            &["vertex", "not finite"],
        ),
        (
            "inf.gltf",
            gltf(f32::NEG_INFINITY).into_bytes(),
            &["vertex", "not finite"],
        ),
    ];
    for (name, bytes, words) in cases {
        std::fs::write(t.path(name), bytes).unwrap();
        let run = t.run(&["convert", name, "-o", "out.spatch"]);
        assert_refused(&t, &run, name, words);
    }
}

/// NaN in a point cloud: the point is dropped and counted, the rest converted.
#[test]
fn nan_in_a_point_cloud_is_dropped_and_counted() {
    let t = TestCommand::new();
    let mut text = String::new();
    for i in 0..40 {
        for j in 0..40 {
            text.push_str(&format!(
                "{} {} 0\n",
                f64::from(i) * 0.01,
                f64::from(j) * 0.01
            ));
        }
    }
    text.push_str("nan 0.1 0\n0.2 inf 0\n");
    std::fs::write(t.path("scan.xyz"), text).unwrap();
    let run = t
        .run(&[
            "from-cloud",
            "scan.xyz",
            "-o",
            "out.spatch",
            "--report",
            "r.json",
        ])
        .success();
    let report: serde_json::Value = t.json("r.json");
    assert_eq!(report["details"]["dropped_non_finite"], 2, "{report}");
    assert_eq!(report["details"]["points"], 1600, "{report}");
    assert!(
        run.stdout.contains("dropped 2 non-finite points"),
        "{}",
        run.stdout
    );
}

/// A NaN in a `.spatch` frame (with the section CRC recomputed, so only the number is
/// wrong): every reader refuses it.
#[test]
fn nan_in_a_spatch_frame() {
    let t = TestCommand::new();
    let golden = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../testdata/format/v1_minimal.spatch");
    let mut bytes = std::fs::read(golden).unwrap();
    // docs/format.md, walk-through: the FRAM section header is at 0x4c, its CRC at 0x5c
    // over the header's first 16 bytes and the payload 0x60..0x88; the origin's x at 0x60.
    bytes[0x60..0x64].copy_from_slice(&f32::NAN.to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&bytes[0x4c..0x5c]);
    crc.update(&bytes[0x60..0x88]);
    bytes[0x5c..0x60].copy_from_slice(&crc.finalize().to_le_bytes());
    std::fs::write(t.path("nan.spatch"), bytes).unwrap();
    for args in [
        &["stats", "nan.spatch"][..],
        &["render", "nan.spatch", "-o", "out.png"],
        &["export", "nan.spatch", "-o", "out.ply"],
    ] {
        let run = t.run(args);
        assert_refused(&t, &run, "nan.spatch", &["frame"]);
        assert!(!t.path("out.png").exists() && !t.path("out.ply").exists());
    }
}

/// An empty file of every format: refused as empty, naming the file.
#[test]
fn empty_files() {
    let t = TestCommand::new();
    for name in ["e.obj", "e.ply", "e.off", "e.gltf", "e.glb"] {
        std::fs::write(t.path(name), b"").unwrap();
        let run = t.run(&["convert", name, "-o", "out.spatch"]);
        assert_refused(&t, &run, name, &["empty"]);
    }
    std::fs::write(t.path("e.xyz"), b"").unwrap();
    let run = t.run(&["from-cloud", "e.xyz", "-o", "out.spatch"]);
    assert_refused(&t, &run, "e.xyz", &["empty"]);
    std::fs::write(t.path("e.spatch"), b"").unwrap();
    let run = t.run(&["stats", "e.spatch"]);
    assert_refused(&t, &run, "e.spatch", &[]);
}

/// One point is no surface: refused, saying how many points there are and how many it needs.
#[test]
fn a_single_point() {
    let t = TestCommand::new();
    std::fs::write(t.path("one.xyz"), b"1 2 3\n").unwrap();
    let run = t.run(&["from-cloud", "one.xyz", "-o", "out.spatch"]);
    assert_refused(&t, &run, "one.xyz", &["1 finite point", "at least 3"]);
}
