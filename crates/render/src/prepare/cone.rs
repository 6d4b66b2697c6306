//! The normal cone of a patch, built once per scene: a cone bounding the
//! exact normals of its cells at their corners (one-sided displacement
//! differences), widened by [`CONE_MARGIN`] for the curvature of bilinear
//! cells between their corners. A frame tests it against the eye
//! ([`crate::plan::cull`]) to drop patches that face away and to skip the
//! per-cell test of patches that face the eye entirely.
//!
//! Based on: L. A. Shirman, S. S. Abi-Ezzi, "The cone of normals technique
//! for fast processing of curved patches", Eurographics 1993.
//!
//! Cost: four corner normals per drawable cell, in lanes; no allocation
//! beyond one vector of corner normals.

use glam::{DMat3, DVec3, IVec4, Vec3, Vec4, Vec4Swizzles};

use spatch_format::EMPTY;

use crate::prepare::normals::unit_normal_lanes;

/// Extra half angle of every normal cone (radians), for the curvature of
/// bilinear cells between their corners.
pub(crate) const CONE_MARGIN: f64 = 0.03;

/// A cone bounding the normals of a patch, in model space.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NormalCone {
    pub(crate) axis: DVec3,
    pub(crate) half_angle: f64,
}

/// What one pass over a level-0 grid's drawable cells finds: the normal
/// cone and the range of the displacements of their corners (the used nodes' range, [`crate::prepare::mip::MipLevel::d_range`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ConeScan {
    pub(crate) cone: NormalCone,
    pub(crate) d_range: (u16, u16),
}

