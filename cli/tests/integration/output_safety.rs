//! Issue 20: no input destroyed, no special file replaced, no temporary file
//! left, no stream read without end, every mistake one line with exit code 2.

use std::os::unix::fs::PermissionsExt;

use crate::test_command::TestCommand;

/// Files in the test folder whose names start with a dot (temporaries).
fn hidden_files(t: &TestCommand) -> Vec<String> {
    std::fs::read_dir(t.dir())
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect()
}

#[test]
fn an_output_naming_an_input_is_refused_and_the_input_kept() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    let original = std::fs::read(t.path("s.spatch")).unwrap();
    std::fs::hard_link(t.path("s.spatch"), t.path("hard.spatch")).unwrap();
    std::os::unix::fs::symlink("s.spatch", t.path("soft.spatch")).unwrap();
    let cases: [&[&str]; 6] = [
        &["render", "s.spatch", "-o", "s.spatch"],
        &["render", "s.spatch", "-o", "x.png", "--stats", "s.spatch"],
        &["render", "s.spatch", "-o", "x.png", "--depth", "./s.spatch"],
        &["export", "s.spatch", "-o", "hard.spatch"],
        &["export", "soft.spatch", "-o", "s.spatch"],
        &["merge", "s.spatch", "hard.spatch", "-o", "soft.spatch"],
    ];
    for args in cases {
        let run = t.run(args);
        run.assert_one_clear_line("same file as the input");
        assert_eq!(std::fs::read(t.path("s.spatch")).unwrap(), original);
        assert!(
            !t.path("x.png").exists(),
            "{args:?}: work done before refusing"
        );
    }
    let run = t.run(&["render", "s.spatch", "-o", "x.png", "--stats", "x.png"]);
    run.assert_one_clear_line("x.png: named as two outputs");
}

#[test]
fn a_folder_as_output_is_one_line_before_any_work() {
    let t = TestCommand::new();
    std::fs::create_dir(t.path("d")).unwrap();
    t.run(&["sphere", "-o", "d"])
        .assert_one_clear_line("d: cannot write output: is a directory");
    t.run(&["sphere", "-o", "no/such/s.spatch"])
        .assert_one_clear_line("does not exist");
}

#[test]
fn symlinks_are_written_through_and_modes_kept() {
    let t = TestCommand::new();
    std::fs::write(t.path("real.spatch"), b"old").unwrap();
    std::fs::set_permissions(
        t.path("real.spatch"),
        std::fs::Permissions::from_mode(0o600),
    )
    .unwrap();
    std::os::unix::fs::symlink("real.spatch", t.path("link.spatch")).unwrap();
    t.small_sphere("link.spatch");
    let link = std::fs::symlink_metadata(t.path("link.spatch")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced");
    let real = std::fs::metadata(t.path("real.spatch")).unwrap();
    assert_eq!(real.permissions().mode() & 0o777, 0o600);
    assert!(real.len() > 1000);
    t.run(&["stats", "link.spatch"]).success();
}

#[test]
fn a_fifo_and_a_device_are_written_in_place() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    let fifo = t.path("pipe");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let reader = std::thread::spawn({
        let fifo = fifo.clone();
        move || std::fs::read(fifo).unwrap()
    });
    t.run(&["export", "s.spatch", "-o", "pipe"]).success();
    let bytes = reader.join().unwrap();
    assert!(bytes.starts_with(b"ply\n"), "{:?}", &bytes[..8]);
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    t.run(&[
        "render",
        "s.spatch",
        "-o",
        "/dev/null",
        "--stats",
        "/dev/stdout",
    ])
    .success();
    assert!(std::fs::metadata("/dev/null")
        .unwrap()
        .file_type()
        .is_char_device());
    assert!(hidden_files(&t).is_empty(), "{:?}", hidden_files(&t));
}

#[test]
fn a_report_on_standard_output_is_json() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    let run = t
        .run(&["render", "s.spatch", "-o", "x.png", "--stats", "-"])
        .success();
    let stats: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert!(stats.is_object());
}

#[test]
fn long_names_work_and_stale_temporaries_are_removed() {
    let t = TestCommand::new();
    let long = format!("{}.spatch", "n".repeat(246));
    assert_eq!(long.len(), 253);
    // Left by killed runs: process ids above the kernel's largest never run.
    for stale in [".spatch.4194999.0.tmp", ".s.spatch.4194998.tmp"] {
        std::fs::write(t.path(stale), b"x").unwrap();
    }
    t.small_sphere(&long);
    assert!(t.path(&long).exists());
    assert!(hidden_files(&t).contains(&".s.spatch.4194998.tmp".to_owned()));
    t.small_sphere("s.spatch");
    assert!(hidden_files(&t).is_empty(), "{:?}", hidden_files(&t));
}

