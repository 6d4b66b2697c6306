//! Tests of [`crate::prepare::mip`].

use crate::grid::CELL_DRAW;
use crate::prepare::corner_fill::fills_cell;
use crate::prepare::mip::*;
use glam::Vec3;
use spatch_format::{Frame, GridSize, Patch, EMPTY};

#[test]
fn a_17_grid_halves_to_9_5_3_2_and_keeps_corner_nodes() {
    let patch = patch_of(17, 17, |i, j| (i + j) as u16);
    let levels = build_mip_pyramid(&patch);
    let sides: Vec<usize> = levels.iter().map(|l| l.cols).collect();
    assert_eq!(sides, vec![17, 9, 5, 3, 2]);
    let last = levels.last().unwrap();
    assert_eq!(last.spacing, 16);
    assert_eq!(last.displacements, vec![0, 16, 16, 32]);
    assert_eq!(last.d_range, (0, 32));
}

/// A patch of `cols × rows` nodes with displacements from `d(i, j)`.
fn patch_of(cols: u32, rows: u32, d: impl Fn(u32, u32) -> u16) -> Patch {
    patch_from(
        cols,
        rows,
        (0..cols * rows).map(|k| d(k % cols, k / cols)).collect(),
    )
}

/// A patch of `cols × rows` nodes with displacements `d` (row-major), on
/// the unit axes.
fn patch_from(cols: u32, rows: u32, d: Vec<u16>) -> Patch {
    let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
    Patch::new(frame, GridSize::new(cols, rows).unwrap(), d, None).unwrap()
}

#[test]
fn odd_sides_halve_through_a_padding_node_that_stays_on_a_plane() {
    // 16 × 15 nodes: 15 and 14 cells, so the columns are padded at
    // levels 0 and 1 and the rows at level 1. On a plane the padding
    // nodes continue the plane exactly, and nodes shared with level 0
    // keep its values.
    let plane = |i: u32, j: u32| (100 + 3 * i + 5 * j) as u16;
    let levels = build_mip_pyramid(&patch_of(16, 15, plane));
    let sides: Vec<[usize; 2]> = levels.iter().map(|l| [l.cols, l.rows]).collect();
    // Level 4 (2 × 2) would have no cell whose corners are level 0's.
    assert_eq!(sides, vec![[16, 15], [9, 8], [5, 5], [3, 3]]);
    for level in &levels {
        let s = level.spacing;
        for j in 0..level.rows {
            for i in 0..level.cols {
                let got = level.displacements[j * level.cols + i];
                assert_eq!(got, plane(i as u32 * s, j as u32 * s), "{i}, {j} at {s}");
            }
        }
        assert_eq!(level.drawable_cells as usize, level.cell_flags.len());
    }
}

#[test]
fn level_one_by_quarters_draws_every_level_zero_cell() {
    // Random grids with holes: halved with quarters, level 1 is level 1
    // with more corners filled and no more cells drawn whole, and every
    // drawable level-0 cell lies in a level-1 cell drawn whole or in a
    // held quarter of a quartered cell (whose corners are filled).
    let mut rng = crate::test_rng::XorShift(0x0004_1a27);
    let mut quartered = 0;
    for case in 0..400 {
        let (cols, rows) = (3 + rng.below(31), 3 + rng.below(31));
        let holes = [3, 30, 70][case % 3];
        let d = rng.holed_grid((cols * rows) as usize, holes, 0, 50);
        let patch = patch_from(cols, rows, d);
        let Some(base) = base_level(&patch) else {
            continue;
        };
        let plain = halve_level(&base).unwrap();
        let by_quarters = halve_quartered(base.as_finer(), None).unwrap();
        for (&a, &b) in plain.cell_flags.iter().zip(&by_quarters.cell_flags) {
            assert!(a & CELL_DRAW != 0 || b & CELL_DRAW == 0, "{cols} x {rows}");
        }
        for (k, (&a, &b)) in plain
            .displacements
            .iter()
            .zip(&by_quarters.displacements)
            .enumerate()
        {
            assert!(a == EMPTY || a == b, "{cols} x {rows}: node {k} moved");
        }
        let hc = by_quarters.cols;
        let mut held = vec![0u8; (hc - 1) * (by_quarters.rows - 1)];
        for q in &by_quarters.quartered {
            held[q.cell as usize] = q.quarters;
            let first = (q.cell as usize / (hc - 1)) * hc + q.cell as usize % (hc - 1);
            for n in [first, first + 1, first + hc, first + hc + 1] {
                assert!(by_quarters.displacements[n] != EMPTY && by_quarters.used[n]);
            }
        }
        quartered += by_quarters.quartered.len();
        let fc = base.cols - 1;
        for (k, &f) in base.cell_flags.iter().enumerate() {
            let (i, j) = (k % fc, k / fc);
            let coarse = (j / 2) * (hc - 1) + i / 2;
            let quarter = (i % 2) + 2 * (j % 2);
            let whole = by_quarters.cell_flags[coarse] & CELL_DRAW != 0;
            if f & CELL_DRAW != 0 {
                assert!(
                    whole || held[coarse] >> quarter & 1 != 0,
                    "{cols} x {rows}, {holes} %: cell {i}, {j} not drawn"
                );
            }
        }
    }
    assert!(quartered > 1000, "{quartered} quartered cells");
}

