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
//!   packed truncation (bit-identical to the scalar conversions of
//!   [`crate::fixed`]).
//! - **Exact**: each node is mapped to window clip coordinates by forward
//!   differences and divided by its depth (one reciprocal per node).
//!
//! Empty nodes and nodes of no drawable cell are written as
//! [`EMPTY_NODE`](crate::fixed::EMPTY_NODE). The caller guarantees the
//! piece lies in front of the near plane (see [`crate::cull`]).
//!
//! [`measure_cells`] then finds the largest projected cell extent (which
//! sets the subdivision) and the screen bounding box. Cost: O(nodes), no
//! allocation once warm (the output vector and the scratch in [`NodeXY`]
//! are reused): ≈ 41 instructions per trilinear node and ≈ 27 per node of
//! measurement on the sphere at 500² (callgrind, `profile_sphere 500 1`).

use glam::{BVec4A, Mat3, Vec3, Vec4};

use crate::fixed::{depth_to_fixed, position_to_fixed, EMPTY_NODE, XY_ONE, Z_FAR};
use crate::mip::MipLevel;
use crate::split::NodeRange;

/// Values per projected node: x, y, depth (fixed point), then up to 6
/// attributes (float bits, see [`crate::fixed::attr_to_bits`]).
pub(crate) const NODE_WIDTH: usize = 9;
/// A projected node (fixed point; see [`crate::fixed`]).
pub(crate) type Node = [i32; NODE_WIDTH];

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

#[inline]
fn fixed_node(s: Vec3) -> Node {
    let mut n = [0; NODE_WIDTH];
    n[0] = position_to_fixed(s.x);
    n[1] = position_to_fixed(s.y);
    n[2] = depth_to_fixed(s.z);
    n
}

/// Lower and upper clamps of [`fixed_lanes`]: the depth lane only.
const LANE_LO: Vec4 = Vec4::new(f32::NEG_INFINITY, f32::NEG_INFINITY, 0.0, 0.0);
const LANE_HI: Vec4 = Vec4::new(f32::INFINITY, f32::INFINITY, 2.0, 0.0);
/// Fixed-point scales of [`fixed_lanes`]: positions, depth.
const LANE_SCALE: Vec4 = Vec4::new(XY_ONE, XY_ONE, Z_FAR as f32, 0.0);

/// The fixed-point `[x, y, depth]` of a screen point in lanes `x, y, z`
/// (lane `w` 0): exactly `position_to_fixed(s.x)`,
/// `position_to_fixed(s.y)`, `depth_to_fixed(s.z)`, for every input.
///
/// Why: the saturating `as` conversions stay scalar (five instructions
/// each plus the repacking; callgrind, `profile_sphere 500 1`). When every
/// lane is below 2^31 in magnitude (always, inside the guard band), the
/// lanes are truncated in one packed step ([`Vec4::trunc`]: `cvttps2dq`
/// and back, exact) and read as integers by adding `1.5 · 2^52` in `f64`,
/// which puts an integer below 2^51 in the low mantissa bits, two's
/// complement; other inputs (huge, infinite, NaN) take the scalar form.
#[inline(always)]
fn fixed_lanes(s: Vec4) -> [i32; 3] {
    const LIMIT: f32 = 2_147_483_648.0; // 2^31
    let q = scaled_lanes(s);
    if q.abs().cmplt(Vec4::splat(LIMIT)).all() {
        truncate_lanes(q)
    } else {
        [
            position_to_fixed(s.x),
            position_to_fixed(s.y),
            depth_to_fixed(s.z),
        ]
    }
}

/// [`fixed_lanes`] for a point whose lanes are known to stay below 2^31
/// once scaled (and finite).
#[cfg(test)]
fn fixed_lanes_in_range(s: Vec4) -> [i32; 3] {
    truncate_lanes(scaled_lanes(s))
}

/// The lanes [`fixed_lanes`] truncates: positions in 1/65536 px, depth
/// clamped to `[0, 2]` and in units of [`Z_FAR`].
#[inline(always)]
fn scaled_lanes(s: Vec4) -> Vec4 {
    s.max(LANE_LO).min(LANE_HI) * LANE_SCALE
}

/// Lanes `x, y, z` of `q` (each below 2^31 in magnitude) truncated to
/// integers (see [`fixed_lanes`]).
#[inline(always)]
fn truncate_lanes(q: Vec4) -> [i32; 3] {
    let b = truncate_lanes4(q);
    [b[0], b[1], b[2]]
}

/// The four lanes of `q` (each below 2^31 in magnitude) truncated to
/// integers. Why all four: the two halves convert as two packed `f64`
/// pairs and store as one word group (callgrind, `profile_sphere 500 1`).
#[inline(always)]
fn truncate_lanes4(q: Vec4) -> [i32; 4] {
    const MAGIC: f64 = 6_755_399_441_055_744.0; // 1.5 · 2^52
    let t = q.trunc().to_array();
    let bits = |v: f32| (v as f64 + MAGIC).to_bits() as i32;
    [bits(t[0]), bits(t[1]), bits(t[2]), bits(t[3])]
}

const EMPTY: Node = {
    let mut n = [0; NODE_WIDTH];
    n[0] = EMPTY_NODE;
    n
};

/// The fixed-point screen positions of the last projected piece, one row
/// of nodes after another (`x` in `xs`, `y` in `ys`, 0 for unused nodes):
/// the same values as the nodes' first two words, laid out for
/// [`measure_cells`]. Why: the measurement reads them a row pair at a time
/// in plain `i32` lanes instead of striding over 36-byte nodes (callgrind,
/// `profile_sphere 500 1`).
#[derive(Debug, Default)]
pub(crate) struct NodeXY {
    pub(crate) xs: Vec<i32>,
    pub(crate) ys: Vec<i32>,
    /// Scratch of the trilinear projection: per node the displacement
    /// weight and the used flag, per row its lanes.
    ws: Vec<f32>,
    used: Vec<bool>,
    rows: Vec<RowLanes>,
    /// Scratch of [`measure_cells`]: per node, 0 at the end of a row,
    /// else all ones.
    wrap: Vec<i32>,
    /// The row length `wrap` was made for.
    wrap_cols: usize,
    /// Scratch of [`measure_cells`]: per node, all ones when its u (v)
    /// edge belongs to a drawn cell.
    umask: Vec<i32>,
    vmask: Vec<i32>,
    /// Scratch of [`measure_cells`]: per cell, 1 when it faces away (see
    /// [`away_cells_small`]).
    away: Vec<u8>,
    /// Per node row, its used positions' box and count, when the
    /// projection found them (the trilinear one within range; else empty,
    /// and [`measure_cells`] scans the positions).
    pub(crate) row_stats: Vec<RowStats>,
}

