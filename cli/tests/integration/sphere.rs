use spatch_format::read_scene;

use crate::test_command::TestCommand;

#[test]
fn default_sphere_meets_the_original_budget_and_bounds() {
    let t = TestCommand::new();
    let run = t.run(&["sphere", "-o", "sphere.spatch"]).success();
    assert!(run.stdout.contains("no gaps"), "{}", run.stdout);
    let bytes = std::fs::metadata(t.path("sphere.spatch")).unwrap().len();
    assert!(bytes < 450_560, "{bytes} bytes");
    let scene = read_scene(&t.path("sphere.spatch")).unwrap();
    assert_eq!(scene.patches().len(), 1362);
    for patch in scene.patches() {
        for (_, _, p) in patch.filled_nodes() {
            let r = (scene.offset() + p.as_dvec3()).length();
            assert!((r - 128.0).abs() <= 0.0051, "node at radius {r}");
        }
    }
}

#[test]
fn output_is_byte_identical_for_one_and_two_threads() {
    let t = TestCommand::new();
    for (threads, name) in [("1", "one.spatch"), ("2", "two.spatch")] {
        t.run_with_env(
            &["sphere", "--compress", "-o", name],
            &[("RAYON_NUM_THREADS", threads)],
        )
        .success();
    }
    assert_eq!(
        std::fs::read(t.path("one.spatch")).unwrap(),
        std::fs::read(t.path("two.spatch")).unwrap()
    );
}

#[test]
fn options_change_the_sphere_and_bad_options_are_refused() {
    let t = TestCommand::new();
    t.small_sphere("small.spatch");
    let scene = read_scene(&t.path("small.spatch")).unwrap();
    assert_eq!(scene.patches().len(), 200);
    assert_eq!(scene.patches()[0].grid().cols(), 9);
    let run = t.run(&["sphere", "--grid", "300", "-o", "bad.spatch"]);
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.starts_with("spatch: error: invalid --grid"),
        "{}",
        run.stderr
    );
    assert!(!t.path("bad.spatch").exists());
}

#[test]
fn too_few_patches_are_reported_as_gaps() {
    let t = TestCommand::new();
    let run = t
        .run(&["sphere", "--patches", "100", "-o", "sparse.spatch"])
        .success();
    assert!(run.stdout.contains("GAPS"), "{}", run.stdout);
}
