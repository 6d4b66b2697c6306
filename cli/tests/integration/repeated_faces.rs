//! `spatch convert` drops faces that repeat an earlier face's three vertices: a source listing
//! faces twice converts to the very file of the clean source; a two-sided export (each face
//! followed by a twin wound the other way) to the clean source's patches, all drawn from both
//! sides whichever copy comes first; a decimated scan's fins (a face and its mirrored twin
//! hanging off the surface by one edge) stay as they are.

use spatch_fixtures::shapes::{uv_sphere, Shape};
use spatch_format::{read_scene, Sides};

use crate::test_command::TestCommand;
use crate::winding::{convert_shape, same_patches_with_b_two_sided};

/// `shape` with the faces `repeat` picks (by index) listed once more after all faces, wound
/// the other way when `mirrored`.
fn with_repeats(shape: &Shape, repeat: impl Fn(usize) -> bool, mirrored: bool) -> Shape {
    let mut out = shape.clone();
    for (f, t) in shape.triangles.iter().enumerate() {
        if repeat(f) {
            out.triangles
                .push(if mirrored { [t[0], t[2], t[1]] } else { *t });
        }
    }
    out
}

/// Converts `shape` (written as `name.ply`); returns the file's bytes and the report's
/// `details.prepare`.
fn convert(t: &TestCommand, name: &str, shape: &Shape) -> (Vec<u8>, serde_json::Value) {
    let (bytes, details) = convert_shape(t, name, shape, &[]);
    (bytes, details["prepare"].clone())
}

#[test]
fn repeated_faces_convert_to_the_clean_file() {
    let t = TestCommand::new();
    let sphere = uv_sphere(1.0, 32, 16);
    let faces = sphere.triangles.len();
    let (clean, prepared) = convert(&t, "clean", &sphere);
    assert_eq!(prepared["dropped_duplicate"], 0);
    let (twice, prepared) = convert(&t, "twice", &with_repeats(&sphere, |_| true, false));
    assert_eq!(prepared["dropped_duplicate"], faces);
    assert_eq!(prepared["dropped_mirrored"], 0);
    assert!(twice == clean, "every face twice gave another file");
    let some = with_repeats(&sphere, |f| f % 7 == 3, false);
    let (some, prepared) = convert(&t, "some", &some);
    assert_eq!(
        prepared["dropped_duplicate"],
        (0..faces).filter(|f| f % 7 == 3).count()
    );
    assert!(
        some == clean,
        "a seventh of the faces twice gave another file"
    );
}

#[test]
fn two_sided_exports_are_drawn_from_both_sides() {
    let t = TestCommand::new();
    let sphere = uv_sphere(1.0, 32, 16);
    let faces = sphere.triangles.len();
    convert(&t, "clean", &sphere);
    let (_, prepared) = convert(&t, "two", &with_repeats(&sphere, |_| true, true));
    assert_eq!(prepared["dropped_duplicate"], faces);
    assert_eq!(prepared["dropped_mirrored"], faces);
    same_patches_with_b_two_sided(&t, "clean.spatch", "two.spatch");

    // The inward copy first: still every patch two-sided.
    let mirror_first = Shape {
        triangles: with_repeats(&sphere, |_| true, true).triangles[faces..].to_vec(),
        ..sphere.clone()
    };
    let both = with_repeats(&mirror_first, |_| true, true);
    convert(&t, "mirror_first", &both);
    let scene = read_scene(&t.path("mirror_first.spatch")).unwrap();
    assert!(!scene.patches().is_empty());
    assert!(scene.patches().iter().all(|p| p.sides() == Sides::Both));
    // Wound outward, with a box: from outside it culled as a closed surface.
    assert!(scene.inside_box().is_some());
    // With --keep-winding the kept copies face either way: two-sided everywhere, no box.
    let ply = "mirror_first.ply";
    t.run(&[
        "convert",
        ply,
        "-o",
        "kept.spatch",
        "-q",
        "--no-error",
        "--keep-winding",
    ])
    .success();
    let scene = read_scene(&t.path("kept.spatch")).unwrap();
    assert!(scene.patches().iter().all(|p| p.sides() == Sides::Both));
    assert_eq!(scene.inside_box(), None);

    // A few mirrored twins (a seam modelled two-sided) leave the rest culled.
    let (_, prepared) = convert(&t, "few", &with_repeats(&sphere, |f| f % 9 == 0, true));
    assert_eq!(
        prepared["dropped_mirrored"],
        (0..faces).filter(|f| f % 9 == 0).count()
    );
    let scene = read_scene(&t.path("few.spatch")).unwrap();
    assert!(scene.patches().iter().all(|p| p.sides() == Sides::Front));
}

#[test]
fn a_decimated_scans_fins_stay_and_open_nothing() {
    let Some(path) = spatch_fixtures::shared_data("bunny/reconstruction/bun_zipper_res2.ply")
    else {
        eprintln!("skipped: ../shared/data/bunny/reconstruction/bun_zipper_res2.ply is missing");
        return;
    };
    let t = TestCommand::new();
    let path = path.to_string_lossy().into_owned();
    let args = [
        "convert",
        &path,
        "-o",
        "r.spatch",
        "-q",
        "--no-error",
        "--report",
        "r.json",
    ];
    t.run(&args).success();
    let details = &t.json::<serde_json::Value>("r.json")["details"];
    let prepared = &details["prepare"];
    // 87 repeats: 75 in fins (dropping a twin would open the fin), 12 inside the surface.
    assert_eq!(prepared["kept_repeats"], 75, "{prepared}");
    assert_eq!(prepared["dropped_duplicate"], 12, "{prepared}");
    // The openings are the scan's own five, as before repeats were looked for.
    assert_eq!(details["sides"]["openings"], 5, "{}", details["sides"]);
}