impl NodeXY {
    /// Clears and sizes both arrays for `len` nodes (all 0), and forgets
    /// the row boxes of the previous piece.
    fn reset(&mut self, len: usize) {
        self.row_stats.clear();
        self.xs.clear();
        self.xs.resize(len, 0);
        self.ys.clear();
        self.ys.resize(len, 0);
    }
}

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
    let cols = range.i1 - range.i0 + 1;
    xy.reset(cols * (range.j1 - range.j0 + 1));
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
    let cols = range.i1 - range.i0 + 1;
    let count = cols * (range.j1 - range.j0 + 1);
    xy.reset(count);
    // The weights along the displacement axis and the used flags: the
    // level's own for whole rows at the level's range (prepared once per
    // scene: [`MipLevel::weights`]), else computed into the scratch. Why:
    // the pass cost ≈ 0.35 M instructions per 500² sphere frame
    // (callgrind, `profile_sphere 500 1`).
    let (ws, used) = if cols == level.cols && d == level.d_range {
        let nodes = range.j0 * cols..(range.j1 + 1) * cols;
        (&level.weights[nodes.clone()], &level.used[nodes])
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

/// Appends the trilinear weights of displacements `disp` along the range
/// `d` (`(dk - d.0) / (d.1 - d.0)`, 0 when the range is flat; meaningless
/// for empty nodes) to `out`, in the operations of the `Vec3` form. Why a
/// pass of its own: it converts in vector lanes.
pub(crate) fn push_weights(disp: &[u16], d: (u16, u16), out: &mut Vec<f32>) {
    let inv_d = if d.1 > d.0 {
        1.0 / (d.1 - d.0) as f32
    } else {
        0.0
    };
    out.extend(disp.iter().map(|&dk| dk.wrapping_sub(d.0) as f32 * inv_d));
}

/// Corners below this many pixels from the origin (in x and y) keep every
/// trilinear node's fixed-point lanes below 2^31 (see
/// [`project_nodes_trilinear`]).
const LANE_SAFE_PX: f32 = 8192.0;
/// [`LANE_SAFE_PX`] in the x and y lanes.
const LANE_SAFE: Vec4 = Vec4::new(LANE_SAFE_PX, LANE_SAFE_PX, 0.0, 0.0);
/// The lanes the bound does not apply to (depth, w).
const DEPTH_LANES: BVec4A = BVec4A::new(false, false, true, true);

/// One row of trilinear nodes in lanes `x, y, depth, 0`: the bottom and
/// top points of its first node and their steps per node.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowLanes {
    bottom: Vec4,
    top: Vec4,
    db: Vec4,
    dt: Vec4,
}

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
                // Lane `w` is 0: the fourth word is the first attribute's 0.
                let [fx, fy, fz, fw] = if CHECKED {
                    let [fx, fy, fz] = fixed_lanes(s);
                    [fx, fy, fz, 0]
                } else {
                    let q = scaled_lanes(s);
                    (lo, hi) = (lo.min(q), hi.max(q));
                    count += !ALL_USED as u32;
                    truncate_lanes4(q)
                };
                node = [fx, fy, fz, fw, 0, 0, 0, 0, 0];
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

/// One node row's used positions: the box `[x_lo, y_lo, x_hi, y_hi]`
/// (empty: `[MAX, MAX, MIN, MIN]`) and the used count.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RowStats {
    pub(crate) bbox: [i32; 4],
    pub(crate) used: u32,
}

impl RowStats {
    /// A row without used nodes.
    const EMPTY: RowStats = RowStats {
        bbox: [i32::MAX, i32::MAX, i32::MIN, i32::MIN],
        used: 0,
    };

    /// From the row's smallest and largest scaled lanes (see
    /// [`scaled_lanes`]) over `count` used nodes.
    #[inline(always)]
    fn of(lo: Vec4, hi: Vec4, count: u32) -> Self {
        if count == 0 {
            return Self::EMPTY;
        }
        let (lo, hi) = (truncate_lanes(lo), truncate_lanes(hi));
        Self {
            bbox: [lo[0], lo[1], hi[0], hi[1]],
            used: count,
        }
    }
}

/// The screen corners of a piece's box over displacements `d`:
/// `[bottom i0, bottom i1]` at `j0` and at `j1` (low `d`), then the same
/// at high `d`.
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

/// Cell flag: the cell is drawn (its four corners are used and, with
/// back-face culling, it does not face away everywhere).
pub(crate) const CELL_DRAW: u8 = 1;
/// Cell flag: the cell also places its last column of sub-nodes (its right
/// neighbour is not drawn).
pub(crate) const CELL_RIGHT: u8 = 2;
/// Cell flag: the cell also places its last row of sub-nodes.
pub(crate) const CELL_TOP: u8 = 4;

/// Projected size of a piece's cells and its screen box.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CellMeasure {
    /// Largest |x| and |y| of the drawn cells' u edges and v edges (fixed
    /// point): `[ux, uy, vx, vy]`.
    pub(crate) edges: [i64; 4],
    pub(crate) drawable_cells: u64,
    /// Drawn cells that draw their right column / top row / both (see
    /// [`crate::cell_bilinear`]).
    pub(crate) right_edges: u64,
    pub(crate) top_edges: u64,
    pub(crate) both_edges: u64,
    /// Cells left out because they face away from the eye everywhere.
    pub(crate) backfacing_cells: u64,
    pub(crate) used_nodes: u64,
    /// Pixel box of the used nodes: x0, y0, x1, y1 (inclusive).
    pub(crate) bbox: [i32; 4],
}

impl CellMeasure {
    /// Nothing measured yet (an empty box).
    const EMPTY: CellMeasure = CellMeasure {
        edges: [0; 4],
        drawable_cells: 0,
        right_edges: 0,
        top_edges: 0,
        both_edges: 0,
        backfacing_cells: 0,
        used_nodes: 0,
        bbox: [i32::MAX, i32::MAX, i32::MIN, i32::MIN],
    };

    /// Sub-nodes placed when every cell is cut into `nu × nv`.
    pub(crate) fn refined_nodes(&self, nu: u64, nv: u64) -> u64 {
        self.drawable_cells * nu * nv
            + nv * self.right_edges
            + nu * self.top_edges
            + self.both_edges
    }
}

/// True when the four corners of the cell whose (0, 0) node is `k` are used.
#[inline]
pub(crate) fn cell_drawable(nodes: &[Node], k: usize, cols: usize) -> bool {
    nodes[k][0] != EMPTY_NODE
        && nodes[k + 1][0] != EMPTY_NODE
        && nodes[k + cols][0] != EMPTY_NODE
        && nodes[k + cols + 1][0] != EMPTY_NODE
}

