//! A mesh plan streamed from a PLY or OBJ file lists the tiles, counts and spacing of the
//! plan made from the loaded mesh, and every face the tasks read has exactly one owner
//! among the listed tiles.

use std::path::Path;

use glam::DVec3;
use spatch_mesh::{load_mesh, prepare_mesh, PrepareOptions};
use spatch_tiling::{census_mesh, census_mesh_file, owns, read_mesh_tile, Plan};

/// The plan of `path`, streamed and loaded (tiles of 1.1, buffer 0.1, the census's spacing).
fn plans(path: &Path) -> (Plan, Plan, f64, f64) {
    let streamed = census_mesh_file(path, 1.1).unwrap();
    let whole = prepare_mesh(&load_mesh(path).unwrap().mesh, &PrepareOptions::default()).0;
    let loaded = census_mesh(&whole, 1.1).unwrap();
    let (sa, la) = (
        streamed.mean_face_area().unwrap(),
        loaded.mean_face_area().unwrap(),
    );
    (
        streamed.plan(path, 0.1, 0.05).unwrap(),
        loaded.plan(path, 0.1, 0.05).unwrap(),
        sa,
        la,
    )
}

/// Checks `path`'s two plans and the owners of the streamed tasks' faces.
fn check(path: &Path) {
    let (streamed, loaded, sa, la) = plans(path);
    assert!(streamed.tiles.len() >= 9, "{} tiles", streamed.tiles.len());
    assert!((sa - la).abs() <= 1e-6 * la, "mean areas {sa} vs {la}");
    assert_eq!(streamed.points, loaded.points);
    // The loader rounds the file's coordinates to f32; the stream keeps them.
    let close = |a: [f64; 3], b: [f64; 3]| (0..3).all(|k| (a[k] - b[k]).abs() < 1e-6);
    assert!(close(streamed.grid.anchor, loaded.grid.anchor));
    assert!(close(streamed.bounds.max, loaded.bounds.max));
    let summary =
        |p: &Plan| -> Vec<([i64; 3], u64)> { p.tiles.iter().map(|t| (t.key, t.points)).collect() };
    assert_eq!(summary(&streamed), summary(&loaded), "{}", path.display());
    let anchor = DVec3::from_array(streamed.grid.anchor);
    let mut owned = 0u64;
    for tile in &streamed.tiles {
        let part = read_mesh_tile(path, anchor, &tile.buffered).unwrap();
        owned += part
            .triangles
            .iter()
            .filter(|t| {
                let [a, b, c] = t.map(|v| part.origin + part.positions[v as usize].as_dvec3());
                owns(&tile.bounds, (a + b + c) / 3.0)
            })
            .count() as u64;
    }
    assert_eq!(
        owned,
        streamed.points,
        "{}: faces owned by the tiles",
        path.display()
    );
}

#[test]
fn streamed_mesh_plans_equal_the_loaded_ones() {
    let dir = tempfile::tempdir().unwrap();
    let torus = spatch_fixtures::shapes::torus(2.0, 0.7, 40, 20);
    let obj = dir.path().join("torus.obj");
    std::fs::write(&obj, torus.to_obj([0.0; 3])).unwrap();
    let ascii = dir.path().join("torus_ascii.ply");
    std::fs::write(&ascii, torus.to_ply_ascii()).unwrap();
    check(&obj);
    check(&ascii);
}

#[test]
fn a_file_with_no_face_has_no_plan() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("points.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\n").unwrap();
    let census = census_mesh_file(&obj, 1.0).unwrap();
    assert!(census.mean_face_area().is_none());
    assert!(census.plan(&obj, 0.1, 0.05).is_err());
}
