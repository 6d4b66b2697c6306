//! Degenerate cameras and options are refused with a typed error.

use glam::DVec3;
use spatch_render::{Camera, CameraProblem, RenderError, RenderOptions, Renderer};

use crate::common::{prepared_sphere, sphere_scene};

#[test]
fn degenerate_cameras_are_refused() {
    let e = DVec3::new(1.0, 2.0, 3.0);
    assert_eq!(
        Camera::look_at(e, e, DVec3::Y, 45.0, 10, 10),
        Err(CameraProblem::EyeIsTarget)
    );
    assert_eq!(
        Camera::look_at(e, DVec3::ZERO, e, 45.0, 10, 10),
        Err(CameraProblem::UpParallelToView)
    );
    assert_eq!(
        Camera::look_at(e, DVec3::ZERO, DVec3::Y, 0.0, 10, 10),
        Err(CameraProblem::FieldOfView)
    );
    assert!(matches!(
        Camera::look_at(e, DVec3::ZERO, DVec3::Y, 45.0, 10, 0),
        Err(CameraProblem::ImageSize { .. })
    ));
    assert!(matches!(
        Camera::look_at(e, DVec3::ZERO, DVec3::Y, 45.0, 9000, 10),
        Err(CameraProblem::ImageSize { .. })
    ));
}

#[test]
fn bad_options_are_refused() {
    let mut o = RenderOptions::default();
    o.ssaa = 0;
    assert!(matches!(
        Renderer::new(o),
        Err(RenderError::InvalidOption { name: "ssaa", .. })
    ));
    let mut o = RenderOptions::default();
    o.guard_band = f32::NAN;
    assert!(Renderer::new(o).is_err());
    // Supersampling beyond the largest internal image is refused at render time.
    let mut o = RenderOptions::default();
    o.ssaa = 4;
    let camera = Camera::look_at(DVec3::Z * 500.0, DVec3::ZERO, DVec3::Y, 45.0, 4000, 100).unwrap();
    assert!(matches!(
        Renderer::new(o).unwrap().render(prepared_sphere(), &camera),
        Err(RenderError::InvalidCamera(CameraProblem::ImageSize { .. }))
    ));
}

#[test]
fn the_automatic_camera_frames_the_whole_sphere() {
    let camera = prepared_sphere().auto_camera(300, 200).unwrap();
    let out = spatch_render::render(sphere_scene(), &camera, &RenderOptions::default()).unwrap();
    let image = &out.image;
    // Nothing touches the border, and the sphere fills most of the height.
    for x in 0..300 {
        assert!(!image.is_covered(x, 0) && !image.is_covered(x, 199));
    }
    for y in 0..200 {
        assert!(!image.is_covered(0, y) && !image.is_covered(299, y));
    }
    let rows = (0..200)
        .filter(|&y| (0..300).any(|x| image.is_covered(x, y)))
        .count();
    assert!(rows > 160, "{rows}");
}
