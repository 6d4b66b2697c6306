//! Broken and hostile inputs: each gives a typed error naming the file and element, or a
//! warning, and never a panic.

use std::path::{Path, PathBuf};

use spatch_fixtures::shapes;
use spatch_mesh::{load_mesh, load_point_cloud, Element, LoadWarning, MeshError};

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn binary_ply_cube() -> Vec<u8> {
    let cube = shapes::cube(1.0);
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment test\nelement vertex {}\n\
         property float x\nproperty float y\nproperty float z\nproperty uchar red\n\
         property uchar green\nproperty uchar blue\nelement face {}\n\
         property list uchar uint vertex_indices\nend_header\n",
        cube.positions.len(),
        cube.triangles.len()
    )
    .into_bytes();
    for p in &cube.positions {
        for c in p {
            out.extend_from_slice(&c.to_le_bytes());
        }
        out.extend_from_slice(&[200, 100, 50]);
    }
    for t in &cube.triangles {
        out.push(3);
        for i in t {
            out.extend_from_slice(&i.to_le_bytes());
        }
    }
    out
}

#[test]
fn nan_is_refused_naming_the_element() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "nan.obj",
        b"v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n",
    );
    // Binary, since ASCII PLY has no spelling for NaN.
    let mut bytes = binary_ply_cube();
    let first_vertex = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let y_of_vertex_2 = first_vertex + 2 * 15 + 4;
    bytes[y_of_vertex_2..y_of_vertex_2 + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let ply = write(dir.path(), "nan.ply", &bytes);
    let off = write(
        dir.path(),
        "nan.off",
        b"OFF\n3 1 0\n0 0 0\nNaN 0 0\n0 1 0\n3 0 1 2\n",
    );
    for (path, index) in [(obj, 2), (ply, 2), (off, 1)] {
        match load_mesh(&path) {
            Err(e @ MeshError::NonFinite { .. }) => {
                let MeshError::NonFinite { element, path: p } = &e else {
                    unreachable!("matched above")
                };
                assert_eq!(*element, Element::Vertex(index));
                assert_eq!(p, &path);
                let message = e.to_string();
                assert!(message.contains(&format!("vertex {index}")), "{message}");
                assert!(message.contains("nan."), "{message}");
            }
            other => panic!("{}: expected NonFinite, got {other:?}", path.display()),
        }
    }
}

#[test]
fn non_finite_cloud_points_are_dropped_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let xyz = write(
        dir.path(),
        "c.xyz",
        b"# x y z r g b\n0 0 0 255 0 0\n1 nan 0 0 255 0\n2 0 0 0 0 255\n",
    );
    let loaded = load_point_cloud(&xyz).unwrap();
    assert_eq!(loaded.cloud.len(), 2);
    assert_eq!(loaded.dropped_non_finite, 1);
    assert_eq!(loaded.cloud.colours.as_ref().unwrap()[1], [0, 0, 255, 255]);
    let normals = write(dir.path(), "n.xyz", b"0 0 0 0.0 0.0 1.0\n1 0 0 0 1 0\n");
    let loaded = load_point_cloud(&normals).unwrap();
    assert!(loaded.cloud.normals.is_some() && loaded.cloud.colours.is_none());
    let bad = write(dir.path(), "b.xyz", b"0 0 0 1 2\n");
    assert!(matches!(
        load_point_cloud(&bad),
        Err(MeshError::Syntax { line: 1, .. })
    ));
}

#[test]
fn bad_indices_and_empty_files_are_typed_errors() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "i.obj",
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n",
    );
    assert!(matches!(
        load_mesh(&obj),
        Err(MeshError::IndexOutOfRange {
            face: 1,
            index: 9,
            vertex_count: 3,
            ..
        })
    ));
    let ply = write(
        dir.path(),
        "i.ply",
        b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
          property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
          0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
    );
    assert!(matches!(
        load_mesh(&ply),
        Err(MeshError::IndexOutOfRange {
            face: 0,
            index: 3,
            ..
        })
    ));
    let empty = write(dir.path(), "e.obj", b"");
    assert!(matches!(
        load_mesh(&empty),
        Err(MeshError::EmptyFile { .. })
    ));
    let no_faces = write(dir.path(), "v.obj", b"v 0 0 0\nv 1 0 0\n");
    assert!(matches!(
        load_mesh(&no_faces),
        Err(MeshError::NoFaces { .. })
    ));
    let unknown = write(dir.path(), "x.3mf", b"solid");
    assert!(matches!(
        load_mesh(&unknown),
        Err(MeshError::UnsupportedFormat { .. })
    ));
    let missing = dir.path().join("missing.obj");
    assert!(matches!(load_mesh(&missing), Err(MeshError::Io { .. })));
}

