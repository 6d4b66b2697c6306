use crate::test_command::TestCommand;

/// Splits a PLY file into its header lines and body length.
fn header(bytes: &[u8]) -> (Vec<String>, usize) {
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let text = String::from_utf8_lossy(&bytes[..end]);
    (text.lines().map(str::to_owned).collect(), bytes.len() - end)
}

fn count(lines: &[String], element: &str) -> usize {
    lines
        .iter()
        .find_map(|l| l.strip_prefix(&format!("element {element} ")))
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn nodes_export_as_standard_point_ply() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    t.run(&["export", &name, "-o", "nodes.ply"]).success();
    let bytes = std::fs::read(t.path("nodes.ply")).unwrap();
    let (lines, body) = header(&bytes);
    assert_eq!(lines[0], "ply");
    assert_eq!(lines[1], "format binary_little_endian 1.0");
    let n = count(&lines, "vertex");
    assert_eq!(n, 200 * 81);
    assert_eq!(body, n * 24, "six floats per vertex");
    // Every exported point lies on the sphere and its normal points outwards.
    let start = bytes.len() - body;
    for record in bytes[start..].chunks_exact(24) {
        let f: Vec<f32> = record
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        let r = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        assert!((r - 10.0).abs() < 0.001, "{r}");
        let radial = (f[0] * f[3] + f[1] * f[4] + f[2] * f[5]) / r;
        assert!(radial > 0.99, "normal not outward: {radial}");
    }
}

#[test]
fn cells_export_as_a_triangle_mesh() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    t.run(&["export", &name, "--cells", "-o", "cells.ply"])
        .success();
    let bytes = std::fs::read(t.path("cells.ply")).unwrap();
    let (lines, body) = header(&bytes);
    let (v, f) = (count(&lines, "vertex"), count(&lines, "face"));
    assert_eq!(v, 200 * 81);
    assert_eq!(f, 200 * 64 * 2);
    assert!(lines.contains(&"property list uchar int vertex_indices".to_owned()));
    assert_eq!(body, v * 24 + f * 13);
}

#[test]
fn an_independent_ply_parser_reads_both_exports() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    t.run(&["export", &name, "-o", "nodes.ply"]).success();
    t.run(&["export", &name, "--cells", "-o", "cells.ply"])
        .success();
    // spatch-mesh reads PLY through ply-rs-bw, a general PLY parser.
    let cloud = spatch_mesh::load_point_cloud(t.path("nodes.ply"))
        .unwrap()
        .cloud;
    assert_eq!(cloud.len(), 200 * 81);
    assert!(cloud.normals.is_some());
    let mesh = spatch_mesh::load_mesh(t.path("cells.ply")).unwrap().mesh;
    assert_eq!(mesh.triangles.len(), 200 * 64 * 2);
    // Outward winding: every triangle's normal points away from the centre.
    for face in mesh.faces() {
        let centre = mesh.world_position(mesh.face_vertex_ids(face)[0]);
        assert!(mesh.face_normal(face).as_dvec3().dot(centre) > 0.0);
    }
}

/// Issue 22, item 6: every format, chosen from the extension, opens in
/// spatch's own loaders (tobj for OBJ, the gltf crate for glTF/GLB,
/// ply-rs-bw for PLY) with one welded mesh per patch.
#[test]
fn issue_22_cells_export_to_every_format_from_the_extension() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    for out in ["c.glb", "c.gltf", "c.obj", "c.ply"] {
        let run = t.run(&["export", &name, "--cells", "-o", out]).success();
        assert!(
            run.stdout
                .contains("200 meshes, 16200 vertices, 25600 triangles"),
            "{out}: {}",
            run.stdout
        );
        let mesh = spatch_mesh::load_mesh(t.path(out)).unwrap().mesh;
        assert_eq!(mesh.triangles.len(), 200 * 64 * 2, "{out}");
        // Welded within each patch: 81 vertices per 9 × 9 patch, not 6 per cell.
        assert!(
            mesh.positions.len() <= 200 * 81,
            "{out}: {}",
            mesh.positions.len()
        );
        for face in mesh.faces().step_by(97) {
            let p = mesh.world_position(mesh.face_vertex_ids(face)[0]);
            assert!((p.length() - 10.0).abs() < 0.01, "{out}: {p}");
            assert!(
                mesh.face_normal(face).as_dvec3().dot(p) > 0.0,
                "{out}: winding"
            );
        }
    }
    let bytes = std::fs::read(t.path("c.glb")).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
}

#[test]
fn issue_22_an_unknown_extension_or_bad_origin_is_refused() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let run = t.run(&["export", &name, "-o", "x.stl"]);
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.contains("x.stl") && run.stderr.contains("--format"),
        "{}",
        run.stderr
    );
    assert!(!t.path("x.stl").exists());
    t.run(&["export", &name, "--format", "obj", "-o", "x.txt"])
        .success();
    let run = t.run(&["export", &name, "--origin", "1,2", "-o", "y.ply"]);
    assert_eq!(run.code, 2);
    assert!(!t.path("y.ply").exists());
}

/// Issue 22, item 5: a scene 1e7 from the origin exports double positions
/// (or float ones after --origin, recorded in the header).
#[test]
fn issue_22_a_far_scene_exports_doubles_or_a_recorded_origin() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    t.run(&[
        "merge",
        "s.spatch",
        "s.spatch",
        "--translate",
        "1e7,0,0",
        "--translate",
        "1e7,0,0",
        "-o",
        "far.spatch",
    ])
    .success();
    let run = t.run(&["export", "far.spatch", "-o", "far.ply"]).success();
    assert!(run.stdout.contains("double positions"), "{}", run.stdout);
    let (lines, _) = header(&std::fs::read(t.path("far.ply")).unwrap());
    assert!(lines.contains(&"property double x".to_owned()));
    t.run(&[
        "export",
        "far.spatch",
        "--origin",
        "1e7,0,0",
        "-o",
        "near.ply",
    ])
    .success();
    let (lines, _) = header(&std::fs::read(t.path("near.ply")).unwrap());
    assert!(lines.contains(&"property float x".to_owned()));
    assert!(
        lines
            .iter()
            .any(|l| l.starts_with("comment origin 10000000 0 0")),
        "{lines:?}"
    );
    let cloud = spatch_mesh::load_point_cloud(t.path("far.ply"))
        .unwrap()
        .cloud;
    let p = cloud.origin + cloud.positions[0].as_dvec3();
    assert!(
        ((p - glam::DVec3::new(1e7, 0.0, 0.0)).length() - 10.0).abs() < 1e-3,
        "{p}"
    );
}
