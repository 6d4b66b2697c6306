//! `spatch convert`'s sharp-edge options: which creases get patches, how dense, bad values.

use crate::test_command::TestCommand;

/// A cube of side 2 as twelve triangles, written as an OBJ file.
fn write_cube_obj(t: &TestCommand, name: &str) -> String {
    let mut text = String::new();
    for k in 0..8 {
        let c = |bit: u32| if k & bit != 0 { 1 } else { -1 };
        text.push_str(&format!("v {} {} {}\n", c(1), c(2), c(4)));
    }
    // Outward-wound quads, fanned into two triangles each (vertices are 1-based).
    for [a, b, c, d] in [
        [1, 3, 4, 2],
        [5, 6, 8, 7],
        [1, 2, 6, 5],
        [3, 7, 8, 4],
        [1, 5, 7, 3],
        [2, 4, 8, 6],
    ] {
        text.push_str(&format!("f {a} {b} {c}\nf {a} {c} {d}\n"));
    }
    std::fs::write(t.path(name), text).unwrap();
    name.to_owned()
}

/// Converts `mesh` with `extra` options and returns the report's edge statistics.
fn edge_stats(t: &TestCommand, mesh: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "convert",
        mesh,
        "-o",
        "cube.spatch",
        "--report",
        "cube.json",
        "--no-error",
        "--spacing",
        "0.2",
    ];
    args.extend_from_slice(extra);
    t.run(&args).success();
    let report: serde_json::Value = t.json("cube.json");
    report["details"]["edges"].clone()
}

#[test]
fn edge_patches_go_only_where_the_surface_leaves_a_gap_unless_asked() {
    let t = TestCommand::new();
    let cube = write_cube_obj(&t, "cube.obj");
    let gaps = edge_stats(&t, &cube, &[]);
    assert_eq!(gaps["creases"], 12, "{gaps}");
    // The fitted faces end exactly on the cube's straight edges.
    assert_eq!(gaps["covered_creases"], 12, "{gaps}");
    assert_eq!(gaps["edge_patches"], 0, "{gaps}");
    // The summary says where the creases went rather than only that none
    // was patched.
    let shown = t
        .run(&[
            "convert",
            &cube,
            "-o",
            "cube.spatch",
            "--no-error",
            "--spacing",
            "0.2",
        ])
        .success();
    assert!(
        shown
            .stdout
            .contains("12 creases in 12 chains (12 covered by the surface patches), 8 corners"),
        "{}",
        shown.stdout
    );

    let all = edge_stats(&t, &cube, &["--all-creases"]);
    assert_eq!(all["covered_creases"], 0, "{all}");
    assert_eq!(all["edge_patches"], 12, "{all}");
    assert_eq!(all["corner_patches"], 8, "{all}");

    let dense = edge_stats(&t, &cube, &["--all-creases", "--edge-resolution", "2"]);
    let nodes = |v: &serde_json::Value| v["nodes"].as_u64().unwrap();
    assert!(nodes(&dense) > 2 * nodes(&all), "{dense} vs {all}");
    let wide = edge_stats(&t, &cube, &["--all-creases", "--edge-strip", "2"]);
    assert!(nodes(&wide) > nodes(&all), "{wide} vs {all}");

    let none = edge_stats(&t, &cube, &["--no-sharp-edges"]);
    assert!(none.is_null(), "{none}");
}

/// `--edge-max-turn` and `--edge-max-stray` decide how long an edge patch runs along a
/// curved crease: a 64-sided cylinder's two round rims (90° creases), every crease patched.
#[test]
fn turn_and_stray_limits_set_how_many_pieces_a_curved_crease_takes() {
    let t = TestCommand::new();
    let obj = spatch_fixtures::shapes::cylinder(1.0, 2.0, 64).to_obj([0.0; 3]);
    std::fs::write(t.path("cylinder.obj"), obj).unwrap();
    let patches = |extra: &[&str]| {
        let mut args = vec!["--all-creases"];
        args.extend_from_slice(extra);
        let stats = edge_stats(&t, "cylinder.obj", &args);
        stats["edge_patches"].as_u64().unwrap()
    };
    let default = patches(&[]);
    assert!(default >= 2, "{default}");
    // The bisector turns 5.6° per side facet: the tighter the limit, the more pieces.
    let tight = patches(&["--edge-max-turn", "5"]);
    let loose = patches(&["--edge-max-turn", "40"]);
    assert!(
        tight > default && default > loose,
        "{tight} {default} {loose}"
    );
    // With the turn unlimited, the stray decides: 0 allows no bend at all, so each rim
    // edge is a piece of its own.
    let straight = patches(&["--edge-max-turn", "90", "--edge-max-stray", "0"]);
    let bent = patches(&["--edge-max-turn", "90", "--edge-max-stray", "4"]);
    assert_eq!(straight, 2 * 64, "one piece per rim edge");
    assert!(bent < straight / 4, "{bent} vs {straight}");
}

