use spatch_format::read_scene;

use crate::test_command::TestCommand;

#[test]
fn merged_patch_counts_add_up() {
    let t = TestCommand::new();
    t.small_sphere("a.spatch");
    t.run(&[
        "sphere",
        "--radius",
        "3",
        "--patches",
        "50",
        "--grid",
        "5",
        "--step",
        "0.001",
        "-o",
        "b.spatch",
    ])
    .success();
    let run = t
        .run(&["merge", "a.spatch", "b.spatch", "-o", "ab.spatch"])
        .success();
    assert!(
        run.stdout.contains("250 patches (200 + 50)"),
        "{}",
        run.stdout
    );
    let merged = read_scene(&t.path("ab.spatch")).unwrap();
    assert_eq!(merged.patches().len(), 250);
    let grids: std::collections::BTreeSet<u16> =
        merged.patches().iter().map(|p| p.grid().cols()).collect();
    assert_eq!(grids.into_iter().collect::<Vec<_>>(), vec![5, 9]);
}

#[test]
fn merge_needs_two_inputs_and_names_a_bad_one() {
    let t = TestCommand::new();
    t.small_sphere("a.spatch");
    assert_eq!(t.run(&["merge", "a.spatch", "-o", "x.spatch"]).code, 2);
    std::fs::write(t.path("junk.spatch"), b"not a scene").unwrap();
    let run = t.run(&["merge", "a.spatch", "junk.spatch", "-o", "x.spatch"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("junk.spatch"), "{}", run.stderr);
    assert!(!t.path("x.spatch").exists());
}
