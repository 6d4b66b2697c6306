//! Issue 20, item 6: `-q/--quiet`, `--json` on every command that reports, one
//! `--threads N` on every command that does work, and no progress drawn when standard
//! error is not a terminal.

use serde_json::Value;

use crate::report_schema::check_shared_keys;
use crate::test_command::TestCommand;

/// A small sphere, a mesh exported from it and a cloud of its nodes.
fn inputs(t: &TestCommand) -> String {
    let scene = t.small_sphere("s.spatch");
    t.run(&["export", &scene, "--cells", "-o", "m.obj"])
        .success();
    t.run(&["export", &scene, "-o", "c.ply"]).success();
    scene
}

/// Every command that reports, with `--json`, as the arguments before it.
fn reporting_commands(scene: &str) -> Vec<Vec<String>> {
    let lines: [&[&str]; 8] = [
        &[
            "sphere",
            "--radius",
            "10",
            "--patches",
            "60",
            "--grid",
            "5",
            "-o",
            "x.spatch",
        ],
        &["convert", "m.obj", "-o", "y.spatch", "--no-error"],
        &["from-cloud", "c.ply", "-o", "z.spatch"],
        &[
            "earth",
            "-o",
            "e.spatch",
            "--level",
            "low",
            "--triangles",
            "2000",
            "--map-width",
            "128",
            "--no-error",
        ],
        &["merge", scene, scene, "-o", "m.spatch"],
        &["export", scene, "-o", "n.ply"],
        &[
            "render", scene, "-o", "r.png", "--width", "48", "--height", "48",
        ],
        &[
            "render", scene, "--bench", "2", "--width", "32", "--height", "32",
        ],
    ];
    lines
        .iter()
        .map(|l| l.iter().map(|s| s.to_string()).collect())
        .collect()
}

#[test]
fn json_prints_one_report_in_the_shared_shape_on_every_reporting_command() {
    let t = TestCommand::new();
    let scene = inputs(&t);
    for args in reporting_commands(&scene) {
        let mut args: Vec<&str> = args.iter().map(String::as_str).collect();
        args.push("--json");
        let run = t.run(&args).success();
        let value: Value = serde_json::from_str(&run.stdout)
            .unwrap_or_else(|e| panic!("{args:?}: {e}\n{}", run.stdout));
        let command = args[0];
        let report = check_shared_keys(&value, command);
        if let Some(output) = &report.output {
            assert!(t.path(output).is_file(), "{args:?}: {output}");
        }
        if args.contains(&"--bench") {
            assert_eq!(value["details"]["bench"]["frames"], 2, "{value}");
            assert!(
                value["details"]["bench"]["ms"]["frame"]["median_ms"]
                    .as_f64()
                    .unwrap()
                    > 0.0
            );
        }
        assert!(run.stderr.is_empty(), "{args:?}: {}", run.stderr);
    }
}

#[test]
fn json_with_the_output_on_standard_output_is_refused_before_any_work() {
    let t = TestCommand::new();
    let scene = inputs(&t);
    for args in [
        vec!["sphere", "-o", "-", "--json"],
        vec!["convert", "m.obj", "-o", "/dev/stdout", "--json"],
        vec!["export", &scene, "-o", "-", "--json"],
        vec!["render", &scene, "-o", "r.png", "--stats", "-", "--json"],
        vec!["merge", &scene, &scene, "-o", "-", "--json"],
    ] {
        let run = t.run(&args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert!(run.stdout.is_empty(), "{args:?}");
        assert!(run.stderr.contains("--json"), "{args:?}: {}", run.stderr);
        run.assert_one_clear_line(if args[0] == "convert" {
            "/dev/stdout"
        } else {
            "-"
        });
    }
    assert!(!t.path("r.png").exists());
}

#[test]
fn quiet_prints_nothing_but_still_writes_and_still_fails_loudly() {
    let t = TestCommand::new();
    let scene = inputs(&t);
    let runs: [&[&str]; 6] = [
        &[
            "-q",
            "sphere",
            "--patches",
            "60",
            "--grid",
            "5",
            "--radius",
            "10",
            "-o",
            "q1.spatch",
        ],
        &[
            "convert",
            "m.obj",
            "-o",
            "q2.spatch",
            "--quiet",
            "--report",
            "q2.json",
            "--no-error",
        ],
        &["from-cloud", "c.ply", "-o", "q3.spatch", "-q"],
        &["merge", &scene, &scene, "-o", "q4.spatch", "-q"],
        &["export", &scene, "-o", "q5.ply", "-q"],
        &[
            "render", &scene, "-o", "q6.png", "-q", "--width", "32", "--height", "32",
        ],
    ];
    for args in runs {
        let run = t.run(args).success();
        assert!(
            run.stdout.is_empty() && run.stderr.is_empty(),
            "{args:?}: {} {}",
            run.stdout,
            run.stderr
        );
    }
    for name in [
        "q1.spatch",
        "q2.spatch",
        "q2.json",
        "q3.spatch",
        "q4.spatch",
        "q5.ply",
        "q6.png",
    ] {
        assert!(t.path(name).is_file(), "{name}");
    }
    // --json still prints with -q: the report is what was asked for.
    let run = t
        .run(&["export", &scene, "-o", "q7.ply", "-q", "--json"])
        .success();
    assert!(
        serde_json::from_str::<Value>(&run.stdout).is_ok(),
        "{}",
        run.stdout
    );
    // Errors are still printed.
    let run = t.run(&["-q", "convert", "missing.obj", "-o", "x.spatch"]);
    assert_eq!(run.code, 2);
    run.assert_one_clear_line("missing.obj");
}

#[test]
fn without_a_terminal_no_progress_is_drawn() {
    let t = TestCommand::new();
    inputs(&t);
    let run = t
        .run(&["convert", "m.obj", "-o", "p.spatch", "--no-error"])
        .success();
    assert!(run.stderr.is_empty(), "{}", run.stderr);
    assert!(run.stdout.contains("p.spatch"), "{}", run.stdout);
}

#[test]
fn every_command_that_does_work_takes_threads_and_the_output_does_not_depend_on_it() {
    let t = TestCommand::new();
    let scene = inputs(&t);
    let commands: [(&[&str], &str); 5] = [
        (
            &["sphere", "--patches", "80", "--grid", "5", "--radius", "10"],
            "spatch",
        ),
        (&["convert", "m.obj", "--no-error"], "spatch"),
        (&["from-cloud", "c.ply"], "spatch"),
        (
            &[
                "earth",
                "--level",
                "low",
                "--triangles",
                "2000",
                "--map-width",
                "128",
                "--no-error",
            ],
            "spatch",
        ),
        (
            &["render", &scene, "--width", "40", "--height", "40"],
            "png",
        ),
    ];
    for (k, (args, ext)) in commands.iter().enumerate() {
        let mut outputs = Vec::new();
        for threads in ["1", "0", "2"] {
            let name = format!("t{k}_{threads}.{ext}");
            let mut full = args.to_vec();
            full.extend(["--threads", threads, "-o", &name, "-q"]);
            t.run(&full).success();
            outputs.push(std::fs::read(t.path(&name)).unwrap());
        }
        assert!(outputs.windows(2).all(|w| w[0] == w[1]), "{args:?}");
    }
    let run = t.run(&["sphere", "-o", "x.spatch", "--threads", "2000"]);
    assert_eq!(run.code, 2);
    run.assert_one_clear_line("--threads");
}
