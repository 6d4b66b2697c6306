//! The shared report shape (docs/report-schema.md): every command's report parses into
//! `spatch_eval::Report` and its shared figures agree with each other.

use serde_json::Value;
use spatch_eval::{Report, REPORT_SCHEMA};

use crate::test_command::TestCommand;

/// Checks the keys and invariants every report shares; returns the typed report (whose stage
/// maps are in key order, since a `Value` sorts its keys).
pub(crate) fn check_shared_keys(value: &Value, command: &str) -> Report<Value> {
    let keys: Vec<&str> = value
        .as_object()
        .expect("a report is an object")
        .keys()
        .map(String::as_str)
        .collect();
    for key in [
        "schema",
        "tool",
        "command",
        "input",
        "output",
        "counts",
        "seconds",
        "stages",
        "measure_seconds",
        "measure_stages",
        "threads",
        "diagonal",
        "error",
        "warnings",
        "details",
    ] {
        assert!(keys.contains(&key), "{command} report lacks {key}: {value}");
    }
    let report: Report<Value> =
        serde_json::from_value(value.clone()).unwrap_or_else(|e| panic!("{command}: {e}"));
    assert_eq!(report.schema, REPORT_SCHEMA);
    assert!(report.tool.starts_with("spatch "), "{}", report.tool);
    assert_eq!(report.command, command);
    assert!(!report.input.is_empty());
    let c = report.counts;
    assert!(c.patches > 0 && c.filled_nodes > 0 && c.filled_nodes <= c.nodes && c.bytes > 0);
    assert!(report.stages.0.iter().all(|(_, s)| *s >= 0.0));
    assert!(!report.stages.0.is_empty());
    // `seconds` is the wall time of the stages: at least their sum.
    assert!(
        report.stages.total() <= report.seconds + 1e-6,
        "{command}: stages {} > seconds {}",
        report.stages.total(),
        report.seconds
    );
    assert!((report.measure_stages.total() - report.measure_seconds).abs() < 1e-6);
    assert!(report.threads >= 1);
    let diagonal = report.diagonal.expect("a diagonal");
    assert!(diagonal > 0.0);
    for (name, e) in &report.error {
        assert!(e.samples > 0, "{name}");
        assert!(e.rms <= e.max && e.p95 <= e.max, "{name}: {e:?}");
        assert!(
            (e.max_rel * diagonal - e.max).abs() <= 1e-9 * e.max.max(1.0),
            "{name}"
        );
        assert!(
            (e.rms_rel * diagonal - e.rms).abs() <= 1e-9 * e.rms.max(1.0),
            "{name}"
        );
    }
    if !report.error.is_empty() {
        assert!(
            report.measure_seconds > 0.0,
            "{command}: error measured in no time"
        );
    }
    assert!(report.details.is_object());
    report
}

/// An icosphere of radius 1 as OBJ.
pub(crate) fn write_ball(t: &TestCommand, name: &str, radius: f32) -> String {
    let shape = spatch_fixtures::shapes::icosphere(radius, 3);
    std::fs::write(t.path(name), shape.to_obj([0.0; 3])).unwrap();
    name.to_owned()
}

/// Points on the unit sphere (a Fibonacci spiral) as XYZ text.
pub(crate) fn write_ball_cloud(t: &TestCommand, name: &str, count: usize) -> String {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut text = String::new();
    for k in 0..count {
        let y = 1.0 - 2.0 * (k as f64 + 0.5) / count as f64;
        let r = (1.0 - y * y).sqrt();
        let a = golden * k as f64;
        text.push_str(&format!("{} {} {}\n", r * a.cos(), y, r * a.sin()));
    }
    std::fs::write(t.path(name), text).unwrap();
    name.to_owned()
}

#[test]
fn every_command_writes_the_shared_shape() {
    let t = TestCommand::new();
    let ball = write_ball(&t, "ball.obj", 1.0);
    t.run(&[
        "convert",
        &ball,
        "-o",
        "ball.spatch",
        "--report",
        "convert.json",
    ])
    .success();
    let cloud = write_ball_cloud(&t, "ball.xyz", 6000);
    t.run(&[
        "from-cloud",
        &cloud,
        "-o",
        "cloud.spatch",
        "--report",
        "cloud.json",
    ])
    .success();
    t.run(&[
        "earth",
        "--level",
        "low",
        "--triangles",
        "3000",
        "--report",
        "earth.json",
        "-o",
        "earth.spatch",
    ])
    .success();
    t.run(&[
        "eval",
        "ball.spatch",
        "--source",
        &ball,
        "--views",
        "2",
        "--size",
        "64",
        "--runs",
        "1",
        "--report",
        "eval.json",
    ])
    .success();

    let convert = check_shared_keys(&t.json("convert.json"), "convert");
    let cloud = check_shared_keys(&t.json("cloud.json"), "from-cloud");
    let earth = check_shared_keys(&t.json("earth.json"), "earth");
    let eval = check_shared_keys(&t.json("eval.json"), "eval");

    // The same scene measured by convert and by eval: same counts and the same error.
    assert_eq!(convert.counts, eval.counts);
    assert_eq!(convert.diagonal, eval.diagonal);
    for name in ["node_to_surface", "surface_to_patch"] {
        let (a, b) = (&convert.error[name], &eval.error[name]);
        assert_eq!(a.samples, b.samples, "{name}");
        assert!(
            (a.max - b.max).abs() <= 1e-6 * a.max.max(1e-9),
            "{name}: {a:?} vs {b:?}"
        );
    }
    let names = |r: &Report<Value>| r.error.keys().cloned().collect::<Vec<_>>();
    assert_eq!(names(&earth), ["node_to_surface", "surface_to_patch"]);
    assert_eq!(names(&cloud), ["cloud_to_patch", "node_to_cloud"]);
    // Stages in the order they ran (read from the text: a `Value` sorts its keys).
    let typed = |name: &str| -> Report<Value> { t.json(name) };
    let (convert, earth, cloud, eval) = (
        typed("convert.json"),
        typed("earth.json"),
        typed("cloud.json"),
        typed("eval.json"),
    );
    assert_eq!(convert.stages.names().next(), Some("load"));
    assert_eq!(convert.stages.names().last(), Some("write"));
    assert_eq!(earth.stages.names().next(), Some("heights"));
    assert_eq!(cloud.stages.names().next(), Some("load"));
    assert_eq!(eval.stages.names().next(), Some("load"));
    assert_eq!(
        convert.measure_stages.names().collect::<Vec<_>>(),
        ["error"]
    );
    assert_eq!(convert.output.as_deref(), Some("ball.spatch"));
    assert_eq!(eval.output, None, "eval wrote no file");
}
