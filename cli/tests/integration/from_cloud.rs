//! `spatch from-cloud`: scenes from point clouds, the report, determinism, bad input.

use spatch_format::read_scene;

use crate::test_command::TestCommand;

/// A jittered 120 × 120 grid on a gentle paraboloid, as XYZ text.
fn write_xyz(t: &TestCommand, name: &str) {
    let mut text = String::new();
    for k in 0..120 * 120 {
        let (i, j) = ((k % 120) as f64, (k / 120) as f64);
        let jitter = ((k * 7919) % 97) as f64 / 97.0 * 0.3;
        let (x, y) = ((i + jitter) * 0.01, (j - jitter) * 0.01);
        let z = 0.2 * ((x - 0.6) * (x - 0.6) + (y - 0.6) * (y - 0.6));
        text.push_str(&format!("{x} {y} {z}\n"));
    }
    std::fs::write(t.path(name), text).unwrap();
}

#[test]
fn xyz_cloud_becomes_a_scene_with_a_report() {
    let t = TestCommand::new();
    write_xyz(&t, "sheet.xyz");
    let run = t
        .run(&[
            "from-cloud",
            "sheet.xyz",
            "-o",
            "sheet.spatch",
            "--report",
            "r.json",
        ])
        .success();
    assert!(run.stdout.contains("patches"), "{}", run.stdout);
    assert!(run.stdout.contains("cloud_to_patch"), "{}", run.stdout);
    let scene = read_scene(&t.path("sheet.spatch")).unwrap();
    assert!(!scene.patches().is_empty());
    let report: serde_json::Value = t.json("r.json");
    crate::report_schema::check_shared_keys(&report, "from-cloud");
    assert_eq!(report["counts"]["patches"], scene.patches().len());
    assert_eq!(report["details"]["points"], 14_400);
    assert!(report["counts"]["nodes"].as_u64().unwrap() < 14_400);
    assert!(report["counts"]["bytes"].as_u64().unwrap() > 0);
    // Stage order survives in the typed report.
    let typed: spatch_eval::Report<serde_json::Value> = t.json("r.json");
    let stages: Vec<&str> = typed.stages.names().collect();
    assert_eq!(stages.first(), Some(&"load"));
    assert_eq!(stages.last(), Some(&"write"));
    assert!(stages.contains(&"range_images") && stages.contains(&"extract"));
    let error = &report["error"];
    let spacing = report["details"]["spacing"].as_f64().unwrap();
    let rms = error["cloud_to_patch"]["rms"].as_f64().unwrap();
    assert!(rms <= 0.5 * spacing, "rms {rms}, spacing {spacing}");
    assert!(
        report["details"]["cloud_error"]["share_beyond_2x_spacing"]
            .as_f64()
            .unwrap()
            <= 0.01
    );
    for key in ["max", "rms", "p95", "max_rel", "rms_rel"] {
        assert!(error["cloud_to_patch"][key].is_number(), "{key}");
        assert!(error["node_to_cloud"][key].is_number(), "{key}");
    }
}

#[test]
fn output_is_byte_identical_for_one_and_two_threads() {
    let t = TestCommand::new();
    write_xyz(&t, "sheet.xyz");
    for (threads, name) in [("1", "one.spatch"), ("2", "two.spatch")] {
        t.run_with_env(
            &["from-cloud", "sheet.xyz", "--smooth", "-o", name],
            &[("RAYON_NUM_THREADS", threads)],
        )
        .success();
    }
    assert_eq!(
        std::fs::read(t.path("one.spatch")).unwrap(),
        std::fs::read(t.path("two.spatch")).unwrap()
    );
}

#[test]
fn the_shared_scan_converts() {
    let Some(scan) = spatch_fixtures_path("pointcloud/hoppe_distcap.ply") else {
        return;
    };
    let t = TestCommand::new();
    t.run(&["from-cloud", &scan, "-o", "distcap.spatch"])
        .success();
    assert!(read_scene(&t.path("distcap.spatch")).unwrap().node_count() < 12_745);
}

/// The shared data file, or `None` when ../shared/data is missing.
fn spatch_fixtures_path(relative: &str) -> Option<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data");
    let path = root.join(relative);
    path.is_file().then(|| path.display().to_string())
}

