//! The point cloud type: positions with optional colours and normals.

use glam::{DVec3, Vec3};

use crate::Aabb;

/// A set of points, positions `f32` relative to an `f64` origin (like
/// [`TriangleMesh`](crate::TriangleMesh)).
///
/// # Guarantees
///
/// As returned by [`load_point_cloud`](crate::load_point_cloud): every position and normal is
/// finite (non-finite points are dropped and counted), `colours` and `normals` have one entry
/// per point, and `origin` is the f64 centre of the points' bounding box.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PointCloud {
    /// World offset of every position.
    pub origin: DVec3,
    /// Point positions relative to `origin`.
    pub positions: Vec<Vec3>,
    /// sRGB RGBA8 colour per point.
    pub colours: Option<Vec<[u8; 4]>>,
    /// Normal per point as given by the file (not renormalised; may be zero).
    pub normals: Option<Vec<Vec3>>,
}

impl PointCloud {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Bounding box of the positions (relative to `origin`).
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().copied())
    }

    /// World (f64) position of point `i`.
    ///
    /// # Panics
    /// When `i` is out of range.
    pub fn world_position(&self, i: usize) -> DVec3 {
        self.origin + self.positions[i].as_dvec3()
    }
}
