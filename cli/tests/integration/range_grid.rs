//! `spatch from-cloud --range-grid`: a thin sheet scanned from both sides by two structured
//! scans keeps its two sides apart with the grids (each view draws only the side facing
//! it) and averages them into one middle surface without (`--range-grid off`); `--align-scans`
//! moves structured scans by their offset before the consensus; `spatch convert` joins a
//! raw scan's samples along its grid.

use crate::test_command::TestCommand;

/// A 61 × 61 grid of 1 mm steps at height `z` in the scan's own frame, as an ASCII PLY with
/// its `range_grid` (the Stanford raw-scan layout; the scanner looks down −z).
pub(crate) fn write_sheet_scan(path: &std::path::Path, z: f64) {
    let side = 61;
    let mut text = format!(
        "ply\nformat ascii 1.0\nobj_info num_cols {side}\nobj_info num_rows {side}\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element range_grid {}\nproperty list uchar int vertex_indices\nend_header\n",
        side * side,
        side * side
    );
    for k in 0..side * side {
        let (x, y) = ((k % side) as f64 - 30.0, (k / side) as f64 - 30.0);
        text.push_str(&format!("{} {} {z}\n", x * 0.001, y * 0.001));
    }
    for k in 0..side * side {
        text.push_str(&format!("1 {k}\n"));
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn range_grids_keep_the_two_sides_of_a_thin_sheet_apart() {
    let t = TestCommand::new();
    // The sheet's top (z = +0.5 mm) seen from above, its bottom seen from below: the
    // same file turned over by a half turn about x.
    write_sheet_scan(&t.path("side.ply"), 0.0005);
    std::fs::write(
        t.path("sheet.conf"),
        "bmesh side.ply 0 0 0 0 0 0 1\nbmesh side.ply 0 0 0 1 0 0 0\n",
    )
    .unwrap();
    let rms = |grid: &str| {
        let report = format!("{grid}.json");
        t.run(&[
            "from-cloud",
            "sheet.conf",
            "--no-consensus",
            "--range-grid",
            grid,
            "-o",
            &format!("{grid}.spatch"),
            "--report",
            &report,
        ])
        .success();
        let report: serde_json::Value = t.json(&report);
        let expected = if grid == "on" { "pca+sight" } else { "pca" };
        assert_eq!(report["details"]["normals"], expected);
        report["error"]["cloud_to_patch"]["rms"].as_f64().unwrap()
    };
    // Off: the views average both sides (1 mm apart, within the 2-spacing front band)
    // into a middle surface 0.5 mm from every point; on: each side gets its own patches.
    let (on, off) = (rms("on"), rms("off"));
    assert!(on < 0.1e-3, "with grids: rms {on}");
    assert!(off > 0.3e-3, "without grids: rms {off}");
    let run = t.run(&[
        "from-cloud",
        "sheet.conf",
        "--range-grid",
        "maybe",
        "-o",
        "x.spatch",
    ]);
    assert_eq!(run.code, 2);
    assert!(!t.path("x.spatch").exists());
}

#[test]
fn align_scans_moves_each_structured_scan_by_its_offset() {
    let t = TestCommand::new();
    // Two structured scans of one flat sheet seen from above, the second registered 0.6 mm
    // too high (and 0.5 mm along x, which a flat sheet cannot tell): the alignment moves
    // each by about half the height offset toward the other, before the consensus.
    write_sheet_scan(&t.path("side.ply"), 0.0);
    std::fs::write(
        t.path("pair.conf"),
        "bmesh side.ply 0 0 0 0 0 0 1\nbmesh side.ply 0.0005 0 0.0006 0 0 0 1\n",
    )
    .unwrap();
    let shift = |align: &str| {
        let report = format!("{align}.json");
        t.run(&[
            "from-cloud",
            "pair.conf",
            "--align-scans",
            align,
            "-o",
            &format!("{align}.spatch"),
            "--report",
            &report,
        ])
        .success();
        let report: serde_json::Value = t.json(&report);
        report["details"]["scan_shift"].as_f64().unwrap()
    };
    let (on, off) = (shift("on"), shift("off"));
    assert!(
        (0.2e-3..0.4e-3).contains(&on),
        "aligned: longest shift {on}"
    );
    assert_eq!(off, 0.0);
    let run = t.run(&[
        "from-cloud",
        "pair.conf",
        "--align-scans",
        "no",
        "-o",
        "y.spatch",
    ]);
    assert_eq!(run.code, 2);
    assert!(!t.path("y.spatch").exists());
}

#[test]
fn the_error_is_measured_against_the_given_or_the_aligned_points() {
    let t = TestCommand::new();
    // Two scans of one flat sheet, the second 0.6 mm too high: aligned, both become one
    // surface, 0.3 mm from each scan as given and on the scans as moved.
    write_sheet_scan(&t.path("side.ply"), 0.0);
    std::fs::write(
        t.path("pair.conf"),
        "bmesh side.ply 0 0 0 0 0 0 1\nbmesh side.ply 0 0 0.0006 0 0 0 1\n",
    )
    .unwrap();
    let rms = |against: &str| {
        let report = format!("{against}.json");
        t.run(&[
            "from-cloud",
            "pair.conf",
            "--error-against",
            against,
            "-o",
            &format!("{against}.spatch"),
            "--report",
            &report,
        ])
        .success();
        let report: serde_json::Value = t.json(&report);
        assert_eq!(report["details"]["cloud_error"]["against"], against);
        report["error"]["cloud_to_patch"]["rms"].as_f64().unwrap()
    };
    let (given, aligned) = (rms("given"), rms("aligned"));
    eprintln!("cloud→patch rms: against the given points {given:.2e}, the aligned {aligned:.2e}");
    assert!((0.2e-3..0.4e-3).contains(&given), "{given}");
    assert!(aligned < 0.05e-3, "{aligned}");
}

#[test]
fn convert_joins_a_raw_scan_along_its_grid() {
    let t = TestCommand::new();
    write_sheet_scan(&t.path("side.ply"), 0.0);
    t.run(&[
        "convert",
        "side.ply",
        "-o",
        "side.spatch",
        "--report",
        "side.json",
    ])
    .success();
    let report: serde_json::Value = t.json("side.json");
    // Two triangles per square of four samples: 60 × 60 squares.
    assert_eq!(report["details"]["triangles"], 2 * 60 * 60, "{report}");
    let rms = report["error"]["surface_to_patch"]["rms_rel"]
        .as_f64()
        .unwrap();
    assert!(rms < 1e-4, "{report}");
}
