//! Golden images: small renders pinned pixel for pixel (issue 21, item 4).
//!
//! Each case makes a scene with `spatch` (the sphere, Spot from `spatch demo`, or a generated
//! shape converted from OBJ), renders it with `spatch render` and compares the decoded RGBA
//! pixels with `testdata/golden/render/<case>.png` exactly. The reason for every case is in
//! `testdata/golden/README.md`.
//!
//! On a mismatch the actual image and a difference image (red where a pixel differs, its
//! brightness the largest channel difference, at least 64) are written to
//! `target/golden-mismatch/` and the assertion names them. `SPATCH_BLESS=1` rewrites the
//! references on purpose instead of comparing; every deliberate change gets its reason in
//! docs/algorithms/render.md.

use std::path::{Path, PathBuf};

use spatch_fixtures::shapes::{self, Shape};

use crate::test_command::TestCommand;

/// Side of the square golden renders.
const SIDE: &str = "96";

/// `testdata/golden/render` of the workspace.
fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/golden/render")
}

/// `target/golden-mismatch` (the integration tests' temporary folder is `target/tmp`).
fn mismatch_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("target/tmp has a parent")
        .join("golden-mismatch")
}

/// A difference image: red where pixels differ, black where they agree.
fn difference(actual: &image::RgbaImage, expected: &image::RgbaImage) -> image::RgbaImage {
    image::RgbaImage::from_fn(actual.width(), actual.height(), |x, y| {
        let (a, e) = (actual.get_pixel(x, y).0, expected.get_pixel(x, y).0);
        let d = (0..4).map(|k| a[k].abs_diff(e[k])).max().unwrap_or(0);
        match d {
            0 => image::Rgba([0, 0, 0, 255]),
            d => image::Rgba([d.max(64), 0, 0, 255]),
        }
    })
}

/// Compares the PNG `rendered` with the golden image of `case` (or rewrites it when
/// `SPATCH_BLESS=1`).
fn check_golden(case: &str, rendered: &Path) {
    let actual = image::open(rendered)
        .unwrap_or_else(|e| panic!("{case}: {} does not decode: {e}", rendered.display()))
        .to_rgba8();
    let reference = golden_dir().join(format!("{case}.png"));
    if std::env::var_os("SPATCH_BLESS").is_some_and(|v| v == "1") {
        std::fs::create_dir_all(golden_dir()).unwrap();
        actual.save(&reference).unwrap();
        return;
    }
    let expected = image::open(&reference)
        .unwrap_or_else(|e| {
            panic!(
                "{case}: no golden image {} ({e}); SPATCH_BLESS=1 writes it",
                reference.display()
            )
        })
        .to_rgba8();
    if actual == expected {
        return;
    }
    let out = mismatch_dir();
    std::fs::create_dir_all(&out).unwrap();
    let (actual_path, diff_path) = (
        out.join(format!("{case}.png")),
        out.join(format!("{case}-diff.png")),
    );
    actual.save(&actual_path).unwrap();
    let differing = if actual.dimensions() == expected.dimensions() {
        let diff = difference(&actual, &expected);
        diff.save(&diff_path).unwrap();
        let changed = actual
            .pixels()
            .zip(expected.pixels())
            .filter(|(a, e)| a != e)
            .count();
        format!(
            "{changed} pixels differ, difference in {}",
            diff_path.display()
        )
    } else {
        format!(
            "size {:?} instead of {:?}",
            actual.dimensions(),
            expected.dimensions()
        )
    };
    panic!(
        "{case}: render differs from {}: {differing}; actual image in {}. If the change is \
         deliberate, rerun with SPATCH_BLESS=1 and give the reason in docs/algorithms/render.md",
        reference.display(),
        actual_path.display()
    );
}

/// Writes `shape` as `name.obj` and converts it with the defaults into `name.spatch`.
fn convert_shape(t: &TestCommand, name: &str, shape: &Shape) -> String {
    let obj = format!("{name}.obj");
    std::fs::write(t.path(&obj), shape.to_obj([0.0; 3])).unwrap();
    let scene = format!("{name}.spatch");
    t.run(&["convert", &obj, "-o", &scene, "--no-error"])
        .success();
    scene
}

/// Renders `scene` at the golden size with `extra` flags and checks it against `case`.
fn render_and_check(t: &TestCommand, case: &str, scene: &str, extra: &[&str]) {
    let png = format!("{case}.png");
    let mut args = vec![
        "render", scene, "-o", &png, "--width", SIDE, "--height", SIDE,
    ];
    args.extend_from_slice(extra);
    t.run(&args).success();
    check_golden(case, &t.path(&png));
}

