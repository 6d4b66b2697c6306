//! `spatch convert` and `spatch demo`: outputs, report keys, colour, bad input.

use spatch_format::{read_scene, ColourChannel};

use crate::test_command::TestCommand;

/// Writes a small closed mesh (an octahedron-like sphere) as an OBJ file.
fn write_sphere_obj(t: &TestCommand, name: &str) -> String {
    let mut text = String::new();
    let (segments, rings) = (24u32, 12u32);
    text.push_str("v 0 0 1\n");
    for r in 1..rings {
        let theta = std::f64::consts::PI * f64::from(r) / f64::from(rings);
        for s in 0..segments {
            let phi = std::f64::consts::TAU * f64::from(s) / f64::from(segments);
            text.push_str(&format!(
                "v {} {} {}\n",
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos()
            ));
        }
    }
    text.push_str("v 0 0 -1\n");
    let ring = |r: u32, s: u32| 2 + (r - 1) * segments + s % segments;
    for s in 0..segments {
        text.push_str(&format!("f 1 {} {}\n", ring(1, s), ring(1, s + 1)));
    }
    for r in 1..rings - 1 {
        for s in 0..segments {
            let (a, b, c, d) = (
                ring(r, s),
                ring(r, s + 1),
                ring(r + 1, s),
                ring(r + 1, s + 1),
            );
            text.push_str(&format!("f {a} {c} {d}\nf {a} {d} {b}\n"));
        }
    }
    let south = 2 + (rings - 1) * segments;
    for s in 0..segments {
        text.push_str(&format!(
            "f {south} {} {}\n",
            ring(rings - 1, s + 1),
            ring(rings - 1, s)
        ));
    }
    std::fs::write(t.path(name), text).unwrap();
    name.to_owned()
}

#[test]
fn convert_writes_the_scene_and_a_report_with_every_key() {
    let t = TestCommand::new();
    let obj = write_sphere_obj(&t, "ball.obj");
    let run = t
        .run(&[
            "convert",
            &obj,
            "-o",
            "ball.spatch",
            "--report",
            "report.json",
        ])
        .success();
    assert!(run.stdout.contains("patches"), "{}", run.stdout);
    let scene = read_scene(&t.path("ball.spatch")).unwrap();
    assert_eq!(scene.channel(), ColourChannel::None);
    let report: serde_json::Value = t.json("report.json");
    crate::report_schema::check_shared_keys(&report, "convert");
    assert_eq!(report["counts"]["patches"], scene.patches().len());
    assert_eq!(
        report["counts"]["bytes"],
        std::fs::metadata(t.path("ball.spatch")).unwrap().len()
    );
    assert_eq!(report["output"], "ball.spatch");
    for key in ["triangles", "regions", "spacing", "colour", "prepare"] {
        assert!(
            report["details"].get(key).is_some(),
            "details lack {key}: {report}"
        );
    }
    for stage in ["load", "segment", "fit", "write"] {
        assert!(report["stages"][stage].is_number(), "{report}");
    }
    for side in ["node_to_surface", "surface_to_patch"] {
        for stat in ["max", "rms", "max_rel", "rms_rel"] {
            assert!(report["error"][side][stat].is_number(), "{report}");
        }
    }
    assert!(
        report["error"]["surface_to_patch"]["max_rel"]
            .as_f64()
            .unwrap()
            < 0.01
    );
}

#[test]
fn thread_count_does_not_change_the_file() {
    let t = TestCommand::new();
    let obj = write_sphere_obj(&t, "ball.obj");
    for (threads, out) in [("1", "one.spatch"), ("2", "two.spatch")] {
        t.run(&[
            "convert",
            &obj,
            "-o",
            out,
            "--threads",
            threads,
            "--no-error",
        ])
        .success();
    }
    assert_eq!(
        std::fs::read(t.path("one.spatch")).unwrap(),
        std::fs::read(t.path("two.spatch")).unwrap()
    );
}

