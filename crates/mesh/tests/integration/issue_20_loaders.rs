//! Issue 20's loader cases: a byte-order mark, CR-only PLY headers, coordinates too far apart
//! to hold in f32, a model spanning 1e10, and references outside the model's folder.

use std::path::{Path, PathBuf};

use spatch_mesh::{load_mesh, FaceId, LoadWarning, MeshError};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn utf8_bom_before_the_first_line_is_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "bom.obj",
        "\u{feff}v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".as_bytes(),
    );
    let mesh = load_mesh(&obj).unwrap().mesh;
    assert_eq!(mesh.positions.len(), 3);
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    let off = write(
        dir.path(),
        "bom.off",
        "\u{feff}OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n".as_bytes(),
    );
    assert_eq!(load_mesh(&off).unwrap().mesh.triangles.len(), 1);
    let stl = write(
        dir.path(),
        "bom.stl",
        "\u{feff}solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
         vertex 0 1 0\nendloop\nendfacet\nendsolid t\n"
            .as_bytes(),
    );
    assert_eq!(load_mesh(&stl).unwrap().mesh.triangles.len(), 1);
}

#[test]
fn cr_only_ply_headers_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let ascii = "ply\rformat ascii 1.0\relement vertex 3\rproperty float x\rproperty float y\r\
                 property float z\relement face 1\rproperty list uchar int vertex_indices\r\
                 end_header\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r";
    let mesh = load_mesh(write(dir.path(), "cr.ply", ascii.as_bytes()))
        .unwrap()
        .mesh;
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    // Binary body: only the header's CRs are line ends.
    let mut binary = b"ply\rformat binary_little_endian 1.0\relement vertex 3\rproperty float x\r\
                       property float y\rproperty float z\relement face 1\r\
                       property list uchar int vertex_indices\rend_header\r"
        .to_vec();
    for p in [[0.0f32, 0.0, 0.0], [13.0, 0.0, 0.0], [0.0, 13.0, 0.0]] {
        for c in p {
            binary.extend_from_slice(&c.to_le_bytes());
        }
    }
    binary.push(3);
    for i in [0i32, 1, 2] {
        binary.extend_from_slice(&i.to_le_bytes());
    }
    let mesh = load_mesh(write(dir.path(), "crb.ply", &binary))
        .unwrap()
        .mesh;
    assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    assert_eq!(mesh.face_area(FaceId(0)), 84.5);
}

#[test]
fn ply_errors_never_echo_raw_control_characters() {
    let dir = tempfile::tempdir().unwrap();
    let bad =
        "ply\rformat ascii 1.0\relement vertex 3\rproperty float x\rbogus\r\rline\rend_header\r";
    let err = load_mesh(write(dir.path(), "bad.ply", bad.as_bytes())).unwrap_err();
    let text = err.to_string();
    assert!(!text.contains('\r') && !text.contains('\n'), "{text:?}");
    let bad = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\x07\nend_header\n0\n";
    let text = load_mesh(write(dir.path(), "bell.ply", bad.as_bytes()))
        .unwrap_err()
        .to_string();
    assert!(!text.chars().any(|c| c.is_control()), "{text:?}");
}

#[test]
fn coordinates_too_far_apart_are_refused_naming_file_and_vertex() {
    let dir = tempfile::tempdir().unwrap();
    for (name, far) in [
        ("e38.obj", "1e38"),
        ("e300.obj", "1e300"),
        ("e16.obj", "-3e16"),
    ] {
        let text = format!("v 0 0 0\nv 1 0 0\nv 0 {far} 0\nf 1 2 3\n");
        let path = write(dir.path(), name, text.as_bytes());
        let err = load_mesh(&path).unwrap_err();
        assert!(
            matches!(err, MeshError::ExtentTooLarge { vertex: 2, .. }),
            "{name}: {err:?}"
        );
        let text = err.to_string();
        assert!(text.starts_with(&path.display().to_string()) && text.contains("vertex 2"));
    }
    // Far from the origin but small is fine: the f64 origin holds the offset.
    let path = write(
        dir.path(),
        "far.obj",
        b"v 1e30 0 0\nv 1e30 1 0\nv 1e30 0 1\nf 1 2 3\n",
    );
    assert!(load_mesh(&path).is_ok());
}

#[test]
fn a_model_spanning_1e10_has_finite_areas_and_normals() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "huge.obj",
        b"v 0 0 0\nv 1e10 0 0\nv 0 1e10 0\nv 1e10 1e10 0\nf 1 2 3\nf 3 2 4\n",
    );
    let mesh = load_mesh(&path).unwrap().mesh;
    for f in 0..2 {
        let area = mesh.face_area(FaceId(f));
        assert!((area / 5e19 - 1.0).abs() < 1e-6, "{area}");
        assert!((mesh.face_normal(FaceId(f)).z - 1.0).abs() < 1e-6);
    }
}

#[test]
fn obj_references_outside_the_folder_are_not_read() {
    let dir = tempfile::tempdir().unwrap();
    let inner = dir.path().join("model");
    std::fs::create_dir(&inner).unwrap();
    write(dir.path(), "outside.mtl", b"newmtl red\nKd 1 0 0\n");
    write(
        &inner,
        "inside.mtl",
        b"newmtl red\nKd 1 0 0\nmap_Kd ../../etc/x.png\n",
    );
    for (lib, outside) in [
        ("../outside.mtl", true),
        ("/etc/passwd", true),
        ("inside.mtl", false),
    ] {
        let text = format!("mtllib {lib}\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let loaded = load_mesh(write(&inner, "m.obj", text.as_bytes())).unwrap();
        let refused: Vec<String> = loaded
            .warnings
            .iter()
            .filter(|w| w.to_string().contains("only files in the model's folder"))
            .map(|w| w.to_string())
            .collect();
        // Either the library itself, or (inside.mtl) its texture, is refused by name.
        assert_eq!(refused.len(), 1, "{lib}: {:?}", loaded.warnings);
        if outside {
            assert!(matches!(
                &loaded.warnings[0],
                LoadWarning::MissingMaterialLibrary { .. }
            ));
        } else {
            assert!(refused[0].contains("../../etc/x.png"), "{refused:?}");
        }
    }
}
