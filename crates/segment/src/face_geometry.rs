//! Per-face unit normals, areas and centroids, computed once per stage.
//!
//! Input: a [`TriangleMesh`]. Output: [`FaceGeometry`] with, for every face, its unit normal
//! (or `None` when the face is degenerate), its area and its centroid.
//!
//! Invariant: a face has a normal exactly when its cross product is longer than
//! [`DEGENERATE_SINE`] times its longest squared edge, i.e. when the sine of its largest
//! angle is not lost in rounding. The cross product is formed in f64 from the f32 corner
//! positions, so slivers with aspect ratios of 10⁴ and more keep a correct normal, and a
//! zero-area face never produces a made-up one. Faces without a normal fit any cone: the
//! stages place them by adjacency alone.
//!
//! Cost: one O(n) pass; 28 bytes per face.
//!
//! Based on: the robust normal test of Shewchuk, *Lecture notes on geometric robustness*
//! (2013), in its simplest (relative-threshold) form.

use glam::Vec3;
use spatch_mesh::TriangleMesh;

/// Ratio of cross-product length to longest squared edge below which a face counts as
/// degenerate (no normal).
pub(crate) const DEGENERATE_SINE: f64 = 1e-9;

/// Normals, areas and centroids of every face of a mesh (see the module docs).
#[derive(Clone, Debug, Default)]
pub(crate) struct FaceGeometry {
    /// Unit normal per face, or `None` for a degenerate face.
    pub(crate) normals: Vec<Option<Vec3>>,
    /// Area per face (zero for degenerate faces).
    pub(crate) areas: Vec<f32>,
    /// Centroid per face (relative to the mesh origin).
    pub(crate) centroids: Vec<Vec3>,
}

impl FaceGeometry {
    /// Number of faces.
    #[inline]
    pub(crate) fn face_count(&self) -> usize {
        self.areas.len()
    }
}

/// Computes the [`FaceGeometry`] of `mesh`.
pub(crate) fn compute_face_geometry(mesh: &TriangleMesh) -> FaceGeometry {
    let n = mesh.face_count();
    let mut geometry = FaceGeometry {
        normals: Vec::with_capacity(n),
        areas: Vec::with_capacity(n),
        centroids: Vec::with_capacity(n),
    };
    for face in mesh.faces() {
        let [a, b, c] = mesh.face_positions(face).map(Vec3::as_dvec3);
        let (ab, bc, ca) = (b - a, c - b, a - c);
        let cross = ab.cross(-ca);
        let longest = ab
            .length_squared()
            .max(bc.length_squared())
            .max(ca.length_squared());
        let length = cross.length();
        let normal = (length > DEGENERATE_SINE * longest && length > 0.0)
            .then(|| (cross / length).as_vec3())
            .filter(|v| v.is_finite());
        geometry.normals.push(normal);
        geometry.areas.push(if normal.is_some() {
            (0.5 * length) as f32
        } else {
            0.0
        });
        geometry
            .centroids
            .push(((a + b + c) * (1.0 / 3.0)).as_vec3());
    }
    geometry
}

/// The unit normal of a triangle given in f64, for tests of the threshold.
#[cfg(test)]
fn normal_of(a: glam::DVec3, b: glam::DVec3, c: glam::DVec3) -> Option<Vec3> {
    let mesh =
        TriangleMesh::new(vec![a.as_vec3(), b.as_vec3(), c.as_vec3()], vec![[0, 1, 2]]).ok()?;
    compute_face_geometry(&mesh).normals[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn slivers_keep_their_normal_and_collinear_faces_have_none() {
        let sliver = normal_of(DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1e-4, 0.0));
        assert_eq!(sliver, Some(Vec3::Z));
        let collinear = normal_of(DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0));
        assert_eq!(collinear, None);
        let point = normal_of(DVec3::ONE, DVec3::ONE, DVec3::ONE);
        assert_eq!(point, None);
    }
}