/// Marks which drawn cells of a `ccols × crows` flag array close their
/// right column ([`CELL_RIGHT`]: the next cell of the row is not drawn)
/// and their top row ([`CELL_TOP`]: the cell above is not drawn). Returns
/// the counts of right, top and both.
pub(crate) fn close_cells(cell_flags: &mut [u8], ccols: usize, crows: usize) -> [u64; 3] {
    let mut counts = [0u64; 3];
    // Why byte arithmetic on row slices: no branch or bounds check per cell
    // (callgrind, `profile_sphere 500 1`: ~4 M instructions per frame
    // before).
    for j in 0..crows {
        let (head, tail) = cell_flags.split_at_mut((j + 1) * ccols);
        let row = &mut head[j * ccols..];
        let above: &[u8] = if j + 1 < crows { &tail[..ccols] } else { &[] };
        // The next cell's and the upper cell's drawn bits, 0 past the end.
        let mut next = [0u8; 64];
        let mut over = [0u8; 64];
        if ccols <= next.len() {
            next[..ccols - 1].copy_from_slice(&row[1..]);
            if !above.is_empty() {
                over[..ccols].copy_from_slice(above);
            }
            let (next, over) = (&next[..ccols], &over[..ccols]);
            let (mut right_n, mut top_n, mut both_n) = (0u32, 0u32, 0u32);
            for ((f, &n), &o) in row.iter_mut().zip(next).zip(over) {
                let drawn = *f & CELL_DRAW;
                let (right, top) = (drawn & !n, drawn & !o);
                *f |= (right * CELL_RIGHT) | (top * CELL_TOP);
                right_n += right as u32;
                top_n += top as u32;
                both_n += (right & top) as u32;
            }
            counts[0] += right_n as u64;
            counts[1] += top_n as u64;
            counts[2] += both_n as u64;
            continue;
        }
        for i in 0..ccols {
            let drawn = row[i] & CELL_DRAW;
            let next = row.get(i + 1).map_or(0, |f| f & CELL_DRAW);
            let over = above.get(i).map_or(0, |f| f & CELL_DRAW);
            let (right, top) = (drawn & !next, drawn & !over);
            row[i] |= (right * CELL_RIGHT) | (top * CELL_TOP);
            counts[0] += right as u64;
            counts[1] += top as u64;
            counts[2] += (right & top) as u64;
        }
    }
    counts
}

