//! Scan sets with a plan: `spatch plan SET.conf --tile S` streams the posed scans, and
//! `spatch from-cloud SET.conf --plan P --tile K` converts one tile of them, byte for byte
//! as the local run over every tile does.

use crate::test_command::TestCommand;

/// A wavy sheet of `side`² points, 2.5 cm apart, as XYZ text.
fn sheet(side: usize) -> String {
    let mut text = String::new();
    for k in 0..side * side {
        let (x, y) = ((k % side) as f64 * 0.025, (k / side) as f64 * 0.025);
        let z = 0.05 * (3.0 * x).sin() * (2.0 * y).cos();
        text.push_str(&format!("{x:.4} {y:.4} {z:.4}\n"));
    }
    text
}

#[test]
fn a_conf_scan_set_is_planned_and_converted_tile_by_tile() {
    let t = TestCommand::new();
    std::fs::write(t.path("a.xyz"), sheet(80)).unwrap();
    std::fs::write(t.path("b.xyz"), sheet(80)).unwrap();
    // b is turned a quarter about z (clockwise seen from +z: the .conf's quaternion is
    // applied as Stanford's scans apply it) and moved 4.5 along x, beside a.
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let conf = format!("bmesh a.xyz 0 0 0 0 0 0 1\nbmesh b.xyz 4.5 0 0 0 0 {h} {h}\n");
    std::fs::write(t.path("set.conf"), conf).unwrap();
    t.run(&[
        "plan",
        "set.conf",
        "--tile",
        "1.5",
        "--buffer",
        "0.2",
        "-o",
        "plan.json",
    ])
    .success();
    let plan: serde_json::Value = t.json("plan.json");
    assert_eq!(plan["points"].as_u64(), Some(2 * 80 * 80));
    let bounds = &plan["bounds"];
    // b's sheet, turned, spans x from 4.5 to 6.475 and y from -1.975 to 0.
    let at = |end: &str, k: usize| bounds[end][k].as_f64().unwrap();
    assert!((at("max", 0) - 6.475).abs() < 1e-3, "{bounds}");
    assert!((at("min", 1) + 1.975).abs() < 1e-3, "{bounds}");
    let tiles = plan["tiles"].as_array().unwrap().len();
    assert!(tiles >= 4, "{tiles} tiles");

    t.run(&["from-cloud", "set.conf", "--plan", "plan.json", "-o", "out"])
        .success();
    let mut patches = 0;
    for k in 0..tiles {
        let name = format!("t{k}.spatch");
        let args = ["from-cloud", "set.conf", "--plan", "plan.json", "--tile"];
        t.run(&[&args[..], &[&k.to_string(), "-o", &name]].concat())
            .success();
        let one = std::fs::read(t.path(&name)).unwrap();
        let local = std::fs::read(t.path(&format!("out/tile_{k:05}.spatch"))).unwrap();
        assert!(one == local, "tile {k} differs from the local run's");
        patches += spatch_format::read_scene(&t.path(&name))
            .unwrap()
            .patches()
            .len();
    }
    assert!(patches > 0);
}
