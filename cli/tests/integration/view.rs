//! Issue 17: `spatch view` — no display, scripted replays whose screenshot
//! equals `spatch render` of the printed command, the orbit benchmark, bad
//! scripts, several scenes, and the window itself under Xvfb when
//! `xvfb-run` is installed.

use std::process::Command;

use crate::test_command::{Run, TestCommand};

/// Runs `spatch` in `t`'s folder with `DISPLAY` and `WAYLAND_DISPLAY` unset.
fn run_without_display(t: &TestCommand, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_spatch"))
        .args(args)
        .current_dir(t.dir())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("spatch runs");
    Run {
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// The arguments of the `spatch render` command a view run printed, with
/// its output renamed `out`.
fn printed_render(stdout: &str, out: &str) -> Vec<String> {
    let line = stdout.lines().last().expect("a printed command");
    let words: Vec<String> = line
        .strip_prefix("spatch ")
        .expect("a spatch command")
        .split_whitespace()
        .map(|w| {
            if w == "view.png" {
                out.to_owned()
            } else {
                w.to_owned()
            }
        })
        .collect();
    assert_eq!(words[0], "render", "{line}");
    words
}

#[test]
fn without_a_display_the_viewer_says_so_in_one_line() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    let run = run_without_display(&t, &["view", "s.spatch"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(
        run.stderr.starts_with("spatch: error: no display ("),
        "{}",
        run.stderr
    );
    assert!(run.stdout.is_empty());
    // A window replay needs one too, and writes no screenshot.
    std::fs::write(t.path("ev.txt"), "orbit 5 5\n").unwrap();
    let args = [
        "view",
        "s.spatch",
        "--script",
        "ev.txt",
        "--screenshot",
        "x.png",
    ];
    assert_eq!(run_without_display(&t, &args).code, 2);
    assert!(!t.path("x.png").exists());
}

#[test]
fn a_scripted_screenshot_equals_the_render_of_the_printed_command() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    let scripts = [
        "orbit 40 10\nzoom 2\nview 5\norbit 100 -30\npan 10 5\n",
        "view 3\nzoom -1\nshading\nmode\n",
        "orbit -200 80\nmip\nssaa\nshading\nshading\nresize 320 200\n",
    ];
    for (k, script) in scripts.iter().enumerate() {
        std::fs::write(t.path("ev.txt"), script).unwrap();
        let shot = format!("shot{k}.png");
        let run = run_without_display(
            &t,
            &[
                "view",
                "s.spatch",
                "--width",
                "400",
                "--height",
                "300",
                "--script",
                "ev.txt",
                "--no-window",
                "--no-overlay",
                "--screenshot",
                &shot,
                "--threads",
                "2",
            ],
        )
        .success();
        let reference = format!("ref{k}.png");
        let args = printed_render(&run.stdout, &reference);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        t.run(&args).success();
        let a = std::fs::read(t.path(&shot)).unwrap();
        let b = std::fs::read(t.path(&reference)).unwrap();
        assert!(a == b, "script {k}: screenshot differs from {:?}", args);
    }
    // The last script resized the view and turned supersampling off.
    let last = std::fs::read_to_string(t.path("ev.txt")).unwrap();
    assert!(last.contains("resize 320 200"));
    let image = image::open(t.path("shot2.png")).unwrap();
    assert_eq!((image.width(), image.height()), (320, 200));
}

#[test]
fn the_overlay_line_is_drawn_only_in_the_bottom_strip() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    std::fs::write(t.path("ev.txt"), "zoom 1\n").unwrap();
    for (name, extra) in [("plain.png", Some("--no-overlay")), ("text.png", None)] {
        let mut args = vec![
            "view",
            "s.spatch",
            "--width",
            "300",
            "--height",
            "200",
            "--script",
            "ev.txt",
            "--no-window",
            "--screenshot",
            name,
        ];
        args.extend(extra);
        run_without_display(&t, &args).success();
    }
    let plain = image::open(t.path("plain.png")).unwrap().to_rgba8();
    let text = image::open(t.path("text.png")).unwrap().to_rgba8();
    let differs = |y: u32| (0..300).any(|x| plain.get_pixel(x, y) != text.get_pixel(x, y));
    assert!((0..100).all(|y| !differs(y)));
    assert!((150..200).any(differs));
    // White text pixels exist in the overlay.
    assert!(text.pixels().any(|p| p.0 == [255, 255, 255, 255]));
}

#[test]
fn the_orbit_benchmark_prints_median_and_worst_frame_times() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    let run = run_without_display(
        &t,
        &[
            "view",
            "s.spatch",
            "--bench-orbit",
            "6",
            "--threads",
            "2",
            "--width",
            "200",
            "--height",
            "160",
        ],
    )
    .success();
    let line = run.stdout.trim();
    assert!(
        line.starts_with("orbit of 6 frames at 200x160, 2 threads: median "),
        "{line}"
    );
    let number_after = |key: &str| -> f64 {
        let rest = line.split(key).nth(1).unwrap().trim_start();
        rest.split(' ').next().unwrap().parse().unwrap()
    };
    let (median, worst) = (number_after("median"), number_after("worst"));
    assert!(median > 0.0 && median <= worst, "{line}");
    assert!(line.ends_with("of 200 patches drawn (median)"), "{line}");
    let args = [
        "view",
        "s.spatch",
        "--bench-orbit",
        "2",
        "--width",
        "200",
        "--height",
        "160",
    ];
    let run = run_without_display(&t, &[&args[..], &["--moving-scale", "2"]].concat()).success();
    assert!(
        run.stdout
            .starts_with("orbit of 2 frames at 200x160 (rendered at 100x80), "),
        "{}",
        run.stdout
    );
}

