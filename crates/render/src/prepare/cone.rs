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
//! Cost: four corner normals per cell, eight cells in lanes; no allocation
//! (two vectors per thread, reused).

use glam::{DMat3, DVec3, Vec3};

use spatch_format::EMPTY;

use crate::isa::Isa;
use crate::prepare::normals::unit_normals;
use crate::prepare::wide::{Lanes, Portable, Wide, LANES};

/// Extra half angle of every normal cone (radians), for the curvature of
/// bilinear cells between their corners.
pub(crate) const CONE_MARGIN: f64 = 0.03;

/// A cone bounding the normals of a patch, in model space.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NormalCone {
    pub(crate) axis: DVec3,
    pub(crate) half_angle: f64,
    /// `sin` and `cos` of `half_angle`, for the per-frame tests
    /// ([`crate::plan::cull`]), which then need no inverse trigonometry.
    pub(crate) sin_cos: (f64, f64),
}

impl NormalCone {
    /// The cone of unit `axis` and `half_angle` (radians).
    pub(crate) fn new(axis: DVec3, half_angle: f64) -> NormalCone {
        NormalCone {
            axis,
            half_angle,
            sin_cos: half_angle.sin_cos(),
        }
    }
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
/// Why eight cells of a row in lanes ([`Wide`], 256-bit registers under
/// AVX2), each corner's normal with its own lanes (the operations of
/// [`unit_normals`], so every normal is the one-by-one value bit for
/// bit), undrawn cells weighted 0 in the sum and left out of the minimum:
/// four cells at a time in glam's 128-bit vectors were 25.4 M of a
/// one-frame bunny render's 167.6 M instructions (callgrind, `spatch
/// render bunny.spatch -o out.png --threads 1`). The sum runs in another
/// order than cell by cell, so the axis may differ from that order's in
/// its last bits; the cone still holds every corner normal (its half
/// angle is measured from that axis). Both instruction sets compute the
/// same cone, bit for bit.
pub(crate) fn compute_normal_cone(
    d: &[u16],
    cols: usize,
    ratios: (f32, f32),
    rotation: &DMat3,
    isa: Isa,
) -> Option<ConeScan> {
    let rows = d.len() / cols;
    if cols < 2 || rows < 2 {
        return None;
    }
    let groups = (cols - 1).div_ceil(LANES);
    // The codes as floats (exact), each row padded with empty codes to
    // whole groups of cells, so padding cells are undrawn.
    let stride = LANES * groups + 1;
    SCRATCH.with_borrow_mut(|(codes, corners)| {
        codes.clear();
        codes.resize(stride * rows, f32::from(EMPTY));
        for (row, src) in codes.chunks_exact_mut(stride).zip(d.chunks_exact(cols)) {
            for (c, &v) in row.iter_mut().zip(src) {
                *c = f32::from(v);
            }
        }
        let grid = Grid {
            codes,
            stride,
            groups,
            ratios,
        };
        match isa {
            Isa::Base => cone_with(Portable, &grid, corners, rotation),
            #[cfg(target_arch = "x86_64")]
            Isa::V3(v3) => v3.vectorize(
                #[inline(always)]
                || cone_with(v3, &grid, corners, rotation),
            ),
        }
    })
}

/// A grid's codes as floats, each row padded to whole groups.
struct Grid<'a> {
    codes: &'a [f32],
    /// Codes a row (`LANES * groups + 1`).
    stride: usize,
    /// Groups of [`LANES`] cells a row.
    groups: usize,
    ratios: (f32, f32),
}

/// Arrays of lanes a group's corner normals and weights take in the
/// scratch: `[corner][x, y, z]` (corners 00, 10, 01, 11), then the
/// weights (1 drawn, 0 not).
const GROUP_ARRAYS: usize = 13;

thread_local! {
    /// Room for one patch's codes and corner groups, kept per thread. Why:
    /// fresh vectors per patch were allocated, written twice (zeroed, then
    /// filled) and freed.
    static SCRATCH: std::cell::RefCell<(Vec<f32>, Vec<Lanes>)> = const {
        std::cell::RefCell::new((Vec::new(), Vec::new()))
    };
}

