//! Issue 18: `spatch plan`, `from-cloud --plan` (one tile, every tile), `spatch index` and
//! `spatch render INDEX` on a small synthetic cityscape.

use spatch_fixtures::Cityscape;
use spatch_format::read_scene;

use crate::test_command::TestCommand;

/// Writes a cityscape of `points` points as binary PLY (float xyz, uchar rgb).
pub(crate) fn write_city(t: &TestCommand, name: &str, points: u64) {
    Cityscape::new(points, 4)
        .write_binary_ply(&t.path(name), false)
        .unwrap();
}

/// Writes `city.ply` (8,000 points) and converts it with `--plan-tile 3.5` (spacing 0.1,
/// pixel factor 1) into `out/`: tiles, `plan.json` and `index.json`.
pub(crate) fn convert_city_in_tiles(t: &TestCommand) {
    write_city(t, "city.ply", 8000);
    t.run(&[
        "from-cloud",
        "city.ply",
        "--plan-tile",
        "3.5",
        "--spacing",
        "0.1",
        "--pixel-factor",
        "1",
        "-o",
        "out",
    ])
    .success();
}

#[test]
fn tiles_run_alone_match_the_local_run_byte_for_byte_and_render_from_the_index() {
    let t = TestCommand::new();
    write_city(&t, "city.ply", 6000);
    t.run(&[
        "plan",
        "city.ply",
        "--tile",
        "3",
        "--buffer",
        "0.8",
        "-o",
        "plan.json",
    ])
    .success();
    let plan: serde_json::Value = t.json("plan.json");
    let tiles = plan["tiles"].as_array().unwrap();
    assert!(tiles.len() >= 4, "{}", tiles.len());
    let owned: u64 = tiles.iter().map(|t| t["points"].as_u64().unwrap()).sum();
    assert_eq!(owned, 6000);
    assert_eq!(plan["points"], 6000);

    t.run(&["from-cloud", "city.ply", "--plan", "plan.json", "-o", "out"])
        .success();
    let index: serde_json::Value = t.json("out/index.json");
    assert_eq!(index["tiles"].as_array().unwrap().len(), tiles.len());
    let mut patches = 0;
    for k in 0..tiles.len() {
        let one = format!("{k}.spatch");
        t.run(&[
            "from-cloud",
            "city.ply",
            "--plan",
            "plan.json",
            "--tile",
            &k.to_string(),
            "--threads",
            "1",
            "-o",
            &one,
        ])
        .success();
        let local = std::fs::read(t.path(&format!("out/tile_{k:05}.spatch"))).unwrap();
        assert!(
            std::fs::read(t.path(&one)).unwrap() == local,
            "tile {k} differs"
        );
        patches += read_scene(&t.path(&one)).unwrap().patches().len();
    }
    let listed: u64 = index["tiles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["patches"].as_u64().unwrap())
        .sum();
    assert_eq!(listed as usize, patches);
    assert!(patches > 0);

    // The index made again from the files alone is the same bytes.
    let first = std::fs::read(t.path("out/index.json")).unwrap();
    t.run(&["index", "plan.json", "out"]).success();
    assert_eq!(std::fs::read(t.path("out/index.json")).unwrap(), first);

    // No spill file is left; the coarse level holds every tile's patches at 1/4 the nodes
    // per axis and draws the whole scene from one file.
    assert!(!t.path("out/.spill").exists());
    let coarse = read_scene(&t.path("out/coarse.spatch")).unwrap();
    assert_eq!(
        index["coarse"]["nodes"].as_u64().unwrap() as usize,
        coarse.node_count()
    );
    let nodes: u64 = index["tiles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["nodes"].as_u64().unwrap())
        .sum();
    let ratio = nodes as f64 / coarse.node_count() as f64;
    assert!(
        ratio > 4.0 && coarse.patches().len() as f64 > 0.8 * patches as f64,
        "{ratio}"
    );
    let far = t
        .run(&["render", "out/index.json", "--coarse", "-o", "coarse.png"])
        .success();
    assert!(!far.stderr.contains("tiles"), "{}", far.stderr);
    t.run(&["render", "0.spatch", "--coarse", "-o", "x.png"])
        .assert_one_clear_line("--coarse");
    // From far enough for its cells to be under a pixel, the level is drawn unasked.
    let cell = index["coarse"]["cell"].as_f64().unwrap();
    assert!(cell > 0.0);
    let far = t
        .run(&[
            "render",
            "out/index.json",
            "--eye",
            "3000,3000,3000",
            "-o",
            "far.png",
        ])
        .success();
    assert!(far.stderr.contains("coarse level"), "{}", far.stderr);

    let all = t
        .run(&["render", "out/index.json", "-o", "all.png"])
        .success();
    assert!(
        all.stderr.contains(&format!(
            "read {n} of {n} tiles",
            n = tiles.len() - empty(&index)
        )),
        "{}",
        all.stderr
    );
    // Looking along +x from the middle of the low-x edge: tiles behind the eye are not read.
    let side = plan["bounds"]["max"][0].as_f64().unwrap();
    let eye = format!("{},{},1.5", side / 2.0, side / 2.0);
    let target = format!("{},{},1.5", side, side / 2.0);
    let part = t
        .run(&[
            "render",
            "out/index.json",
            "--eye",
            &eye,
            "--target",
            &target,
            "-o",
            "part.png",
        ])
        .success();
    let read: usize = part
        .stderr
        .split("read ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        read > 0 && read < tiles.len() - empty(&index),
        "{}",
        part.stderr
    );
}

/// Tiles of an index with no patch.
fn empty(index: &serde_json::Value) -> usize {
    index["tiles"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| t["patches"] == 0)
        .count()
}

#[test]
fn plan_tile_runs_plan_and_tiles_in_one_go() {
    let t = TestCommand::new();
    convert_city_in_tiles(&t);
    let plan: serde_json::Value = t.json("out/plan.json");
    assert_eq!(plan["spacing"].as_f64().unwrap() as f32, 0.1);
    let index: serde_json::Value = t.json("out/index.json");
    let tiles = plan["tiles"].as_array().unwrap().len();
    assert!(tiles >= 4, "{tiles}");
    assert_eq!(index["tiles"].as_array().unwrap().len(), tiles);
    assert!((plan["grid"]["buffer"].as_f64().unwrap() - 1.6).abs() < 1e-6);
}

#[test]
fn bad_plans_and_tiles_are_one_clear_line() {
    let t = TestCommand::new();
    write_city(&t, "city.ply", 3000);
    t.run(&["plan", "missing.ply", "--tile", "3", "-o", "p.json"])
        .assert_one_clear_line("missing.ply");
    t.run(&[
        "plan", "city.ply", "--tile", "3", "--buffer", "2", "-o", "p.json",
    ])
    .assert_one_clear_line("buffer");
    assert!(!t.path("p.json").exists());
    std::fs::write(t.path("bad.json"), "{\"version\": 1}").unwrap();
    t.run(&[
        "from-cloud",
        "city.ply",
        "--plan",
        "bad.json",
        "--tile",
        "0",
        "-o",
        "a.spatch",
    ])
    .assert_one_clear_line("bad.json");
    t.run(&[
        "plan", "city.ply", "--tile", "3", "--buffer", "0.5", "-o", "p.json",
    ])
    .success();
    t.run(&[
        "from-cloud",
        "city.ply",
        "--plan",
        "p.json",
        "--tile",
        "999",
        "-o",
        "a.spatch",
    ])
    .assert_one_clear_line("p.json");
    assert!(!t.path("a.spatch").exists());
    // An input cut short after planning: the local run fails in one line, no spill left.
    let bytes = std::fs::read(t.path("city.ply")).unwrap();
    std::fs::write(t.path("city.ply"), &bytes[..bytes.len() / 2]).unwrap();
    t.run(&["from-cloud", "city.ply", "--plan", "p.json", "-o", "out"])
        .assert_one_clear_line("city.ply");
    assert!(!t.path("out/.spill").exists());
}