#[test]
fn obj_features_negative_indices_polygons_and_colours() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "q.obj",
        b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 1 1 0 0 0 1\nv 0 1 0 1 1 1\n\
          vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf -4/-4 -3/-3 -2/-2 -1/-1\n",
    );
    let loaded = load_mesh(&obj).unwrap();
    assert_eq!(loaded.mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(
        loaded.mesh.vertex_colours.as_ref().unwrap()[2],
        [0, 0, 255, 255]
    );
    let uvs = loaded.mesh.face_uvs.as_ref().unwrap();
    assert_eq!(uvs[1][2], glam::Vec2::new(0.0, 1.0));
    assert!(loaded
        .warnings
        .contains(&LoadWarning::PolygonsTriangulated { count: 1 }));
}

#[test]
fn missing_material_library_and_texture_are_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let obj = write(
        dir.path(),
        "m.obj",
        b"mtllib nowhere.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    );
    let loaded = load_mesh(&obj).unwrap();
    assert!(matches!(
        loaded.warnings[0],
        LoadWarning::MissingMaterialLibrary { .. }
    ));
    assert!(!loaded.mesh.has_colour());

    write(
        dir.path(),
        "t.mtl",
        b"newmtl red\nKd 1 0 0\nTr 1.0\nnewmtl tex\nKd 0.8 0.8 0.8\n\
          map_Kd -s 2 2 1 -clamp on missing.png\n",
    );
    let obj = write(
        dir.path(),
        "t.obj",
        b"mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
          usemtl red\nf 1/1 2/2 3/3\nusemtl tex\nf 1/1 3/3 2/2\n",
    );
    let loaded = load_mesh(&obj).unwrap();
    let mesh = &loaded.mesh;
    assert!(mesh.has_colour());
    assert_eq!(mesh.materials[0].base_colour, [1.0, 0.0, 0.0, 1.0]);
    assert_eq!(
        mesh.colour_at(spatch_mesh::FaceId(0), glam::Vec3::X),
        Some([255, 0, 0, 255])
    );
    assert!(mesh.materials[1].texture.is_none());
    assert!(loaded
        .warnings
        .iter()
        .any(|w| matches!(w, LoadWarning::TextureUnreadable { .. })));
    assert!(loaded.warnings.iter().any(
        |w| matches!(w, LoadWarning::TextureOptionIgnored { option, .. } if option == "-clamp on")
    ));
}

#[test]
fn gltf_with_required_compression_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let gltf = write(
        dir.path(),
        "d.gltf",
        br#"{"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],
            "extensionsRequired":["KHR_draco_mesh_compression"],"meshes":[]}"#,
    );
    let err = load_mesh(&gltf).unwrap_err();
    assert!(
        matches!(&err, MeshError::GltfExtensionRequired { extension, .. } if extension == "KHR_draco_mesh_compression")
    );
    assert!(err.to_string().contains("KHR_draco_mesh_compression"));
}

#[test]
fn gltf_with_embedded_buffer_and_node_transform() {
    // One triangle, data URI buffer (3 positions as f32), node translated by 1e6 in x and
    // scaled by -1 in z (mirroring: winding must be flipped back).
    let mut bytes = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        bytes.extend_from_slice(&v.to_le_bytes());
    }
    let b64 = base64_encode(&bytes);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],
        "nodes":[{{"children":[1],"translation":[1000000,0,0]}},{{"mesh":0,"scale":[1,1,-1]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
            "min":[0,0,0],"max":[1,1,0]}}],
        "bufferViews":[{{"buffer":0,"byteLength":36}}],
        "buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{b64}"}}]}}"#
    );
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "t.gltf", json.as_bytes());
    let mesh = load_mesh(&path).unwrap().mesh;
    assert_eq!(mesh.triangles, vec![[0, 2, 1]]);
    let world = mesh.world_position(spatch_mesh::VertexId(1));
    assert!((world - glam::DVec3::new(1_000_001.0, 0.0, 0.0)).length() < 1e-9);
    // The mirror turns the front face from +z to -z; the winding flip keeps the front face
    // counter-clockwise, so the face normal follows.
    assert!(mesh.face_normal(spatch_mesh::FaceId(0)).z < -0.99);
}

