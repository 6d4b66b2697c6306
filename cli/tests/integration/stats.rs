use serde_json::Value;

use crate::test_command::TestCommand;

#[test]
fn json_has_every_documented_key_with_right_values() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let run = t.run(&["stats", &name, "--json"]).success();
    let v: Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(v["patches"], 200);
    assert_eq!(v["nodes"], 200 * 81);
    assert_eq!(v["filled_nodes"], 200 * 81);
    assert_eq!(
        v["bytes"].as_u64().unwrap(),
        std::fs::metadata(t.path(&name)).unwrap().len()
    );
    assert_eq!(v["colour"], "none");
    assert_eq!(v["grid"]["9x9"], 200);
    let bits = v["displacement_bits"].as_object().unwrap();
    assert_eq!(bits.values().map(|n| n.as_u64().unwrap()).sum::<u64>(), 200);
    for tag in ["SCNE", "FRAM", "DISP"] {
        assert!(v["sections"][tag]["raw"].as_u64().unwrap() > 0, "{tag}");
        assert!(v["sections"][tag]["stored"].as_u64().unwrap() > 0, "{tag}");
    }
    for axis in 0..3 {
        let (lo, hi) = (
            v["bounds"]["min"][axis].as_f64().unwrap(),
            v["bounds"]["max"][axis].as_f64().unwrap(),
        );
        assert!(
            (lo + 10.0).abs() < 0.01 && (hi - 10.0).abs() < 0.01,
            "{lo} {hi}"
        );
    }
    assert!((v["frame_lengths"]["az"]["max"].as_f64().unwrap() - 0.001).abs() < 1e-9);
    // A closed sphere: every patch front-only, no opening, no inside box.
    assert_eq!(v["sides"]["front"], 200);
    assert_eq!(v["sides"]["both"], 0);
    assert_eq!(v["sides"]["openings"], 0);
    assert!(v["sides"]["inside_box"].is_null());
}

#[test]
fn table_names_counts_and_sections() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let run = t.run(&["stats", &name]).success();
    for needle in ["patches                200", "DISP", "FRAM", "9x9: 200"] {
        assert!(
            run.stdout.contains(needle),
            "{needle} missing in\n{}",
            run.stdout
        );
    }
}

#[test]
fn compression_shows_in_bits_per_node() {
    let t = TestCommand::new();
    t.run(&["sphere", "--compress", "-o", "c.spatch"]).success();
    let v: Value =
        serde_json::from_str(&t.run(&["stats", "c.spatch", "--json"]).success().stdout).unwrap();
    assert_eq!(v["sections"]["DISP"]["codec"], "predictive");
    assert!(v["displacement_bits_per_node"].as_f64().unwrap() < 4.0);
}