#[test]
fn out_of_range_edge_options_are_refused() {
    let t = TestCommand::new();
    let cube = write_cube_obj(&t, "cube.obj");
    for (flag, value) in [
        ("--edge-resolution", "0.5"),
        ("--edge-strip", "0.1"),
        ("--crease-angle", "180"),
        ("--edge-max-stray", "-0.5"),
        ("--edge-max-stray", "4.5"),
        ("--edge-max-stray", "NaN"),
        ("--edge-max-turn", "0"),
        ("--edge-max-turn", "91"),
        ("--edge-max-turn", "inf"),
        ("--soft-crease", "-1"),
        ("--soft-crease", "180"),
        ("--soft-crease", "NaN"),
    ] {
        // `--flag=value`, so a negative value is not taken for a flag.
        let run = t.run(&[
            "convert",
            &cube,
            "-o",
            "out.spatch",
            &format!("{flag}={value}"),
        ]);
        assert_eq!(run.code, 2, "{flag} {value}: {}", run.stderr);
        assert!(run.stderr.contains(flag), "{}", run.stderr);
        assert!(run.stderr.starts_with("spatch: error:"), "{}", run.stderr);
        assert!(!t.path("out.spatch").exists());
    }
}

/// Pieces the surface and the other edge patches already cover lose their patch by
/// default; `--keep-covered-pieces` keeps one patch per piece (Duck.glb, skipped when the
/// shared data is missing).
#[test]
fn covered_pieces_are_dropped_unless_kept() {
    let Some(duck) = spatch_fixtures::shared_data("gltf/Duck.glb") else {
        return;
    };
    let t = TestCommand::new();
    let duck = duck.to_str().unwrap();
    let stats = |extra: &[&str]| {
        let mut args = vec![
            "convert",
            duck,
            "-o",
            "duck.spatch",
            "--report",
            "duck.json",
            "--no-error",
        ];
        args.extend_from_slice(extra);
        t.run(&args).success();
        let report: serde_json::Value = t.json("duck.json");
        report["details"]["edges"].clone()
    };
    let count = |v: &serde_json::Value, key: &str| v[key].as_u64().unwrap();
    let dropped = stats(&[]);
    let kept = stats(&["--keep-covered-pieces"]);
    assert_eq!(count(&kept, "covered_pieces"), 0, "{kept}");
    assert!(count(&dropped, "covered_pieces") > 0, "{dropped}");
    assert_eq!(count(&dropped, "pieces"), count(&kept, "pieces"));
    assert_eq!(
        count(&dropped, "edge_patches") + count(&dropped, "covered_pieces"),
        count(&kept, "edge_patches"),
        "{dropped} vs {kept}"
    );
}

/// Pieces that meet at a crease vertex share a patch by default; `--separate-pieces` gives
/// each its own (fuze.obj, skipped when the shared data is missing).
#[test]
fn pieces_are_joined_unless_separate() {
    let Some(fuze) = spatch_fixtures::shared_data("textured_obj/fuze/fuze.obj") else {
        return;
    };
    let t = TestCommand::new();
    let fuze = fuze.to_str().unwrap();
    let stats = |extra: &[&str]| {
        let mut args = vec![
            "convert",
            fuze,
            "-o",
            "fuze.spatch",
            "--report",
            "fuze.json",
            "--no-error",
        ];
        args.extend_from_slice(extra);
        t.run(&args).success();
        let report: serde_json::Value = t.json("fuze.json");
        report["details"]["edges"].clone()
    };
    let count = |v: &serde_json::Value, key: &str| v[key].as_u64().unwrap();
    let joined = stats(&[]);
    let separate = stats(&["--separate-pieces"]);
    assert_eq!(count(&separate, "joined_pieces"), 0, "{separate}");
    assert!(count(&joined, "joined_pieces") > 0, "{joined}");
    assert_eq!(count(&joined, "pieces"), count(&separate, "pieces"));
    assert!(
        count(&joined, "edge_patches") < count(&separate, "edge_patches"),
        "{joined} vs {separate}"
    );
}