/// Measures the projected cells of `range` of `level`, whose node
/// positions are in `xy` (see [`NodeXY`]), and appends one flag byte per
/// cell (row-major, [`CELL_DRAW`], [`CELL_RIGHT`], [`CELL_TOP`]) to
/// `flags`, and per row of cells the pixel rows its used nodes span
/// (`[lo, hi]`, inclusive; empty rows give `lo > hi`) to `spans`.
///
/// With `back_sign` ±1 (back-face culling on: the sign of the local map's
/// determinant), a cell is left out when the screen cross product of its
/// edges has that sign at all four corners: the Jacobian determinant of a
/// bilinear cell is bilinear in `(s, t)`, so the whole drawn cell then faces
/// away from the eye (a front-facing cell of the closed surface covers the
/// same pixels). `back_sign = 0` keeps every cell with four used corners.
///
/// The same decisions as the straightforward measurement over the node
/// array ([`measure_cells_reference`], kept for the tests), in fewer
/// instructions. Why (callgrind, `profile_sphere 500 1`; ≈ 155
/// instructions per cell before): which cells have four used corners, and
/// their closing flags without back-face culling, come from the level
/// ([`MipLevel::cell_flags`]); the row boxes come from the projection when
/// it kept them ([`NodeXY::row_stats`]); on pieces spanning less than
/// 2^24 units (256 px) the back-face test runs in `f64` lanes
/// ([`away_cells_small`]) and the largest edges in flat `f32` passes over
/// the whole piece ([`piece_edges_small`], [`piece_edges_masked_small`]);
/// wider pieces take them row by row in `i32` or `i64`.
pub(crate) fn measure_cells(
    level: &MipLevel,
    range: NodeRange,
    xy: &mut NodeXY,
    back_sign: i64,
    flags: &mut Vec<u8>,
    spans: &mut Vec<[i32; 2]>,
) -> CellMeasure {
    let (cols, rows) = (range.i1 - range.i0 + 1, range.j1 - range.j0 + 1);
    let (ccols, crows) = (cols - 1, rows - 1);
    let (lcols, lccols) = (level.cols, level.cols - 1);
    let mut m = CellMeasure::EMPTY;
    // Node rows: the used nodes' box and the pixel rows of each row of cells.
    let (mut x0, mut y0, mut x1, mut y1) = (i32::MAX, i32::MAX, i32::MIN, i32::MIN);
    let first_span = spans.len();
    spans.resize(first_span + crows, [i32::MAX, i32::MIN]);
    // Each row's box and count: from the projection when it kept them,
    // else from the positions.
    if xy.row_stats.len() != rows {
        xy.row_stats.clear();
        for j in 0..rows {
            let (xl, xh, lo, hi, n) = row_box(
                &level.used[(range.j0 + j) * lcols + range.i0..][..cols],
                &xy.xs[j * cols..][..cols],
                &xy.ys[j * cols..][..cols],
            );
            xy.row_stats.push(RowStats {
                bbox: [xl, lo, xh, hi],
                used: n as u32,
            });
        }
    }
    let stats = &xy.row_stats[..rows];
    // Why separate passes over the row boxes: no branch or index check per
    // row (callgrind, `profile_sphere 500 1`).
    for (span, pair) in spans[first_span..].iter_mut().zip(stats.windows(2)) {
        let (a, b) = (pair[0].bbox, pair[1].bbox);
        *span = [a[1].min(b[1]) >> 16, a[3].max(b[3]) >> 16];
    }
    for s in stats {
        (x0, y0) = (x0.min(s.bbox[0]), y0.min(s.bbox[1]));
        (x1, y1) = (x1.max(s.bbox[2]), y1.max(s.bbox[3]));
        m.used_nodes += s.used as u64;
    }
    if m.used_nodes > 0 {
        m.bbox = [x0 >> 16, y0 >> 16, x1 >> 16, y1 >> 16];
    }
    // Differences of two used positions fit in `i32` when the box does
    // (always within the guard band; else the `i64` form).
    let narrow = m.used_nodes > 0
        && (x1 as i64 - x0 as i64) <= i32::MAX as i64
        && (y1 as i64 - y0 as i64) <= i32::MAX as i64;
    // And they are exact in `f32` below 2^24 units (256 pixels).
    let small = narrow && (x1 as i64 - x0 as i64) < 1 << 24 && (y1 as i64 - y0 as i64) < 1 << 24;
    let base = flags.len();
    let whole = range.i0 == 0 && range.j0 == 0 && cols == lcols && rows == level.rows;
    let out = if whole && back_sign == 0 {
        // No back-face test on the whole level: the level's flags as they are.
        flags.extend_from_slice(&level.cell_flags);
        m.drawable_cells = level.drawable_cells as u64;
        &mut flags[base..]
    } else {
        flags.resize(base + ccols * crows, 0);
        let out = &mut flags[base..];
        if small && back_sign != 0 {
            // Which cells face away, for the whole piece in `f64` lanes.
            // Why: the `i64` test per cell cost ≈ 40 instructions (2.7 M
            // per 500² sphere frame; callgrind, `profile_sphere 500 1`).
            xy.away.clear();
            xy.away.resize(crows * cols - 1, 0);
            if back_sign > 0 {
                away_cells_small::<1>(&xy.xs, &xy.ys, cols, &mut xy.away);
            } else {
                away_cells_small::<-1>(&xy.xs, &xy.ys, cols, &mut xy.away);
            }
        }
        for (cj, row) in out.chunks_exact_mut(ccols).enumerate() {
            let mask = &level.cell_flags[(range.j0 + cj) * lccols + range.i0..][..ccols];
            if small && back_sign != 0 {
                let away = &xy.away[cj * cols..][..ccols];
                let (mut drawn, mut back) = (0u32, 0u32);
                for ((f, &mask), &away) in row.iter_mut().zip(mask).zip(away) {
                    let candidate = mask & CELL_DRAW;
                    *f = candidate & !away;
                    drawn += *f as u32;
                    back += (candidate & away) as u32;
                }
                m.drawable_cells += drawn as u64;
                m.backfacing_cells += back as u64;
                continue;
            }
            let (lo, hi) = (cj * cols, (cj + 1) * cols);
            let (xl, yl) = (&xy.xs[lo..lo + cols], &xy.ys[lo..lo + cols]);
            let (xh, yh) = (&xy.xs[hi..hi + cols], &xy.ys[hi..hi + cols]);
            let (drawn, back) = match back_sign {
                1 => mark_row::<1>(xl, yl, xh, yh, mask, row),
                -1 => mark_row::<-1>(xl, yl, xh, yh, mask, row),
                _ => mark_row::<0>(xl, yl, xh, yh, mask, row),
            };
            m.drawable_cells += drawn;
            m.backfacing_cells += back;
        }
        out
    };
    let mut edges = [0u64; 4];
    let all_drawn = m.drawable_cells as usize == ccols * crows;
    if small && all_drawn {
        // Every cell drawn: every edge of the piece, in flat passes. Why:
        // rows of 17 nodes left a set-up and a remainder per row and per
        // edge component (callgrind, `profile_sphere 500 1`).
        if (xy.wrap.len(), xy.wrap_cols) != (cols * rows, cols) {
            xy.wrap_cols = cols;
            xy.wrap.clear();
            xy.wrap
                .extend((0..cols * rows).map(|k| -((k % cols != cols - 1) as i32)));
        }
        edges = piece_edges_small(&xy.xs, &xy.ys, cols, &xy.wrap);
    } else if small && m.drawable_cells > 0 {
        // Some cells not drawn: the same passes, each edge masked by
        // whether a drawn cell has it. Why: as above, for the pieces the
        // back-face test cut (callgrind, `profile_sphere 500 1`).
        // The level's own masks when its flags are the piece's (a whole
        // level with trimmed cells, no cell facing away). Why: building
        // them per frame cost ≈ 2 M instructions on the trimmed sphere
        // (callgrind, `profile_sphere 500 1 1 trimmed`).
        let (um, vm) = match &level.edge_masks {
            Some((um, vm)) if whole && back_sign == 0 => (um, vm),
            _ => {
                drawn_edge_masks(out, cols, rows, &mut xy.umask, &mut xy.vmask);
                (&xy.umask, &xy.vmask)
            }
        };
        edges = piece_edges_masked_small(&xy.xs, &xy.ys, cols, um, vm);
    }
    for (cj, row) in out.chunks_exact(ccols).enumerate() {
        // Done by the flat passes, or no cell drawn (no edge, nothing to
        // close: such a piece is dropped).
        if small || m.drawable_cells == 0 {
            break;
        }
        let (lo, hi) = (cj * cols, (cj + 1) * cols);
        let (xl, yl) = (&xy.xs[lo..lo + cols], &xy.ys[lo..lo + cols]);
        let (xh, yh) = (&xy.xs[hi..hi + cols], &xy.ys[hi..hi + cols]);
        let e = if narrow {
            row_edges_narrow(xl, yl, xh, yh, row)
        } else {
            row_edges_wide(xl, yl, xh, yh, row)
        };
        for (a, b) in edges.iter_mut().zip(e) {
            *a = (*a).max(b);
        }
    }
    m.edges = edges.map(|e| e as i64);
    // Closing flags: the level's own when the piece is the whole level and
    // no cell faced away.
    let [right, top, both] = if whole && m.backfacing_cells == 0 {
        out.copy_from_slice(&level.cell_flags);
        level.closing
    } else if m.drawable_cells == 0 {
        [0; 3]
    } else {
        close_cells(out, ccols, crows)
    };
    (m.right_edges, m.top_edges, m.both_edges) = (right, top, both);
    m
}

/// Per node of a `cols × rows` piece with cell flags `flags`: in `um`,
/// all ones when a drawn cell has the u edge starting there, and in `vm`
/// the same for the v edge (see [`piece_edges_masked_small`]).
pub(crate) fn drawn_edge_masks(
    flags: &[u8],
    cols: usize,
    rows: usize,
    um: &mut Vec<i32>,
    vm: &mut Vec<i32>,
) {
    um.clear();
    um.resize(cols * rows, 0);
    vm.clear();
    vm.resize(cols * rows, 0);
    for (cj, row) in flags.chunks_exact(cols - 1).enumerate() {
        let (lo, hi) = (cj * cols, (cj + 1) * cols);
        let (ul, uh) = um[lo..hi + cols].split_at_mut(cols);
        let vl = &mut vm[lo..hi];
        for (i, &f) in row.iter().enumerate() {
            let d = -((f & CELL_DRAW) as i32);
            ul[i] |= d;
            uh[i] |= d;
            vl[i] |= d;
            vl[i + 1] |= d;
        }
    }
}

