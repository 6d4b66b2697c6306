//! Node normals reconstructed in patch space from displacement
//! differences, and the table slot of each node's differences.
//!
//! In patch space a node's normal depends only on the displacement
//! differences around it and on the ratios `rx = |az| / |ax|`,
//! `ry = |az| / |ay|`: with `gi = d[i+1] - d[i-1]` and `gj = d[j+1] -
//! d[j-1]` (one-sided differences doubled at borders and next to empty
//! nodes, 0 when both neighbours are missing), the normal is
//! `(-gi · rx / 2, -gj · ry / 2, 1)`, normalized. The differences are small
//! integers, so a table indexed by `(gi, gj)` for the current ratios (the
//! normal buffer, [`crate::prepare::normal_buffer`]) computes each distinct
//! normal once; the slot of every node is found once per scene
//! ([`grid_slots`]).
//!
//! Cost: a few compares per node for the slots, one normalization per
//! distinct normal.

use glam::Vec3;

use crate::prepare::wide::Wide;

/// Differences in `-RADIUS..=RADIUS` are cached; others are computed.
const RADIUS: i32 = 32;
pub(crate) const SIDE: usize = (2 * RADIUS + 1) as usize;

/// The table slot of a node whose differences lie outside the table.
pub(crate) const OUTSIDE_TABLE: u16 = u16::MAX;

/// The table slot of differences `(gi, gj)` (the same for every ratio and
/// frame), or [`OUTSIDE_TABLE`]. Why slots: the differences depend on the
/// displacements only, so [`crate::prepare::mip`] finds them once per scene and a
/// frame starts from the slot (callgrind, `profile_sphere 500 1`: the
/// per-node border logic was ~4 M instructions per frame). One unsigned
/// compare per difference: it runs for every node of a scene.
#[inline(always)]
pub(crate) fn table_slot(gi: i32, gj: i32) -> u16 {
    let (x, y) = (
        gi.wrapping_add(RADIUS) as u32,
        gj.wrapping_add(RADIUS) as u32,
    );
    if x < SIDE as u32 && y < SIDE as u32 {
        (y as usize * SIDE + x as usize) as u16
    } else {
        OUTSIDE_TABLE
    }
}

/// The patch-space normal for differences `(gi, gj)` and ratios `(rx, ry)`
/// (not normalized: z is 1).
#[inline]
pub(crate) fn reconstruct_normal(gi: i32, gj: i32, rx: f32, ry: f32) -> Vec3 {
    Vec3::new(-(gi as f32) * rx * 0.5, -(gj as f32) * ry * 0.5, 1.0)
}

/// The differences `(gi, gj)` of table slot `index` (the inverse of
/// [`table_slot`]).
pub(crate) fn slot_differences(index: usize) -> (i32, i32) {
    (
        (index % SIDE) as i32 - RADIUS,
        (index / SIDE) as i32 - RADIUS,
    )
}

/// Displacement differences `(gi, gj)` at node `(i, j)` of a grid (see the
/// module header for borders and empty neighbours).
#[inline]
pub(crate) fn node_differences(
    d: &[u16],
    cols: usize,
    rows: usize,
    i: usize,
    j: usize,
    empty: u16,
) -> (i32, i32) {
    let at = |i: usize, j: usize| d[j * cols + i];
    let centre = at(i, j) as i32;
    let diff = |prev: Option<u16>, next: Option<u16>| match (prev, next) {
        (Some(p), Some(n)) => n as i32 - p as i32,
        (Some(p), None) => 2 * (centre - p as i32),
        (None, Some(n)) => 2 * (n as i32 - centre),
        (None, None) => 0,
    };
    let get = |i: Option<usize>, j: Option<usize>| match (i, j) {
        (Some(i), Some(j)) if i < cols && j < rows && at(i, j) != empty => Some(at(i, j)),
        _ => None,
    };
    let gi = diff(get(i.checked_sub(1), Some(j)), get(Some(i + 1), Some(j)));
    let gj = diff(get(Some(i), j.checked_sub(1)), get(Some(i), Some(j + 1)));
    (gi, gj)
}