#[test]
fn the_sphere_in_every_shading_and_both_modes() {
    let t = TestCommand::new();
    let scene = t.small_sphere("sphere.spatch");
    for (case, flags) in [
        ("sphere_phong_patches", &["--shading", "phong"][..]),
        ("sphere_gouraud_patches", &["--shading", "gouraud"][..]),
        ("sphere_flat_patches", &["--shading", "flat"][..]),
        (
            "sphere_phong_triangles",
            &["--shading", "phong", "--mode", "triangles"][..],
        ),
        (
            "sphere_gouraud_triangles",
            &["--shading", "gouraud", "--mode", "triangles"][..],
        ),
    ] {
        render_and_check(&t, case, &scene, flags);
    }
}

/// Runs `spatch demo` into `demo/` at 128² with the texture-blind conversion (texture
/// spacing and colour grids off: Spot with a colour per node).
fn texture_blind_demo(t: &TestCommand) {
    t.run(&[
        "demo",
        "-o",
        "demo",
        "--size",
        "128",
        "--no-error",
        "--texels-per-node",
        "0",
        "--colour-grid",
        "0",
    ])
    .success();
}

#[test]
fn spot_with_its_texture() {
    let t = TestCommand::new();
    // The golden image is the texture-blind conversion (texture spacing and colour grids
    // off).
    texture_blind_demo(&t);
    check_golden("spot_textured", &t.path("demo/spot.png"));
}

/// Flat shading of a coloured scan: each cell's colour from its first corner's albedo, read
/// by the resolve pass from the level's prepared cell normals (the same image as when the
/// planning shaded every node).
#[test]
fn spot_flat_with_its_node_colours() {
    let t = TestCommand::new();
    texture_blind_demo(&t);
    render_and_check(&t, "spot_flat", "demo/spot.spatch", &["--shading", "flat"]);
}

#[test]
fn spot_with_its_colour_grids() {
    // The demo's own conversion: colour grids on, so the pieces cut 4 and
    // more draw by pixel-centre coverage with the grid's margin and their
    // folds by sub-quads (raster/centre_piece.rs).
    let t = TestCommand::new();
    t.run(&["demo", "-o", "demo", "--size", "128", "--no-error"])
        .success();
    check_golden("spot_colour_grid", &t.path("demo/spot.png"));
}

#[test]
fn an_open_tube_seen_into_one_end() {
    let t = TestCommand::new();
    let scene = convert_shape(&t, "tube", &shapes::open_tube(1.0, 3.0, 48, 12));
    // The eye above one end, looking down the tube at a slant: its inside shows.
    let eye = ["--eye", "2.2,1.5,4.5", "--target", "0,0,0"];
    render_and_check(&t, "open_tube_default", &scene, &eye);
    let mut flags = eye.to_vec();
    flags.extend_from_slice(&["--mode", "triangles"]);
    render_and_check(&t, "open_tube_triangles", &scene, &flags);
}

/// Covered pixels of an RGBA PNG (rendered on the default transparent background).
pub(crate) fn covered(path: &Path) -> usize {
    let image = image::open(path).unwrap().to_rgba8();
    image.pixels().filter(|p| p.0[3] > 0).count()
}

#[test]
fn the_tube_inside_shows_with_auto_culling_and_not_with_back() {
    let t = TestCommand::new();
    let scene = convert_shape(&t, "tube", &shapes::open_tube(1.0, 3.0, 48, 12));
    // Straight down the axis: everything seen is the inside.
    let along = [
        "--eye", "0,0,6", "--target", "0,0,0", "--width", "64", "--height", "64",
    ];
    let mut pixels = Vec::new();
    for cull in ["auto", "back", "none"] {
        let png = format!("{cull}.png");
        let mut args = vec!["render", &scene, "-o", &png, "--cull", cull];
        args.extend_from_slice(&along);
        t.run(&args).success();
        pixels.push(covered(&t.path(&png)));
    }
    let [auto, back, none] = [pixels[0], pixels[1], pixels[2]];
    assert!(back * 20 < auto, "back {back}, auto {auto}");
    assert_eq!(auto, none, "auto draws the whole inside");
    assert!(auto > 64 * 64 / 8, "{auto}");
}

#[test]
fn a_concave_crease_in_both_modes() {
    let t = TestCommand::new();
    let scene = convert_shape(&t, "block", &shapes::l_block(1.0));
    // Looking into the inner corner of the L, whose vertical edge is a concave crease.
    let eye = ["--eye", "3.5,3.0,3.2", "--target", "1,1,0.5"];
    render_and_check(&t, "l_block_patches", &scene, &eye);
    let mut flags = eye.to_vec();
    flags.extend_from_slice(&["--mode", "triangles"]);
    render_and_check(&t, "l_block_triangles", &scene, &flags);
}
