//! glTF written by gltfpack (testdata/meshes/gltfpack, see SOURCE.md there): quantized and
//! meshopt-compressed files load to the same surface as the f32 original, within the
//! quantization step; hostile variants give one typed error, never a panic.

use std::path::{Path, PathBuf};

use glam::DVec3;
use spatch_mesh::{
    load_mesh, prepare_mesh, FaceId, GltfProblem, MeshError, OutsideReason, PrepareOptions,
    TriangleMesh, VertexId,
};

fn testdata(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../testdata/meshes/gltfpack")
        .join(name)
}

fn world_positions(mesh: &TriangleMesh) -> Vec<DVec3> {
    (0..mesh.positions.len() as u32)
        .map(|v| mesh.world_position(VertexId(v)))
        .collect()
}

/// Area-weighted normal sum (zero for a closed surface) and signed volume, in world units.
fn area_and_volume(mesh: &TriangleMesh) -> (f64, f64) {
    let p = world_positions(mesh);
    let mut area = 0.0;
    let mut volume = 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| p[i as usize]);
        area += (b - a).cross(c - a).length() / 2.0;
        volume += a.dot(b.cross(c)) / 6.0;
    }
    (area, volume)
}

fn assert_matches_reference(name: &str, tolerance: f64) {
    let reference = load_mesh(testdata("torus.gltf")).unwrap().mesh;
    let loaded = load_mesh(testdata(name)).unwrap();
    let mesh = prepare_mesh(&loaded.mesh, &PrepareOptions::default()).0;
    assert_eq!(mesh.triangles.len(), reference.triangles.len(), "{name}");
    let reference_points = world_positions(&reference);
    for p in world_positions(&mesh) {
        let nearest = reference_points
            .iter()
            .map(|q| (p - *q).length())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest <= tolerance,
            "{name}: {p} is {nearest} from the torus"
        );
    }
    let (area, volume) = area_and_volume(&mesh);
    let (ref_area, ref_volume) = area_and_volume(&reference);
    assert!(
        (area / ref_area - 1.0).abs() < 1e-3,
        "{name}: area {area} vs {ref_area}"
    );
    // Same sign: the winding survived quantization, strip/index coding and the node scale.
    assert!(
        (volume / ref_volume - 1.0).abs() < 1e-3,
        "{name}: volume {volume} vs {ref_volume}"
    );
    // Normals follow the surface (octahedral / normalized-byte normals dequantized).
    let normals = mesh.vertex_normals.as_ref().expect("normals kept");
    for (f, t) in mesh.triangles.iter().enumerate() {
        let face = mesh.face_normal(FaceId(f as u32));
        for &v in t {
            let n = normals[v as usize];
            assert!(n.dot(face) > 0.8, "{name}: normal {n} against face {face}");
        }
    }
}

#[test]
fn quantized_gltf_matches_the_original() {
    // 14-bit positions over a 5-unit extent: steps of 3e-4.
    assert_matches_reference("torus_quantized.glb", 5e-4);
}

#[test]
fn meshopt_gltf_matches_the_original() {
    assert_matches_reference("torus_meshopt.glb", 5e-4);
    assert_matches_reference("torus_meshopt_noq.glb", 1e-6);
}

#[test]
fn meshopt_gltf_with_external_buffer_and_exponential_filter_matches() {
    assert_matches_reference("torus_meshopt_cc.gltf", 1e-3);
}

fn copy_to(dir: &Path, name: &str) -> PathBuf {
    let to = dir.join(name);
    std::fs::copy(testdata(name), &to).unwrap();
    to
}

#[test]
fn corrupt_meshopt_data_is_an_error_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(testdata("torus_meshopt.glb")).unwrap();
    // Flip bytes across the binary chunk (past the JSON), one position at a time.
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let bin_start = 20 + json_len + 8;
    let mut errors = 0;
    for at in (bin_start..bytes.len()).step_by(97) {
        let mut broken = bytes.clone();
        broken[at] ^= 0xa5;
        let path = dir.path().join("broken.glb");
        std::fs::write(&path, &broken).unwrap();
        if let Err(e) = load_mesh(&path) {
            assert!(!e.to_string().contains('\n'));
            errors += 1;
        }
    }
    // Most flips break the stream's structure; some only change values.
    assert!(errors > 0);
    // Truncating the compressed chunk never panics either.
    for cut in (bin_start..bytes.len()).step_by(251) {
        let path = dir.path().join("cut.glb");
        std::fs::write(&path, &bytes[..cut]).unwrap();
        assert!(load_mesh(&path).is_err());
    }
}

