//! The pipeline on generated shapes.

use glam::Vec3;
use spatch_convert::{convert, ConvertError, ConvertInput, ConvertOptions};
use spatch_format::{decode_scene, ColourChannel};
use spatch_mesh::TriangleMesh;

fn mesh_of(shape: &spatch_fixtures::Shape) -> TriangleMesh {
    TriangleMesh::new(
        shape.positions.iter().map(|&p| Vec3::from(p)).collect(),
        shape.triangles.clone(),
    )
    .unwrap()
}

#[test]
fn a_torus_converts_with_every_stage_timed() {
    let mesh = mesh_of(&spatch_fixtures::shapes::torus(1.0, 0.3, 64, 24));
    let c = convert(ConvertInput::Mesh(mesh), &ConvertOptions::default()).unwrap();
    let names: Vec<&str> = c.report.stages.iter().map(|s| s.name).collect();
    assert_eq!(
        names,
        [
            "load",
            "prepare",
            "adjacency",
            "orient",
            "segment",
            "fit",
            "edges",
            "sides",
            "encode"
        ]
    );
    assert!(c.report.counts.patches > 4);
    assert_eq!(c.report.counts.patches, c.scene.patches().len());
    assert!(c.report.counts.filled_nodes <= c.report.counts.nodes);
    assert_eq!(c.report.counts.bytes, c.bytes.len());
    assert_eq!(c.report.colour, "none");
    assert_eq!(c.scene.channel(), ColourChannel::None);
    assert_eq!(decode_scene(&c.bytes).unwrap(), c.scene);
    assert!(c.report.seconds >= c.report.stage_seconds("fit").unwrap());
}

#[test]
fn one_and_two_threads_give_identical_files() {
    let mesh = mesh_of(&spatch_fixtures::shapes::icosphere(2.0, 4));
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| convert(ConvertInput::Mesh(mesh.clone()), &ConvertOptions::default()))
            .unwrap()
            .bytes
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn a_mesh_of_only_degenerate_faces_is_refused() {
    let mesh =
        TriangleMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], vec![[0, 1, 2]]).unwrap();
    let err = convert(ConvertInput::Mesh(mesh), &ConvertOptions::default()).unwrap_err();
    assert!(matches!(err, ConvertError::NoSurface { faces: 1 }), "{err}");
}

#[test]
fn a_missing_file_names_the_file() {
    let err = convert(
        ConvertInput::Path("no/such/model.ply".as_ref()),
        &ConvertOptions::default(),
    )
    .unwrap_err();
    assert!(err.to_string().contains("no/such/model.ply"), "{err}");
}

#[test]
fn a_model_far_from_the_origin_keeps_its_place() {
    let shape = spatch_fixtures::shapes::icosphere(1.0, 3);
    let world: Vec<glam::DVec3> = shape
        .positions
        .iter()
        .map(|&p| Vec3::from(p).as_dvec3() + glam::DVec3::splat(1e6))
        .collect();
    let mesh = TriangleMesh::from_world_positions(&world, shape.triangles.clone()).unwrap();
    let c = convert(ConvertInput::Mesh(mesh), &ConvertOptions::default()).unwrap();
    let (lo, hi) = c.scene.bounds().unwrap();
    let centre = (lo + hi) * 0.5;
    assert!(
        (centre - glam::DVec3::splat(1e6)).length() < 0.05,
        "{centre}"
    );
}

#[test]
fn an_open_tube_records_its_openings_and_a_torus_none() {
    use spatch_format::Sides;
    let torus = mesh_of(&spatch_fixtures::shapes::torus(1.0, 0.3, 64, 24));
    let closed = convert(ConvertInput::Mesh(torus), &ConvertOptions::default()).unwrap();
    assert!(closed.scene.openings().is_empty());
    assert!(closed
        .scene
        .patches()
        .iter()
        .all(|p| p.sides() == Sides::Front));
    assert_eq!(closed.report.sides.two_sided_patches, 0);
    let tube = mesh_of(&spatch_fixtures::shapes::open_tube(1.0, 3.0, 48, 12));
    let open = convert(ConvertInput::Mesh(tube), &ConvertOptions::default()).unwrap();
    assert_eq!(open.scene.openings().len(), 2, "two rims");
    assert!(open
        .scene
        .patches()
        .iter()
        .all(|p| p.sides() == Sides::ThroughOpenings));
    assert_eq!(open.report.sides.openings, 2);
    for o in open.scene.openings() {
        assert!((o.radius() - 1.0).abs() < 0.01, "{}", o.radius());
        assert!(o.normal().z.abs() > 0.999 && o.half_thickness() < 1e-3);
    }
}