/// [`compute_normal_cone`] with the lanes of `w`.
#[inline(always)]
fn cone_with<W: Wide>(
    w: W,
    grid: &Grid<'_>,
    corners: &mut Vec<Lanes>,
    rotation: &DMat3,
) -> Option<ConeScan> {
    let scan = scan_groups(w, grid, corners)?;
    Some(finish_cone(w, scan, corners, rotation))
}

/// The sum of the drawn cells' corner normals (per lane) and their codes'
/// range (`None` when no cell is drawn), their normals and weights written
/// to `corners` ([`GROUP_ARRAYS`] a group).
#[inline(always)]
fn scan_groups<W: Wide>(
    w: W,
    grid: &Grid<'_>,
    corners: &mut Vec<Lanes>,
) -> Option<([Lanes; 3], (u16, u16))> {
    let empty = w.splat(f32::from(EMPTY));
    let (zero, one, two) = (w.splat(0.0), w.splat(1.0), w.splat(2.0));
    let negated = (w.splat(-grid.ratios.0), w.splat(-grid.ratios.1));
    let mut sum = [zero; 3];
    let (mut lo, mut hi) = (empty, zero);
    let rows = grid.codes.chunks_exact(grid.stride);
    corners.resize(grid.groups * (rows.len() - 1) * GROUP_ARRAYS, [0.0; LANES]);
    let mut out = corners.chunks_exact_mut(GROUP_ARRAYS);
    for (below, above) in rows.clone().zip(rows.skip(1)) {
        for g in 0..grid.groups {
            let at = |row: &[f32], k: usize| w.load(&row[LANES * g + k..]);
            let (b0, b1, a0, a1) = (at(below, 0), at(below, 1), at(above, 0), at(above, 1));
            // The empty code is the largest: a cell is drawn when its
            // largest corner is not empty.
            let top = w.max(w.max(w.max(b0, b1), a0), a1);
            let weight = w.select_lt(top, empty, one, zero);
            let least = w.min(w.min(w.min(b0, b1), a0), a1);
            lo = w.min(lo, w.select_lt(top, empty, least, empty));
            hi = w.max(hi, w.mul(top, weight));
            // Differences over one spacing, doubled (as a node normal's).
            let (du_b, du_t) = (w.mul(w.sub(b1, b0), two), w.mul(w.sub(a1, a0), two));
            let (dv_l, dv_r) = (w.mul(w.sub(a0, b0), two), w.mul(w.sub(a1, b1), two));
            let group = out.next().expect("sized above");
            let pairs = [(du_b, dv_l), (du_b, dv_r), (du_t, dv_l), (du_t, dv_r)];
            for (k, (du, dv)) in pairs.into_iter().enumerate() {
                let normal = unit_normals(w, du, dv, negated);
                for (c, (s, n)) in sum.iter_mut().zip(normal).enumerate() {
                    *s = w.add(*s, w.mul(n, weight));
                    group[3 * k + c] = w.lanes(n);
                }
            }
            group[12] = w.lanes(weight);
        }
    }
    let lo = w.lanes(lo).into_iter().fold(f32::from(EMPTY), f32::min);
    let hi = w.lanes(hi).into_iter().fold(0.0, f32::max);
    let sum = [w.lanes(sum[0]), w.lanes(sum[1]), w.lanes(sum[2])];
    (lo < f32::from(EMPTY)).then_some((sum, (lo as u16, hi as u16)))
}

/// The sum of eight lanes, pairwise.
#[inline(always)]
fn lane_sum(v: &Lanes) -> f32 {
    ((v[0] + v[4]) + (v[1] + v[5])) + ((v[2] + v[6]) + (v[3] + v[7]))
}

/// The cosines between the normals `[x, y, z]` and the unit axis `(ax,
/// ay, az)`, in `Vec3::dot`'s order.
#[inline(always)]
fn corner_cos<W: Wide>(w: W, xyz: &[Lanes], (ax, ay, az): (W::V, W::V, W::V)) -> W::V {
    let (x, y, z) = (w.load(&xyz[0]), w.load(&xyz[1]), w.load(&xyz[2]));
    w.add(w.add(w.mul(x, ax), w.mul(y, ay)), w.mul(z, az))
}

