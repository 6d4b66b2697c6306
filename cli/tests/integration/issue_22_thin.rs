//! Issue 22 item 4 from the user's side: a thin mesh converts to patches, a mesh no spacing
//! can sample is refused naming `--spacing` (exit 2, no output), and a cube with every other
//! triangle wound the wrong way converts to the clean cube's file (the converter rewinds it),
//! or, with `--keep-winding`, with a warning about its error.

use crate::test_command::TestCommand;

/// A unit cube of 12 triangles; `flip` winds every other triangle the wrong way.
fn cube_obj(flip: bool) -> String {
    let mut text = String::new();
    for v in [
        [0, 0, 0],
        [1, 0, 0],
        [1, 1, 0],
        [0, 1, 0],
        [0, 0, 1],
        [1, 0, 1],
        [1, 1, 1],
        [0, 1, 1],
    ] {
        text.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2]));
    }
    let faces = [
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    for (k, f) in faces.iter().enumerate() {
        let [a, b, c] = if flip && k % 2 == 0 {
            [f[0], f[2], f[1]]
        } else {
            *f
        };
        text.push_str(&format!("f {} {} {}\n", a + 1, b + 1, c + 1));
    }
    text
}

#[test]
fn a_lone_thin_triangle_converts_to_patches() {
    let t = TestCommand::new();
    std::fs::write(
        t.path("sliver.obj"),
        "v 0 0 0\nv 10 0 0\nv 3 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let run = t
        .run(&["convert", "sliver.obj", "-o", "s.spatch", "--no-error"])
        .success();
    assert!(!run.stdout.contains(": 0 patches"), "{}", run.stdout);
    assert!(t.path("s.spatch").exists());
}

#[test]
fn a_surface_no_spacing_can_sample_is_refused_naming_the_option() {
    let t = TestCommand::new();
    std::fs::write(
        t.path("hair.obj"),
        "v 0 0 0\nv 1 0 0\nv 0.5 1e-7 0\nf 1 2 3\n",
    )
    .unwrap();
    let run = t.run(&["convert", "hair.obj", "-o", "h.spatch"]);
    run.assert_one_clear_line("hair.obj");
    assert!(run.stderr.contains("--spacing"), "{}", run.stderr);
    assert!(!t.path("h.spatch").exists());
}

#[test]
fn a_cube_with_flipped_triangles_is_rewound_or_warns_about_its_error() {
    let t = TestCommand::new();
    std::fs::write(t.path("flipped.obj"), cube_obj(true)).unwrap();
    std::fs::write(t.path("cube.obj"), cube_obj(false)).unwrap();
    let clean = t.run(&["convert", "cube.obj", "-o", "c.spatch"]).success();
    assert!(!clean.stdout.contains("error budget"), "{}", clean.stdout);
    let rewound = t
        .run(&["convert", "flipped.obj", "-o", "f.spatch"])
        .success();
    assert!(
        rewound
            .stdout
            .contains("winding: 6 of 12 faces turned over"),
        "{}",
        rewound.stdout
    );
    assert!(
        !rewound.stdout.contains("error budget"),
        "{}",
        rewound.stdout
    );
    // Half its faces were wound wrong, not most: the very file of the clean cube.
    let read = |name: &str| std::fs::read(t.path(name)).unwrap();
    assert!(
        read("f.spatch") == read("c.spatch"),
        "the rewound cube differs"
    );
    let kept = t
        .run(&["convert", "flipped.obj", "-o", "k.spatch", "--keep-winding"])
        .success();
    assert!(
        kept.stdout.contains("times the error budget"),
        "{}",
        kept.stdout
    );
}
