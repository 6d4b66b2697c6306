//! The stability suite: stiff and extreme inputs, each test named after its case and stating
//! the expected behaviour (a bounded error or a clear refusal), run through the `spatch`
//! binary as a user would meet them.
//!
//! - `degenerate`: sliver and zero-area triangles, nearly parallel and exactly opposite
//!   normals across an edge, duplicate vertices, non-manifold edges and bow-tie vertices, a
//!   single triangle.
//! - `scale`: a model at 1e-6 and 1e6 scale and 1e6 units from the origin keeps the relative
//!   error it has at unit scale at the origin.
//! - `overflow`: heights that overflow 8-bit displacements get 16-bit codes and keep their
//!   error bound.
//! - `views`: a patch seen exactly edge-on, patches crossing the near plane and behind the
//!   eye, a camera inside the model.
//! - `bad_files`: NaN and infinity in every input format, empty files, a single point.
//! - `regressions`: every file under `testdata/regression/` (inputs the fuzzers found
//!   interesting) goes through its reader without a panic.

mod bad_files;
mod degenerate;
mod overflow;
mod regressions;
mod scale;
mod views;

use crate::test_command::TestCommand;

/// Writes an OBJ file of `positions` and 0-based `triangles` and returns its name.
pub(crate) fn write_obj(
    t: &TestCommand,
    name: &str,
    positions: &[[f64; 3]],
    triangles: &[[u32; 3]],
) -> String {
    let mut text = String::new();
    for p in positions {
        text.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    for f in triangles {
        text.push_str(&format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1));
    }
    std::fs::write(t.path(name), text).unwrap();
    name.to_owned()
}

/// Converts `input` with `extra` options and returns the JSON report.
pub(crate) fn convert_report(t: &TestCommand, input: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "convert",
        input,
        "-o",
        "out.spatch",
        "--report",
        "report.json",
    ];
    args.extend_from_slice(extra);
    t.run(&args).success();
    t.json("report.json")
}

/// `report.error.<side>.<stat>` as a number.
pub(crate) fn error(report: &serde_json::Value, side: &str, stat: &str) -> f64 {
    report["error"][side][stat]
        .as_f64()
        .unwrap_or_else(|| panic!("no error.{side}.{stat} in {report}"))
}

/// Asserts a refusal: exit code 2, one error line naming `file` and containing every one of
/// `words`, and no output file.
pub(crate) fn assert_refused(
    t: &TestCommand,
    run: &crate::test_command::Run,
    file: &str,
    words: &[&str],
) {
    run.assert_one_clear_line(file);
    let line = run.stderr.trim();
    for w in words {
        assert!(line.contains(w), "{file}: '{w}' missing from: {line}");
    }
    assert!(
        !t.path("out.spatch").exists(),
        "{file}: partial output left"
    );
}
