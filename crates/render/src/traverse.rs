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
//!   PSNR).
//! - **Exact**: each node is mapped to window clip coordinates by forward
//!   differences and divided by its depth (one reciprocal per node).
//!
//! Empty nodes and nodes of no drawable cell are written as
//! [`EMPTY_NODE`](crate::fixed::EMPTY_NODE). The caller guarantees the
//! piece lies in front of the near plane (see [`crate::cull`]).
//!
//! [`measure_cells`] then finds the largest projected cell extent (which
//! sets the subdivision) and the screen bounding box. Cost: O(nodes), no
//! allocation (the output vector is reused).

use glam::{Mat3, Vec3};

use crate::fixed::{depth_to_fixed, position_to_fixed, EMPTY_NODE};
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

const EMPTY: Node = {
    let mut n = [0; NODE_WIDTH];
    n[0] = EMPTY_NODE;
    n
};

/// Projects every node of `range` exactly, appending to `out`.
pub(crate) fn project_nodes_exact(
    level: &MipLevel,
    range: NodeRange,
    p: &Projector,
    out: &mut Vec<Node>,
) {
    let [mi, mj, md] = [p.map.x_axis, p.map.y_axis, p.map.z_axis];
    for j in range.j0..=range.j1 {
        let row = j * level.cols;
        let mut base = p.map * Vec3::new(range.i0 as f32, j as f32, 0.0) + p.t0;
        for k in row + range.i0..=row + range.i1 {
            let d = level.displacements[k];
            if level.used[k] {
                let c = base + md * d as f32;
                let inv = 1.0 / c.z;
                out.push(fixed_node(Vec3::new(
                    c.x * inv,
                    c.y * inv,
                    c.z * p.z_scale + p.z_offset,
                )));
            } else {
                out.push(EMPTY);
            }
            base += mi;
        }
        let _ = mj;
    }
}

/// Projects the nodes of `range` by trilinear interpolation of its box
/// corners (`d` is the range's displacement range), appending to `out`.
pub(crate) fn project_nodes_trilinear(
    level: &MipLevel,
    range: NodeRange,
    d: (u16, u16),
    p: &Projector,
    out: &mut Vec<Node>,
) {
    let (lo, hi) = range.local_box(d);
    let corner = |a: bool, b: bool, c: bool| {
        p.screen(Vec3::new(
            if a { hi.x } else { lo.x },
            if b { hi.y } else { lo.y },
            if c { hi.z } else { lo.z },
        ))
    };
    let c = [
        [corner(false, false, false), corner(true, false, false)],
        [corner(false, true, false), corner(true, true, false)],
        [corner(false, false, true), corner(true, false, true)],
        [corner(false, true, true), corner(true, true, true)],
    ];
    let inv_i = 1.0 / (range.i1 - range.i0) as f32;
    let inv_j = 1.0 / (range.j1 - range.j0) as f32;
    let inv_d = if d.1 > d.0 {
        1.0 / (d.1 - d.0) as f32
    } else {
        0.0
    };
    // Why a pre-sized slice: writing nodes in place instead of pushing
    // them one by one saves the per-node capacity check and the zeroing of
    // the attribute words (callgrind, `profile_sphere 500 1`).
    let cols = range.i1 - range.i0 + 1;
    let base = out.len();
    out.resize(base + cols * (range.j1 - range.j0 + 1), EMPTY);
    let mut rows_out = out[base..].chunks_exact_mut(cols);
    for j in range.j0..=range.j1 {
        let v = (j - range.j0) as f32 * inv_j;
        // Corners of the bilinear slice at this row: bottom (d lo) and top (d hi).
        let b0 = c[0][0].lerp(c[1][0], v);
        let b1 = c[0][1].lerp(c[1][1], v);
        let t0 = c[2][0].lerp(c[3][0], v);
        let t1 = c[2][1].lerp(c[3][1], v);
        let (db, dt) = ((b1 - b0) * inv_i, (t1 - t0) * inv_i);
        let (mut bottom, mut top) = (b0, t0);
        let row = j * level.cols;
        let Some(dst) = rows_out.next() else {
            return;
        };
        let (used, disp) = (
            &level.used[row + range.i0..=row + range.i1],
            &level.displacements[row + range.i0..=row + range.i1],
        );
        for ((node, &u), &dk) in dst.iter_mut().zip(used).zip(disp) {
            if u {
                let w = (dk - d.0) as f32 * inv_d;
                let s = bottom + (top - bottom) * w;
                node[0] = position_to_fixed(s.x);
                node[1] = position_to_fixed(s.y);
                node[2] = depth_to_fixed(s.z);
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

/// Measures the projected cells of a `cols × rows` node array and appends
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
pub(crate) fn measure_cells(
    nodes: &[Node],
    cols: usize,
    rows: usize,
    back_sign: i64,
    flags: &mut Vec<u8>,
    spans: &mut Vec<[i32; 2]>,
) -> CellMeasure {
    let mut m = CellMeasure {
        edges: [0; 4],
        drawable_cells: 0,
        right_edges: 0,
        top_edges: 0,
        both_edges: 0,
        backfacing_cells: 0,
        used_nodes: 0,
        bbox: [i32::MAX, i32::MAX, i32::MIN, i32::MIN],
    };
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
    // Pass 2: which drawn cells close their right column / top row. Why
    // byte arithmetic on row slices: no branch or bounds check per cell
    // (callgrind, `profile_sphere 500 1`: ~4 M instructions per frame
    // before).
    for j in 0..crows {
        let (head, tail) = cell_flags.split_at_mut((j + 1) * ccols);
        let row = &mut head[j * ccols..];
        let above: &[u8] = if j + 1 < crows { &tail[..ccols] } else { &[] };
        for i in 0..ccols {
            let drawn = row[i] & CELL_DRAW;
            let next = row.get(i + 1).map_or(0, |f| f & CELL_DRAW);
            let over = above.get(i).map_or(0, |f| f & CELL_DRAW);
            let (right, top) = (drawn & !next, drawn & !over);
            row[i] |= (right * CELL_RIGHT) | (top * CELL_TOP);
            m.right_edges += right as u64;
            m.top_edges += top as u64;
            m.both_edges += (right & top) as u64;
        }
    }
    m
}

/// Pass 1 of [`measure_cells`]: which cells are drawn (`CELL_DRAW`), and
/// the largest edges of those. `BACK` is the back-face sign (0: no test).
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
        project_nodes_exact(level, range, &p, &mut a);
        project_nodes_trilinear(level, range, range.d_range(level).unwrap(), &p, &mut b);
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x[0] - y[0]).abs() <= 4 && (x[1] - y[1]).abs() <= 4,
                "{x:?} {y:?}"
            );
            assert!((x[2] - y[2]).abs() <= 64);
        }
        let mut flags = Vec::new();
        let mut spans = Vec::new();
        let m = measure_cells(&a, 5, 5, 0, &mut flags, &mut spans);
        assert_eq!(spans.len(), 4);
        assert!(spans.iter().all(|s| s[0] <= s[1]));
        assert_eq!(flags.len(), 16);
        assert_eq!(m.drawable_cells, 16);
        assert_eq!(m.refined_nodes(1, 1), 25);
        assert_eq!(m.refined_nodes(2, 2), 81);
        assert_eq!(m.refined_nodes(2, 1), 45);
    }
}