/// The used positions of one node row: smallest and largest x, smallest
/// and largest y (`MAX, MIN` when none) and the used count.
fn row_box(used: &[bool], xs: &[i32], ys: &[i32]) -> (i32, i32, i32, i32, usize) {
    let n = used.iter().filter(|&&u| u).count();
    if n == xs.len() {
        // Why a plain pass for full rows: it runs in vector lanes
        // (callgrind, `profile_sphere 500 1`).
        let ((xl, xh), (lo, hi)) = (min_max(xs), min_max(ys));
        return (xl, xh, lo, hi, n);
    }
    let (mut lo, mut hi, mut xl, mut xh) = (i32::MAX, i32::MIN, i32::MAX, i32::MIN);
    for ((&u, &x), &y) in used.iter().zip(xs).zip(ys) {
        if u {
            (xl, xh, lo, hi) = (xl.min(x), xh.max(x), lo.min(y), hi.max(y));
        }
    }
    (xl, xh, lo, hi, n)
}

/// Largest `|x|` and `|y|` of every u and v edge (`[ux, uy, vx, vy]`) of
/// a piece of `cols` nodes per row whose cells are all drawn and whose
/// positions differ by less than 2^24 (exact in `f32`; `maxps` and `andps`
/// are single instructions where `u32` lanes need several without
/// SSE4.1). `wrap[k]` is 0 for the last node of a row (no u edge), else
/// all ones.
fn piece_edges_small(xs: &[i32], ys: &[i32], cols: usize, wrap: &[i32]) -> [u64; 4] {
    let n = xs.len();
    let m = n - cols;
    let d = |a: i32, b: i32| (b.wrapping_sub(a) as f32).abs();
    let du = |a: i32, b: i32, w: i32| (b.wrapping_sub(a) & w) as f32;
    // Rows 0..rows - 1: their u edges and the v edges above them.
    let (x0, x1, xv) = (&xs[..m], &xs[1..m + 1], &xs[cols..cols + m]);
    let (y0, y1, yv) = (&ys[..m], &ys[1..m + 1], &ys[cols..cols + m]);
    let w = &wrap[..m];
    let mut e = [0f32; 4];
    for k in 0..m {
        e[0] = e[0].max(du(x0[k], x1[k], w[k]).abs());
        e[1] = e[1].max(du(y0[k], y1[k], w[k]).abs());
        e[2] = e[2].max(d(x0[k], xv[k]));
        e[3] = e[3].max(d(y0[k], yv[k]));
    }
    // The last row's u edges.
    let (x0, x1, y0, y1) = (&xs[m..n - 1], &xs[m + 1..], &ys[m..n - 1], &ys[m + 1..]);
    for k in 0..cols - 1 {
        e[0] = e[0].max(d(x0[k], x1[k]));
        e[1] = e[1].max(d(y0[k], y1[k]));
    }
    e.map(|v| v as u64)
}

/// [`piece_edges_small`] for a piece whose cells are not all drawn:
/// `um[k]` (`vm[k]`) is all ones when node `k`'s u (v) edge belongs to a
/// drawn cell, else 0.
fn piece_edges_masked_small(
    xs: &[i32],
    ys: &[i32],
    cols: usize,
    um: &[i32],
    vm: &[i32],
) -> [u64; 4] {
    let n = xs.len();
    let m = n - cols;
    let d = |a: i32, b: i32, w: i32| ((b.wrapping_sub(a) & w) as f32).abs();
    let mut e = [0f32; 4];
    let (x0, x1, y0, y1, um) = (&xs[..n - 1], &xs[1..], &ys[..n - 1], &ys[1..], &um[..n - 1]);
    for k in 0..n - 1 {
        e[0] = e[0].max(d(x0[k], x1[k], um[k]));
        e[1] = e[1].max(d(y0[k], y1[k], um[k]));
    }
    let (x0, xv, y0, yv, vm) = (&xs[..m], &xs[cols..], &ys[..m], &ys[cols..], &vm[..m]);
    for k in 0..m {
        e[2] = e[2].max(d(x0[k], xv[k], vm[k]));
        e[3] = e[3].max(d(y0[k], yv[k], vm[k]));
    }
    e.map(|v| v as u64)
}

/// The smallest and largest values of a non-empty slice. Why through
/// `f64` (exact for every `i32`): `minpd` and `maxpd` are single
/// instructions where `i32` lanes need four without SSE4.1 (callgrind,
/// `profile_sphere 500 1`: ≈ 350 → ≈ 150 instructions per row of 17).
#[inline]
fn min_max(v: &[i32]) -> (i32, i32) {
    let (lo, hi) = v
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            let x = x as f64;
            (lo.min(x), hi.max(x))
        });
    (lo as i32, hi as i32)
}

/// For every cell of a piece of `cols` nodes per row (its (0, 0) node at
/// `k`; `away[k]` for `k` below `(rows - 1) · cols - 1`, the last node of
/// a row giving a meaningless value), 1 when the cross products of its
/// edges have sign `BACK` at all four corners (it faces away), as
/// [`mark_row`] decides. For positions whose differences are below 2^24:
/// the products are then below 2^48 and their difference below 2^49, exact
/// in `f64`, so the signs are those of the `i64` form.
fn away_cells_small<const BACK: i64>(xs: &[i32], ys: &[i32], cols: usize, away: &mut [u8]) {
    let m = away.len();
    let (xa, xb) = (&xs[..m], &xs[1..m + 1]);
    let (xc, xd) = (&xs[cols..cols + m], &xs[cols + 1..cols + 1 + m]);
    let (ya, yb) = (&ys[..m], &ys[1..m + 1]);
    let (yc, yd) = (&ys[cols..cols + m], &ys[cols + 1..cols + 1 + m]);
    let sign = BACK as f64;
    for k in 0..m {
        let d = |p: i32, q: i32| q.wrapping_sub(p) as f64;
        let (u0, v0) = (
            (d(xa[k], xb[k]), d(ya[k], yb[k])),
            (d(xa[k], xc[k]), d(ya[k], yc[k])),
        );
        let (u1, v1) = (
            (d(xc[k], xd[k]), d(yc[k], yd[k])),
            (d(xb[k], xd[k]), d(yb[k], yd[k])),
        );
        let faces = |u: (f64, f64), v: (f64, f64)| (u.0 * v.1 - u.1 * v.0) * sign > 0.0;
        away[k] = (faces(u0, v0) & faces(u0, v1) & faces(u1, v0) & faces(u1, v1)) as u8;
    }
}

