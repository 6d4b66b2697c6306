//! Node traversal: the screen position and depth of every node of a piece
//! of patch, in fixed point.
//!
//! Two projections:
//! - **Trilinear** (the original work's shortcut): the 8 corners of the
//!   piece's bounding box (node range × displacement range, in patch space)
//!   are projected, and each node's screen position and depth are
//!   interpolated trilinearly from them — per node a few multiply-adds and
//!   no division. Depth is exact (it is affine in model space); x and y are
//!   not perspective-correct: the error grows with the square of the depth
//!   range of the piece over its distance (see `--stats` for its cost in
//!   PSNR). The three values of a node share four `f32` lanes and one
//!   packed truncation ([`crate::plan::lanes`], bit-identical to the scalar
//!   conversions of [`crate::fixed`]).
//! - **Exact**: each node is mapped to window clip coordinates by forward
//!   differences and divided by its depth (one reciprocal per node).
//!
//! Empty nodes and nodes of no drawable cell are written as
//! [`crate::fixed::EMPTY_NODE`]. The caller guarantees the
//! piece lies in front of the near plane (see [`crate::plan::cull`]).
//!
//! Cost: O(nodes), no allocation once warm (the output vector and the
//! scratch in [`NodeXY`] are reused): ≈ 41 instructions per trilinear node
//! on the sphere at 500² (callgrind, `profile_sphere 500 1`).

use glam::{BVec4A, Mat3, Vec3, Vec4};

use crate::fixed::{depth_to_fixed, position_to_fixed, Node, EMPTY_NODE, NODE_WIDTH};
use crate::grid::push_weights;
use crate::plan::lanes::{fixed_lanes, scaled_lanes, truncate_lanes4};
use crate::plan::node_xy::{NodeXY, RowLanes, RowStats};
use crate::plan::split::NodeRange;
use crate::prepare::mip::MipLevel;

/// The map from level-local coordinates `(i, j, d)` to `(X, Y, W)`, and
/// the depth normalization.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Projector {
    pub(crate) map: Mat3,
    pub(crate) t0: Vec3,
    /// Normalized depth = `W · z_scale + z_offset`.
    pub(crate) z_scale: f32,
    pub(crate) z_offset: f32,
}

impl Projector {
    /// Window position and normalized depth of a local point.
    #[inline]
    pub(crate) fn screen(&self, p: Vec3) -> Vec3 {
        let c = self.map * p + self.t0;
        let inv = 1.0 / c.z;
        Vec3::new(c.x * inv, c.y * inv, c.z * self.z_scale + self.z_offset)
    }
}

/// The local map of mip level `m` (node spacing `2^m`) from level 0's.
pub(crate) fn level_map(map: &Mat3, m: usize) -> Mat3 {
    let s = (1u32 << m) as f32;
    Mat3::from_cols(map.x_axis * s, map.y_axis * s, map.z_axis)
}

#[inline]
fn fixed_node(s: Vec3) -> Node {
    let mut n = [0; NODE_WIDTH];
    n[0] = position_to_fixed(s.x);
    n[1] = position_to_fixed(s.y);
    n[2] = depth_to_fixed(s.z);
    n
}

const EMPTY: Node = {
    let mut n = [0; NODE_WIDTH];
    n[0] = EMPTY_NODE;
    n
};

/// Projects every node of `range` exactly, appending to `out` (and the
/// positions to `xy`, see [`NodeXY`]).
pub(crate) fn project_nodes_exact(
    level: &MipLevel,
    range: NodeRange,
    p: &Projector,
    out: &mut Vec<Node>,
    xy: &mut NodeXY,
) {
    let [mi, md] = [p.map.x_axis, p.map.z_axis];
    let (cols, rows) = range.size();
    xy.reset(cols * rows);
    let mut at = 0;
    for j in range.j0..=range.j1 {
        let row = j * level.cols;
        let mut base = p.map * Vec3::new(range.i0 as f32, j as f32, 0.0) + p.t0;
        for k in row + range.i0..=row + range.i1 {
            let d = level.displacements[k];
            if level.used[k] {
                let c = base + md * d as f32;
                let inv = 1.0 / c.z;
                let n = fixed_node(Vec3::new(
                    c.x * inv,
                    c.y * inv,
                    c.z * p.z_scale + p.z_offset,
                ));
                (xy.xs[at], xy.ys[at]) = (n[0], n[1]);
                out.push(n);
            } else {
                out.push(EMPTY);
            }
            base += mi;
            at += 1;
        }
    }
}