#[test]
fn meshopt_triangle_count_not_a_multiple_of_three_is_refused() {
    // meshoptimizer's index decoder asserts on such a count (an abort, not an error).
    let dir = tempfile::tempdir().unwrap();
    let bytes = std::fs::read(testdata("torus_meshopt.glb")).unwrap();
    let from = br#""mode":"TRIANGLES","count":3072"#;
    let at = bytes.windows(from.len()).position(|w| w == from).unwrap();
    let mut broken = bytes.clone();
    broken[at + from.len() - 1] = b'1';
    let path = dir.path().join("count.glb");
    std::fs::write(&path, &broken).unwrap();
    assert!(matches!(
        load_mesh(&path),
        Err(MeshError::GltfPrimitive {
            problem: GltfProblem::BadAccessor { .. },
            ..
        })
    ));
}

#[test]
fn buffer_uri_outside_the_folder_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("model");
    std::fs::create_dir(&inner).unwrap();
    copy_to(dir.path(), "torus.bin");
    let text = std::fs::read_to_string(testdata("torus.gltf")).unwrap();
    let cases = [
        ("../torus.bin", OutsideReason::ParentComponent),
        ("%2E%2E/torus.bin", OutsideReason::ParentComponent),
        ("/etc/passwd", OutsideReason::Absolute),
        ("file:///etc/passwd", OutsideReason::Absolute),
    ];
    for (uri, reason) in cases {
        let path = inner.join("escape.gltf");
        std::fs::write(&path, text.replace("\"torus.bin\"", &format!("{uri:?}"))).unwrap();
        match load_mesh(&path) {
            Err(e @ MeshError::ReferenceOutsideFolder { .. }) => {
                assert!(
                    matches!(e, MeshError::ReferenceOutsideFolder { reason: r, .. } if r == reason)
                );
                let text = e.to_string();
                assert!(
                    text.contains("refusing to read") && !text.contains('\n'),
                    "{text}"
                );
            }
            other => panic!("{uri}: {other:?}"),
        }
    }
    // The same file beside the model loads.
    copy_to(&inner, "torus.bin");
    let path = inner.join("ok.gltf");
    std::fs::write(&path, &text).unwrap();
    assert!(load_mesh(&path).is_ok());
}

#[test]
fn position_accessor_index_out_of_range_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    copy_to(dir.path(), "torus.bin");
    let text = std::fs::read_to_string(testdata("torus.gltf")).unwrap();
    for (from, to) in [
        ("\"POSITION\": 0", "\"POSITION\": 99"),
        ("\"NORMAL\": 1", "\"NORMAL\": 4"),
        ("\"indices\": 3", "\"indices\": 4294967295"),
    ] {
        assert!(text.contains(from), "{from}");
        let path = dir.path().join("bad.gltf");
        std::fs::write(&path, text.replace(from, to)).unwrap();
        match load_mesh(&path) {
            Err(MeshError::GltfPrimitive {
                problem:
                    GltfProblem::MissingAccessor {
                        accessor_count: 4, ..
                    },
                ..
            }) => {}
            other => panic!("{to}: {other:?}"),
        }
    }
}

#[test]
fn draco_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(testdata("torus.gltf"))
        .unwrap()
        .replace(
            "\"asset\"",
            "\"extensionsRequired\": [\"KHR_draco_mesh_compression\"], \"asset\"",
        );
    let path = dir.path().join("draco.gltf");
    std::fs::write(&path, text).unwrap();
    copy_to(dir.path(), "torus.bin");
    assert!(matches!(
        load_mesh(&path),
        Err(MeshError::GltfExtensionRequired { extension, .. }) if extension == "KHR_draco_mesh_compression"
    ));
}
