//! The camera as `spatch render` flags, and the camera those flags make.
//!
//! The printed numbers are rounded; so that a PNG rendered from the printed
//! flags equals the viewer's frame pixel for pixel, the viewer renders with
//! the rounded camera itself: [`CameraLine::new`] formats the numbers and
//! parses them back the way `spatch render` does.

use glam::DVec3;
use spatch_render::{Camera, CameraProblem};

use crate::orbit::Orbit;

/// Decimals of the up vector's components.
const UP_DECIMALS: usize = 6;
/// Decimals of the field of view, degrees.
const FOV_DECIMALS: usize = 4;
/// Positions are rounded to this fraction of the scene's radius.
const POSITION_STEP: f64 = 1e-6;

/// The decimals of positions in a scene of bounding radius `radius`: a
/// step of at most 1e-6 · radius.
pub fn position_decimals(radius: f64) -> usize {
    if !(radius.is_finite() && radius > 0.0) {
        return 6;
    }
    let decimals = -(radius * POSITION_STEP).log10();
    decimals.ceil().clamp(0.0, 15.0) as usize
}

/// A camera and its flags.
#[derive(Debug, Clone)]
pub struct CameraLine {
    /// `--eye x,y,z --target x,y,z --up x,y,z --fov f`.
    pub flags: String,
    /// The camera those flags give `spatch render` at this size.
    pub camera: Camera,
}

impl CameraLine {
    /// The rounded camera of `orbit` at `width × height` with positions to
    /// `decimals` places.
    pub fn new(
        orbit: &Orbit,
        decimals: usize,
        width: u32,
        height: u32,
    ) -> Result<CameraLine, CameraProblem> {
        let (eye_text, eye) = rounded(orbit.eye, decimals);
        let (target_text, target) = rounded(orbit.target, decimals);
        let (up_text, up) = rounded(orbit.up, UP_DECIMALS);
        let fov_text = tidy(format!("{:.*}", FOV_DECIMALS, orbit.fov_y_degrees));
        let fov = parse(&fov_text);
        let camera = Camera::look_at(eye, target, up, fov, width, height)?;
        Ok(CameraLine {
            flags: format!(
                "--eye {eye_text} --target {target_text} --up {up_text} --fov {fov_text}"
            ),
            camera,
        })
    }
}

/// `v` as `x,y,z` with `decimals` places, and the vector that text reads as.
fn rounded(v: DVec3, decimals: usize) -> (String, DVec3) {
    let parts: Vec<String> = v
        .to_array()
        .iter()
        .map(|c| tidy(format!("{c:.decimals$}")))
        .collect();
    let back = DVec3::new(parse(&parts[0]), parse(&parts[1]), parse(&parts[2]));
    (parts.join(","), back)
}

/// Trailing zeros (and a bare point) dropped, `-0` as `0`: the same number,
/// shorter.
fn tidy(mut text: String) -> String {
    if text.contains('.') {
        while text.ends_with('0') {
            text.pop();
        }
        if text.ends_with('.') {
            text.pop();
        }
    }
    if text == "-0" {
        text = "0".into();
    }
    text
}

/// A number this module formatted (always valid).
fn parse(text: &str) -> f64 {
    text.parse().unwrap_or(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_follow_the_scene_size() {
        assert_eq!(position_decimals(1.0), 6);
        assert_eq!(position_decimals(0.08), 8);
        assert_eq!(position_decimals(1000.0), 3);
        assert_eq!(position_decimals(5e9), 0);
    }

    #[test]
    fn printed_numbers_read_back_as_the_camera() {
        let orbit = Orbit {
            eye: DVec3::new(0.123_456_789, -2.0, 1e-9),
            target: DVec3::new(-0.5, 0.0, 0.25),
            up: DVec3::new(0.0, 0.999_999_9, 0.000_447_2),
            fov_y_degrees: 40.0,
        };
        let line = CameraLine::new(&orbit, 6, 640, 480).unwrap();
        assert_eq!(
            line.flags,
            "--eye 0.123457,-2,0 --target -0.5,0,0.25 --up 0,1,0.000447 --fov 40"
        );
        assert_eq!(line.camera.eye(), DVec3::new(0.123457, -2.0, 0.0));
        assert_eq!(line.camera.up(), DVec3::new(0.0, 1.0, 0.000447));
        assert_eq!((line.camera.width(), line.camera.height()), (640, 480));
    }
}