/// Projects the nodes of `range` by trilinear interpolation of its box
/// corners (`d` is the range's displacement range), appending to `out`
/// (and the positions to `xy`, see [`NodeXY`]).
/// One function, though long: a hot kernel (every node a frame projects
/// passes through its inner loop).
#[inline(always)]
pub(crate) fn project_nodes_trilinear(
    level: &MipLevel,
    range: NodeRange,
    d: (u16, u16),
    p: &Projector,
    out: &mut Vec<Node>,
    xy: &mut NodeXY,
) {
    let c = projected_box_corners(range, d, p);
    let inv_i = 1.0 / (range.i1 - range.i0) as f32;
    let inv_j = 1.0 / (range.j1 - range.j0) as f32;
    let (cols, rows) = range.size();
    let count = cols * rows;
    xy.reset(count);
    // The weights along the displacement axis and the used flags: the
    // level's own for whole rows at the level's range (found once per
    // scene, on first use: [`MipLevel::weights`]), else computed into the
    // scratch. Why:
    // the pass cost ≈ 0.35 M instructions per 500² sphere frame
    // (callgrind, `profile_sphere 500 1`).
    let (ws, used) = if cols == level.cols && d == level.d_range {
        let nodes = range.j0 * cols..(range.j1 + 1) * cols;
        (&level.weights()[nodes.clone()], &level.used[nodes])
    } else {
        let (ws, used) = (&mut xy.ws, &mut xy.used);
        ws.clear();
        used.clear();
        for j in range.j0..=range.j1 {
            let row = j * level.cols;
            let nodes = row + range.i0..=row + range.i1;
            push_weights(&level.displacements[nodes.clone()], d, ws);
            used.extend_from_slice(&level.used[nodes]);
        }
        (&xy.ws[..], &xy.used[..])
    };
    // Every node's x and y are convex combinations of the corners' (row
    // lerps, steps along the row, the displacement weight in [0, 1]) up to
    // the rounding of at most `cols + 4` `f32` operations in a row of at
    // most 257 nodes (`GridSize::MAX_SIDE`), below 0.01 % of the largest
    // corner: corners below `LANE_SAFE_PX` (a NaN fails the test) keep
    // every node below 8193 px, its lanes below 2^30 (see
    // [`fixed_lanes`]). The depth lane is clamped (a NaN gives 0 in both
    // forms).
    let c = c.map(|pair| pair.map(|s| s.extend(0.0)));
    let bounded = c
        .iter()
        .flatten()
        .all(|s| (s.abs().cmplt(LANE_SAFE) | DEPTH_LANES).all());
    // Every cell drawable: every node is used.
    let all_used = level.drawable_cells as usize == (level.cols - 1) * (level.rows - 1);
    // Each row's first bottom and top points (`d` low and high) and their
    // steps: `Vec3::lerp`'s operations, lane by lane.
    xy.rows.clear();
    xy.rows.extend((range.j0..=range.j1).map(|j| {
        let v = (j - range.j0) as f32 * inv_j;
        let lerp = |a: Vec4, b: Vec4| a * (1.0 - v) + b * v;
        let b0 = lerp(c[0][0], c[1][0]);
        let b1 = lerp(c[0][1], c[1][1]);
        let t0 = lerp(c[2][0], c[3][0]);
        let t1 = lerp(c[2][1], c[3][1]);
        RowLanes {
            bottom: b0,
            top: t0,
            db: (b1 - b0) * inv_i,
            dt: (t1 - t0) * inv_i,
        }
    }));
    let piece = PieceLanes {
        rows: &xy.rows,
        cols,
        ws,
        used,
    };
    let (xs, ys) = (&mut xy.xs[..], &mut xy.ys[..]);
    let stats = &mut xy.row_stats;
    stats.clear();
    if bounded {
        stats.resize(xy.rows.len(), RowStats::EMPTY);
    }
    let stats = &mut stats[..];
    match (bounded, all_used) {
        (true, true) => piece.project::<false, true>(out, xs, ys, stats),
        (true, false) => piece.project::<false, false>(out, xs, ys, stats),
        (false, _) => piece.project::<true, false>(out, xs, ys, stats),
    }
}