#[test]
fn a_terminated_run_leaves_no_temporary_file() {
    let t = TestCommand::new();
    for delay_ms in [30, 120, 300] {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_spatch"))
            .args([
                "sphere",
                "--patches",
                "20000",
                "--grid",
                "33",
                "-o",
                "big.spatch",
            ])
            .current_dir(t.dir())
            .stderr(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(delay_ms));
        let killed = std::process::Command::new("kill")
            .args(["-TERM", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(killed.success());
        let _ = child.wait().unwrap();
        assert!(hidden_files(&t).is_empty(), "{:?}", hidden_files(&t));
    }
}

#[test]
fn endless_streams_are_refused_at_once() {
    let t = TestCommand::new();
    for device in ["/dev/zero", "/dev/urandom"] {
        let started = std::time::Instant::now();
        t.run(&["stats", device])
            .assert_one_clear_line("not a .spatch file");
        assert!(started.elapsed().as_secs() < 10, "{device}");
    }
}

#[test]
fn a_scene_reads_from_standard_input() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    let file = std::fs::File::open(t.path("s.spatch")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_spatch"))
        .args(["stats", "-", "--json"])
        .stdin(file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stats: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(stats["patches"], 200, "{stats}");
}

#[test]
fn bad_option_values_are_one_line() {
    let t = TestCommand::new();
    let cases: [&[&str]; 8] = [
        &["sphere", "--patches", "abc", "-o", "s.spatch"],
        &["sphere", "--grid", "1", "-o", "s.spatch"],
        &["sphere"],
        &["sphere", "--no-such-flag", "-o", "s.spatch"],
        &["convert", "m.obj", "-o", "m.spatch", "--grid", "999"],
        &["render", "s.spatch", "-o", "x.png", "--eye", "1,2"],
        &["render", "s.spatch", "-o", "x.png", "--mode", "voxels"],
        &["no-such-command"],
    ];
    for args in cases {
        let run = t.run(args);
        run.assert_one_clear_line("");
    }
    assert!(hidden_files(&t).is_empty());
}

#[test]
fn an_absurd_exaggeration_is_refused_without_hanging() {
    let t = TestCommand::new();
    for value in ["1e20", "1e25", "1e30", "-1e30"] {
        let started = std::time::Instant::now();
        let run = t.run(&["earth", "--exaggeration", value, "-o", "e.spatch"]);
        run.assert_one_clear_line("--exaggeration");
        assert!(started.elapsed().as_secs() < 30, "{value}");
        assert!(!t.path("e.spatch").exists());
    }
}

#[test]
fn completions_and_the_manual_page_are_printed() {
    let t = TestCommand::new();
    let bash = t.run(&["completions", "bash"]).success();
    assert!(bash.stdout.contains("spatch") && bash.stdout.contains("from-cloud"));
    let zsh = t.run(&["completions", "zsh"]).success();
    assert!(
        zsh.stdout.starts_with("#compdef spatch"),
        "{}",
        &zsh.stdout[..40]
    );
    let man = t.run(&["man"]).success();
    assert!(man.stdout.contains(".TH spatch 1"));
    assert!(
        man.stdout.contains("spatch\\-render"),
        "no subcommand pages"
    );
    t.run(&["man", "-o", "spatch.1"]).success();
    assert!(std::fs::read_to_string(t.path("spatch.1"))
        .unwrap()
        .contains(".SH"));
}

#[test]
fn an_extension_naming_another_format_is_refused() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    t.run(&["render", "s.spatch", "-o", "t.jpg"])
        .assert_one_clear_line("t.jpg: this output is written as a PNG image");
    t.run(&["export", "s.spatch", "-o", "t.stl"])
        .assert_one_clear_line("t.stl: cannot tell the format");
    t.run(&["export", "s.spatch", "--format", "ply", "-o", "t.obj"])
        .assert_one_clear_line("t.obj: this output is written as a PLY file");
    t.run(&["sphere", "-o", "t.png"])
        .assert_one_clear_line("t.png");
    for refused in ["t.jpg", "t.stl", "t.obj"] {
        assert!(!t.path(refused).exists(), "{refused}");
    }
    // Unknown extensions are the user's choice.
    t.run(&["render", "s.spatch", "-o", "t.PNG", "--stats", "t.txt"])
        .success();
}

#[test]
fn the_eye_far_away_gets_a_true_message() {
    let t = TestCommand::new();
    t.small_sphere("s.spatch");
    t.run(&["render", "s.spatch", "-o", "x.png", "--eye", "1e300,0,0"])
        .assert_one_clear_line("too far from the origin");
}
