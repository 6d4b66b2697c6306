//! `spatch convert` winds every connected piece consistently and outward: a source with
//! scattered faces turned over converts to the very file of its outward twin; one wound
//! inward to its twin's patches, all marked two-sided (it may be a room seen from inside);
//! `--keep-winding` keeps the file's winding; an open bowl wound into its hollow shows from
//! below with the default culling; a room wound inward keeps its walls seen from inside.

use spatch_fixtures::shapes::{open_tube, torus, uv_sphere, Shape};
use spatch_format::{read_scene, Sides};

use crate::golden::covered;
use crate::test_command::TestCommand;

/// `shape` with the faces `turn` picks (by index) wound the other way.
fn turned(shape: &Shape, turn: impl Fn(usize) -> bool) -> Shape {
    let mut out = shape.clone();
    for (f, t) in out.triangles.iter_mut().enumerate() {
        if turn(f) {
            t.swap(1, 2);
        }
    }
    out
}

/// Converts `shape` (written as `name.ply`) with `extra` options; returns the file's bytes
/// and the report's `details`.
pub(crate) fn convert_shape(
    t: &TestCommand,
    name: &str,
    shape: &Shape,
    extra: &[&str],
) -> (Vec<u8>, serde_json::Value) {
    std::fs::write(t.path(&format!("{name}.ply")), shape.to_ply_ascii()).unwrap();
    let (ply, out, report) = (
        format!("{name}.ply"),
        format!("{name}.spatch"),
        format!("{name}.json"),
    );
    let mut args = vec![
        "convert",
        &ply,
        "-o",
        &out,
        "-q",
        "--no-error",
        "--report",
        &report,
    ];
    args.extend_from_slice(extra);
    t.run(&args).success();
    let report: serde_json::Value = t.json(&report);
    (
        std::fs::read(t.path(&out)).unwrap(),
        report["details"].clone(),
    )
}

/// [`convert_shape`], returning the file's bytes and the report's `details.orient`.
fn convert(
    t: &TestCommand,
    name: &str,
    shape: &Shape,
    extra: &[&str],
) -> (Vec<u8>, serde_json::Value) {
    let (bytes, details) = convert_shape(t, name, shape, extra);
    (bytes, details["orient"].clone())
}

/// Asserts that the scenes `a` and `b` hold the same patches apart from their sides, and
/// that every patch of `b` is two-sided.
pub(crate) fn same_patches_with_b_two_sided(t: &TestCommand, a: &str, b: &str) {
    let (a, b) = (
        read_scene(&t.path(a)).unwrap(),
        read_scene(&t.path(b)).unwrap(),
    );
    assert_eq!(a.patches().len(), b.patches().len());
    for (p, q) in a.patches().iter().zip(b.patches()) {
        assert_eq!(q.sides(), Sides::Both);
        assert!(p.clone().with_sides(Sides::Both) == *q, "a patch differs");
    }
}

#[test]
fn inward_and_scattered_windings_convert_to_the_outward_patches() {
    let t = TestCommand::new();
    for (name, shape) in [
        ("sphere", uv_sphere(1.0, 32, 16)),
        ("tube", open_tube(1.0, 2.0, 32, 8)),
        ("torus", torus(1.0, 0.3, 48, 16)),
    ] {
        assert!(shape.signed_volume() > 0.0, "{name} is built outward");
        let (outward, orient) = convert(&t, &format!("{name}_out"), &shape, &[]);
        assert_eq!(orient["flipped_faces"], 0, "{name}: {orient}");
        let (inward, orient) = convert(&t, &format!("{name}_in"), &turned(&shape, |_| true), &[]);
        assert_eq!(
            orient["flipped_faces"],
            shape.triangles.len(),
            "{name}: {orient}"
        );
        assert_eq!(
            (orient["pieces"].as_u64(), orient["inward_pieces"].as_u64()),
            (Some(1), Some(1))
        );
        assert!(inward != outward, "{name}: not marked two-sided");
        same_patches_with_b_two_sided(
            &t,
            &format!("{name}_out.spatch"),
            &format!("{name}_in.spatch"),
        );
        let scattered = turned(&shape, |f| f % 3 == 1);
        let (mixed, orient) = convert(&t, &format!("{name}_mixed"), &scattered, &[]);
        // Faces 1, 4, 7, ... turned; the walk starts from face 0, which faces out.
        let turned_faces = (shape.triangles.len() + 1) / 3;
        assert_eq!(orient["flipped_faces"], turned_faces, "{name}: {orient}");
        assert!(
            mixed == outward,
            "{name}: the scattered source gives another file"
        );
        let (kept, orient) = convert(
            &t,
            &format!("{name}_kept"),
            &turned(&shape, |_| true),
            &["--keep-winding"],
        );
        assert!(orient.is_null(), "{name}: {orient}");
        assert!(kept != outward, "{name}: --keep-winding changed nothing");
    }
}

/// The lower half of a sphere (z ≤ 0), wound into its hollow (fronts facing up inside it).
fn inward_bowl() -> Shape {
    let sphere = uv_sphere(1.0, 48, 24);
    let below = |v: u32| sphere.positions[v as usize][2] <= 1e-6;
    let mut bowl = sphere.clone();
    bowl.triangles.retain(|t| t.iter().all(|&v| below(v)));
    turned(&bowl, |_| true)
}

