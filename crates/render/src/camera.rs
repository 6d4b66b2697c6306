//! The camera: a right-handed OpenGL look-at with a vertical field of view,
//! and its resolution into the matrices the rasterizer uses.
//!
//! Conventions (those of `gluLookAt` + `gluPerspective` + `glViewport`):
//! the eye looks down its -z axis, `up` is projected to the image's +y,
//! normalized device coordinates map to window pixels with `x_w = (x_ndc + 1)
//! · W / 2`, and PNG row 0 is the top of the image (`y_png = (1 - y_ndc) · H /
//! 2`). Pixel `(c, r)` is sampled at its centre `(c + 0.5, r + 0.5)`. A mesh
//! rendered by an OpenGL renderer with the same eye, target, up, field of
//! view and viewport covers the same pixel centres.
//!
//! Depth is the linear eye-space depth `w = -z_eye`; automatic near and far
//! planes enclose the scene's bounding box (near is at least far / 1000).
//!
//! Cost: O(1); all maths in f64, cast to f32 per patch after composing with
//! the patch frame (so far-from-origin models keep their precision).

use glam::{DMat3, DVec3, Mat3, Vec3};

use crate::error::CameraProblem;

/// The largest image side, in pixels after supersampling (fixed-point range).
pub const MAX_IMAGE_SIDE: u32 = 8192;

/// A pinhole camera.
///
/// # Guarantees
/// Finite eye, target and up; eye ≠ target; up not parallel to the view
/// direction; field of view in (0°, 180°); sides in 1..=[`MAX_IMAGE_SIDE`];
/// when given, `0 < near < far`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    eye: DVec3,
    target: DVec3,
    up: DVec3,
    fov_y_degrees: f64,
    near: Option<f64>,
    far: Option<f64>,
    width: u32,
    height: u32,
}

impl Camera {
    /// Default vertical field of view of [`Camera::framing`], degrees.
    pub const DEFAULT_FOV_Y_DEGREES: f64 = 40.0;
    /// Default image width (as the original work).
    pub const DEFAULT_WIDTH: u32 = 500;
    /// Default image height (as the original work).
    pub const DEFAULT_HEIGHT: u32 = 500;
    /// Direction from the target to the eye of the automatic camera: 35°
    /// azimuth to the right of +z and 25° elevation above the xz plane.
    pub const THREE_QUARTER_DIRECTION: [f64; 3] = [0.519_837, 0.422_618, 0.742_404];

    /// The largest eye or target coordinate accepted, in model units (the
    /// message of [`CameraProblem::TooFar`] states it): far
    /// beyond any scene's useful range, and small enough that lengths and
    /// products of coordinates stay finite in `f64`.
    pub const MAX_COORDINATE: f64 = 1e15;