/// Corners below this many pixels from the origin (in x and y) keep every
/// trilinear node's fixed-point lanes below 2^31 (see
/// [`project_nodes_trilinear`]).
const LANE_SAFE_PX: f32 = 8192.0;
/// [`LANE_SAFE_PX`] in the x and y lanes.
const LANE_SAFE: Vec4 = Vec4::new(LANE_SAFE_PX, LANE_SAFE_PX, 0.0, 0.0);
/// The lanes the bound does not apply to (depth, w).
const DEPTH_LANES: BVec4A = BVec4A::new(false, false, true, true);

/// A piece's trilinear rows and its nodes' weights and used flags (row
/// after row, `cols` per row).
struct PieceLanes<'a> {
    rows: &'a [RowLanes],
    cols: usize,
    ws: &'a [f32],
    used: &'a [bool],
}

impl PieceLanes<'_> {
    /// Appends the piece's nodes to `out` and writes the used ones'
    /// positions to `xs` and `ys`. `CHECKED`: lanes may exceed 2^31 (see
    /// [`fixed_lanes`]); `ALL_USED`: every node is used. Why the steps
    /// accumulate: the same sums, in the same order, as the `Vec3` form
    /// this replaced (images bit-identical). Why one `extend` over the
    /// whole piece: one capacity check, each node written once (attribute
    /// words included), and a row change costs a compare per node instead
    /// of a loop set-up per row (callgrind, `profile_sphere 500 1`).
    /// With `CHECKED` off, `stats` receives each node row's [`RowStats`].
    #[inline(always)]
    fn project<const CHECKED: bool, const ALL_USED: bool>(
        self,
        out: &mut Vec<Node>,
        xs: &mut [i32],
        ys: &mut [i32],
        stats: &mut [RowStats],
    ) {
        let Self {
            rows,
            cols,
            ws,
            used,
        } = self;
        let Some(&first) = rows.first() else {
            return;
        };
        let RowLanes {
            mut bottom,
            mut top,
            mut db,
            mut dt,
        } = first;
        let (mut row, mut col) = (0, 0);
        // The row's smallest and largest scaled lanes and used nodes. Why
        // here: truncation is monotonic, so the truncated extremes are the
        // extremes of the truncated positions, two packed operations per
        // node where the measurement scanned every row again (callgrind,
        // `profile_sphere 500 1`).
        let (mut lo, mut hi, mut count) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0u32);
        let nodes = ws.iter().zip(used).zip(xs.iter_mut().zip(ys.iter_mut()));
        out.extend(nodes.map(move |((&w, &u), (x, y))| {
            let mut node = EMPTY;
            if ALL_USED || u {
                let s = bottom + (top - bottom) * w;
                // Lane `w` is 0: the node's fourth word.
                let [fx, fy, fz, fw] = if CHECKED {
                    let [fx, fy, fz] = fixed_lanes(s);
                    [fx, fy, fz, 0]
                } else {
                    let q = scaled_lanes(s);
                    (lo, hi) = (lo.min(q), hi.max(q));
                    count += !ALL_USED as u32;
                    truncate_lanes4(q)
                };
                node = [fx, fy, fz, fw];
                (*x, *y) = (fx, fy);
            }
            bottom += db;
            top += dt;
            col += 1;
            if col == cols {
                if let (false, Some(out)) = (CHECKED, stats.get_mut(row)) {
                    let used = if ALL_USED { cols as u32 } else { count };
                    *out = RowStats::of(lo, hi, used);
                    (lo, hi, count) = (Vec4::INFINITY, Vec4::NEG_INFINITY, 0);
                }
                (row, col) = (row + 1, 0);
                if let Some(&next) = rows.get(row) {
                    (bottom, top, db, dt) = (next.bottom, next.top, next.db, next.dt);
                }
            }
            node
        }));
    }
}

