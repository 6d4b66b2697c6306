//! Whether a source and a scene occupy the same space, checked before anything is measured.
//!
//! Input: a [`Scene`] and a [`Source`]. Output: an [`Overlap`]: both bounding boxes in model
//! space (f64, the scene's offset and every patch's precise origin applied, the source's
//! origin added) and whether they meet. Boxes count as meeting when they intersect once each
//! is grown by [`OVERLAP_TOLERANCE`] of the larger of the two diagonals on every side, so a
//! scene whose nodes lie a quantization step outside its source (or a flat source, whose box
//! has no thickness) still meets it.
//!
//! A scene measured against a source it does not overlap has every distance of the order of
//! the gap between them: no figure says anything about the conversion, and the image error
//! would render two different places. [`crate::evaluate()`] refuses such a pair with
//! [`crate::EvalError::NoOverlap`] before it measures.
//!
//! Cost: one pass over the filled nodes and one over the source's points.

use glam::DVec3;
use spatch_format::Scene;

use crate::Source;

/// Growth of each box before the test, as a fraction of the larger diagonal.
pub const OVERLAP_TOLERANCE: f64 = 0.01;

/// The two boxes and whether they meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// The source's bounding box `(min, max)` in model space.
    pub source: (DVec3, DVec3),
    /// The scene's bounding box `(min, max)` in model space (filled nodes).
    pub scene: (DVec3, DVec3),
    /// Whether the boxes meet (see the module docs).
    pub meets: bool,
}

/// Compares the boxes of `scene` and `source`; `None` when either has no point.
pub fn source_overlap(scene: &Scene, source: &Source) -> Option<Overlap> {
    let scene_box = scene.bounds()?;
    let (origin, bounds) = match source {
        Source::Mesh(m) => (m.origin, m.bounds()),
        Source::Cloud(c) => (c.origin, c.bounds()),
    };
    if !(bounds.min.cmple(bounds.max).all()) {
        return None;
    }
    let source_box = (
        origin + bounds.min.as_dvec3(),
        origin + bounds.max.as_dvec3(),
    );
    let diagonal = |(lo, hi): (DVec3, DVec3)| (hi - lo).length();
    let grow = OVERLAP_TOLERANCE * diagonal(scene_box).max(diagonal(source_box));
    let meets = (source_box.0 - grow).cmple(scene_box.1 + grow).all()
        && (scene_box.0 - grow).cmple(source_box.1 + grow).all();
    Some(Overlap {
        source: source_box,
        scene: scene_box,
        meets,
    })
}

/// `[x0, y0, z0] to [x1, y1, z1]` with four significant digits.
pub(crate) fn box_text((lo, hi): (DVec3, DVec3)) -> String {
    format!(
        "[{:.4e}, {:.4e}, {:.4e}] to [{:.4e}, {:.4e}, {:.4e}]",
        lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use spatch_format::{ColourChannel, Frame, GridSize, Patch};
    use spatch_mesh::TriangleMesh;

    fn unit_scene(offset: DVec3) -> Scene {
        let frame = Frame::new(Vec3::ZERO, Vec3::X * 0.1, Vec3::Y * 0.1, Vec3::Z * 0.01).unwrap();
        let patch = Patch::new(frame, GridSize::new(11, 11).unwrap(), vec![0; 121], None).unwrap();
        Scene::new(offset, ColourChannel::None, vec![patch]).unwrap()
    }

    fn flat_square() -> Source {
        let mesh = TriangleMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
            vec![[0, 1, 2], [2, 1, 3]],
        )
        .unwrap();
        Source::Mesh(mesh)
    }

    #[test]
    fn a_flat_source_meets_its_scene() {
        let o = source_overlap(&unit_scene(DVec3::ZERO), &flat_square()).unwrap();
        assert!(o.meets, "{o:?}");
    }

    #[test]
    fn a_source_beside_the_scene_does_not_meet_it() {
        let o = source_overlap(&unit_scene(DVec3::new(5.0, 0.0, 0.0)), &flat_square()).unwrap();
        assert!(!o.meets, "{o:?}");
        assert_eq!(o.scene.0, DVec3::new(5.0, 0.0, 0.0));
        // Just within the tolerance still meets.
        let o = source_overlap(&unit_scene(DVec3::new(1.01, 0.0, 0.0)), &flat_square()).unwrap();
        assert!(o.meets, "{o:?}");
    }
}
