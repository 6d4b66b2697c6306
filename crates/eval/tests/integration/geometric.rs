//! The geometric error on known cases and on the converted bunny.

use glam::Vec3;
use spatch_convert::{convert, ConvertInput, ConvertOptions};
use spatch_eval::geometric::node_to_surface_distances;
use spatch_eval::{geometric_error, node_to_surface, surface_to_patch};
use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
use spatch_mesh::{sample_surface, Bvh, TriangleMesh};

fn square_mesh() -> TriangleMesh {
    TriangleMesh::new(
        vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
        vec![[0, 1, 2], [2, 1, 3]],
    )
    .unwrap()
}

/// One patch of 11 × 11 nodes over the unit square at height `z`, with `hole` nodes emptied.
fn square_scene(z: f32, hole: &[(usize, usize)]) -> Scene {
    let frame = Frame::new(
        Vec3::new(0.0, 0.0, z),
        Vec3::X * 0.1,
        Vec3::Y * 0.1,
        Vec3::Z * 0.01,
    )
    .unwrap();
    let mut d = vec![0u16; 121];
    for &(i, j) in hole {
        d[j * 11 + i] = spatch_format::EMPTY;
    }
    let patch = Patch::new(frame, GridSize::new(11, 11).unwrap(), d, None).unwrap();
    Scene::new(glam::DVec3::ZERO, ColourChannel::None, vec![patch]).unwrap()
}

fn samples(mesh: &TriangleMesh, n: usize) -> Vec<Vec3> {
    sample_surface(mesh, n, 1)
        .into_iter()
        .map(|s| s.point)
        .collect()
}

#[test]
fn a_lifted_patch_is_measured_at_its_height() {
    let mesh = square_mesh();
    let bvh = Bvh::new(&mesh);
    let e = node_to_surface(&square_scene(0.25, &[]), &mesh, &bvh);
    assert_eq!(e.samples, 121);
    assert!((e.max - 0.25).abs() < 1e-6 && (e.rms - 0.25).abs() < 1e-6);
    let s = surface_to_patch(&square_scene(0.25, &[]), &mesh, &samples(&mesh, 2000));
    assert!((s.max - 0.25).abs() < 1e-5, "{s:?}");
    assert!((e.max_rel - 0.25 / 2f64.sqrt()).abs() < 1e-6);
}

#[test]
fn a_hole_shows_in_surface_to_patch_only() {
    let mesh = square_mesh();
    let bvh = Bvh::new(&mesh);
    // Emptying node (5, 5) removes the four cells around it: a 0.2 × 0.2 hole.
    let scene = square_scene(0.0, &[(5, 5)]);
    assert!(node_to_surface(&scene, &mesh, &bvh).max < 1e-6);
    let s = surface_to_patch(&scene, &mesh, &samples(&mesh, 20_000));
    assert!(s.max > 0.08 && s.max <= 0.1 + 1e-5, "{s:?}");
    let whole = surface_to_patch(&square_scene(0.0, &[]), &mesh, &samples(&mesh, 20_000));
    assert!(whole.max < 1e-5);
}

#[test]
fn offsets_are_applied_in_f64() {
    let mut mesh = square_mesh();
    mesh.origin = glam::DVec3::splat(1e7);
    let frame = Frame::new(Vec3::ZERO, Vec3::X * 0.1, Vec3::Y * 0.1, Vec3::Z * 0.01).unwrap();
    let patch = Patch::new(frame, GridSize::new(11, 11).unwrap(), vec![0; 121], None).unwrap();
    let scene = Scene::new(glam::DVec3::splat(1e7), ColourChannel::None, vec![patch]).unwrap();
    let e = geometric_error(&scene, &mesh, 3);
    assert!(
        e.node_to_surface.max < 1e-6 && e.surface_to_patch.max < 1e-5,
        "{e:?}"
    );
}

#[test]
fn bounded_node_searches_give_the_unbounded_distances() {
    // A converted sphere moved off its source, so every node has a real distance.
    let shape = spatch_fixtures::shapes::icosphere(1.0, 3);
    let mesh = TriangleMesh::new(
        shape.positions.iter().map(|&p| Vec3::from(p)).collect(),
        shape.triangles.clone(),
    )
    .unwrap();
    let c = convert(ConvertInput::Mesh(mesh.clone()), &ConvertOptions::default()).unwrap();
    let mut source = mesh;
    source.origin += glam::DVec3::new(0.03, -0.02, 0.05);
    let bvh = Bvh::new(&source);
    let got = node_to_surface_distances(&c.scene, &source, &bvh);
    let shift = (c.scene.offset() - source.origin).as_vec3();
    let expected: Vec<f32> = c
        .scene
        .patches()
        .iter()
        .flat_map(|p| {
            p.filled_nodes()
                .map(|(_, _, q)| q + shift)
                .collect::<Vec<_>>()
        })
        .map(|q| bvh.closest_point(q, f32::INFINITY).unwrap().distance)
        .collect();
    assert_eq!(got.len(), expected.len());
    assert!(got.iter().any(|&d| d > 0.01));
    assert_eq!(got, expected);
}

#[test]
fn a_converted_sphere_is_close_and_has_no_holes() {
    let shape = spatch_fixtures::shapes::icosphere(1.0, 4);
    let mesh = TriangleMesh::new(
        shape.positions.iter().map(|&p| Vec3::from(p)).collect(),
        shape.triangles.clone(),
    )
    .unwrap();
    let c = convert(ConvertInput::Mesh(mesh), &ConvertOptions::default()).unwrap();
    let e = geometric_error(&c.scene, &c.mesh, 5);
    // Nodes: within the largest half step of any patch (plus f32 slack).
    let half_step = c
        .scene
        .patches()
        .iter()
        .map(|p| p.frame().lengths()[2] * 0.5)
        .fold(0.0f32, f32::max);
    assert!(
        e.node_to_surface.max <= f64::from(half_step) + 1e-5,
        "{e:?}"
    );
    // A closed sphere: every sample is under some cell.
    assert!(e.surface_to_patch.max_rel < 0.002, "{e:?}");
    assert!(e.surface_to_patch.rms_rel < 0.0002, "{e:?}");
}

/// Issue 4's targets on the Stanford bunny (run in release to be quick:
/// `cargo test --release -p spatch-eval -- bunny`).
#[test]
fn bunny_meets_the_issue_targets() {
    let path = spatch_fixtures::require_shared!("bunny/reconstruction/bun_zipper.ply");
    // The default conversion, sharp-edge patches included (they go only where the surface
    // patches leave a gap at a crease).
    let c = convert(ConvertInput::Path(&path), &ConvertOptions::default()).unwrap();
    assert_eq!(c.mesh.face_count(), 69_451);
    assert!(
        c.report.counts.nodes <= 441_014,
        "{} nodes",
        c.report.counts.nodes
    );
    assert!(
        c.report.counts.bytes <= 1_830_000,
        "{} bytes",
        c.report.counts.bytes
    );
    let e = geometric_error(&c.scene, &c.mesh, 1);
    let diag = e.diagonal;
    assert!(e.surface_to_patch.max_rel <= 0.005, "{e:?}");
    assert!(e.surface_to_patch.rms_rel <= 0.0005, "{e:?}");
    let step = c
        .scene
        .patches()
        .iter()
        .map(|p| f64::from(p.frame().lengths()[2]))
        .fold(0.0, f64::max);
    assert!(e.node_to_surface.max <= step + 0.001 * diag, "{e:?}");
}