    /// A look-at camera. `fov_y_degrees` is the vertical field of view.
    pub fn look_at(
        eye: DVec3,
        target: DVec3,
        up: DVec3,
        fov_y_degrees: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, CameraProblem> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite() && fov_y_degrees.is_finite()) {
            return Err(CameraProblem::NotFinite);
        }
        let reach = eye.abs().max_element().max(target.abs().max_element());
        if reach > Self::MAX_COORDINATE {
            return Err(CameraProblem::TooFar);
        }
        let forward = target - eye;
        if forward.length() <= 1e-12 * (1.0 + eye.length()) {
            return Err(CameraProblem::EyeIsTarget);
        }
        let side = forward.normalize().cross(up);
        if up.length() == 0.0 || side.length() <= 1e-9 * up.length() {
            return Err(CameraProblem::UpParallelToView);
        }
        if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
            return Err(CameraProblem::FieldOfView);
        }
        check_size(width, height)?;
        Ok(Self {
            eye,
            target,
            up,
            fov_y_degrees,
            near: None,
            far: None,
            width,
            height,
        })
    }

    /// The automatic camera: looks at `centre` from the three-quarter
    /// direction ([`Self::THREE_QUARTER_DIRECTION`], y up) at the distance
    /// where a sphere of `radius` fills the narrower side of the view with a
    /// 5 % margin.
    pub fn framing(
        centre: DVec3,
        radius: f64,
        fov_y_degrees: f64,
        width: u32,
        height: u32,
    ) -> Result<Self, CameraProblem> {
        if !(centre.is_finite() && radius.is_finite()) {
            return Err(CameraProblem::NotFinite);
        }
        if !(fov_y_degrees > 0.0 && fov_y_degrees < 180.0) {
            return Err(CameraProblem::FieldOfView);
        }
        check_size(width, height)?;
        let radius = if radius > 0.0 {
            radius
        } else {
            // A single point: any positive size frames it.
            1e-3 * (1.0 + centre.length())
        };
        let half_y = (fov_y_degrees.to_radians() / 2.0).tan();
        let half_x = half_y * width as f64 / height as f64;
        let half = half_x.min(half_y).atan();
        let distance = radius / half.sin() * 1.05;
        let dir = DVec3::from_array(Self::THREE_QUARTER_DIRECTION).normalize();
        Self::look_at(
            centre + dir * distance,
            centre,
            DVec3::Y,
            fov_y_degrees,
            width,
            height,
        )
    }

    /// Sets (or clears with `None`) the near and far planes; unset planes
    /// are chosen from the scene bounds at render time.
    pub fn with_clip_planes(
        mut self,
        near: Option<f64>,
        far: Option<f64>,
    ) -> Result<Self, CameraProblem> {
        let ok = |v: Option<f64>| v.is_none_or(|v| v.is_finite() && v > 0.0);
        if !(ok(near) && ok(far)) {
            return Err(CameraProblem::ClipPlanes);
        }
        if let (Some(n), Some(f)) = (near, far) {
            if n >= f {
                return Err(CameraProblem::ClipPlanes);
            }
        }
        self.near = near;
        self.far = far;
        Ok(self)
    }

    /// The same camera with another image size.
    pub fn with_size(mut self, width: u32, height: u32) -> Result<Self, CameraProblem> {
        check_size(width, height)?;
        self.width = width;
        self.height = height;
        Ok(self)
    }

    /// The eye position.
    pub fn eye(&self) -> DVec3 {
        self.eye
    }
    /// The point looked at.
    pub fn target(&self) -> DVec3 {
        self.target
    }
    /// The up vector as given.
    pub fn up(&self) -> DVec3 {
        self.up
    }
    /// Vertical field of view in degrees.
    pub fn fov_y_degrees(&self) -> f64 {
        self.fov_y_degrees
    }
    /// The near plane, when set.
    pub fn near(&self) -> Option<f64> {
        self.near
    }
    /// The far plane, when set.
    pub fn far(&self) -> Option<f64> {
        self.far
    }
    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
}

fn check_size(width: u32, height: u32) -> Result<(), CameraProblem> {
    let ok = |s: u32| (1..=MAX_IMAGE_SIDE).contains(&s);
    if ok(width) && ok(height) {
        Ok(())
    } else {
        Err(CameraProblem::ImageSize {
            max: MAX_IMAGE_SIDE,
        })
    }
}

/// A camera resolved for one frame: pixel size (after supersampling), clip
/// planes, and the map from model space to "window clip" coordinates
/// `(X, Y, W)` with pixel `x = X / W`, `y = Y / W` (row 0 at the top) and
/// `W` the linear eye depth.
#[derive(Debug, Clone, Copy)]
pub(crate) struct View {
    pub(crate) eye: DVec3,
    /// Rows of the world → window-clip map (applied to `p - eye`).
    rows: [DVec3; 3],
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) near: f64,
    pub(crate) far: f64,
    /// Unit vectors of the eye frame in world space: right, up, back.
    pub(crate) basis: [DVec3; 3],
}

impl View {
    /// Resolves `camera` at `scale`× its size; missing clip planes enclose
    /// `bounds` (the scene's model-space box).
    pub(crate) fn new(
        camera: &Camera,
        scale: u32,
        bounds: Option<(DVec3, DVec3)>,
    ) -> Result<Self, CameraProblem> {
        let width = camera.width.saturating_mul(scale);
        let height = camera.height.saturating_mul(scale);
        check_size(width, height)?;
        let back = (camera.eye - camera.target).normalize();
        let right = camera.up.cross(back).normalize();
        let up = back.cross(right);
        let (auto_near, auto_far) = auto_clip_planes(camera.eye, -back, bounds);
        let far = camera
            .far
            .unwrap_or(auto_far.max(camera.near.unwrap_or(0.0) * 2.0));
        let near = camera
            .near
            .unwrap_or((auto_near).min(far * 0.5).max(far * 1e-3));
        if !(near > 0.0 && near < far && far.is_finite()) {
            return Err(CameraProblem::ClipPlanes);
        }
        let f = 1.0 / (camera.fov_y_degrees.to_radians() / 2.0).tan();
        let aspect = width as f64 / height as f64;
        let (w2, h2) = (width as f64 / 2.0, height as f64 / 2.0);
        // clip x = f/aspect · x_e, clip y = f · y_e, W = -z_e;
        // X = (clip x + W) · w/2, Y = (W - clip y) · h/2.
        let fwd = -back;
        let rows = [(right * (f / aspect) + fwd) * w2, (fwd - up * f) * h2, fwd];
        Ok(Self {
            eye: camera.eye,
            rows,
            width,
            height,
            near,
            far,
            basis: [right, up, back],
        })
    }