/// The normal cone of the level-0 grid `d` (`cols` nodes a row, `EMPTY`
/// for no node) with ratios `(rx, ry)` whose unit axes are the columns of
/// `rotation`, or `None` when no cell has four filled corners: the axis is
/// the normalized sum of the unit normals at the four corners of every
/// drawable cell, the half angle the largest angle between the axis and
/// one of them, plus [`CONE_MARGIN`]. Read from the nodes (a cell is
/// drawable when its four corners are filled), so preparation needs no
/// cell flags of level 0, which are built when a frame first draws the
/// patch ([`crate::prepare::patch::PreparedPatch::level`]). Why lanes
/// throughout (a cell's four corners summed and tested side by side, kept
/// as three lane vectors): the sum and the angles over a list of normals
/// were two thirds of this function, and the function a quarter of a
/// one-frame render of the perfect sphere (callgrind, `spatch render
/// sphere.spatch`).
pub(crate) fn compute_normal_cone(
    d: &[u16],
    cols: usize,
    ratios: (f32, f32),
    rotation: &DMat3,
) -> Option<ConeScan> {
    let cells = (cols - 1) * (d.len() / cols).saturating_sub(1);
    // Written by index into room for every cell. Why not pushed: the
    // growth check's call made the loop keep its sums on the stack
    // (callgrind, `spatch render bunny.spatch -o out.png --threads 1`).
    let mut corners = vec![[Vec4::ZERO; 3]; cells];
    let mut count = 0;
    let mut sum = [Vec4::ZERO; 3];
    // The drawn cells' corner range, in float lanes (exact for codes;
    // SSE2 has no packed 32-bit integer minimum).
    let (mut lo, mut hi) = (Vec4::splat(f32::MAX), Vec4::ZERO);
    let empty = Vec4::splat(EMPTY.into());
    let node_rows = d.chunks_exact(cols);
    for (below, above) in node_rows.clone().zip(node_rows.skip(1)) {
        for (b, a) in below.windows(2).zip(above.windows(2)) {
            // The corners d00, d10, d01, d11, and their differences over
            // one spacing, doubled (the form of a node normal's
            // differences): du = [d10 - d00, d10 - d00, d11 - d01, d11 -
            // d01], dv = [d01 - d00, d11 - d10, d01 - d00, d11 - d10]. Why
            // integer lanes: one packed subtraction and conversion each
            // (exact, so the normals are those of the scalar form). A cell
            // is drawable when none of its corners is empty: one packed
            // compare.
            let c = IVec4::new(b[0].into(), b[1].into(), a[0].into(), a[1].into());
            let cf = c.as_vec4();
            if cf.cmpeq(empty).any() {
                continue;
            }
            (lo, hi) = (lo.min(cf), hi.max(cf));
            let du = (c.yyww() - c.xxzz()) * 2;
            let dv = (c.zwzw() - c.xyxy()) * 2;
            let n = unit_normal_lanes(du.as_vec4(), dv.as_vec4(), ratios);
            for (s, c) in sum.iter_mut().zip(n) {
                *s += c;
            }
            corners[count] = n;
            count += 1;
        }
    }
    if count == 0 {
        return None;
    }
    let axis = Vec3::new(
        sum[0].element_sum(),
        sum[1].element_sum(),
        sum[2].element_sum(),
    )
    .normalize_or(Vec3::Z);
    let [ax, ay, az] = axis.to_array().map(Vec4::splat);
    // The cosines in `Vec3::dot`'s order, lane by lane.
    let min_cos = corners[..count]
        .iter()
        .fold(Vec4::ONE, |m, [x, y, z]| m.min(*x * ax + *y * ay + *z * az))
        .min_element()
        .clamp(-1.0, 1.0);
    let half_angle = (min_cos as f64).acos() + CONE_MARGIN;
    let cone = NormalCone {
        axis: (*rotation * axis.as_dvec3()).normalize(),
        half_angle,
    };
    Some(ConeScan {
        cone,
        d_range: (lo.min_element() as u16, hi.max_element() as u16),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::mip::base_level;
    use crate::prepare::normals::reconstruct_normal;
    use spatch_format::{Frame, GridSize, Patch};

    #[test]
    fn corner_normals_in_lanes_equal_normals_one_by_one() {
        let mut rng = crate::test_rng::XorShift(0xc0de_5eed);
        for _ in 0..2000 {
            let g = |r: &mut crate::test_rng::XorShift| r.below(401) as i32 - 200;
            let gi = [g(&mut rng), g(&mut rng), g(&mut rng), g(&mut rng)];
            let gj = [g(&mut rng), g(&mut rng), g(&mut rng), g(&mut rng)];
            let ratios = (0.001 + rng.unit() * 0.2, 0.001 + rng.unit() * 0.2);
            let as_lanes = |g: [i32; 4]| IVec4::from_array(g).as_vec4();
            let [x, y, z] = unit_normal_lanes(as_lanes(gi), as_lanes(gj), ratios);
            for k in 0..4 {
                let one = reconstruct_normal(gi[k], gj[k], ratios.0, ratios.1).normalize();
                assert_eq!(
                    [x[k], y[k], z[k]].map(f32::to_bits),
                    one.to_array().map(f32::to_bits)
                );
            }
        }
    }

    #[test]
    fn the_cone_holds_every_corner_normal_around_their_mean() {
        // Random grids, some nodes empty, some steps steep: the axis is the
        // direction of the corners' mean normal (summed one by one in cell
        // order, up to rounding) and the half angle reaches the farthest.
        let mut rng = crate::test_rng::XorShift(0xc09e_5eed);
        let frame = Frame::new(
            glam::Vec3::ZERO,
            glam::Vec3::X,
            glam::Vec3::Y,
            glam::Vec3::Z,
        )
        .unwrap();
        let mut checked = 0;
        for case in 0..300 {
            let (cols, rows) = (2 + rng.below(16) as usize, 2 + rng.below(16) as usize);
            let step = [1, 3, 40][case % 3];
            let d: Vec<u16> = (0..cols * rows)
                .map(|_| match rng.below(12) {
                    0 => EMPTY,
                    _ => (30_000 + rng.below(step * 8)) as u16,
                })
                .collect();
            let grid = GridSize::new(cols as u32, rows as u32).unwrap();
            let patch = Patch::new(frame, grid, d.clone(), None).unwrap();
            let Some(level) = base_level(&patch) else {
                assert!(compute_normal_cone(&d, cols, (0.1, 0.1), &DMat3::IDENTITY).is_none());
                continue;
            };
            let ratios = (0.01 + rng.unit() * 0.3, 0.01 + rng.unit() * 0.3);
            let scan = compute_normal_cone(&d, cols, ratios, &DMat3::IDENTITY).unwrap();
            // The by-product is the level's own range.
            assert_eq!(scan.d_range, level.d_range, "case {case}");
            let cone = scan.cone;
            let at = |i: usize, j: usize| d[j * cols + i] as i32;
            let mut corners = Vec::new();
            for j in 0..rows - 1 {
                for i in 0..cols - 1 {
                    if !level.cell_is_drawable(i, j) {
                        continue;
                    }
                    let (d00, d10, d01, d11) =
                        (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
                    let (b, t) = (2 * (d10 - d00), 2 * (d11 - d01));
                    let (l, r) = (2 * (d01 - d00), 2 * (d11 - d10));
                    for (gi, gj) in [(b, l), (b, r), (t, l), (t, r)] {
                        corners.push(reconstruct_normal(gi, gj, ratios.0, ratios.1).normalize());
                    }
                }
            }
            let mean = corners.iter().copied().sum::<Vec3>().normalize_or(Vec3::Z);
            assert!(
                cone.axis.angle_between(mean.as_dvec3()) < 1e-5,
                "case {case}"
            );
            let widest = corners
                .iter()
                .map(|n| n.as_dvec3().angle_between(cone.axis))
                .fold(0.0, f64::max);
            assert!(
                widest <= cone.half_angle - CONE_MARGIN + 1e-4,
                "case {case}"
            );
            assert!(
                widest >= cone.half_angle - CONE_MARGIN - 1e-3,
                "case {case}"
            );
            checked += 1;
        }
        assert!(checked > 250, "{checked}");
    }
}
