//! The choice between f32 and f64 positions for formats that store either
//! (PLY), and the origin shift every writer applies.
//!
//! An f32 coordinate `c` is off by up to half an ulp, 2^-24·|c|. Written
//! relative to the shift origin, the worst coordinate `M` (largest
//! magnitude) therefore loses up to 2^-24·M. [`PositionType::Auto`] keeps
//! f32 while that is at most [`F32_TOLERANCE`] (1e-5) of the median
//! patch's extent `L` (the diagonal of its vertices' box), i.e. within
//! about 1e-6 of any model ten patches wide, wherever it lies; otherwise it
//! writes f64 (error 2^-53·M, negligible). The median patch, not the whole
//! export, sets the scale so that a merged scene's parts far apart (each
//! small against the distance between them) keep their own precision. A
//! model far from its origin (UTM coordinates, a scene at 1e7) thus gets
//! doubles, or f32 again after an explicit `--origin` near it.

use glam::DVec3;

use crate::PatchMesh;

/// The largest f32 rounding, as a fraction of the median patch extent,
/// that [`PositionType::Auto`] accepts (see the module header).
pub const F32_TOLERANCE: f64 = 1e-5;

/// The number type of exported positions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum PositionType {
    /// f32 when it loses at most 1e-5 of a median patch's extent, else f64.
    #[default]
    Auto,
    /// Always f32 (PLY `float`).
    F32,
    /// Always f64 (PLY `double`).
    F64,
}

/// The type `requested` resolves to for `meshes` shifted by `-origin`:
/// `true` for f64.
pub fn needs_f64(meshes: &[PatchMesh], origin: DVec3, requested: PositionType) -> bool {
    match requested {
        PositionType::F32 => false,
        PositionType::F64 => true,
        PositionType::Auto => {
            let reach = meshes
                .iter()
                .flat_map(|m| (0..m.positions.len()).map(move |k| m.world_position(k) - origin))
                .map(|p| p.abs().max_element())
                .fold(0.0, f64::max);
            let rounding = reach * 2f64.powi(-24);
            rounding > F32_TOLERANCE * median_extent(meshes)
        }
    }
}

/// The median over meshes of the diagonal of their vertices' box (0 for
/// no mesh).
fn median_extent(meshes: &[PatchMesh]) -> f64 {
    let mut extents: Vec<f64> = meshes
        .iter()
        .map(|m| {
            let (lo, hi) = m.positions.iter().fold(
                (glam::Vec3::INFINITY, glam::Vec3::NEG_INFINITY),
                |(lo, hi), &p| (lo.min(p), hi.max(p)),
            );
            f64::from((hi - lo).length())
        })
        .collect();
    if extents.is_empty() {
        return 0.0;
    }
    extents.sort_by(f64::total_cmp);
    extents[extents.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn mesh(origin: DVec3) -> PatchMesh {
        PatchMesh {
            patch: 0,
            origin,
            positions: vec![Vec3::ZERO, Vec3::ONE],
            normals: vec![Vec3::Z; 2],
            colours: None,
            triangles: Vec::new(),
        }
    }

    #[test]
    fn far_models_get_doubles_unless_shifted_near() {
        let near = [mesh(DVec3::splat(-0.5))];
        assert!(!needs_f64(&near, DVec3::ZERO, PositionType::Auto));
        let far = [mesh(DVec3::new(1e7, 0.0, 0.0))];
        assert!(needs_f64(&far, DVec3::ZERO, PositionType::Auto));
        assert!(!needs_f64(
            &far,
            DVec3::new(1e7, 0.0, 0.0),
            PositionType::Auto
        ));
        assert!(!needs_f64(&far, DVec3::ZERO, PositionType::F32));
        assert!(needs_f64(&near, DVec3::ZERO, PositionType::F64));
        assert!(!needs_f64(&[], DVec3::ZERO, PositionType::Auto));
        // A part 1e4 away from a near one: the pair is wide, but each part
        // would lose 1e-5 of a patch in f32.
        let pair = [mesh(DVec3::ZERO), mesh(DVec3::new(1e4, 0.0, 0.0))];
        assert!(needs_f64(&pair, DVec3::ZERO, PositionType::Auto));
    }
}
