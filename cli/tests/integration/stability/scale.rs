//! Scale and position do not change the relative error: the frames are f32 around an f64
//! scene offset, and every tolerance in the pipeline follows the model's own size.

use spatch_fixtures::shapes;

use super::{convert_report, error};
use crate::test_command::TestCommand;

/// Converts an icosphere of radius `radius` centred at `centre` and returns the report.
fn sphere_report(radius: f32, centre: f64) -> serde_json::Value {
    let t = TestCommand::new();
    let obj = shapes::icosphere(radius, 3).to_obj([centre; 3]);
    std::fs::write(t.path("ball.obj"), obj).unwrap();
    convert_report(&t, "ball.obj", &["--threads", "1"])
}

/// `(surface_to_patch max_rel, rms_rel, node_to_surface max_rel)`.
fn relative(report: &serde_json::Value) -> [f64; 3] {
    [
        error(report, "surface_to_patch", "max_rel"),
        error(report, "surface_to_patch", "rms_rel"),
        error(report, "node_to_surface", "max_rel"),
    ]
}

fn assert_close(case: &str, got: [f64; 3], unit: [f64; 3], tolerance: f64) {
    for (g, u) in got.iter().zip(unit) {
        assert!(
            (g - u).abs() <= tolerance * u.max(1e-12),
            "{case}: {got:?} against {unit:?} at unit scale"
        );
    }
}

/// 1e6 units from the origin on every axis: the f64 scene offset keeps the error what it is
/// at the origin, within 1 % (the target), and the patch count the same.
#[test]
fn a_model_1e6_units_from_the_origin() {
    let origin = sphere_report(1.0, 0.0);
    let far = sphere_report(1.0, 1e6);
    assert_eq!(origin["counts"], far["counts"], "{origin}\n{far}");
    assert_close("1e6 away", relative(&far), relative(&origin), 0.01);
}

/// Patch counts within 5 % of each other.
fn assert_similar_counts(case: &str, got: &serde_json::Value, unit: &serde_json::Value) {
    let (g, u) = (
        got["counts"]["patches"].as_f64().unwrap(),
        unit["counts"]["patches"].as_f64().unwrap(),
    );
    assert!((g - u).abs() <= 0.05 * u, "{case}: {g} patches against {u}");
}

/// A model a millionth of a unit across: spacing, tolerances and quantization steps all
/// follow the model's size, so it converts like the unit model. Not bit for bit: its f32
/// vertices round differently, which moves the segmenter's ties (a patch more or less), so
/// the relative error is held within 25 % and the patch count within 5 %.
#[test]
fn a_model_at_1e_minus_6_scale() {
    let unit = sphere_report(1.0, 0.0);
    let tiny = sphere_report(1e-6, 0.0);
    assert_similar_counts("1e-6 scale", &tiny, &unit);
    assert_close("1e-6 scale", relative(&tiny), relative(&unit), 0.25);
}

/// A model a million units across: as the tiny one, like the unit model.
#[test]
fn a_model_at_1e6_scale() {
    let unit = sphere_report(1.0, 0.0);
    let huge = sphere_report(1e6, 0.0);
    assert_similar_counts("1e6 scale", &huge, &unit);
    assert_close("1e6 scale", relative(&huge), relative(&unit), 0.25);
}