/// The table slot ([`table_slot`]) of every node of a `cols × rows` grid,
/// row-major: [`node_differences`] at each node (by [`grid_differences`]).
pub(crate) fn grid_slots(d: &[u16], cols: usize, rows: usize, empty: u16) -> Vec<u16> {
    let (mut gi, mut gj) = (Vec::new(), Vec::new());
    grid_differences(d, cols, rows, empty, (&mut gi, &mut gj));
    gi.iter()
        .zip(&gj)
        .map(|(&gi, &gj)| table_slot(gi, gj))
        .collect()
}

/// The differences `(gi, gj)` of [`node_differences`] of every node of a
/// `cols × rows` grid `d` whose empty code is `empty`, row-major
/// (meaningless for empty nodes), written over `gi` and `gj` (their room
/// reused). Why the whole grid in two flat passes,
/// every node by one branch-free rule ([`difference`]), the rows outside
/// the grid read as empty codes and each row's first and last node
/// corrected after: the loops run in vector lanes over the whole grid; a
/// row at a time (15–17 nodes on a scan) left most nodes to the loops'
/// scalar remainders (8.5 M of a one-frame bunny render's 192.7 M
/// instructions; callgrind, `spatch render bunny.spatch -o out.png
/// --threads 1`).
#[inline(always)]
pub(crate) fn grid_differences(
    d: &[u16],
    cols: usize,
    rows: usize,
    empty: u16,
    (gi, gj): (&mut Vec<i32>, &mut Vec<i32>),
) {
    let n = cols * rows;
    let d = &d[..n];
    let across = |below: &[u16], centre: &[u16], above: &[u16], out: &mut Vec<i32>| {
        let nodes = below.iter().zip(centre).zip(above);
        out.extend(nodes.map(|((&b, &c), &a)| difference(b, c, a, empty)));
    };
    // On the stack for grids up to 64 nodes a row (an allocation per
    // level otherwise).
    let (stack, heap);
    let outside: &[u16] = if cols <= 64 {
        stack = [empty; 64];
        &stack[..cols]
    } else {
        heap = vec![empty; cols];
        &heap
    };
    // Room for whole groups of eight, which the shading inputs pad them to
    // ([`crate::prepare::patch`]).
    let room = n.next_multiple_of(8);
    gj.clear();
    gj.reserve(room);
    if rows == 1 {
        across(outside, d, outside, gj);
    } else {
        across(outside, &d[..cols], &d[cols..2 * cols], gj);
        across(&d[..n - 2 * cols], &d[cols..n - cols], &d[2 * cols..], gj);
        across(&d[n - 2 * cols..n - cols], &d[n - cols..], outside, gj);
    }
    gi.clear();
    gi.reserve(room);
    if cols == 1 {
        gi.resize(n, 0);
        return;
    }
    gi.push(difference(empty, d[0], d[1], empty));
    across(&d[..n - 2], &d[1..n - 1], &d[2..], gi);
    gi.push(difference(d[n - 2], d[n - 1], empty, empty));
    // Each row's ends read past the row: neither neighbour there exists.
    for row in 0..rows {
        let (first, last) = (row * cols, (row + 1) * cols - 1);
        gi[first] = difference(empty, d[first], d[first + 1], empty);
        gi[last] = difference(d[last - 1], d[last], empty, empty);
    }
}

/// The difference across a node `centre` from its neighbours `prev` and
/// `next` (the module header's rule: central, one-sided doubled next to an
/// `empty` neighbour, 0 between two), without a branch: an empty
/// neighbour is replaced by the centre and the difference doubled unless
/// both neighbours are filled.
#[inline(always)]
fn difference(prev: u16, centre: u16, next: u16, empty: u16) -> i32 {
    let (p_in, n_in) = (prev != empty, next != empty);
    let p = if p_in { prev } else { centre } as i32;
    let n = if n_in { next } else { centre } as i32;
    (n - p) * (2 - (p_in & n_in) as i32)
}

