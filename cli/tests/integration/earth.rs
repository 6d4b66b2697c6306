use serde_json::Value;

use crate::test_command::TestCommand;

#[test]
fn the_built_in_map_gives_the_original_low_level() {
    let t = TestCommand::new();
    let run = t
        .run(&[
            "earth",
            "--level",
            "low",
            "--no-error",
            "--holes",
            "--report",
            "r.json",
            "-o",
            "e.spatch",
        ])
        .success();
    assert!(run.stdout.contains("built-in map"), "{}", run.stdout);
    let r = t.json::<Value>("r.json");
    crate::report_schema::check_shared_keys(&r, "earth");
    let patches = r["counts"]["patches"].as_u64().unwrap() as f64;
    assert!(
        (383.0 * 0.85..=383.0 * 1.15).contains(&patches),
        "{patches} patches"
    );
    assert!(
        r["counts"]["bytes"].as_u64().unwrap() <= 450_000,
        "{}",
        r["counts"]["bytes"]
    );
    assert_eq!(r["details"]["colour"], "rgb8");
    assert_eq!(r["details"]["globe"]["triangles"], 40_500);
    // No cracks at the seam or the poles: 14 views of the globe mesh against the patches.
    assert_eq!(r["details"]["holes"]["views"].as_array().unwrap().len(), 14);
    assert!(
        r["details"]["holes"]["fraction"].as_f64().unwrap() <= 0.0005,
        "{}",
        r["details"]["holes"]
    );
    for stage in ["heights", "globe", "segment", "fit", "write"] {
        assert!(
            r["stages"][stage].as_f64().is_some(),
            "stage {stage} missing"
        );
    }
    let scene = spatch_format::read_scene(&t.path("e.spatch")).unwrap();
    // Every node sits near the radius-128 globe (heights are at most 1.5).
    for patch in scene.patches() {
        for (_, _, p) in patch.filled_nodes() {
            let r = (scene.offset() + p.as_dvec3()).length();
            assert!((127.9..=129.6).contains(&r), "node at radius {r}");
        }
    }
}

#[test]
fn the_shared_map_and_relief_convert() {
    let (Some(map), Some(relief)) = (
        spatch_fixtures::shared_data("earth/earth_nasa_2048x1024.jpg"),
        spatch_fixtures::shared_data("earth/earth_relief8_1350x675.png"),
    ) else {
        return;
    };
    let t = TestCommand::new();
    let map = map.display().to_string();
    let relief = relief.display().to_string();
    t.run(&[
        "earth", "--colour", &map, "--level", "medium", "--report", "m.json", "-o", "m.spatch",
    ])
    .success();
    let r = t.json::<Value>("m.json");
    let patches = r["counts"]["patches"].as_u64().unwrap() as f64;
    assert!(
        (1128.0 * 0.85..=1128.0 * 1.15).contains(&patches),
        "{patches} patches"
    );
    assert!(r["counts"]["bytes"].as_u64().unwrap() <= 1_350_000);
    assert_eq!(
        r["details"]["globe"]["map"][0], 1024,
        "the 2048-wide map is halved"
    );
    // The globe mesh is the source of the error: it must be small.
    assert!(r["error"]["surface_to_patch"]["max_rel"].as_f64().unwrap() < 0.005);
    t.run(&[
        "earth",
        "--colour",
        &map,
        "--elevation",
        &relief,
        "--sea-level",
        "92",
        "--level",
        "low",
        "--no-error",
        "-o",
        "r.spatch",
    ])
    .success();
    let scene = spatch_format::read_scene(&t.path("r.spatch")).unwrap();
    let radii: Vec<f64> = scene
        .patches()
        .iter()
        .flat_map(|p| {
            p.filled_nodes()
                .map(|(_, _, q)| (scene.offset() + q.as_dvec3()).length())
        })
        .collect();
    let below = radii.iter().filter(|&&r| r < 127.8).count();
    let above = radii.iter().filter(|&&r| r > 128.2).count();
    assert!(
        below > 1000 && above > 1000,
        "sea floor {below} nodes, land {above} nodes"
    );
}

#[test]
fn bad_maps_fail_with_the_file_named() {
    let t = TestCommand::new();
    std::fs::write(t.path("broken.png"), b"not an image").unwrap();
    let run = t.run(&["earth", "--colour", "broken.png", "-o", "e.spatch"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("broken.png"), "{}", run.stderr);
    let run = t.run(&["earth", "--elevation", "missing.png", "-o", "e.spatch"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("missing.png"), "{}", run.stderr);
    assert!(!t.path("e.spatch").exists());
}