#[test]
fn bad_clouds_fail_cleanly_without_output() {
    let t = TestCommand::new();
    std::fs::write(t.path("one.xyz"), "1 2 3\n").unwrap();
    std::fs::write(t.path("nan.xyz"), "nan 0 0\n0 inf 0\n").unwrap();
    std::fs::write(
        t.path("broken.ply"),
        "ply\nformat ascii 1.0\nelement vertex 5\n",
    )
    .unwrap();
    for (file, expect) in [
        ("missing.ply", "missing.ply"),
        ("one.xyz", "at least 3"),
        ("nan.xyz", "nan.xyz"),
        ("broken.ply", "broken.ply"),
    ] {
        let run = t.run(&["from-cloud", file, "-o", "out.spatch"]);
        assert_eq!(run.code, 2, "{file}: {}", run.stderr);
        let lines: Vec<&str> = run.stderr.lines().collect();
        assert_eq!(lines.len(), 1, "{file}: {}", run.stderr);
        assert!(lines[0].starts_with("spatch: error: "), "{}", lines[0]);
        assert!(lines[0].contains(expect), "{file}: {}", lines[0]);
        assert!(!t.path("out.spatch").exists(), "{file}");
    }
    let run = t.run(&["from-cloud", "one.xyz", "-o", "out.spatch", "--views", "0"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("views"), "{}", run.stderr);
}

#[test]
fn no_consensus_leaves_the_points_where_they_are() {
    let t = TestCommand::new();
    write_xyz(&t, "sheet.xyz");
    t.run(&[
        "from-cloud",
        "sheet.xyz",
        "-o",
        "a.spatch",
        "--report",
        "a.json",
        "--consensus",
    ])
    .success();
    t.run(&[
        "from-cloud",
        "sheet.xyz",
        "-o",
        "b.spatch",
        "--report",
        "b.json",
        "--no-consensus",
    ])
    .success();
    // One scan: no consensus unless asked for.
    t.run(&[
        "from-cloud",
        "sheet.xyz",
        "-o",
        "c.spatch",
        "--report",
        "c.json",
    ])
    .success();
    let (a, b): (serde_json::Value, serde_json::Value) = (t.json("a.json"), t.json("b.json"));
    assert!(a["details"]["consensus_points"].as_u64().unwrap() > 14_000);
    assert_eq!(b["details"]["consensus_points"], 0);
    assert_eq!(
        t.json::<serde_json::Value>("c.json")["details"]["consensus_points"],
        0
    );
}

/// Two 0.5 m pieces 300 m apart at 7 mm, as XYZ text.
fn write_far_pieces(t: &TestCommand, name: &str) {
    let mut text = String::new();
    for x0 in [0.0, 300.0] {
        for k in 0..71 * 71 {
            let (i, j) = ((k % 71) as f64, (k / 71) as f64);
            let jitter = ((k * 7919) % 97) as f64 / 97.0 * 0.002;
            let (x, y) = (i * 0.007 + jitter, j * 0.007 - jitter);
            text.push_str(&format!("{} {y} {}\n", x0 + x, 0.05 * (3.0 * x).sin()));
        }
    }
    std::fs::write(t.path(name), text).unwrap();
}

#[test]
fn far_pieces_are_tiled_and_a_tile_over_budget_needs_allow_coarsening() {
    let t = TestCommand::new();
    write_far_pieces(&t, "far.xyz");
    let run = t
        .run(&["from-cloud", "far.xyz", "-o", "far.spatch"])
        .success();
    assert!(run.stdout.contains(" tiles of "), "{}", run.stdout);
    assert!(!run.stdout.contains("warning"), "{}", run.stdout);
    let big = [
        "from-cloud",
        "far.xyz",
        "-o",
        "big.spatch",
        "--tile-size",
        "1000",
    ];
    let run = t.run(&big);
    assert_eq!(run.code, 2, "{}", run.stderr);
    run.assert_one_clear_line("far.xyz");
    assert!(run.stderr.contains("--allow-coarsening"), "{}", run.stderr);
    assert!(!t.path("big.spatch").exists());
    let mut coarse = big.to_vec();
    coarse.push("--allow-coarsening");
    let run = t.run(&coarse).success();
    assert!(
        run.stdout.contains("warning: a tile's range images"),
        "{}",
        run.stdout
    );
    assert!(t.path("big.spatch").exists());
}