/// The unit normals [`reconstruct_normal`]`(gi, gj, rx, ry).normalize()`
/// of eight nodes as lanes `[x, y, z]` of `w`, given the ratios negated
/// `(-rx, -ry)`, with the same operations in the same order as one by one
/// (`-g · r` is `g · -r` exactly), so each lane equals its one-by-one
/// value. `gi` and `gj` hold integer differences (exact in `f32`).
#[inline(always)]
pub(crate) fn unit_normals<W: Wide>(
    w: W,
    gi: W::V,
    gj: W::V,
    (nrx, nry): (W::V, W::V),
) -> [W::V; 3] {
    let (half, one) = (w.splat(0.5), w.splat(1.0));
    // As `reconstruct_normal`: `(-g · r · 0.5, ..., 1)`.
    let x = w.mul(w.mul(gi, nrx), half);
    let y = w.mul(w.mul(gj, nry), half);
    // As `Vec3::normalize`: times `1 / sqrt(x·x + y·y + z·z)`, with z = 1.
    let length = w.sqrt(w.add(w.add(w.mul(x, x), w.mul(y, y)), one));
    let inverse = w.div(one, length);
    [w.mul(x, inverse), w.mul(y, inverse), inverse]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slot_exists_exactly_within_the_radius() {
        for gi in -RADIUS - 3..=RADIUS + 3 {
            for gj in [-RADIUS - 1, -RADIUS, -1, 0, 7, RADIUS, RADIUS + 1] {
                let slot = table_slot(gi, gj);
                if gi.abs() > RADIUS || gj.abs() > RADIUS {
                    assert_eq!(slot, OUTSIDE_TABLE, "{gi}, {gj}");
                } else {
                    assert_eq!(slot_differences(slot as usize), (gi, gj));
                }
            }
        }
        assert_eq!(table_slot(i32::MAX, 0), OUTSIDE_TABLE);
        assert_eq!(table_slot(0, i32::MIN), OUTSIDE_TABLE);
    }

    #[test]
    fn grid_slots_are_the_slots_of_each_nodes_differences() {
        // Random codes with empty nodes and large steps (some outside the
        // table), on grids from 2 × 2 up.
        let mut rng = crate::test_rng::XorShift(0x5107_5eed);
        for case in 0..400 {
            let (cols, rows) = (2 + rng.below(7) as usize, 2 + rng.below(7) as usize);
            // Every other grid has few empty nodes, so whole rows take the
            // the filled-row case.
            let empties = if case % 2 == 0 { 8 } else { 60 };
            let d: Vec<u16> = (0..cols * rows)
                .map(|_| match rng.below(empties) {
                    0 => 9,
                    1 => rng.below(200) as u16,
                    _ => 100 + rng.below(12) as u16,
                })
                .collect();
            let slots = grid_slots(&d, cols, rows, 9);
            for j in 0..rows {
                for i in 0..cols {
                    let (gi, gj) = node_differences(&d, cols, rows, i, j, 9);
                    assert_eq!(slots[j * cols + i], table_slot(gi, gj), "{i}, {j}");
                }
            }
        }
    }

    #[test]
    fn grid_differences_are_each_nodes_differences() {
        // Grids from 1 × 1 up (single rows and columns included), empty
        // codes from none to most, steps in and beyond the table.
        // The same two vectors for every grid, so a grid's differences
        // must overwrite the last grid's.
        let mut rng = crate::test_rng::XorShift(0xd1ff_5eed);
        let (mut gi, mut gj) = (vec![-7; 50], vec![-7; 50]);
        for case in 0..600 {
            let (cols, rows) = (1 + rng.below(20) as usize, 1 + rng.below(20) as usize);
            let empties = [1000, 10, 3][case % 3];
            let d: Vec<u16> = (0..cols * rows)
                .map(|_| match rng.below(empties) {
                    0 => 9,
                    _ => 100 + rng.below(300) as u16,
                })
                .collect();
            grid_differences(&d, cols, rows, 9, (&mut gi, &mut gj));
            assert_eq!((gi.len(), gj.len()), (cols * rows, cols * rows));
            for j in 0..rows {
                for i in 0..cols {
                    let k = j * cols + i;
                    if d[k] == 9 {
                        continue;
                    }
                    let want = node_differences(&d, cols, rows, i, j, 9);
                    assert_eq!((gi[k], gj[k]), want, "{cols} x {rows}: {i}, {j}");
                }
            }
        }
    }

    #[test]
    fn differences_are_one_sided_at_borders_and_holes() {
        const E: u16 = u16::MAX;
        // 3 x 2 grid, row-major.
        let d = [10, 12, 20, 11, E, 15];
        assert_eq!(node_differences(&d, 3, 2, 1, 0, E), (10, 0));
        assert_eq!(node_differences(&d, 3, 2, 0, 0, E), (4, 2));
        assert_eq!(node_differences(&d, 3, 2, 0, 1, E), (0, 2));
    }
}
