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