fn base64_encode(bytes: &[u8]) -> String {
    const TABLE: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(TABLE[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn binary_ply_with_colours_loads() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "cube.ply", &binary_ply_cube());
    let mesh = load_mesh(&path).unwrap().mesh;
    assert_eq!(mesh.triangles.len(), 12);
    assert_eq!(
        mesh.vertex_colours.as_ref().unwrap()[0],
        [200, 100, 50, 255]
    );
}

/// Every prefix of a valid file is either a valid file or an error, never a panic.
#[test]
fn truncated_files_give_errors_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    let cube = shapes::cube(1.0);
    let mut cases: Vec<(&str, Vec<u8>)> = vec![
        ("t.obj", cube.to_obj([0.0; 3]).into_bytes()),
        ("t.ply", cube.to_ply_ascii().into_bytes()),
        ("b.ply", binary_ply_cube()),
        (
            "t.off",
            b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n4 0 2 3 1\n".to_vec(),
        ),
    ];
    if let Some(glb) = spatch_fixtures::shared_data("gltf/BoxTextured.glb") {
        cases.push(("t.glb", std::fs::read(glb).unwrap()));
    }
    for (name, bytes) in &cases {
        let path = dir.path().join(name);
        let mut errors = 0;
        // Every prefix of small files; about 600 evenly spread prefixes of larger ones (each
        // full-length glTF prefix decodes a PNG, which dominates the run time).
        let step = (bytes.len() / 600).max(1);
        let lengths: Vec<usize> = (0..bytes.len()).step_by(step).collect();
        for &len in &lengths {
            std::fs::write(&path, &bytes[..len]).unwrap();
            if load_mesh(&path).is_err() {
                errors += 1;
            }
            if name.ends_with(".ply") {
                let _ = load_point_cloud(&path);
            }
        }
        assert!(
            errors > lengths.len() / 2,
            "{name}: only {errors} prefixes failed"
        );
        std::fs::write(&path, bytes).unwrap();
        assert!(load_mesh(&path).is_ok(), "{name}: the whole file must load");
    }
}

/// Random bytes after a valid header: errors or meshes, never panics.
#[test]
fn garbage_bodies_do_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut rng = spatch_fixtures::XorShift(0x1234_5678_9abc_def0);
    let headers: [(&str, &[u8]); 4] = [
        ("g.obj", b"v 0 0 0\n"),
        ("g.ply", b"ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"),
        ("g.off", b"OFF\n3 1 0\n"),
        ("g.glb", b"glTF\x02\x00\x00\x00"),
    ];
    for (name, header) in headers {
        let path = dir.path().join(name);
        for round in 0..100 {
            let mut bytes = header.to_vec();
            let len = (rng.next_u64() % 200) as usize;
            for _ in 0..len {
                let r = rng.next_u64();
                // Half the rounds use text-like bytes so text parsers get past tokenizing.
                bytes.push(if round % 2 == 0 {
                    b"0123456789 .-\nfv/e"[(r % 18) as usize]
                } else {
                    r as u8
                });
            }
            std::fs::write(&path, &bytes).unwrap();
            let _ = load_mesh(&path);
        }
    }
}

/// An ASCII PLY whose body the reader cannot parse is refused in one line that quotes the
/// line it could not read (the reader's apostrophes unescaped, the line's stray carriage
/// return not written raw).
#[test]
fn an_unreadable_ply_line_is_quoted_plainly() {
    let dir = tempfile::tempdir().unwrap();
    let header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                  property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    let body = "0 0 0\nnan 0 0\r\n0 1 0\n3 0 1 2\n";
    let path = write(dir.path(), "bad.ply", format!("{header}{body}").as_bytes());
    match load_mesh(&path) {
        Err(e @ MeshError::Ply { .. }) => {
            let message = e.to_string();
            assert_eq!(message.lines().count(), 1, "{message}");
            assert!(
                !message.contains('\r') && !message.contains("\\'"),
                "{message}"
            );
            assert!(message.contains("Couldn't read"), "{message}");
            assert!(message.ends_with("cannot read 'nan 0 0'"), "{message}");
        }
        other => panic!("expected a PLY error, got {other:?}"),
    }
}
