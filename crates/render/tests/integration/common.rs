//! Shared set-up: the default perfect sphere (built once) and a camera
//! looking at it from a known position.

use std::sync::OnceLock;

use glam::DVec3;
use spatch_format::Scene;
use spatch_render::{Camera, PreparedScene};

/// Radius of the default perfect sphere.
pub(crate) const RADIUS: f64 = 128.0;

pub(crate) fn sphere_scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| {
        spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())
            .expect("default sphere")
            .scene
    })
}

pub(crate) fn prepared_sphere() -> &'static PreparedScene {
    static PREPARED: OnceLock<PreparedScene> = OnceLock::new();
    PREPARED.get_or_init(|| PreparedScene::new(sphere_scene()))
}

/// The known camera: eye on a skewed axis at `distance` from the centre,
/// 30° vertical field of view, square image of `size`.
pub(crate) fn known_camera(distance: f64, size: u32) -> Camera {
    let dir = known_eye_direction();
    Camera::look_at(dir * distance, DVec3::ZERO, DVec3::Y, 30.0, size, size).expect("camera")
}

/// The unit direction from the centre to the known camera's eye.
pub(crate) fn known_eye_direction() -> DVec3 {
    DVec3::new(0.3, 0.5, 0.8).normalize()
}

/// The analytic silhouette of a sphere of `RADIUS` at the origin seen by
/// `known_camera(distance, size)`: a circle centred on the image centre
/// (the eye looks at the centre) of radius `size/2 · tan(asin(R/D)) /
/// tan(fov/2)` pixels.
pub(crate) fn silhouette_radius_px(distance: f64, size: u32) -> f64 {
    let half = (RADIUS / distance).asin();
    size as f64 / 2.0 * half.tan() / 15f64.to_radians().tan()
}