#[test]
fn an_inward_bowl_shows_from_below_with_default_culling() {
    let t = TestCommand::new();
    let bowl = inward_bowl();
    convert(&t, "bowl", &bowl, &[]);
    convert(&t, "bowl_kept", &bowl, &["--keep-winding"]);
    let render = |scene: &str, out: &str, cull: &str| {
        t.run(&[
            "render",
            scene,
            "-o",
            out,
            "--width",
            "96",
            "--height",
            "96",
            "--eye",
            "0.3,0.2,-4",
            "--target",
            "0,0,-0.3",
            "--up",
            "0,1,0",
            "--cull",
            cull,
        ])
        .success();
        covered(&t.path(out))
    };
    let reference = render("bowl.spatch", "none.png", "none");
    let oriented = render("bowl.spatch", "auto.png", "auto");
    let kept = render("bowl_kept.spatch", "kept.png", "auto");
    assert!(reference > 2000, "the bowl covers {reference} px");
    assert!(
        oriented.abs_diff(reference) * 200 <= reference,
        "default culling draws {oriented} px of {reference}"
    );
    // The defect the orientation removes: kept wound inward, the culling drops its outside.
    assert!(
        kept * 2 < reference,
        "--keep-winding draws {kept} px of {reference}"
    );
}

#[test]
fn a_real_scan_wound_inward_converts_to_the_same_patches() {
    let Some(path) = spatch_fixtures::shared_data("bunny/reconstruction/bun_zipper_res2.ply")
    else {
        eprintln!("skipped: ../shared/data/bunny/reconstruction/bun_zipper_res2.ply is missing");
        return;
    };
    let mesh = spatch_mesh::load_mesh(&path).unwrap().mesh;
    let shape = Shape {
        positions: mesh.positions.iter().map(|p| p.to_array()).collect(),
        triangles: mesh.triangles.clone(),
    };
    let t = TestCommand::new();
    // The decimated scan holds 87 repeated faces (repeated_faces.rs): the 12 inside the
    // surface are dropped, the few faces wound against their piece turned.
    let (_, orient) = convert(&t, "res2", &shape, &[]);
    let as_given = orient["flipped_faces"].as_u64().unwrap();
    assert!(as_given < 20, "{orient}");
    let kept = t.json::<serde_json::Value>("res2.json")["details"]["prepare"]["output_faces"]
        .as_u64()
        .unwrap();
    let (_, orient) = convert(&t, "res2_in", &turned(&shape, |_| true), &[]);
    assert_eq!(orient["flipped_faces"], kept - as_given, "{orient}");
    same_patches_with_b_two_sided(&t, "res2.spatch", "res2_in.spatch");
}

#[test]
fn a_room_wound_inward_keeps_its_walls_from_inside() {
    // A closed box wound to face its inside, as a room's model is: rewound outward, it
    // would cull every wall from an eye inside it; marked two-sided, it fills the view.
    let t = TestCommand::new();
    let room = turned(&spatch_fixtures::shapes::cube(4.0), |_| true);
    let (_, orient) = convert(&t, "room", &room, &[]);
    assert_eq!(orient["wound_inward"], true, "{orient}");
    for (eye, target) in [
        ("0.3,0.2,0.1", "1,0.2,0.1"),
        ("-0.5,0.5,0.4", "-0.5,-1,0.4"),
    ] {
        t.run(&[
            "render",
            "room.spatch",
            "-o",
            "in.png",
            "--width",
            "64",
            "--height",
            "64",
            "--eye",
            eye,
            "--target",
            target,
            "--up",
            "0,0,1",
            "--fov",
            "60",
            "--near",
            "0.05",
        ])
        .success();
        let empty = 64 * 64 - covered(&t.path("in.png"));
        assert_eq!(empty, 0, "from {eye}: {empty} px show no wall");
    }
}

#[test]
fn from_outside_its_box_a_surface_wound_inward_draws_its_outward_twins_image() {
    // Wound inward, a sphere and a room get an inside box (container 1.4): from an eye
    // outside it their two-sided patches are culled as the outward twin's, pixel for pixel.
    let t = TestCommand::new();
    for (name, shape) in [
        ("sphere", uv_sphere(1.0, 32, 16)),
        ("room", spatch_fixtures::shapes::cube(4.0)),
    ] {
        convert(&t, &format!("{name}_out"), &shape, &[]);
        let inward = turned(&shape, |_| true);
        let (_, details) = convert_shape(&t, &format!("{name}_in"), &inward, &[]);
        let spacing = details["spacing"].as_f64().unwrap();
        let stats = t
            .run(&["stats", &format!("{name}_in.spatch"), "--json"])
            .success();
        let stats: serde_json::Value = serde_json::from_str(&stats.stdout).unwrap();
        assert!(stats["sections"]["INSD"].is_object(), "{name}: no INSD");
        let sides = &stats["sides"];
        assert_eq!(sides["both"], stats["patches"], "{name}: {sides}");
        // The box is the shape's (the unit sphere's, the 4-unit cube's) grown by the spacing.
        let reach = if name == "sphere" { 1.0 } else { 2.0 } + spacing;
        for axis in 0..3 {
            let (lo, hi) = (
                sides["inside_box"]["min"][axis].as_f64().unwrap(),
                sides["inside_box"]["max"][axis].as_f64().unwrap(),
            );
            let near = |a: f64, b: f64| (a - b).abs() < 1e-5;
            assert!(near(lo, -reach) && near(hi, reach), "{name}: {sides}");
        }
        let image = |which: &str| {
            let (scene, out) = (
                format!("{name}_{which}.spatch"),
                format!("{name}_{which}.png"),
            );
            t.run(&[
                "render", &scene, "-o", &out, "--width", "80", "--height", "80",
            ])
            .success();
            std::fs::read(t.path(&out)).unwrap()
        };
        assert!(image("in") == image("out"), "{name}: the images differ");
    }
}
