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

use glam::{DMat3, DVec3, Vec3, Vec4};

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
/// patch ([`crate::prepare::patch::PreparedPatch::level`]).
///
/// Why four cells of a row in lanes, each corner's normal with its own
/// lanes ([`unit_normal_lanes`], so every normal is the one-by-one value
/// bit for bit), undrawn cells weighted 0 in the sum and left out of the
/// minimum: one cell at a time (its four corners in lanes, gathered and
/// shuffled from the codes) was 27.4 M of a one-frame bunny render's
/// 185 M instructions (callgrind, `spatch render bunny.spatch -o out.png
/// --threads 1`). The sum runs in another order than cell by cell, so
/// the axis may differ from that order's in its last bits; the cone still
/// holds every corner normal (its half angle is measured from that axis).
pub(crate) fn compute_normal_cone(
    d: &[u16],
    cols: usize,
    ratios: (f32, f32),
    rotation: &DMat3,
) -> Option<ConeScan> {
    let rows = d.len() / cols;
    if cols < 2 || rows < 2 {
        return None;
    }
    let groups = (cols - 1).div_ceil(4);
    // The codes as floats (exact), each row padded with empty codes to
    // whole groups of four cells, so padding cells are undrawn.
    let stride = 4 * groups + 1;
    let mut codes = vec![f32::from(EMPTY); stride * rows];
    for (row, src) in codes.chunks_exact_mut(stride).zip(d.chunks_exact(cols)) {
        for (c, &v) in row.iter_mut().zip(src) {
            *c = f32::from(v);
        }
    }
    CORNERS.with_borrow_mut(|corners| {
        let scan = scan_groups(&codes, stride, groups, ratios, corners)?;
        Some(finish_cone(scan, corners, rotation))
    })
}

/// Four cells' corner normals (`[corner][x, y, z]`, corners 00, 10, 01,
/// 11) and their weights (1 drawn, 0 not).
type CornerGroup = ([[Vec4; 3]; 4], Vec4);

thread_local! {
    /// Room for one patch's corner groups, kept per thread. Why: a fresh
    /// vector per patch was written twice (zeroed, then filled).
    static CORNERS: std::cell::RefCell<Vec<CornerGroup>> = const {
        std::cell::RefCell::new(Vec::new())
    };
}

/// The sum of the drawn cells' corner normals and their codes' range
/// (`None` when no cell is drawn), their normals written to `corners`
/// (resized to the grid's groups).
fn scan_groups(
    codes: &[f32],
    stride: usize,
    groups: usize,
    ratios: (f32, f32),
    corners: &mut Vec<CornerGroup>,
) -> Option<([Vec4; 3], (u16, u16))> {
    let empty = Vec4::splat(f32::from(EMPTY));
    let mut sum = [Vec4::ZERO; 3];
    let (mut lo, mut hi) = (empty, Vec4::ZERO);
    let mut any = false;
    // Written by index, not pushed. Why: the growth check's call made the
    // loop keep its sums and normals on the stack.
    corners.resize(
        groups * (codes.len() / stride - 1),
        ([[Vec4::ZERO; 3]; 4], Vec4::ZERO),
    );
    let mut next = 0;
    for (below, above) in codes
        .chunks_exact(stride)
        .zip(codes.chunks_exact(stride).skip(1))
    {
        for g in 0..groups {
            // One unaligned load each (`from_slice` gathers lane by lane).
            let at = |row: &[f32], k: usize| {
                let lanes: [f32; 4] = row[4 * g + k..4 * g + k + 4].try_into().expect("four");
                Vec4::from(lanes)
            };
            let (b0, b1, a0, a1) = (at(below, 0), at(below, 1), at(above, 0), at(above, 1));
            // The empty code is the largest: a cell is drawn when its
            // largest corner is not empty.
            let top = b0.max(b1).max(a0).max(a1);
            let drawn = top.cmplt(empty);
            any |= drawn.any();
            let w = Vec4::select(drawn, Vec4::ONE, Vec4::ZERO);
            lo = lo.min(Vec4::select(drawn, b0.min(b1).min(a0).min(a1), empty));
            hi = hi.max(top * w);
            // Differences over one spacing, doubled (as a node normal's).
            let (du_b, du_t) = ((b1 - b0) * 2.0, (a1 - a0) * 2.0);
            let (dv_l, dv_r) = ((a0 - b0) * 2.0, (a1 - b1) * 2.0);
            let pairs = [(du_b, dv_l), (du_b, dv_r), (du_t, dv_l), (du_t, dv_r)];
            let normals = pairs.map(|(du, dv)| unit_normal_lanes(du, dv, ratios));
            for n in &normals {
                for (s, c) in sum.iter_mut().zip(n) {
                    *s += *c * w;
                }
            }
            corners[next] = (normals, w);
            next += 1;
        }
    }
    any.then(|| (sum, (lo.min_element() as u16, hi.max_element() as u16)))
}

/// The cone around the normalized `sum` through the widest of `corners`.
fn finish_cone(
    (sum, d_range): ([Vec4; 3], (u16, u16)),
    corners: &[CornerGroup],
    rotation: &DMat3,
) -> ConeScan {
    let axis = Vec3::new(
        sum[0].element_sum(),
        sum[1].element_sum(),
        sum[2].element_sum(),
    )
    .normalize_or(Vec3::Z);
    let [ax, ay, az] = axis.to_array().map(Vec4::splat);
    // The cosines in `Vec3::dot`'s order, lane by lane; undrawn lanes 1.
    let mut min_cos = Vec4::ONE;
    for (normals, w) in corners {
        let cos = normals.map(|[x, y, z]| x * ax + y * ay + z * az);
        let least = cos[0].min(cos[1]).min(cos[2]).min(cos[3]);
        min_cos = min_cos.min(Vec4::select(w.cmpeq(Vec4::ONE), least, Vec4::ONE));
    }
    let min_cos = min_cos.min_element().clamp(-1.0, 1.0);
    let half_angle = (min_cos as f64).acos() + CONE_MARGIN;
    let cone = NormalCone {
        axis: (*rotation * axis.as_dvec3()).normalize(),
        half_angle,
    };
    ConeScan { cone, d_range }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::mip::base_level;
    use crate::prepare::normals::reconstruct_normal;
    use glam::IVec4;
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