    /// The map `local (u, v, t) → (X, Y, W)` of points `origin + u·a + v·b +
    /// t·c`, as an f32 matrix (columns: the images of a, b, c) and
    /// translation.
    pub(crate) fn local_map(&self, origin: DVec3, axes: [DVec3; 3]) -> (Mat3, Vec3) {
        let m = DMat3::from_cols(self.rows[0], self.rows[1], self.rows[2]).transpose();
        let t = m * (origin - self.eye);
        let cols = axes.map(|a| (m * a).as_vec3());
        (Mat3::from_cols(cols[0], cols[1], cols[2]), t.as_vec3())
    }

    /// Window-clip coordinates of a world point (f64).
    #[cfg(test)]
    pub(crate) fn clip_of(&self, p: DVec3) -> DVec3 {
        let d = p - self.eye;
        DVec3::new(
            self.rows[0].dot(d),
            self.rows[1].dot(d),
            self.rows[2].dot(d),
        )
    }

    /// Normalized depth (0 at near, 1 at far) of eye depth `w`.
    pub(crate) fn depth_scale(&self) -> (f32, f32) {
        let inv = 1.0 / (self.far - self.near);
        (inv as f32, (-self.near * inv) as f32)
    }
}

/// Near and far planes that enclose a box seen from `eye` along `forward`.
fn auto_clip_planes(eye: DVec3, forward: DVec3, bounds: Option<(DVec3, DVec3)>) -> (f64, f64) {
    let Some((lo, hi)) = bounds else {
        return (0.01, 100.0);
    };
    let mut nearest = f64::INFINITY;
    let mut farthest = f64::NEG_INFINITY;
    for k in 0..8 {
        let c = DVec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let d = (c - eye).dot(forward);
        nearest = nearest.min(d);
        farthest = farthest.max(d);
    }
    let extent = (hi - lo).length().max(1e-9);
    let far = if farthest > 0.0 {
        farthest + 0.01 * extent
    } else {
        extent
    };
    let near = if nearest > 0.0 {
        nearest - 0.01 * extent
    } else {
        0.0
    };
    (near, far)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_projects_to_the_image_centre_and_up_is_the_top() {
        let cam = Camera::look_at(
            DVec3::new(0.0, 0.0, 10.0),
            DVec3::ZERO,
            DVec3::Y,
            90.0,
            200,
            100,
        )
        .unwrap();
        let v = View::new(&cam, 1, None).unwrap();
        let c = v.clip_of(DVec3::ZERO);
        assert!((c.x / c.z - 100.0).abs() < 1e-9 && (c.y / c.z - 50.0).abs() < 1e-9);
        assert!((c.z - 10.0).abs() < 1e-12);
        // At depth 10 with a 90° vertical fov, y = 10 is the top edge (row 0).
        let top = v.clip_of(DVec3::new(0.0, 10.0, 0.0));
        assert!((top.y / top.z).abs() < 1e-9);
        // x = 20 at aspect 2 is the right edge.
        let right = v.clip_of(DVec3::new(20.0, 0.0, 0.0));
        assert!((right.x / right.z - 200.0).abs() < 1e-9);
    }

    #[test]
    fn degenerate_cameras_are_refused() {
        let e = DVec3::new(0.0, 0.0, 5.0);
        assert_eq!(
            Camera::look_at(e, e, DVec3::Y, 45.0, 10, 10),
            Err(CameraProblem::EyeIsTarget)
        );
        // Issue 20: 1e300 squared is infinite, which made this "the same point".
        let far = DVec3::new(1e300, 0.0, 0.0);
        assert_eq!(
            Camera::look_at(far, DVec3::ZERO, DVec3::Y, 45.0, 10, 10),
            Err(CameraProblem::TooFar)
        );
        assert_eq!(
            Camera::look_at(e, DVec3::ZERO, DVec3::Z, 45.0, 10, 10),
            Err(CameraProblem::UpParallelToView)
        );
        assert_eq!(
            Camera::look_at(e, DVec3::ZERO, DVec3::Y, 180.0, 10, 10),
            Err(CameraProblem::FieldOfView)
        );
        assert!(Camera::look_at(e, DVec3::ZERO, DVec3::Y, 45.0, 0, 10).is_err());
        assert!(Camera::look_at(DVec3::NAN, DVec3::ZERO, DVec3::Y, 45.0, 1, 1).is_err());
        let cam = Camera::look_at(e, DVec3::ZERO, DVec3::Y, 45.0, 10, 10).unwrap();
        assert!(cam.with_clip_planes(Some(2.0), Some(1.0)).is_err());
        assert!(cam.with_clip_planes(Some(-1.0), None).is_err());
    }
}
