//! The viewer's camera: an eye orbiting a target, with pan and zoom, the
//! six axis views and the automatic camera to reset to.
//!
//! The state is an eye, a target and a unit up vector orthogonal to the
//! view direction. Orbiting turns the eye about the target: a horizontal
//! drag about the camera's up axis, a vertical one about its right axis
//! (the up vector turns with it, so the camera can go over the poles).
//! Panning moves eye and target together in the image plane so that the
//! point at the target's depth follows the cursor; zooming scales the
//! eye's distance to the target.

use glam::{DQuat, DVec3};
use spatch_render::Camera;

/// Radians of orbit per pixel of drag (a drag across 1000 px turns ~290°).
pub const ORBIT_RADIANS_PER_PIXEL: f64 = 0.005;
/// Factor of the eye's distance per wheel notch towards the target.
pub const ZOOM_PER_STEP: f64 = 0.9;

/// One of the six axis views: the eye sits on that side of the target
/// and looks down the opposite direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Eye on +x, looking down -x (key 1).
    PosX,
    /// Eye on -x, looking down +x (key 2).
    NegX,
    /// Eye on +y, looking down -y, -z up on screen (key 3).
    PosY,
    /// Eye on -y, looking down +y, +z up on screen (key 4).
    NegY,
    /// Eye on +z, looking down -z (key 5).
    PosZ,
    /// Eye on -z, looking down +z (key 6).
    NegZ,
}

impl Axis {
    /// The axis of number key `k` (1..=6).
    pub fn of_key(k: u8) -> Option<Axis> {
        [
            Axis::PosX,
            Axis::NegX,
            Axis::PosY,
            Axis::NegY,
            Axis::PosZ,
            Axis::NegZ,
        ]
        .get(usize::from(k).wrapping_sub(1))
        .copied()
    }

    /// Unit vector from the target to the eye.
    pub fn eye_direction(self) -> DVec3 {
        match self {
            Axis::PosX => DVec3::X,
            Axis::NegX => DVec3::NEG_X,
            Axis::PosY => DVec3::Y,
            Axis::NegY => DVec3::NEG_Y,
            Axis::PosZ => DVec3::Z,
            Axis::NegZ => DVec3::NEG_Z,
        }
    }

    /// The up vector of the view: +y, except for the views along y.
    pub fn up(self) -> DVec3 {
        match self {
            Axis::PosY => DVec3::NEG_Z,
            Axis::NegY => DVec3::Z,
            _ => DVec3::Y,
        }
    }
}

/// Eye, target, up and field of view of the viewer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The eye position.
    pub eye: DVec3,
    /// The point looked at and orbited.
    pub target: DVec3,
    /// Unit up vector, orthogonal to `target - eye`.
    pub up: DVec3,
    /// Vertical field of view, degrees.
    pub fov_y_degrees: f64,
}

impl Orbit {
    /// The orbit of a camera (its up vector made orthogonal and unit).
    pub fn of_camera(camera: &Camera) -> Orbit {
        let forward = (camera.target() - camera.eye()).normalize();
        let right = forward.cross(camera.up()).normalize();
        Orbit {
            eye: camera.eye(),
            target: camera.target(),
            up: right.cross(forward),
            fov_y_degrees: camera.fov_y_degrees(),
        }
    }

    /// Distance from the eye to the target.
    pub fn distance(&self) -> f64 {
        (self.eye - self.target).length()
    }

    /// Unit view direction, eye to target.
    pub fn forward(&self) -> DVec3 {
        (self.target - self.eye).normalize()
    }

    /// Unit right vector of the image.
    pub fn right(&self) -> DVec3 {
        self.forward().cross(self.up).normalize()
    }

    /// Turns the eye about the target by a drag of `dx, dy` pixels (right
    /// and down positive): dragging right turns the scene right.
    pub fn orbit(&mut self, dx: f64, dy: f64) {
        let yaw = DQuat::from_axis_angle(self.up, -dx * ORBIT_RADIANS_PER_PIXEL);
        let pitch = DQuat::from_axis_angle(self.right(), -dy * ORBIT_RADIANS_PER_PIXEL);
        let turn = pitch * yaw;
        let offset = turn * (self.eye - self.target);
        self.eye = self.target + offset;
        self.up = self.orthogonal_up(turn * self.up);
    }

    /// Moves eye and target by a drag of `dx, dy` pixels (right and down
    /// positive) in an image `height` pixels tall: the scene follows the
    /// cursor at the target's depth.
    pub fn pan(&mut self, dx: f64, dy: f64, height: u32) {
        let half = (self.fov_y_degrees.to_radians() / 2.0).tan();
        let per_pixel = 2.0 * half * self.distance() / f64::from(height.max(1));
        let shift = (self.right() * -dx + self.up * dy) * per_pixel;
        self.eye += shift;
        self.target += shift;
    }

    /// Moves the eye `steps` wheel notches towards the target (negative:
    /// away); each notch scales the distance by [`ZOOM_PER_STEP`].
    pub fn zoom(&mut self, steps: f64) {
        let factor = ZOOM_PER_STEP.powf(steps);
        let offset = (self.eye - self.target) * factor;
        // Keep the eye off the target (the camera needs a direction).
        let floor = 1e-9 * (1.0 + self.target.length());
        if offset.length() > floor {
            self.eye = self.target + offset;
        }
    }

    /// Looks at the target along an axis, keeping the distance.
    pub fn axis_view(&mut self, axis: Axis) {
        self.eye = self.target + axis.eye_direction() * self.distance();
        self.up = axis.up();
    }

    /// `up` made unit and orthogonal to the view direction (rounding drift).
    fn orthogonal_up(&self, up: DVec3) -> DVec3 {
        let forward = self.forward();
        (up - forward * up.dot(forward)).normalize()
    }
}
