//! Which reference pixels a scan set saw: whether a hole is surface no scan recorded (the
//! scan campaign's fault) or surface the conversion lost.
//!
//! Input: the merged cloud of the scan set, its spacing `s`, and per view the reference
//! mesh's depth image with its camera. Output: per view, how many of the counted (eroded)
//! reference pixels, and how many of the hole pixels, have no cloud point within
//! [`SEEN_WITHIN`] `s` of the surface point the pixel shows ("unseen").
//!
//! Method: each pixel's surface point is the eye plus the linear eye depth times the ray
//! through the pixel centre, scaled so its component along the view axis is 1; the nearest
//! cloud point comes from a kd-tree (`spatch_cloud::PointTree`). The figure checks itself:
//! on a well-covered object almost every reference pixel is seen, so a wrong unprojection
//! would show as most pixels unseen.

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use spatch_cloud::PointTree;
use spatch_mesh::PointCloud;
use spatch_render::Camera;

/// A surface point is seen when a cloud point lies within this many spacings of it.
pub(crate) const SEEN_WITHIN: f32 = 2.0;

/// The cloud as a kd-tree in its own frame, with the frame's origin and the spacing.
pub(crate) struct Coverage {
    tree: PointTree,
    origin: DVec3,
    spacing: f32,
}

impl Coverage {
    /// Indexes `cloud` (spacing estimated as `from-cloud` does).
    pub(crate) fn new(cloud: &PointCloud) -> Result<Coverage, String> {
        let spacing = spatch_cloud::estimate_spacing(&cloud.positions)
            .map_err(|e| e.to_string())?
            .spacing;
        let tree = PointTree::build(&cloud.positions).map_err(|e| e.to_string())?;
        Ok(Coverage {
            tree,
            origin: cloud.origin,
            spacing,
        })
    }

    /// The spacing of the cloud (model units).
    pub(crate) fn spacing(&self) -> f32 {
        self.spacing
    }

    /// For every pixel of `pixels` (indices into a `camera`-sized image whose linear eye
    /// depths are `depth`), whether no cloud point lies within [`SEEN_WITHIN`] spacings of
    /// the surface point it shows.
    pub(crate) fn unseen(&self, camera: &Camera, depth: &[f32], pixels: &[usize]) -> Vec<bool> {
        let limit = (SEEN_WITHIN * self.spacing).powi(2);
        pixels
            .par_iter()
            .map(|&k| {
                let p = surface_point(camera, k, f64::from(depth[k]));
                let q: Vec3 = (p - self.origin).as_vec3();
                self.tree.nearest(q).0 > limit
            })
            .collect()
    }
}

/// The world point of pixel `k` of `camera`'s image at linear eye depth `depth`.
fn surface_point(camera: &Camera, k: usize, depth: f64) -> DVec3 {
    let (w, h) = (f64::from(camera.width()), f64::from(camera.height()));
    let (x, y) = (
        (k % camera.width() as usize) as f64,
        (k / camera.width() as usize) as f64,
    );
    let forward = (camera.target() - camera.eye()).normalize();
    let right = forward.cross(camera.up()).normalize();
    let up = right.cross(forward);
    let half_y = (camera.fov_y_degrees().to_radians() / 2.0).tan();
    let half_x = half_y * w / h;
    let sx = (2.0 * (x + 0.5) / w - 1.0) * half_x;
    let sy = (1.0 - 2.0 * (y + 0.5) / h) * half_y;
    camera.eye() + (forward + right * sx + up * sy) * depth
}
