//! `spatch from-cloud` on scan sets and scanner formats: bun.conf, several inputs, LAS/LAZ,
//! PTS and XYZ layouts through the binary, and malformed files (one line, exit 2, no output).

use spatch_format::read_scene;

use crate::test_command::TestCommand;

/// The shared data folder (`SPATCH_SHARED_DATA` or ../shared/data), when present.
fn shared(relative: &str) -> Option<String> {
    let path = spatch_fixtures::shared_data(relative)?;
    Some(path.display().to_string())
}

/// A 60 × 60 gently curved sheet of points as `x y z` values, shifted by `dx`.
pub(super) fn sheet(dx: f64) -> Vec<[f64; 3]> {
    (0..3600)
        .map(|k| {
            let (x, y) = ((k % 60) as f64 * 0.01 + dx, (k / 60) as f64 * 0.01);
            [x, y, 0.3 * (x - dx - 0.3) * (x - dx - 0.3)]
        })
        .collect()
}

/// Writes `points` as a LAS (or LAZ, by extension) file with RGB, 1 mm steps.
pub(super) fn write_las(path: &std::path::Path, points: &[[f64; 3]]) {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(7).unwrap();
    let mm = las::Transform {
        scale: 0.001,
        offset: 0.0,
    };
    builder.transforms = las::Vector {
        x: mm,
        y: mm,
        z: mm,
    };
    let mut writer = las::Writer::from_path(path, builder.into_header().unwrap()).unwrap();
    for (k, &[x, y, z]) in points.iter().enumerate() {
        let c = (k % 256) as u16 * 257;
        writer
            .write_point(las::Point {
                x,
                y,
                z,
                color: Some(las::Color::new(c, 0, 65535 - c)),
                gps_time: Some(0.0),
                ..las::Point::default()
            })
            .unwrap();
    }
    writer.close().unwrap();
}

#[test]
fn bun_conf_converts_all_ten_scans() {
    let Some(conf) = shared("bunny/data/bun.conf") else {
        return;
    };
    let t = TestCommand::new();
    let run = t.run(&["from-cloud", &conf, "-o", "b.spatch"]).success();
    assert!(run.stdout.contains("read 10 scans"), "{}", run.stdout);
    assert!(run.stdout.contains("from 362272 points"), "{}", run.stdout);
    let scene = read_scene(&t.path("b.spatch")).unwrap();
    assert!(scene.node_count() < 362_272);
}

#[test]
fn several_files_and_formats_convert_together() {
    let t = TestCommand::new();
    write_las(&t.path("a.laz"), &sheet(0.0));
    let text: String = sheet(1.0)
        .iter()
        .map(|p| format!("{} {} {} 0 0 1 200 100 50\n", p[0], p[1], p[2]))
        .collect();
    std::fs::write(t.path("b.xyz"), text).unwrap();
    let pts: String = std::iter::once("3600\n".to_string())
        .chain(
            sheet(2.0)
                .iter()
                .map(|p| format!("{} {} {} -200 10 20 30\n", p[0], p[1], p[2])),
        )
        .collect();
    std::fs::write(t.path("c.pts"), pts).unwrap();
    let run = t
        .run(&["from-cloud", "a.laz", "b.xyz", "c.pts", "-o", "abc.spatch"])
        .success();
    assert!(run.stdout.contains("read 3 scans"), "{}", run.stdout);
    assert!(run.stdout.contains("from 10800 points"), "{}", run.stdout);
    let scene = read_scene(&t.path("abc.spatch")).unwrap();
    let (lo, hi) = scene.bounds().unwrap();
    // The three sheets side by side: x from 0 to 2.59.
    assert!(lo.x < 0.05 && hi.x > 2.5, "{lo} {hi}");
    assert_ne!(
        scene.channel(),
        spatch_format::ColourChannel::None,
        "the inputs' colours are kept"
    );
}

#[test]
fn columns_option_reads_a_layout() {
    let t = TestCommand::new();
    let text: String = sheet(0.0)
        .iter()
        .map(|p| format!("7 {} {} {}\n", p[0], p[1], p[2]))
        .collect();
    std::fs::write(t.path("s.txt"), text).unwrap();
    t.run(&[
        "from-cloud",
        "s.txt",
        "--columns",
        "skip,x,y,z",
        "-o",
        "s.spatch",
    ])
    .success();
    let (_, hi) = read_scene(&t.path("s.spatch")).unwrap().bounds().unwrap();
    assert!(hi.x > 0.55 && hi.x < 0.65, "{hi}");
    let run = t.run(&[
        "from-cloud",
        "s.txt",
        "--columns",
        "x,y,w",
        "-o",
        "s2.spatch",
    ]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("unknown column `w`"), "{}", run.stderr);
    assert!(!t.path("s2.spatch").exists());
}

#[test]
fn malformed_scan_files_fail_in_one_line_without_output() {
    let t = TestCommand::new();
    write_las(&t.path("good.las"), &sheet(0.0));
    let las = std::fs::read(t.path("good.las")).unwrap();
    std::fs::write(t.path("short.las"), &las[..las.len() - 500]).unwrap();
    std::fs::write(t.path("head.laz"), &las[..40]).unwrap();
    std::fs::write(t.path("junk.e57"), b"ASTM-E57 and nothing more").unwrap();
    std::fs::write(t.path("bad.conf"), "bmesh x.ply 0 0 0\n").unwrap();
    std::fs::write(t.path("bad.pts"), "2\n1 2 3 4 5 6 7\n1 2 3\n").unwrap();
    for (file, expect) in [
        ("short.las", "truncated"),
        ("head.laz", "not a readable LAS/LAZ file"),
        ("junk.e57", "not a readable E57 file"),
        ("bad.conf", "line 1: expected 7 pose values"),
        ("bad.pts", "line 3: expected 7 values, found 3"),
    ] {
        let run = t.run(&["from-cloud", "good.las", file, "-o", "out.spatch"]);
        run.assert_one_clear_line(file);
        assert!(run.stderr.contains(expect), "{file}: {}", run.stderr);
        assert!(!t.path("out.spatch").exists(), "{file}");
    }
}
