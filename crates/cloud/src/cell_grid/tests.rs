//! Unit tests of the cell grid: visits within a radius and near a run, item lists, clipped
//! ranges, hash probes on a sheet, boxes of a point.

use super::*;
use spatch_mesh::SplitMix64;

fn build_slice(boxes: &[(Vec3, Vec3)]) -> Option<(CellGrid, Vec<u32>)> {
    CellGrid::build(boxes.len(), |k| boxes[k])
}

/// Random small boxes with a few long ones.
fn boxes(n: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut rng = SplitMix64::new(seed);
    let mut r = || rng.next_f64() as f32;
    (0..n)
        .map(|k| {
            let lo = Vec3::new(r(), r(), r() * 0.1);
            let size = if k % 97 == 0 { 0.5 } else { 0.01 };
            (lo, lo + Vec3::new(r(), r(), r()) * size)
        })
        .collect()
}

fn box_axis_gap(p: Vec3, (lo, hi): (Vec3, Vec3)) -> f32 {
    (lo - p).max(p - hi).max(Vec3::ZERO).max_element()
}

#[test]
fn every_box_within_the_radius_is_visited() {
    let boxes = boxes(5000, 4);
    let (grid, order) = build_slice(&boxes).unwrap();
    assert!(!grid.extras().is_empty() && grid.extras().len() <= MAX_EXTRAS);
    let mut rng = SplitMix64::new(8);
    for _ in 0..500 {
        let p = Vec3::new(
            rng.next_f64() as f32,
            rng.next_f64() as f32,
            rng.next_f64() as f32 * 0.2,
        );
        let r = rng.next_f64() * 0.02;
        let mut seen = vec![false; boxes.len()];
        for k in grid.extras() {
            seen[order[k] as usize] = true;
        }
        // In two steps as the search does: the cells within reach, then the rest.
        let first = grid.cells_within(p, 0.0);
        let mark =
            |items: std::ops::Range<usize>| items.for_each(|k| seen[order[k] as usize] = true);
        grid.visit(&first, &CellRange::EMPTY, mark);
        let mark =
            |items: std::ops::Range<usize>| items.for_each(|k| seen[order[k] as usize] = true);
        grid.visit(&grid.cells_within(p, r), &first, mark);
        for (k, &b) in boxes.iter().enumerate() {
            if f64::from(box_axis_gap(p, b)) <= r {
                assert!(seen[k], "box {k} missed from {p} within {r}");
            }
        }
    }
}

#[test]
fn visit_near_reads_every_box_near_a_run_and_skips_far_cells() {
    // Small boxes and one in 16 six times longer: too many for the extras, so they stay
    // in the grid and widen every range.
    let mut boxes = boxes(5000, 6);
    for b in boxes.iter_mut().step_by(16) {
        b.1 = b.0 + (b.1 - b.0) * 6.0;
    }
    let (grid, order) = build_slice(&boxes).unwrap();
    let mut gridded = vec![true; boxes.len()];
    for k in grid.extras() {
        gridded[order[k] as usize] = false;
    }
    let mut rng = SplitMix64::new(9);
    let (mut read, mut whole) = (0usize, 0usize);
    for _ in 0..300 {
        let lo = Vec3::new(
            rng.next_f64() as f32,
            rng.next_f64() as f32,
            rng.next_f64() as f32 * 0.1,
        );
        let hi = lo + Vec3::splat(rng.next_f64() as f32 * 0.02);
        let gap = rng.next_f64() * 0.01;
        let range = grid.cells_near(lo.as_dvec3(), hi.as_dvec3(), gap);
        let mut seen = vec![false; boxes.len()];
        grid.visit_near(&range, (lo.as_dvec3(), hi.as_dvec3()), gap, |items| {
            read += items.len();
            items.for_each(|k| seen[order[k] as usize] = true);
        });
        grid.visit(&range, &CellRange::EMPTY, |items| whole += items.len());
        for (k, &(blo, bhi)) in boxes.iter().enumerate() {
            let axis_gap = (lo - bhi).max(blo - hi).max(Vec3::ZERO).max_element();
            if gridded[k] && f64::from(axis_gap) <= gap {
                assert!(seen[k], "box {k} missed near {lo}..{hi} within {gap}");
            }
        }
    }
    // The long boxes widen every cell range; most cells read by `visit` are skipped.
    assert!(read * 2 < whole, "{read} of {whole} items read");
}

#[test]
fn every_item_is_listed_once() {
    let boxes = boxes(3000, 2);
    let (grid, order) = build_slice(&boxes).unwrap();
    let mut all = order.clone();
    all.sort_unstable();
    assert_eq!(all, (0..3000).collect::<Vec<u32>>());
    assert_eq!(grid.extras().end, order.len());
    // Every gridded item is in the run of the grid cell holding its box centre.
    for (at, &k) in order[..grid.extras().start].iter().enumerate() {
        let (lo, hi) = boxes[k as usize];
        let c = grid.cell_of(centre_and_half(lo, hi).0);
        assert!(grid.items(c).contains(&at), "item {k}");
    }
}

#[test]
fn ranges_are_clipped_to_the_grid() {
    let (grid, _) = build_slice(&boxes(2000, 5)).unwrap();
    let whole = grid.cells_within(Vec3::splat(0.5), 10.0);
    assert_eq!(
        whole.count(),
        grid.dims.iter().map(|&d| d as f64).product::<f64>()
    );
    assert_eq!(grid.cells_within(Vec3::splat(50.0), 1.0).count(), 0.0);
    let nan = grid.cells_within(Vec3::NAN, 0.0);
    assert_eq!(nan, whole);
    assert_eq!(CellRange::EMPTY.count(), 0.0);
}

#[test]
fn hash_probes_stay_short_on_a_flat_sheet() {
    // A million cells of a plane: regular keys must not cluster in the table.
    let n = 1000;
    let b: Vec<(Vec3, Vec3)> = (0..n * n)
        .map(|k| {
            let lo = Vec3::new((k % n) as f32, (k / n) as f32, 0.0) * 1e-3;
            (lo, lo + Vec3::new(1e-3, 1e-3, 0.0))
        })
        .collect();
    let (grid, _) = build_slice(&b).unwrap();
    let mask = grid.slots.len() - 1;
    assert_eq!(grid.starts.len() % (BLOCK_CELLS + 1), 0);
    let (mut probes, mut keys) = (0usize, 0usize);
    for slot in grid.slots.iter().filter(|s| s.key != EMPTY_KEY) {
        let mut at = grid.hash(slot.key);
        probes += 1;
        while grid.slots[at].key != slot.key {
            at = (at + 1) & mask;
            probes += 1;
        }
        keys += 1;
    }
    let mean = probes as f64 / keys as f64;
    eprintln!(
        "{keys} grid blocks, {} slots, {mean} probes per hit",
        grid.slots.len()
    );
    assert!(mean < 2.0, "{mean} probes per hit");
}

#[test]
fn point_boxes_are_not_gridded() {
    let b = vec![(Vec3::ONE, Vec3::ONE); 10];
    assert!(build_slice(&b).is_none());
    assert!(build_slice(&[]).is_none());
}
