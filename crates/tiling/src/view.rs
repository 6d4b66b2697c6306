//! Which boxes a camera can see: a conservative test of a box against the view pyramid
//! (its four side planes and the plane through the eye), so a tiled scene's viewer loads
//! only tiles that may be drawn.
//!
//! A box is dropped only when all eight corners lie outside one plane; a box that straddles
//! a pyramid edge from outside is kept (a few extra tiles, never a missing one).

use glam::DVec3;

use crate::plan::WorldBox;

/// A perspective camera's view pyramid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewPyramid {
    eye: DVec3,
    forward: DVec3,
    right: DVec3,
    up: DVec3,
    tan_x: f64,
    tan_y: f64,
    far: Option<f64>,
}

impl ViewPyramid {
    /// The pyramid of a camera at `eye` looking at `target` with `up`, a vertical field of
    /// view of `fov_y_degrees` and an image `width × height`, optionally cut at `far`;
    /// `None` when eye and target coincide or `up` is along the view.
    pub fn new(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_y_degrees: f64,
        (width, height): (u32, u32),
        far: Option<f64>,
    ) -> Option<ViewPyramid> {
        let forward = (target - eye).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        let tan_y = (fov_y_degrees.to_radians() / 2.0).tan();
        Some(ViewPyramid {
            eye,
            forward,
            right,
            up: right.cross(forward),
            tan_x: tan_y * f64::from(width) / f64::from(height.max(1)),
            tan_y,
            far,
        })
    }

    /// Whether a point at view coordinates `l` (right, up, forward) is inside `plane`: the
    /// eye's plane, the four sides, the far plane.
    fn inside(&self, plane: usize, l: &[f64; 3]) -> bool {
        match plane {
            0 => l[2] >= 0.0,
            1 => l[0] <= l[2] * self.tan_x,
            2 => -l[0] <= l[2] * self.tan_x,
            3 => l[1] <= l[2] * self.tan_y,
            4 => -l[1] <= l[2] * self.tan_y,
            _ => self.far.is_none_or(|f| l[2] <= f),
        }
    }

    /// Whether any part of `b` may be in view (see the module documentation).
    pub fn may_see(&self, b: &WorldBox) -> bool {
        let corners: Vec<DVec3> = (0..8)
            .map(|c| {
                DVec3::new(
                    if c & 1 == 0 { b.min[0] } else { b.max[0] },
                    if c & 2 == 0 { b.min[1] } else { b.max[1] },
                    if c & 4 == 0 { b.min[2] } else { b.max[2] },
                )
            })
            .collect();
        let local: Vec<[f64; 3]> = corners
            .iter()
            .map(|&p| {
                let d = p - self.eye;
                [d.dot(self.right), d.dot(self.up), d.dot(self.forward)]
            })
            .collect();
        // Out of view when every corner is outside one of the six planes.
        (0..6).all(|plane| local.iter().any(|l| self.inside(plane, l)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box_at(x: f64, y: f64, z: f64) -> WorldBox {
        WorldBox::new(DVec3::new(x, y, z), DVec3::new(x + 1.0, y + 1.0, z + 1.0))
    }

    #[test]
    fn boxes_ahead_are_seen_and_behind_or_aside_are_not() {
        let view = ViewPyramid::new(
            DVec3::ZERO,
            DVec3::new(0.0, 10.0, 0.0),
            DVec3::Z,
            60.0,
            (100, 100),
            None,
        )
        .unwrap();
        assert!(view.may_see(&unit_box_at(-0.5, 10.0, -0.5)));
        // Behind the eye.
        assert!(!view.may_see(&unit_box_at(-0.5, -10.0, -0.5)));
        // Far to the side: at y = 10 the half width is 10 tan 30° ≈ 5.8.
        assert!(!view.may_see(&unit_box_at(20.0, 10.0, -0.5)));
        assert!(view.may_see(&unit_box_at(5.0, 10.0, -0.5)));
        // Straddling the eye.
        assert!(view.may_see(&unit_box_at(-0.5, -0.5, -0.5)));
        let near = ViewPyramid::new(DVec3::ZERO, DVec3::Y, DVec3::Z, 60.0, (100, 100), Some(5.0));
        assert!(!near.unwrap().may_see(&unit_box_at(-0.5, 10.0, -0.5)));
    }
}