#[test]
fn bad_input_gives_one_line_exit_2_and_no_output() {
    let t = TestCommand::new();
    let run = t.run(&["convert", "missing.obj", "-o", "out.spatch"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("missing.obj"), "{}", run.stderr);
    assert_eq!(run.stderr.trim().lines().count(), 1, "{}", run.stderr);
    std::fs::write(
        t.path("broken.obj"),
        "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let run = t.run(&["convert", "broken.obj", "-o", "out.spatch"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("broken.obj"), "{}", run.stderr);
    assert!(!t.path("out.spatch").exists());
    let run = t.run(&["convert", "broken.obj", "-o", "out.spatch", "--grid", "1"]);
    assert_eq!(run.code, 2);
}

#[test]
fn demo_needs_no_input_and_fills_its_folder() {
    let t = TestCommand::new();
    let run = t.run(&["demo", "-o", "demo", "--size", "64"]).success();
    assert!(run.stdout.contains("demo"), "{}", run.stdout);
    let scene = read_scene(&t.path("demo/spot.spatch")).unwrap();
    assert_ne!(scene.channel(), ColourChannel::None, "the cow is textured");
    assert!(t.path("demo/report.json").is_file());
    assert!(t.path("demo/source/spot.obj").is_file());
    // The OBJ names its material library, so its texture is found without the fallback.
    assert!(t.path("demo/source/spot.mtl").is_file());
    assert!(!run.stdout.contains("warning"), "{}", run.stdout);
    assert!(!run.stderr.contains("warning"), "{}", run.stderr);
    let png = std::fs::read(t.path("demo/spot.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
}

/// A unit quad textured with a 72 × 72 checkerboard of 8-texel squares (OBJ, MTL, PNG).
fn write_checker_quad(t: &TestCommand) -> String {
    let image = image::RgbImage::from_fn(72, 72, |x, y| {
        if (x / 8 + y / 8).is_multiple_of(2) {
            image::Rgb([230, 40, 20])
        } else {
            image::Rgb([20, 60, 240])
        }
    });
    image.save(t.path("checker.png")).unwrap();
    std::fs::write(
        t.path("quad.mtl"),
        "newmtl m\nKd 1 1 1\nmap_Kd checker.png\n",
    )
    .unwrap();
    let obj = "mtllib quad.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n\
               vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nf 1/1 2/2 3/3\nf 3/3 2/2 4/4\n";
    std::fs::write(t.path("quad.obj"), obj).unwrap();
    t.path("quad.obj").to_string_lossy().into_owned()
}

#[test]
fn colour_grids_are_written_reported_and_budgeted() {
    let t = TestCommand::new();
    let obj = write_checker_quad(&t);
    let base = [
        "convert",
        obj.as_str(),
        "--spacing",
        "0.1",
        "--texels-per-node",
        "0",
        "--no-error",
    ];
    let run = |out: &str, extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(&["-o", out, "--report", "report.json"]);
        args.extend_from_slice(extra);
        t.run(&args).success();
        let report: serde_json::Value = t.json("report.json");
        (read_scene(&t.path(out)).unwrap(), report)
    };
    let (scene, report) = run(
        "grid.spatch",
        &["--colour-grid", "1", "--colour-budget", "1M"],
    );
    let grid = scene.patches()[0].colour_grid().expect("a colour grid");
    // 10 cells of 7.2 texels: 7 colour cells per node cell.
    assert_eq!(grid.factor(), 7);
    assert_eq!(report["details"]["colour_grids"]["max_factor"], 7);
    assert_eq!(report["details"]["colour_grids"]["budget_limited"], false);
    assert_eq!(
        std::fs::read(t.path("grid.spatch")).unwrap()[7],
        3,
        "version 1.3 (CGRX)"
    );
    assert_eq!(report["details"]["colour_grids"]["shared"], 0);
    // Without the colour floor, a budget below the full grid lowers it.
    let full = report["details"]["colour_grids"]["bytes"].as_u64().unwrap();
    let half = (full / 2).to_string();
    let (scene, report) = run(
        "half.spatch",
        &["--colour-budget", &half, "--colour-floor", "0"],
    );
    assert!(report["details"]["colour_grids"]["bytes"].as_u64().unwrap() <= full / 2);
    assert!(scene.patches()[0]
        .colour_grid()
        .is_none_or(|g| g.factor() < 7));
    // With it (30 dB by default), even a budget of 0 bytes keeps the checks' grid.
    let (scene, report) = run("floor.spatch", &["--colour-budget", "0"]);
    assert_eq!(report["details"]["colour_grids"]["floor_limited"], true);
    let kept = scene.patches()[0].colour_grid().expect("held by the floor");
    assert!((2..=7).contains(&kept.factor()), "{}", kept.factor());
    // Grids are on by default (one sample per texel, within the default 1x budget down to
    // the colour floor) and `--colour-grid 0` turns them off.
    let (scene, report) = run("default.spatch", &["--colour-budget", "1M"]);
    assert_eq!(
        scene.patches()[0].colour_grid().expect("a grid").factor(),
        7
    );
    let (_, report_1x) = run("default_1x.spatch", &[]);
    for r in [&report, &report_1x] {
        assert_eq!(r["details"]["colour_grids"]["wanted_factor"], 7);
    }
    let (scene, _) = run("none.spatch", &["--colour-grid", "0"]);
    assert!(scene.patches()[0].colour_grid().is_none());
    assert_eq!(
        std::fs::read(t.path("none.spatch")).unwrap()[7],
        1,
        "version 1.1"
    );
    let bad = t.run(&["convert", &obj, "-o", "x.spatch", "--colour-budget", "-3x"]);
    assert_eq!(bad.code, 2, "{}", bad.stderr);
    assert!(!t.path("x.spatch").exists());
}

/// `--max-neighbour-tilt` reaches the fitter: under 75° the flat half's outer nodes no
/// longer take the steep fall past the diagonal, so fewer nodes are filled; out of range
/// it is refused.
#[test]
fn a_neighbour_tilt_limit_leaves_steep_outer_nodes_empty() {
    let t = TestCommand::new();
    // Flat up to the diagonal, falling 85° from z beyond it.
    let fold = spatch_fixtures::shapes::folded_square(8, 85.0);
    std::fs::write(t.path("fold.obj"), fold.to_obj([0.0; 3])).unwrap();
    let obj = "fold.obj";
    let filled = |extra: &[&str]| {
        let mut args = vec!["convert", obj, "-o", "fold.spatch", "--report", "r.json"];
        args.extend_from_slice(&["--no-error", "--no-sharp-edges", "--spacing", "0.05"]);
        args.extend_from_slice(extra);
        t.run(&args).success();
        let report: serde_json::Value = t.json("r.json");
        report["counts"]["filled_nodes"].as_u64().unwrap()
    };
    let all = filled(&[]);
    let limited = filled(&["--max-neighbour-tilt", "75"]);
    assert!(
        limited < all,
        "{limited} filled nodes under 75°, {all} without"
    );
    assert_eq!(filled(&["--max-neighbour-tilt", "90"]), all);
    for bad in ["0", "91", "nan"] {
        let run = t.run(&[
            "convert",
            obj,
            "-o",
            "bad.spatch",
            "--max-neighbour-tilt",
            bad,
        ]);
        assert_eq!(run.code, 2, "{bad}: {}", run.stderr);
        assert!(!t.path("bad.spatch").exists());
    }
}