/// The cone around the normalized `sum` through the widest of `corners`.
#[inline(always)]
fn finish_cone<W: Wide>(
    w: W,
    (sum, d_range): ([Lanes; 3], (u16, u16)),
    corners: &[Lanes],
    rotation: &DMat3,
) -> ConeScan {
    let axis =
        Vec3::new(lane_sum(&sum[0]), lane_sum(&sum[1]), lane_sum(&sum[2])).normalize_or(Vec3::Z);
    let (ax, ay, az) = (w.splat(axis.x), w.splat(axis.y), w.splat(axis.z));
    let (half, one) = (w.splat(0.5), w.splat(1.0));
    // The cosines in `Vec3::dot`'s order, lane by lane; undrawn lanes 1.
    let mut min_cos = one;
    for group in corners.chunks_exact(GROUP_ARRAYS) {
        let axis = (ax, ay, az);
        let (c0, c1) = (
            corner_cos(w, &group[0..3], axis),
            corner_cos(w, &group[3..6], axis),
        );
        let (c2, c3) = (
            corner_cos(w, &group[6..9], axis),
            corner_cos(w, &group[9..12], axis),
        );
        let least = w.min(w.min(w.min(c0, c1), c2), c3);
        let weight = w.load(&group[12]);
        min_cos = w.min(min_cos, w.select_lt(weight, half, one, least));
    }
    let min_cos = w.lanes(min_cos).into_iter().fold(1.0, f32::min);
    let half_angle = (min_cos.clamp(-1.0, 1.0) as f64).acos() + CONE_MARGIN;
    let cone = NormalCone::new((*rotation * axis.as_dvec3()).normalize(), half_angle);
    ConeScan { cone, d_range }
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
        for _ in 0..1000 {
            let g = |r: &mut crate::test_rng::XorShift| r.below(401) as f32 - 200.0;
            let gi: Lanes = std::array::from_fn(|_| g(&mut rng));
            let gj: Lanes = std::array::from_fn(|_| g(&mut rng));
            let ratios = (0.001 + rng.unit() * 0.2, 0.001 + rng.unit() * 0.2);
            let negated = |w: Portable| (w.splat(-ratios.0), w.splat(-ratios.1));
            let normals = unit_normals(
                Portable,
                Portable.load(&gi),
                Portable.load(&gj),
                negated(Portable),
            );
            let [x, y, z] = normals.map(|v| Portable.lanes(v));
            #[cfg(target_arch = "x86_64")]
            if let Some(v3) = pulp::x86::V3::try_new() {
                let n = (v3.splat(-ratios.0), v3.splat(-ratios.1));
                let wide = unit_normals(v3, v3.load(&gi), v3.load(&gj), n).map(|v| v3.lanes(v));
                assert_eq!(
                    wide.map(|v| v.map(f32::to_bits)),
                    [x, y, z].map(|v| v.map(f32::to_bits))
                );
            }
            for l in 0..LANES {
                let one =
                    reconstruct_normal(gi[l] as i32, gj[l] as i32, ratios.0, ratios.1).normalize();
                let got = [x[l], y[l], z[l]].map(f32::to_bits);
                assert_eq!(got, one.to_array().map(f32::to_bits));
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
            let best = Isa::detect(true);
            let Some(level) = base_level(&patch) else {
                let none = compute_normal_cone(&d, cols, (0.1, 0.1), &DMat3::IDENTITY, best);
                assert!(none.is_none());
                continue;
            };
            let ratios = (0.01 + rng.unit() * 0.3, 0.01 + rng.unit() * 0.3);
            let scan = compute_normal_cone(&d, cols, ratios, &DMat3::IDENTITY, best).unwrap();
            // Every instruction set finds the same cone, bit for bit.
            let base = compute_normal_cone(&d, cols, ratios, &DMat3::IDENTITY, Isa::Base).unwrap();
            assert_eq!(base.cone.axis.to_array(), scan.cone.axis.to_array());
            assert_eq!(
                base.cone.half_angle.to_bits(),
                scan.cone.half_angle.to_bits()
            );
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