/// Depth units (fixed point) by which a node's depth may come out nearer
/// than its box's nearest corner: `f32` rounding of the corners and of the
/// node lanes (a few units at depths up to 2^28) and the forward
/// differencing of sub-nodes (one unit per step, fewer than 1024 steps).
const BOX_DEPTH_SLACK: i32 = 1 << 12;

/// A lower bound (fixed point) of the depth of every node of `range`
/// over displacements `d`, and of every sample drawn between them: the
/// nearest corner of the piece's box, less [`BOX_DEPTH_SLACK`]. Depth is
/// linear in the local position, so no point of the box is nearer than
/// its nearest corner, whether nodes are projected exactly or trilinearly
/// (trilinear nodes are convex combinations of the corners).
pub(crate) fn nearest_box_depth(range: NodeRange, d: (u16, u16), p: &Projector) -> i32 {
    let corners = projected_box_corners(range, d, p);
    let near = corners
        .iter()
        .flatten()
        .fold(f32::INFINITY, |m, c| m.min(c.z));
    depth_to_fixed(near).saturating_sub(BOX_DEPTH_SLACK)
}

/// The screen corners of a piece's box over displacements `d`:
/// `[bottom i0, bottom i1]` at `j0` and at `j1` (low `d`), then the same
/// at high `d`.
#[inline(always)]
fn projected_box_corners(range: NodeRange, d: (u16, u16), p: &Projector) -> [[Vec3; 2]; 4] {
    let (lo, hi) = range.local_box(d);
    let corner = |a: bool, b: bool, c: bool| {
        p.screen(Vec3::new(
            if a { hi.x } else { lo.x },
            if b { hi.y } else { lo.y },
            if c { hi.z } else { lo.z },
        ))
    };
    [
        [corner(false, false, false), corner(true, false, false)],
        [corner(false, true, false), corner(true, true, false)],
        [corner(false, false, true), corner(true, false, true)],
        [corner(false, true, true), corner(true, true, true)],
    ]
}

