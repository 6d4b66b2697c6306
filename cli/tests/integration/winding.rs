//! `spatch convert` winds every connected piece consistently and outward: a source wound
//! inward, or with scattered faces turned over, converts to the very file of its outward
//! twin; `--keep-winding` keeps the file's winding; an open bowl wound into its hollow shows
//! from below with the default culling.

use spatch_fixtures::shapes::{open_tube, torus, uv_sphere, Shape};

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
/// and the report's `details.orient`.
fn convert(
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
        report["details"]["orient"].clone(),
    )
}

#[test]
fn inward_and_scattered_windings_convert_to_the_outward_file() {
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
            (
                orient["pieces"].as_u64(),
                orient["reversed_pieces"].as_u64()
            ),
            (Some(1), Some(1))
        );
        assert!(
            inward == outward,
            "{name}: the inward source gives another file"
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

/// Pixels of `image` other than its top-left corner's colour (the background).
fn covered(t: &TestCommand, image: &str) -> usize {
    let rgb = image::open(t.path(image)).unwrap().to_rgb8();
    let background = *rgb.get_pixel(0, 0);
    rgb.pixels().filter(|&&p| p != background).count()
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
        covered(&t, out)
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
fn a_real_scan_wound_inward_converts_to_the_same_file() {
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
    let (outward, orient) = convert(&t, "res2", &shape, &[]);
    assert_eq!(orient["flipped_faces"], 0, "{orient}");
    let (inward, orient) = convert(&t, "res2_in", &turned(&shape, |_| true), &[]);
    assert_eq!(orient["flipped_faces"], shape.triangles.len(), "{orient}");
    assert!(inward == outward, "the inward scan gives another file");
}
