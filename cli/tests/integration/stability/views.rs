//! Extreme views of converted and hand-made scenes render without panics and without
//! anything from behind the eye.

use glam::{DVec3, Vec3};
use spatch_fixtures::shapes;
use spatch_format::{read_scene, ColourChannel, Frame, GridSize, Patch, Scene};
use spatch_render::{Camera, Culling, PreparedScene, RenderOptions, Renderer};

use super::convert_report;
use crate::test_command::TestCommand;

/// A converted icosphere of radius 1 at the origin, ready to render.
fn converted_ball() -> PreparedScene {
    let t = TestCommand::new();
    std::fs::write(
        t.path("ball.obj"),
        shapes::icosphere(1.0, 4).to_obj([0.0; 3]),
    )
    .unwrap();
    convert_report(&t, "ball.obj", &["--no-error"]);
    PreparedScene::new(&read_scene(&t.path("out.spatch")).unwrap())
}

fn render(
    scene: &PreparedScene,
    camera: &Camera,
    culling: Culling,
) -> spatch_render::RenderedImage {
    let mut options = RenderOptions::default();
    options.culling = culling;
    render_with(scene, camera, options)
}

fn render_with(
    scene: &PreparedScene,
    camera: &Camera,
    options: RenderOptions,
) -> spatch_render::RenderedImage {
    Renderer::new(options)
        .unwrap()
        .render(scene, camera)
        .unwrap()
        .image
}

/// A flat 17 × 17 patch seen from a point in its own plane projects to a line: at most the
/// two pixel rows around the horizon are drawn, every drawn depth is finite and positive.
#[test]
fn a_patch_seen_exactly_edge_on() {
    let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01).unwrap();
    let patch = Patch::new(
        frame,
        GridSize::new(17, 17).unwrap(),
        vec![0; 17 * 17],
        None,
    )
    .unwrap();
    let scene =
        PreparedScene::new(&Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch]).unwrap());
    let eye = DVec3::new(8.0, -40.0, 0.0);
    let camera = Camera::look_at(eye, DVec3::new(8.0, 8.0, 0.0), DVec3::Z, 40.0, 200, 200).unwrap();
    for culling in [Culling::None, Culling::Back] {
        let image = render(&scene, &camera, culling);
        assert!(
            image.covered_count() <= 2 * 200,
            "{culling:?}: {} pixels drawn for a patch seen edge-on",
            image.covered_count()
        );
        for &d in image.depth().iter().filter(|d| d.is_finite()) {
            assert!(d > 0.0, "{culling:?}: depth {d}");
        }
    }
}

/// The eye inside a converted ball, near its wall and looking at it (the near plane cuts
/// the closest patches; the rest of the ball lies behind the eye): the inside fills the
/// view (but for seams between patches, magnified this close: under 1 % of the pixels), at
/// depths between the near plane and the far wall, never behind the eye.
#[test]
fn patches_crossing_the_near_plane_and_behind_the_eye() {
    let ball = converted_ball();
    for (eye, target) in [
        (DVec3::new(0.0, 0.0, 0.9), DVec3::new(0.0, 0.0, 2.0)),
        (DVec3::new(0.0, 0.0, 0.99), DVec3::new(1.0, 0.0, 0.99)),
    ] {
        let camera = Camera::look_at(eye, target, DVec3::Y, 60.0, 160, 120).unwrap();
        let image = render(&ball, &camera, Culling::None);
        assert!(
            image.covered_count() * 100 >= 160 * 120 * 99,
            "eye {eye}: {} of {} pixels",
            image.covered_count(),
            160 * 120
        );
        for &d in image.depth().iter().filter(|d| d.is_finite()) {
            assert!(
                f64::from(d) >= image.near() * 0.999 && d <= 2.0,
                "eye {eye}: depth {d} (near {})",
                image.near()
            );
        }
    }
    // Outside, 0.2 above the surface and looking at the centre, the near plane at 0.25: it
    // cuts the cap of the ball nearer than that (z > 0.95) out of the middle of the view.
    // The ring around is drawn, nothing nearer than the plane, and the middle is empty.
    let eye = DVec3::new(0.0, 0.0, 1.2);
    let camera = Camera::look_at(eye, DVec3::ZERO, DVec3::Y, 90.0, 160, 120)
        .unwrap()
        .with_clip_planes(Some(0.25), Some(3.0))
        .unwrap();
    let image = render(&ball, &camera, Culling::Back);
    assert!(image.covered_count() > 1000, "{}", image.covered_count());
    assert!(!image.is_covered(80, 60), "the cut cap is drawn");
    for &d in image.depth().iter().filter(|d| d.is_finite()) {
        assert!(
            f64::from(d) >= image.near() * 0.999,
            "depth {d} (near {})",
            image.near()
        );
    }
}

/// The eye at the centre of a converted ball: every pixel sees the inside at about the
/// radius (eye depth between R·cos(half diagonal field of view) and R). Every pixel by
/// default; with the gap fill, whose sparser lattice can leave a gap its pass does not close
/// where two patches meet, all but one pixel in five thousand.
#[test]
fn a_camera_inside_the_model() {
    let ball = converted_ball();
    let camera = Camera::look_at(
        DVec3::ZERO,
        DVec3::new(1.0, 0.3, 0.2),
        DVec3::Y,
        50.0,
        160,
        120,
    )
    .unwrap();
    let mut options = RenderOptions::default();
    options.culling = Culling::None;
    let image = render_with(&ball, &camera, options);
    assert_eq!(image.covered_count(), 160 * 120);
    options.gap_fill = true;
    let filled = render_with(&ball, &camera, options);
    assert!(filled.covered_count() * 5000 >= 160 * 120 * 4999);
    for image in [image, filled] {
        for &d in image.depth().iter().filter(|d| d.is_finite()) {
            assert!(d > 0.6 && d <= 1.01, "depth {d}");
        }
    }
}
