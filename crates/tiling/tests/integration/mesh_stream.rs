//! A mesh tile streamed from a PLY (ASCII, binary with quads and an extra face property)
//! or an OBJ holds the same faces as the tile cut from the whole loaded mesh.

use std::path::Path;

use glam::DVec3;
use spatch_mesh::{load_mesh, prepare_mesh, PrepareOptions, TriangleMesh};
use spatch_tiling::{can_stream_mesh, make_mesh_plan, mesh_tile, read_mesh_tile};

/// The torus's quads as a binary little-endian PLY whose faces carry a flag byte first.
fn binary_quads(m: u32, n: u32) -> Vec<u8> {
    let shape = spatch_fixtures::shapes::torus(2.0, 0.7, m, n);
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\nproperty uchar flags\n\
         property list uchar uint vertex_indices\nend_header\n",
        shape.positions.len(),
        m * n
    )
    .into_bytes();
    for p in &shape.positions {
        p.iter().for_each(|c| out.extend(c.to_le_bytes()));
    }
    let v = |i: u32, j: u32| (i % m) * n + j % n;
    for i in 0..m {
        for j in 0..n {
            out.extend([7u8, 4]);
            for k in [v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)] {
                out.extend(k.to_le_bytes());
            }
        }
    }
    out
}

/// Each triangle's world corners.
fn corners(mesh: &TriangleMesh) -> Vec<[DVec3; 3]> {
    let world = |v: u32| mesh.origin + mesh.positions[v as usize].as_dvec3();
    mesh.triangles.iter().map(|t| t.map(world)).collect()
}

/// Whether every triangle of `a` matches a distinct one of `b` within f32 rounding.
fn contains_triangles(b: &[[DVec3; 3]], a: &[[DVec3; 3]]) -> bool {
    let close =
        |x: &[DVec3; 3], y: &[DVec3; 3]| x.iter().all(|p| y.iter().any(|q| p.distance(*q) < 1e-5));
    let mut used = vec![false; b.len()];
    a.iter().all(|x| {
        let found = (0..b.len()).find(|&j| !used[j] && close(x, &b[j]));
        found.map(|j| used[j] = true).is_some()
    })
}

/// Checks every tile of `path`; `polygons`: the file has polygons, whose triangles a
/// tile reads together when the polygon touches it (the cut keeps triangles one by one).
fn check_format(path: &Path, polygons: bool) {
    assert!(can_stream_mesh(path).unwrap(), "{}", path.display());
    let whole = prepare_mesh(&load_mesh(path).unwrap().mesh, &PrepareOptions::default()).0;
    let plan = make_mesh_plan(&whole, path, 1.7, 0.2, 0.05).unwrap();
    assert!(plan.tiles.len() >= 9);
    let anchor = DVec3::from_array(plan.grid.anchor);
    let mut faces = 0;
    for tile in &plan.tiles {
        let streamed = read_mesh_tile(path, anchor, &tile.buffered).unwrap();
        let cut = mesh_tile(&whole, &tile.buffered);
        assert_eq!(streamed.origin, anchor);
        let (read, cut_faces) = (streamed.triangles.len(), cut.triangles.len());
        assert!(
            if polygons {
                read <= 2 * cut_faces
            } else {
                read == cut_faces
            },
            "{} tile {}: {read} faces streamed, {cut_faces} cut",
            path.display(),
            tile.index
        );
        assert!(
            contains_triangles(&corners(&streamed), &corners(&cut)),
            "{} tile {}: {} faces streamed, {} cut",
            path.display(),
            tile.index,
            streamed.triangles.len(),
            cut.triangles.len()
        );
        faces += streamed.triangles.len();
    }
    assert!(
        faces > whole.triangles.len(),
        "tiles overlap by their buffers"
    );
}

#[test]
fn streamed_tiles_hold_the_faces_of_the_whole_mesh_tiles() {
    let dir = tempfile::tempdir().unwrap();
    let torus = spatch_fixtures::shapes::torus(2.0, 0.7, 40, 20);
    let obj = dir.path().join("torus.obj");
    std::fs::write(&obj, torus.to_obj([0.0; 3])).unwrap();
    let ascii = dir.path().join("torus_ascii.ply");
    std::fs::write(&ascii, torus.to_ply_ascii()).unwrap();
    let binary = dir.path().join("quads.ply");
    std::fs::write(&binary, binary_quads(40, 20)).unwrap();
    check_format(&obj, false);
    check_format(&ascii, false);
    check_format(&binary, true);
}

#[test]
fn an_obj_with_materials_is_not_streamed() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("m.obj");
    std::fs::write(&obj, "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    assert!(!can_stream_mesh(&obj).unwrap());
}

#[test]
fn a_face_naming_a_missing_vertex_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("bad.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").unwrap();
    let area = spatch_tiling::WorldBox::new(DVec3::splat(-1.0), DVec3::splat(2.0));
    let err = read_mesh_tile(&obj, DVec3::ZERO, &area).unwrap_err();
    assert!(err.to_string().contains("vertex 8"), "{err}");
}
