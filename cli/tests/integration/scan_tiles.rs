//! Structured scan sets through tiles (`--plan`, `--plan-tile`) behave as the untiled run:
//! each tile's points keep their scanners (sight lines: the two sides of a thin sheet stay
//! apart), and the scans are aligned once for the whole set, the shifts kept in the plan
//! and used alike by every tile.

use std::path::Path;

use spatch_cloud::measure_cloud_error;
use spatch_scan::{load_scans, ScanOptions};

use crate::test_command::TestCommand;

/// Grid steps a side of each scan (1 mm apart): 121 mm, over several 70 mm tiles.
const SIDE: usize = 121;

/// A `SIDE`² grid of 1 mm steps at height `z` in the scan's own frame, as an ASCII PLY with
/// its `range_grid` (the Stanford raw-scan layout; the scanner looks down −z).
fn write_grid_scan(path: &Path, z: f64) {
    let mut text = format!(
        "ply\nformat ascii 1.0\nobj_info num_cols {SIDE}\nobj_info num_rows {SIDE}\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element range_grid {}\nproperty list uchar int vertex_indices\nend_header\n",
        SIDE * SIDE,
        SIDE * SIDE
    );
    let half = (SIDE / 2) as f64;
    for k in 0..SIDE * SIDE {
        let (x, y) = ((k % SIDE) as f64 - half, (k / SIDE) as f64 - half);
        text.push_str(&format!("{} {} {z}\n", x * 0.001, y * 0.001));
    }
    for k in 0..SIDE * SIDE {
        text.push_str(&format!("1 {k}\n"));
    }
    std::fs::write(path, text).unwrap();
}

/// Cloud→patch RMS of the tiles of the folder `dir` (joined) against the scan set `conf`.
fn tiled_rms(t: &TestCommand, conf: &str, dir: &str) -> f64 {
    let mut scenes = Vec::new();
    for entry in std::fs::read_dir(t.path(dir)).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "spatch") {
            let scene = spatch_format::read_scene(&path).unwrap();
            if !scene.patches().is_empty() {
                scenes.push(scene);
            }
        }
    }
    assert!(scenes.len() > 1, "{} tiles with patches", scenes.len());
    let scene = spatch_format::Scene::merge(scenes).unwrap();
    let loaded = load_scans(&[t.path(conf)], &ScanOptions::default()).unwrap();
    let error = measure_cloud_error(&loaded.cloud, &scene, 0.001).unwrap();
    error.cloud_to_patch.distance.rms
}

#[test]
fn tiles_of_a_structured_scan_set_keep_the_sides_of_a_thin_sheet_apart() {
    let t = TestCommand::new();
    // Top (z = +0.5 mm) seen from above, bottom from below (the file turned over about x).
    write_grid_scan(&t.path("side.ply"), 0.0005);
    let conf = "bmesh side.ply 0 0 0 0 0 0 1\nbmesh side.ply 0 0 0 1 0 0 0\n";
    std::fs::write(t.path("sheet.conf"), conf).unwrap();
    let untiled = |grid: &str| {
        let report = format!("u_{grid}.json");
        let args = ["from-cloud", "sheet.conf", "--no-consensus", "--range-grid"];
        let out = ["-o", "u.spatch", "--report", &report];
        t.run(&[&args[..], &[grid], &out[..]].concat()).success();
        let report: serde_json::Value = t.json(&report);
        report["error"]["cloud_to_patch"]["rms"].as_f64().unwrap()
    };
    let tiled = |grid: &str| {
        let dir = format!("tiles_{grid}");
        let args = ["from-cloud", "sheet.conf", "--no-consensus", "--range-grid"];
        let out = ["--plan-tile", "0.07", "-o", &dir];
        t.run(&[&args[..], &[grid], &out[..]].concat()).success();
        tiled_rms(&t, "sheet.conf", &dir)
    };
    let (u_on, t_on, t_off) = (untiled("on"), tiled("on"), tiled("off"));
    eprintln!("rms: untiled {u_on:.2e}, tiled {t_on:.2e}, tiled without grids {t_off:.2e}");
    // With the scanners each side gets its own patches, tiled or not; without them the
    // views average both sides into a middle surface 0.5 mm from every point.
    assert!(u_on < 0.1e-3 && t_on < 0.1e-3, "{u_on} {t_on}");
    assert!((t_on - u_on).abs() < 0.05e-3, "{u_on} {t_on}");
    assert!(t_off > 0.3e-3, "{t_off}");
}

/// The `[x, y, z]` shifts of a JSON array of arrays.
fn shifts(value: &serde_json::Value) -> Vec<[f64; 3]> {
    let all = value
        .as_array()
        .unwrap_or_else(|| panic!("no shifts: {value}"));
    all.iter()
        .map(|s| [0, 1, 2].map(|k| s[k].as_f64().unwrap()))
        .collect()
}

#[test]
fn tiles_move_each_scan_by_the_shift_of_the_whole_set() {
    let t = TestCommand::new();
    // Two structured scans of one flat sheet seen from above, the second registered 0.6 mm
    // too high: aligned, each moves about 0.3 mm toward the other.
    write_grid_scan(&t.path("flat.ply"), 0.0);
    let conf = "bmesh flat.ply 0 0 0 0 0 0 1\nbmesh flat.ply 0.0005 0 0.0006 0 0 0 1\n";
    std::fs::write(t.path("pair.conf"), conf).unwrap();
    let args = ["from-cloud", "pair.conf", "-o", "u.spatch", "--report"];
    t.run(&[&args[..], &["u.json"]].concat()).success();
    let report: serde_json::Value = t.json("u.json");
    let whole = shifts(&report["details"]["scan_shifts"]);

    t.run(&["plan", "pair.conf", "--tile", "0.07", "-o", "plan.json"])
        .success();
    let plan: serde_json::Value = t.json("plan.json");
    let planned = shifts(&plan["scan_shifts"]);
    assert_eq!(planned.len(), 2);
    for (a, b) in whole.iter().zip(&planned) {
        assert!(
            (a[2] - b[2]).abs() < 0.03e-3,
            "untiled {a:?}, planned {b:?}"
        );
    }
    assert!((planned[0][2] - 0.3e-3).abs() < 0.1e-3, "{planned:?}");
    assert!((planned[1][2] + 0.3e-3).abs() < 0.1e-3, "{planned:?}");

    // --plan-tile computes the same shifts into its own plan.json.
    let args = [
        "from-cloud",
        "pair.conf",
        "--plan-tile",
        "0.07",
        "-o",
        "made",
    ];
    t.run(&args).success();
    let made: serde_json::Value = t.json("made/plan.json");
    assert_eq!(made["scan_shifts"], plan["scan_shifts"]);

    // Every tile takes the plan's shifts: each converted alone is the local run's file.
    t.run(&[
        "from-cloud",
        "pair.conf",
        "--plan",
        "plan.json",
        "-o",
        "out",
    ])
    .success();
    let tiles = plan["tiles"].as_array().unwrap().len();
    assert!(tiles >= 4, "{tiles} tiles");
    for k in 0..tiles {
        let name = format!("t{k}.spatch");
        let args = ["from-cloud", "pair.conf", "--plan", "plan.json", "--tile"];
        t.run(&[&args[..], &[&k.to_string(), "-o", &name]].concat())
            .success();
        let one = std::fs::read(t.path(&name)).unwrap();
        let local = std::fs::read(t.path(&format!("out/tile_{k:05}.spatch"))).unwrap();
        assert!(one == local, "tile {k} differs from the local run's");
    }
}