#[test]
fn a_bad_script_is_one_clear_line_and_writes_nothing() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    std::fs::write(t.path("ev.txt"), "orbit 1 2\nspin 3\n").unwrap();
    let args = [
        "view",
        "s.spatch",
        "--script",
        "ev.txt",
        "--no-window",
        "--screenshot",
        "x.png",
    ];
    let run = run_without_display(&t, &args);
    run.assert_one_clear_line("ev.txt: line 2: unknown event \"spin\"");
    assert!(!t.path("x.png").exists());
    let run = run_without_display(&t, &["view", "missing.spatch", "--bench-orbit", "2"]);
    run.assert_one_clear_line("missing.spatch");
    let run = run_without_display(&t, &["view", "s.spatch", "--screenshot", "x.png"]);
    assert_eq!(run.code, 2, "--screenshot needs --script: {}", run.stderr);
}

#[test]
fn several_scenes_are_shown_together_and_printed_as_a_merge() {
    let t = TestCommand::new();
    t.small_sphere("a.spatch");
    t.small_sphere("b.spatch");
    std::fs::write(t.path("ev.txt"), "orbit 10 0\n").unwrap();
    let args = [
        "view",
        "a.spatch",
        "b.spatch",
        "--script",
        "ev.txt",
        "--no-window",
        "--no-overlay",
        "--screenshot",
        "ab.png",
        "--width",
        "200",
        "--height",
        "150",
    ];
    let run = run_without_display(&t, &args).success();
    let line = run.stdout.trim();
    let (merge, render) = line.split_once(" && ").expect(line);
    assert_eq!(merge, "spatch merge a.spatch b.spatch -o view.spatch");
    let merge: Vec<&str> = merge.split_whitespace().skip(1).collect();
    t.run(&merge).success();
    let render = printed_render(render, "ref.png");
    let render: Vec<&str> = render.iter().map(String::as_str).collect();
    t.run(&render).success();
    assert!(std::fs::read(t.path("ab.png")).unwrap() == std::fs::read(t.path("ref.png")).unwrap());
    let bench = run_without_display(&t, &["view", "a.spatch", "b.spatch", "--bench-orbit", "2"]);
    assert!(bench.success().stdout.contains("of 400 patches"));
}

#[test]
fn under_xvfb_the_window_screenshot_equals_the_render() {
    let found = Command::new("xvfb-run").arg("--help").output().is_ok();
    if !found {
        eprintln!(
            "skipped: xvfb-run is not installed (Debian package xvfb; .ci/view_test installs it)"
        );
        return;
    }
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    std::fs::write(t.path("ev.txt"), "orbit 60 -20\nzoom 1\n").unwrap();
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x1024x24"])
        .arg(env!("CARGO_BIN_EXE_spatch"))
        .args([
            "view",
            "s.spatch",
            "--width",
            "320",
            "--height",
            "240",
            "--script",
            "ev.txt",
            "--no-overlay",
            "--screenshot",
            "win.png",
        ])
        .current_dir(t.dir())
        .output()
        .expect("xvfb-run runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let args = printed_render(&stdout, "ref.png");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    t.run(&args).success();
    assert!(std::fs::read(t.path("win.png")).unwrap() == std::fs::read(t.path("ref.png")).unwrap());
}

#[test]
fn a_tiled_scene_index_is_viewed_whole_and_its_printed_render_matches() {
    let t = TestCommand::new();
    crate::tiled::convert_city_in_tiles(&t);
    std::fs::write(t.path("ev.txt"), "orbit 30 -20\nzoom 1\n").unwrap();
    let view = |inputs: &[&str]| {
        let mut args = vec!["view"];
        args.extend_from_slice(inputs);
        args.extend_from_slice(&[
            "--width",
            "200",
            "--height",
            "150",
            "--script",
            "ev.txt",
            "--no-window",
            "--no-overlay",
            "--screenshot",
            "shot.png",
        ]);
        run_without_display(&t, &args)
    };
    let run = view(&["out/index.json"]).success();
    let args = printed_render(&run.stdout, "ref.png");
    assert_eq!(args[1], "out/index.json", "{args:?}");
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    t.run(&args).success();
    let shot = image::open(t.path("shot.png")).unwrap().to_rgba8();
    assert_eq!(
        shot.as_raw(),
        image::open(t.path("ref.png")).unwrap().to_rgba8().as_raw()
    );
    let background = *shot.get_pixel(0, 0);
    assert!(shot.pixels().filter(|p| **p != background).count() > 1000);
    // An index with other scenes: one line, exit 2, no screenshot.
    std::fs::remove_file(t.path("shot.png")).unwrap();
    let run = view(&["out/index.json", "out/index.json"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("viewed on its own"), "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(!t.path("shot.png").exists());
}