#[test]
fn coarse_levels_draw_every_cell_their_finer_level_draws() {
    // Grids of 2–33 nodes a side with holes from none to most nodes:
    // each counted level halves, has a drawable cell, and holds every
    // drawable cell of the level below in one of its drawable cells
    // unless that coarse cell holds too few finer cells to be filled
    // (`corner_fill.rs`: those are left to neighbouring patches);
    // without holes the count is every halving the sides allow that
    // keeps a cell of level-0 corners.
    let mut rng = crate::test_rng::XorShift(0x001e_7e15);
    let mut deep = 0;
    for case in 0..600 {
        let side = |r: &mut crate::test_rng::XorShift| match r.below(2) {
            0 => [3, 5, 9, 17, 33][r.below(5) as usize],
            _ => 2 + r.below(32),
        };
        let (cols, rows) = (side(&mut rng), side(&mut rng));
        let holes = [0, 3, 30, 70, 95][case % 5];
        let d = rng.holed_grid((cols * rows) as usize, holes, 0, 50);
        let patch = patch_from(cols, rows, d);
        let Some(base) = base_level(&patch) else {
            continue;
        };
        let count = coarse_level_count(&base.displacements, [base.cols, base.rows]);
        let mut level = base.clone();
        for m in 0..count {
            let next = halve_level(&level).expect("a counted level halves");
            assert!(next.drawable_cells > 0, "{cols} x {rows}, level {}", m + 1);
            let (fc, fr) = (level.cols - 1, level.rows - 1);
            let drawn = |i: usize, j: usize| {
                let flag = |i: usize, j: usize| level.cell_flags[j * fc + i] & CELL_DRAW;
                let ends = |n: usize, end: usize| n..(n + 2).min(end);
                ends(2 * i, fc)
                    .flat_map(|a| ends(2 * j, fr).map(move |b| (a, b)))
                    .map(|(a, b)| u8::from(flag(a, b) != 0))
                    .sum::<u8>()
            };
            for (k, &f) in level.cell_flags.iter().enumerate() {
                let (i, j) = (k % fc, k / fc);
                let filled =
                    fills_cell([fc, fr], [i / 2, j / 2], drawn(i / 2, j / 2), level.spacing);
                if f & CELL_DRAW != 0 && filled {
                    assert!(
                        next.cell_is_drawable(i / 2, j / 2),
                        "{cols} x {rows}, {holes} %: cell {i}, {j} of level {m}"
                    );
                }
            }
            level = next;
        }
        if holes == 0 {
            let (mut c, mut r, mut expected) = (cols as usize, rows as usize, 0);
            // A level needs a cell whose corners are level 0's nodes.
            let reach = |n: usize, m: usize| (n - 1) >> m >= 1;
            while expected + 1 < MAX_MIP_LEVELS
                && c >= 3
                && r >= 3
                && reach(cols as usize, expected + 1)
                && reach(rows as usize, expected + 1)
            {
                (c, r, expected) = (
                    halved_side(c).unwrap(),
                    halved_side(r).unwrap(),
                    expected + 1,
                );
            }
            assert_eq!(count, expected, "{cols} x {rows}");
        }
        deep += (count >= 2) as usize;
    }
    assert!(deep > 20, "{deep} grids with two coarse levels or more");
}
