//! The reference of the cell measurement and its tests: the
//! straightforward pass over the node array that
//! [`measure_cells`](crate::plan::measure::measure_cells) must equal
//! bit for bit, on random pieces of both projections.

use crate::fixed::{Node, EMPTY_NODE};
use crate::grid::{close_cells, CELL_DRAW};
use crate::plan::measure::{measure_cells, row_edges_narrow, row_edges_wide, CellMeasure};
use crate::plan::node_xy::NodeXY;
use crate::plan::project::tests::{random_levels, random_part};
use crate::plan::project::{project_nodes_exact, project_nodes_trilinear, Projector};
use crate::plan::split::NodeRange;
use crate::test_rng::XorShift;
use glam::{Mat3, Vec3};
use spatch_format::{Frame, GridSize, Patch};

/// The straightforward measurement that [`measure_cells`] must equal (the
/// reference of its tests): measures the projected cells of a `cols × rows`
/// node array and appends
/// one flag byte per cell (row-major, the flags of
/// [`crate::grid`]) to `flags`, and per row of cells the pixel rows its used
/// nodes span (`[lo, hi]`, inclusive; empty rows give `lo > hi`) to
/// `spans`.
///
/// With `back_sign` ±1 (back-face culling on: the sign of the local map's
/// determinant), a cell is left out when the screen cross product of its
/// edges has that sign at all four corners: the Jacobian determinant of a
/// bilinear cell is bilinear in `(s, t)`, so the whole drawn cell then faces
/// away from the eye (a front-facing cell of the closed surface covers the
/// same pixels). `back_sign = 0` keeps every cell with four used corners.
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

#[test]
fn trilinear_equals_exact_for_an_affine_view() {
    let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
    let d: Vec<u16> = (0..25).map(|k| (k * 7 % 11) as u16).collect();
    let patch = Patch::new(frame, GridSize::new(5, 5).unwrap(), d, None).unwrap();
    let level = &crate::prepare::mip::build_mip_pyramid(&patch)[0];
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
        // A perspective map whose displacement axis may fold cells over;
        // one case in three with cells of about 20 px, pieces wider than
        // 256 px (the row path).
        let scale = [8.0, 8.0, 40.0][(case / 4) % 3];
        let mut r = |s: f32| (rng.unit() - 0.5) * s;
        let p = Projector {
            map: Mat3::from_cols(
                Vec3::new(scale + r(6.0), r(6.0), r(0.02)),
                Vec3::new(r(6.0), scale + r(6.0), r(0.02)),
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
                let (c, rws) = range.size();
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

/// The `i32` row lanes equal the `i64` form on random rows with undrawn
/// cells, within their range.
#[test]
fn narrow_edges_equal_wide_edges() {
    let mut rng = XorShift(12345);
    for _ in 0..400 {
        let n = 1 + rng.below64(20) as usize;
        // Positions spanning 2^28 (narrow).
        let mut v = || -> Vec<i32> {
            (0..=n)
                .map(|_| rng.below64(1 << 28) as i32 + (1 << 20))
                .collect()
        };
        let (xl, yl, xh, yh) = (v(), v(), v(), v());
        let row: Vec<u8> = (0..n).map(|_| (rng.below64(3) != 0) as u8).collect();
        let wide = row_edges_wide(&xl, &yl, &xh, &yh, &row);
        assert_eq!(row_edges_narrow(&xl, &yl, &xh, &yh, &row), wide);
    }
}