/// The straightforward trilinear projection that
/// [`project_nodes_trilinear`] must equal bit for bit (the reference of its
/// tests): per node, `Vec3` lanes and the scalar conversions of
/// [`crate::fixed`].
#[cfg(test)]
pub(crate) fn project_nodes_trilinear_reference(
    level: &MipLevel,
    range: NodeRange,
    d: (u16, u16),
    p: &Projector,
    out: &mut Vec<Node>,
) {
    let c = projected_box_corners(range, d, p);
    let inv_i = 1.0 / (range.i1 - range.i0) as f32;
    let inv_j = 1.0 / (range.j1 - range.j0) as f32;
    let inv_d = if d.1 > d.0 {
        1.0 / (d.1 - d.0) as f32
    } else {
        0.0
    };
    for j in range.j0..=range.j1 {
        let v = (j - range.j0) as f32 * inv_j;
        let b0 = c[0][0].lerp(c[1][0], v);
        let b1 = c[0][1].lerp(c[1][1], v);
        let t0 = c[2][0].lerp(c[3][0], v);
        let t1 = c[2][1].lerp(c[3][1], v);
        let (db, dt) = ((b1 - b0) * inv_i, (t1 - t0) * inv_i);
        let (mut bottom, mut top) = (b0, t0);
        for k in j * level.cols + range.i0..=j * level.cols + range.i1 {
            if level.used[k] {
                let w = (level.displacements[k] - d.0) as f32 * inv_d;
                out.push(fixed_node(bottom + (top - bottom) * w));
            } else {
                out.push(EMPTY);
            }
            bottom += db;
            top += dt;
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::test_rng::XorShift;
    use spatch_format::{Frame, GridSize, Patch};

    /// The mip levels of a random patch of 2–18 × 2–18 nodes, `holes` % of
    /// them empty, displacements below 400.
    pub(crate) fn random_levels(rng: &mut XorShift, holes: u64) -> Vec<MipLevel> {
        let (cols, rows) = (2 + rng.below64(17) as usize, 2 + rng.below64(17) as usize);
        let d: Vec<u16> = (0..cols * rows)
            .map(|_| {
                if rng.below64(100) < holes {
                    spatch_format::EMPTY
                } else {
                    rng.below64(400) as u16
                }
            })
            .collect();
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let grid = GridSize::new(cols as u32, rows as u32).unwrap();
        let patch = Patch::new(frame, grid, d, None).unwrap();
        crate::prepare::mip::build_mip_pyramid(&patch)
    }

    /// A random part of `level`, at least one cell.
    pub(crate) fn random_part(rng: &mut XorShift, level: &MipLevel) -> NodeRange {
        let i0 = rng.below64(level.cols as u64 - 1) as usize;
        let j0 = rng.below64(level.rows as u64 - 1) as usize;
        let i1 = i0 + 1 + rng.below64((level.cols - 1 - i0) as u64) as usize;
        let j1 = j0 + 1 + rng.below64((level.rows - 1 - j0) as u64) as usize;
        NodeRange { i0, j0, i1, j1 }
    }

    /// The lane-wise trilinear projection writes the same nodes and
    /// positions, bit for bit, as the straightforward `Vec3` form, on
    /// random pieces (with and without empty nodes, whole and part
    /// levels) and maps with small and huge screen coordinates (the checked
    /// path).
    #[test]
    fn trilinear_lanes_equal_the_reference() {
        let mut rng = XorShift(0x1357_9bdf_2468_ace0);
        for case in 0..400 {
            let levels = random_levels(&mut rng, [0, 0, 5, 30][case % 4]);
            let Some(level) = levels.first() else {
                continue;
            };
            let scale = [8.0, 8.0, 3000.0, 1e6][case % 4 / 2 * 2 + (case / 4) % 2];
            let mut r = |s: f32| (rng.unit() - 0.5) * s;
            let p = Projector {
                map: Mat3::from_cols(
                    Vec3::new(scale + r(6.0), r(6.0), r(0.02)),
                    Vec3::new(r(6.0), scale + r(6.0), r(0.02)),
                    Vec3::new(r(0.2), r(0.2), r(0.001)),
                ),
                t0: Vec3::new(r(200.0), r(200.0), 2.0),
                z_scale: 0.1 + r(0.1),
                z_offset: r(0.5),
            };
            let whole = NodeRange::whole(level);
            for range in [whole, random_part(&mut rng, level)] {
                let Some(dr) = range.d_range(level) else {
                    continue;
                };
                let (mut want, mut got) = (vec![EMPTY], vec![EMPTY]);
                project_nodes_trilinear_reference(level, range, dr, &p, &mut want);
                let mut xy = NodeXY::default();
                project_nodes_trilinear(level, range, dr, &p, &mut got, &mut xy);
                assert_eq!(got, want, "case {case} {range:?}");
                for (k, n) in want[1..].iter().enumerate() {
                    if n[0] != EMPTY_NODE {
                        assert_eq!((xy.xs[k], xy.ys[k]), (n[0], n[1]), "case {case}");
                    }
                }
            }
        }
    }
}