/// Draw flags of one row of cells between node rows `(xl, yl)` and
/// `(xh, yh)`: the level's `mask` minus the cells facing away (`BACK`: the
/// back-face sign, 0 for no test). Returns the drawn and back-facing
/// counts.
#[inline]
fn mark_row<const BACK: i64>(
    xl: &[i32],
    yl: &[i32],
    xh: &[i32],
    yh: &[i32],
    mask: &[u8],
    row: &mut [u8],
) -> (u64, u64) {
    let n = row.len();
    let (mut drawn, mut back) = (0, 0);
    let (xl, yl, xh, yh, mask) = (
        &xl[..n + 1],
        &yl[..n + 1],
        &xh[..n + 1],
        &yh[..n + 1],
        &mask[..n],
    );
    // The left corners of a cell are the right corners of the previous
    // one. Why carried: four loads per cell instead of eight, and the test
    // stops at the first corner that does not face away (most cells: the
    // first; callgrind, `profile_sphere 500 1`).
    let (mut a, mut c) = ((xl[0] as i64, yl[0] as i64), (xh[0] as i64, yh[0] as i64));
    for i in 0..n {
        let mut f = mask[i] & CELL_DRAW;
        let b = (xl[i + 1] as i64, yl[i + 1] as i64);
        let d = (xh[i + 1] as i64, yh[i + 1] as i64);
        if BACK != 0 && f != 0 {
            let edge = |p: (i64, i64), q: (i64, i64)| (q.0 - p.0, q.1 - p.1);
            let away = |u: (i64, i64), v: (i64, i64)| (u.0 * v.1 - u.1 * v.0) * BACK > 0;
            let (u0, v0) = (edge(a, b), edge(a, c));
            if away(u0, v0) {
                let (u1, v1) = (edge(c, d), edge(b, d));
                if away(u0, v1) && away(u1, v0) && away(u1, v1) {
                    f = 0;
                    back += 1;
                }
            }
        }
        (a, c) = (b, d);
        row[i] = f;
        drawn += f as u64;
    }
    (drawn, back)
}

/// Largest `|x|` and `|y|` of the u and v edges of the drawn cells of one
/// row (`[ux, uy, vx, vy]`), for positions whose differences fit in `i32`.
/// Why branch-free masking: the loop runs in vector lanes.
#[inline]
fn row_edges_narrow(xl: &[i32], yl: &[i32], xh: &[i32], yh: &[i32], row: &[u8]) -> [u64; 4] {
    let n = row.len();
    let (xl0, xl1, yl0, yl1) = (&xl[..n], &xl[1..n + 1], &yl[..n], &yl[1..n + 1]);
    let (xh0, xh1, yh0, yh1) = (&xh[..n], &xh[1..n + 1], &yh[..n], &yh[1..n + 1]);
    let mut e = [0u32; 4];
    for i in 0..n {
        let keep = 0u32.wrapping_sub((row[i] & CELL_DRAW) as u32);
        let d = |a: i32, b: i32| b.wrapping_sub(a).unsigned_abs() & keep;
        e[0] = e[0].max(d(xl0[i], xl1[i]).max(d(xh0[i], xh1[i])));
        e[1] = e[1].max(d(yl0[i], yl1[i]).max(d(yh0[i], yh1[i])));
        e[2] = e[2].max(d(xl0[i], xh0[i]).max(d(xl1[i], xh1[i])));
        e[3] = e[3].max(d(yl0[i], yh0[i]).max(d(yl1[i], yh1[i])));
    }
    e.map(u64::from)
}

/// [`row_edges_narrow`] in `i64`, for any positions.
fn row_edges_wide(xl: &[i32], yl: &[i32], xh: &[i32], yh: &[i32], row: &[u8]) -> [u64; 4] {
    let mut e = [0u64; 4];
    let d = |a: i32, b: i32| (b as i64 - a as i64).unsigned_abs();
    for (i, &f) in row.iter().enumerate() {
        if f & CELL_DRAW == 0 {
            continue;
        }
        e[0] = e[0].max(d(xl[i], xl[i + 1])).max(d(xh[i], xh[i + 1]));
        e[1] = e[1].max(d(yl[i], yl[i + 1])).max(d(yh[i], yh[i + 1]));
        e[2] = e[2].max(d(xl[i], xh[i])).max(d(xl[i + 1], xh[i + 1]));
        e[3] = e[3].max(d(yl[i], yh[i])).max(d(yl[i + 1], yh[i + 1]));
    }
    e
}

/// The straightforward measurement that [`measure_cells`] must equal (the
/// reference of its tests): measures the projected cells of a `cols × rows`
/// node array and appends
/// one flag byte per cell (row-major, [`CELL_DRAW`], [`CELL_RIGHT`],
/// [`CELL_TOP`]) to `flags`, and per row of cells the pixel rows its used
/// nodes span (`[lo, hi]`, inclusive; empty rows give `lo > hi`) to
/// `spans`.
///
/// With `back_sign` ±1 (back-face culling on: the sign of the local map's
/// determinant), a cell is left out when the screen cross product of its
/// edges has that sign at all four corners: the Jacobian determinant of a
/// bilinear cell is bilinear in `(s, t)`, so the whole drawn cell then faces
/// away from the eye (a front-facing cell of the closed surface covers the
/// same pixels). `back_sign = 0` keeps every cell with four used corners.
#[cfg(test)]
pub(crate) fn measure_cells_reference(
    nodes: &[Node],
    cols: usize,
    rows: usize,
    back_sign: i64,
    flags: &mut Vec<u8>,
    spans: &mut Vec<[i32; 2]>,
) -> CellMeasure {
    let mut m = CellMeasure::EMPTY;
    let (mut x0, mut y0, mut x1, mut y1) = (i32::MAX, i32::MAX, i32::MIN, i32::MIN);
    // Why spans per row of cells: a band skips the rows of cells outside
    // it without reading their nodes (callgrind, `profile_sphere 500 1`:
    // the per-band scan of node rows was ~6 M instructions per frame).
    let first_span = spans.len();
    spans.resize(first_span + rows - 1, [i32::MAX, i32::MIN]);
    let mut below = (i32::MAX, i32::MIN);
    for (j, row) in nodes[..cols * rows].chunks_exact(cols).enumerate() {
        let (mut lo, mut hi) = (i32::MAX, i32::MIN);
        for n in row {
            if n[0] != EMPTY_NODE {
                m.used_nodes += 1;
                x0 = x0.min(n[0]);
                x1 = x1.max(n[0]);
                lo = lo.min(n[1]);
                hi = hi.max(n[1]);
            }
        }
        y0 = y0.min(lo);
        y1 = y1.max(hi);
        if j > 0 {
            spans[first_span + j - 1] = [below.0.min(lo) >> 16, below.1.max(hi) >> 16];
        }
        below = (lo, hi);
    }
    if m.used_nodes > 0 {
        m.bbox = [x0 >> 16, y0 >> 16, x1 >> 16, y1 >> 16];
    }
    let (ccols, crows) = (cols - 1, rows - 1);
    let base = flags.len();
    flags.resize(base + ccols * crows, 0);
    let cell_flags = &mut flags[base..];
    // Why one copy per sign: the back-face test compares the four cross
    // products with a constant sign instead of multiplying by it
    // (callgrind, `profile_sphere 500 1`).
    match back_sign {
        1 => mark_drawn_cells::<1>(nodes, cols, cell_flags, &mut m),
        -1 => mark_drawn_cells::<-1>(nodes, cols, cell_flags, &mut m),
        _ => mark_drawn_cells::<0>(nodes, cols, cell_flags, &mut m),
    }
    let [right, top, both] = close_cells(cell_flags, ccols, crows);
    (m.right_edges, m.top_edges, m.both_edges) = (right, top, both);
    m
}

