use crate::test_command::TestCommand;

/// Every command that reads a scene, with its output argument.
const READERS: [&[&str]; 3] = [
    &["stats"],
    &["export", "-o", "out.ply"],
    &["merge", "good.spatch", "-o", "out.spatch"],
];

#[test]
fn missing_truncated_and_corrupt_files_fail_cleanly() {
    let t = TestCommand::new();
    t.small_sphere("good.spatch");
    let good = std::fs::read(t.path("good.spatch")).unwrap();
    std::fs::write(t.path("truncated.spatch"), &good[..good.len() / 2]).unwrap();
    let mut flipped = good.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0x40;
    std::fs::write(t.path("flipped.spatch"), &flipped).unwrap();
    let mut future = good.clone();
    future[6] = 9;
    std::fs::write(t.path("future.spatch"), &future).unwrap();
    std::fs::write(t.path("empty.spatch"), b"").unwrap();
    for (file, needle) in [
        ("missing.spatch", "cannot read"),
        ("truncated.spatch", "truncated"),
        ("flipped.spatch", "checksum"),
        ("future.spatch", "major version 9"),
        ("empty.spatch", "not a .spatch file"),
    ] {
        for reader in READERS {
            let mut args: Vec<&str> = reader.to_vec();
            args.insert(1.min(args.len()), file);
            if reader[0] == "stats" {
                args = vec!["stats", file];
            }
            let run = t.run(&args);
            run.assert_one_clear_line(file);
            assert!(run.stderr.contains(needle), "{file}: {}", run.stderr);
            assert!(!t.path("out.ply").exists() && !t.path("out.spatch").exists());
        }
    }
}

#[test]
fn usage_errors_exit_with_two_and_help_has_examples() {
    let t = TestCommand::new();
    assert_eq!(t.run(&["no-such-command"]).code, 2);
    assert_eq!(t.run(&["sphere"]).code, 2, "missing -o");
    for command in ["sphere", "stats", "export", "merge"] {
        let run = t.run(&[command, "--help"]).success();
        assert!(
            run.stdout.contains("Example:"),
            "{command} --help has no example"
        );
    }
    assert!(t
        .run(&["--version"])
        .success()
        .stdout
        .starts_with("spatch "));
}

#[test]
fn an_unwritable_output_is_an_error_without_partial_files() {
    let t = TestCommand::new();
    let run = t.run(&["sphere", "-o", "no/such/folder/s.spatch"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr.contains("no/such/folder/s.spatch"),
        "{}",
        run.stderr
    );
    assert_eq!(std::fs::read_dir(t.dir()).unwrap().count(), 0);
}

#[test]
fn a_point_cloud_given_to_convert_is_refused_with_the_command_that_reads_it() {
    let t = TestCommand::new();
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    std::fs::write(t.path("points.ply"), ply).unwrap();
    let run = t.run(&["convert", "points.ply", "-o", "points.spatch"]);
    run.assert_one_clear_line("points.ply");
    assert!(run.stderr.contains("no faces"), "{}", run.stderr);
    assert!(run.stderr.contains("spatch from-cloud"), "{}", run.stderr);
    assert!(!t.path("points.spatch").exists());
}
