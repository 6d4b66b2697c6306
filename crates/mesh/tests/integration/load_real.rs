//! Loading the real models of the shared data set.

use spatch_fixtures::require_shared;
use spatch_mesh::{load_mesh, load_point_cloud, LoadWarning};

#[test]
fn bunny_zipper_counts() {
    let path = require_shared!("bunny/reconstruction/bun_zipper.ply");
    let loaded = load_mesh(&path).unwrap();
    let mesh = &loaded.mesh;
    assert_eq!(mesh.positions.len(), 35_947);
    assert_eq!(mesh.triangles.len(), 69_451);
    let mut used = vec![false; mesh.positions.len()];
    mesh.triangles
        .iter()
        .flatten()
        .for_each(|&i| used[i as usize] = true);
    assert_eq!(used.iter().filter(|&&u| u).count(), 34_834);
    assert!(!mesh.has_colour());
    assert!(mesh.vertex_normals.is_none());
    // The bunny is about 0.15 m across; the origin is its bounding-box centre.
    let d = mesh.diagonal();
    assert!((0.2..0.3).contains(&d), "diagonal {d}");
    assert!(mesh.bounds().centre().length() < 1e-6);
}

#[test]
fn bunny_obj_matches_the_ply() {
    let obj = require_shared!("bunny/stanford-bunny.obj");
    let ply = require_shared!("bunny/reconstruction/bun_zipper.ply");
    let a = load_mesh(obj).unwrap().mesh;
    let b = load_mesh(ply).unwrap().mesh;
    assert_eq!(a.triangles, b.triangles);
    assert_eq!(a.positions.len(), b.positions.len());
}

#[test]
fn mannequin_binary_ply_has_colours_and_normals() {
    let path = require_shared!("head/mannequin.ply");
    let mesh = load_mesh(&path).unwrap().mesh;
    assert_eq!(mesh.positions.len(), 11_335);
    assert_eq!(mesh.triangles.len(), 22_653);
    assert!(mesh.has_colour());
    let colours = mesh.vertex_colours.as_ref().unwrap();
    // Float colours in 0..1 became bytes: not all black, not all white.
    assert!(colours.iter().any(|c| c[0] > 20 && c[0] < 235));
    let normals = mesh.vertex_normals.as_ref().unwrap();
    let unit = normals
        .iter()
        .filter(|n| (n.length() - 1.0).abs() < 1e-3)
        .count();
    assert!(unit > normals.len() * 99 / 100);
}

#[test]
fn cad_models_load_in_both_formats() {
    for (ply, off, vertices, triangles) in [
        ("cad/cube-meshed.ply", "cad/cube-meshed.off", 866, 1728),
        ("cad/cylinder.ply", "cad/cylinder.off", 1200, 2262),
    ] {
        let ply = load_mesh(require_shared!(ply)).unwrap().mesh;
        let off = load_mesh(require_shared!(off)).unwrap().mesh;
        assert_eq!(ply.positions.len(), vertices);
        assert_eq!(ply.triangles.len(), triangles);
        assert_eq!(ply.triangles, off.triangles);
        // PLY floats are f32 and OFF text is read as f64: equal to f32 precision.
        let worst = ply
            .positions
            .iter()
            .zip(&off.positions)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .fold(0.0f32, f32::max);
        assert!(worst < 1e-6, "largest difference {worst}");
    }
    let fandisk = load_mesh(require_shared!("cad/fandisk.obj")).unwrap().mesh;
    assert_eq!(fandisk.positions.len(), 6475);
    assert_eq!(fandisk.triangles.len(), 12_946);
    assert!(!fandisk.has_colour());
}

#[test]
fn fuze_obj_is_textured_and_visible() {
    let path = require_shared!("textured_obj/fuze/fuze.obj");
    let loaded = load_mesh(&path).unwrap();
    let mesh = &loaded.mesh;
    assert_eq!(mesh.triangles.len(), 1000);
    assert!(mesh.has_colour());
    let texture = mesh.materials[0].texture.as_ref().unwrap();
    assert_eq!((texture.width, texture.height), (1024, 1024));
    // `Tr 1.0` must not make it transparent.
    assert_eq!(mesh.materials[0].base_colour[3], 1.0);
    let c = mesh
        .colour_at(spatch_mesh::FaceId(0), glam::Vec3::splat(1.0 / 3.0))
        .unwrap();
    assert_eq!(c[3], 255);
    assert!(mesh.vertex_normals.is_some());
}

#[test]
fn spot_picks_up_its_texture() {
    let path = require_shared!("textured_obj/spot/spot_triangulated.obj");
    let loaded = load_mesh(&path).unwrap();
    assert_eq!(loaded.mesh.triangles.len(), 5856);
    assert!(loaded.mesh.has_colour());
    assert!(loaded.warnings.iter().any(
        |w| matches!(w, LoadWarning::TextureGuessed { path } if path.ends_with("spot_texture.png"))
    ));
}

#[test]
fn gltf_samples_have_textures() {
    let duck = load_mesh(require_shared!("gltf/Duck.glb")).unwrap();
    assert_eq!(duck.mesh.triangles.len(), 4212);
    assert_eq!(duck.mesh.positions.len(), 2399);
    assert!(duck.mesh.has_colour());
    assert!(duck.mesh.materials.iter().any(|m| m.texture.is_some()));
    assert!(duck.warnings.is_empty(), "{:?}", duck.warnings);
    let boxed = load_mesh(require_shared!("gltf/BoxTextured.glb")).unwrap();
    assert_eq!(boxed.mesh.triangles.len(), 12);
    assert_eq!(boxed.mesh.positions.len(), 24);
    assert!(boxed.mesh.has_colour());
    assert!(boxed.mesh.face_uvs.is_some());
    // The box is a unit cube after its node transform: diagonal sqrt(3).
    assert!((boxed.mesh.diagonal() - 3f32.sqrt()).abs() < 1e-4);
}

#[test]
fn point_clouds_load() {
    let hoppe = load_point_cloud(require_shared!("pointcloud/hoppe_distcap.ply")).unwrap();
    assert_eq!(hoppe.cloud.len(), 12_745);
    assert_eq!(hoppe.dropped_non_finite, 0);
    let scan = load_point_cloud(require_shared!("bunny/data/bun000.ply")).unwrap();
    assert_eq!(scan.cloud.len(), 40_256);
    assert!(scan.cloud.colours.is_none());
    // A mesh's vertices are a cloud too.
    let mannequin = load_point_cloud(require_shared!("head/mannequin.ply")).unwrap();
    assert_eq!(mannequin.cloud.len(), 11_335);
    assert!(mannequin.cloud.colours.is_some() && mannequin.cloud.normals.is_some());
}

#[test]
fn a_cloud_is_not_a_mesh() {
    let path = require_shared!("pointcloud/hoppe_distcap.ply");
    assert!(matches!(
        load_mesh(path),
        Err(spatch_mesh::MeshError::NoFaces { .. })
    ));
}

#[test]
fn raw_range_scans_load_as_meshes_joined_along_their_grid() {
    // The counts `bench/range_grid_mesh.py` (numpy, written apart from this reader) gives
    // the same scans with the same rule.
    for (scan, points, triangles) in [
        ("bunny/data/bun000.ply", 40_256, 75_496),
        ("bunny/data/chin.ply", 37_738, 68_435),
    ] {
        let loaded = load_mesh(require_shared!(scan)).unwrap();
        assert_eq!(loaded.mesh.positions.len(), points, "{scan}");
        assert_eq!(loaded.mesh.triangles.len(), triangles, "{scan}");
    }
}