/// Pass 1 of [`measure_cells_reference`]: which cells are drawn (`CELL_DRAW`), and
/// the largest edges of those. `BACK` is the back-face sign (0: no test).
#[cfg(test)]
fn mark_drawn_cells<const BACK: i64>(
    nodes: &[Node],
    cols: usize,
    cell_flags: &mut [u8],
    m: &mut CellMeasure,
) {
    // Why row slices and windows: no index arithmetic or bounds check per
    // corner (callgrind, `profile_sphere 500 1`).
    let ccols = cols - 1;
    let diff = |p: &Node, q: &Node| (q[0] as i64 - p[0] as i64, q[1] as i64 - p[1] as i64);
    for (j, out) in cell_flags.chunks_exact_mut(ccols).enumerate() {
        let below = &nodes[j * cols..(j + 1) * cols];
        let above = &nodes[(j + 1) * cols..(j + 2) * cols];
        for ((f, lo), hi) in out.iter_mut().zip(below.windows(2)).zip(above.windows(2)) {
            let (a, b, c, d) = (&lo[0], &lo[1], &hi[0], &hi[1]);
            if a[0] == EMPTY_NODE || b[0] == EMPTY_NODE || c[0] == EMPTY_NODE || d[0] == EMPTY_NODE
            {
                continue;
            }
            let (u0, u1, v0, v1) = (diff(a, b), diff(c, d), diff(a, c), diff(b, d));
            if BACK != 0 {
                let cross = |u: (i64, i64), v: (i64, i64)| (u.0 * v.1 - u.1 * v.0) * BACK;
                if cross(u0, v0) > 0 && cross(u0, v1) > 0 && cross(u1, v0) > 0 && cross(u1, v1) > 0
                {
                    m.backfacing_cells += 1;
                    continue;
                }
            }
            *f = CELL_DRAW;
            m.edges[0] = m.edges[0].max(u0.0.abs()).max(u1.0.abs());
            m.edges[1] = m.edges[1].max(u0.1.abs()).max(u1.1.abs());
            m.edges[2] = m.edges[2].max(v0.0.abs()).max(v1.0.abs());
            m.edges[3] = m.edges[3].max(v0.1.abs()).max(v1.1.abs());
            m.drawable_cells += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::XorShift;
    use spatch_format::{Frame, GridSize, Patch};

    #[test]
    fn trilinear_equals_exact_for_an_affine_view() {
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let d: Vec<u16> = (0..25).map(|k| (k * 7 % 11) as u16).collect();
        let patch = Patch::new(frame, GridSize::new(5, 5).unwrap(), d, None).unwrap();
        let level = &crate::mip::build_mip_pyramid(&patch)[0];
        // W constant: an affine map, where trilinear interpolation is exact.
        let p = Projector {
            map: Mat3::from_cols(
                Vec3::new(20.0, 3.0, 0.0),
                Vec3::new(-2.0, 18.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
            ),
            t0: Vec3::new(40.0, 40.0, 2.0),
            z_scale: 0.1,
            z_offset: 0.0,
        };
        let range = NodeRange::whole(level);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        project_nodes_exact(level, range, &p, &mut a, &mut NodeXY::default());
        let mut xy = NodeXY::default();
        project_nodes_trilinear(
            level,
            range,
            range.d_range(level).unwrap(),
            &p,
            &mut b,
            &mut xy,
        );
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x[0] - y[0]).abs() <= 4 && (x[1] - y[1]).abs() <= 4,
                "{x:?} {y:?}"
            );
            assert!((x[2] - y[2]).abs() <= 64);
        }
        let mut flags = Vec::new();
        let mut spans = Vec::new();
        let m = measure_cells_reference(&a, 5, 5, 0, &mut flags, &mut spans);
        assert_eq!(spans.len(), 4);
        assert!(spans.iter().all(|s| s[0] <= s[1]));
        assert_eq!(flags.len(), 16);
        assert_eq!(m.drawable_cells, 16);
        assert_eq!(m.refined_nodes(1, 1), 25);
        assert_eq!(m.refined_nodes(2, 2), 81);
        assert_eq!(m.refined_nodes(2, 1), 45);
    }

    /// The packed conversion equals the scalar ones for every kind of
    /// input: small and large, negative, fractional, at the 2^31 and 2^23
    /// edges, infinite and NaN.
    #[test]
    fn fixed_lanes_equal_the_scalar_conversions() {
        let mut rng = XorShift(0x5eed_1234_abcd_0001);
        let edges = [
            0.0,
            -0.0,
            1.0 / 65536.0,
            -1.0 / 65536.0,
            0.999_999_9,
            -0.999_999_9,
            127.999_99,
            128.0,
            -128.000_01,
            32_767.998,
            32_768.0,
            -32_768.0,
            -32_769.0,
            1e9,
            -1e9,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MIN_POSITIVE,
            2.1,
            -2.1,
        ];
        for case in 0..200_000 {
            let pick = |rng: &mut XorShift| match rng.below(4) {
                0 => edges[rng.below(edges.len() as u32) as usize],
                1 => (rng.unit() - 0.5) * 1024.0,
                2 => (rng.unit() - 0.5) * 70_000.0,
                _ => f32::from_bits(rng.next_u32()),
            };
            let s = Vec4::new(pick(&mut rng), pick(&mut rng), pick(&mut rng), 0.0);
            let want = [
                position_to_fixed(s.x),
                position_to_fixed(s.y),
                depth_to_fixed(s.z),
            ];
            assert_eq!(fixed_lanes(s), want, "case {case}: {s:?}");
            let q = s * LANE_SCALE;
            if s.is_finite() && q.x.abs() < 2_147_483_648.0 && q.y.abs() < 2_147_483_648.0 {
                assert_eq!(fixed_lanes_in_range(s), want, "case {case}: {s:?}");
            }
        }
    }

    /// The mip levels of a random patch of 2–18 × 2–18 nodes, `holes` % of
    /// them empty, displacements below 400.
    fn random_levels(rng: &mut XorShift, holes: u64) -> Vec<MipLevel> {
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
        crate::mip::build_mip_pyramid(&patch)
    }

    /// A random part of `level`, at least one cell.
    fn random_part(rng: &mut XorShift, level: &MipLevel) -> NodeRange {
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

    /// `measure_cells` (level masks, positions in rows, `i32` lanes, closing
    /// flags copied from the level) gives the same flags, spans and
    /// measures as the straightforward pass over the nodes, on random
    /// grids with empty nodes, whole and split pieces, folded maps (cells
    /// facing away) and both projections.
    #[test]
    fn measure_cells_equals_the_reference_on_random_pieces() {
        let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
        let mut backfacing = 0;
        // One scratch for every piece, as a chunk keeps it.
        let mut xy = NodeXY::default();
        for case in 0..300 {
            let levels = random_levels(&mut rng, [0, 0, 5, 30][case % 4]);
            let Some(level) = levels.first() else {
                continue;
            };
            // A perspective map whose displacement axis may fold cells over.
            let mut r = |s: f32| (rng.unit() - 0.5) * s;
            let p = Projector {
                map: Mat3::from_cols(
                    Vec3::new(8.0 + r(6.0), r(6.0), r(0.02)),
                    Vec3::new(r(6.0), 8.0 + r(6.0), r(0.02)),
                    Vec3::new(r(0.2), r(0.2), r(0.001)),
                ),
                t0: Vec3::new(60.0 + r(40.0), 60.0 + r(40.0), 2.0),
                z_scale: 0.1,
                z_offset: 0.0,
            };
            let whole = NodeRange::whole(level);
            for range in [whole, random_part(&mut rng, level)] {
                let Some(dr) = range.d_range(level) else {
                    continue;
                };
                for back_sign in [-1, 0, 1] {
                    let mut nodes = Vec::new();
                    if case % 2 == 0 {
                        project_nodes_trilinear(level, range, dr, &p, &mut nodes, &mut xy);
                    } else {
                        project_nodes_exact(level, range, &p, &mut nodes, &mut xy);
                    }
                    let (c, rws) = (range.i1 - range.i0 + 1, range.j1 - range.j0 + 1);
                    let (mut f0, mut s0, mut f1, mut s1) = (vec![7], vec![], vec![7], vec![]);
                    let a = measure_cells_reference(&nodes, c, rws, back_sign, &mut f0, &mut s0);
                    let b = measure_cells(level, range, &mut xy, back_sign, &mut f1, &mut s1);
                    assert_eq!(f0, f1, "case {case} {range:?} sign {back_sign}");
                    assert_eq!(s0, s1);
                    assert_eq!(a.edges, b.edges);
                    assert_eq!(
                        (a.drawable_cells, a.backfacing_cells, a.used_nodes, a.bbox),
                        (b.drawable_cells, b.backfacing_cells, b.used_nodes, b.bbox)
                    );
                    assert_eq!(
                        (a.right_edges, a.top_edges, a.both_edges),
                        (b.right_edges, b.top_edges, b.both_edges)
                    );
                    backfacing += b.backfacing_cells;
                }
            }
        }
        // The maps fold some cells over: the back-face path is exercised.
        assert!(backfacing > 0);
    }

    /// The `i32` row lanes and the `f32` piece passes (whole and masked)
    /// equal the `i64` form on random rows with undrawn cells, within their
    /// ranges.
    #[test]
    fn narrow_and_small_edges_equal_wide_edges() {
        let mut rng = XorShift(12345);
        for case in 0..400 {
            let n = 1 + rng.below64(20) as usize;
            // Positions spanning 2^28 (narrow) or just under 2^24 (small).
            let span = if case % 2 == 0 {
                1 << 28
            } else {
                (1 << 24) - 1
            };
            let mut v = || -> Vec<i32> {
                (0..=n)
                    .map(|_| rng.below64(span) as i32 + (1 << 20))
                    .collect()
            };
            let (xl, yl, xh, yh) = (v(), v(), v(), v());
            let row: Vec<u8> = (0..n).map(|_| (rng.below64(3) != 0) as u8).collect();
            let wide = row_edges_wide(&xl, &yl, &xh, &yh, &row);
            assert_eq!(row_edges_narrow(&xl, &yl, &xh, &yh, &row), wide);
            if case % 2 == 1 {
                // The row as a piece of two node rows.
                let cols = n + 1;
                let (xs, ys) = ([&xl[..], &xh].concat(), [&yl[..], &yh].concat());
                let (mut um, mut vm) = (vec![0; 2 * cols], vec![0; 2 * cols]);
                for (i, _) in row.iter().enumerate().filter(|(_, &f)| f & CELL_DRAW != 0) {
                    (um[i], um[cols + i], vm[i], vm[i + 1]) = (-1, -1, -1, -1);
                }
                assert_eq!(piece_edges_masked_small(&xs, &ys, cols, &um, &vm), wide);
                let full = vec![CELL_DRAW; n];
                let wrap: Vec<i32> = (0..2 * cols)
                    .map(|k| -((k % cols != cols - 1) as i32))
                    .collect();
                assert_eq!(
                    piece_edges_small(&xs, &ys, cols, &wrap),
                    row_edges_wide(&xl, &yl, &xh, &yh, &full)
                );
            }
        }
    }

    /// `close_cells` marks exactly the drawn cells whose right or upper
    /// neighbour is not drawn (or missing), on narrow and wide rows.
    #[test]
    fn closing_flags_follow_the_neighbours() {
        let mut rng = XorShift(777);
        for case in 0..200 {
            let ccols = 1 + rng.below64(if case % 4 == 0 { 100 } else { 20 }) as usize;
            let crows = 1 + rng.below64(12) as usize;
            let drawn: Vec<bool> = (0..ccols * crows).map(|_| rng.below64(4) != 0).collect();
            let mut flags: Vec<u8> = drawn.iter().map(|&d| d as u8 * CELL_DRAW).collect();
            let counts = close_cells(&mut flags, ccols, crows);
            let mut expected = [0u64; 3];
            for j in 0..crows {
                for i in 0..ccols {
                    let k = j * ccols + i;
                    let right = drawn[k] && (i + 1 == ccols || !drawn[k + 1]);
                    let top = drawn[k] && (j + 1 == crows || !drawn[k + ccols]);
                    let want = (drawn[k] as u8 * CELL_DRAW)
                        | (right as u8 * CELL_RIGHT)
                        | (top as u8 * CELL_TOP);
                    assert_eq!(flags[k], want, "case {case} cell ({i}, {j})");
                    expected[0] += right as u64;
                    expected[1] += top as u64;
                    expected[2] += (right && top) as u64;
                }
            }
            assert_eq!(counts, expected);
        }
    }
}
