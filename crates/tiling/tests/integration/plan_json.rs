//! A plan written and read back holds the exact f64 bounds, anchor and sizes it was made
//! with, so a task decides ownership (`[min, max)` against the plan's boxes) on the very
//! values the plan computed. serde_json writes the shortest decimal that reads back to the
//! same f64, and parses with correct rounding only with its `float_roundtrip` feature: its
//! default parser can land one unit in the last place off (this test fails without it).

use spatch_tiling::{Plan, PlanGrid, PlanTile, WorldBox, PLAN_VERSION};

/// `n` f64 values from a fixed linear congruential sequence, spread over the magnitudes a
/// plan meets (survey coordinates to millimetre tile buffers), with full 53-bit fractions.
fn awkward_values(n: usize) -> Vec<f64> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    (0..n)
        .map(|k| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let fraction = (state >> 11) as f64 / (1u64 << 53) as f64;
            let scale = [1e-3, 0.37, 50.0, 4.1e3, 6.4e6, 4.0e7][k % 6];
            let sign = if k % 7 == 3 { -1.0 } else { 1.0 };
            sign * scale * (1.0 + fraction)
        })
        .collect()
}

#[test]
fn a_plan_read_back_has_bit_identical_bounds() {
    let values = awkward_values(6 * 8000);
    let mut chunks = values.chunks_exact(6);
    let mut next_box = || {
        let c = chunks.next().unwrap();
        WorldBox {
            min: [c[0], c[1], c[2]],
            max: [c[3], c[4], c[5]],
        }
    };
    let tiles: Vec<PlanTile> = (0..3998)
        .map(|index| PlanTile {
            index,
            key: [index as i64, -1, 0],
            bounds: next_box(),
            buffered: next_box(),
            points: index as u64,
        })
        .collect();
    let plan = Plan {
        version: PLAN_VERSION,
        input: "city.las".to_string(),
        points: 1,
        skipped_non_finite: 0,
        bounds: WorldBox {
            min: [6.4e6 + 1.0 / 3.0, -0.1, -1.999_997_377_395_629_9],
            max: [6.4e6 + 50.0 / 7.0, 0.3, 1.0 / 3.0],
        },
        spacing: 0.1,
        pixel_factor: 1.0,
        grid: PlanGrid {
            anchor: [6.4e6 + 1.0 / 3.0, 4_000_000.2, -7.7],
            size: 50.0 / 3.0,
            buffer: 0.1 + 0.2,
        },
        tiles,
        scan_shifts: Some(vec![[1.0 / 3.0, -2e-7, 0.0], [0.0, 0.25, -1e-300]]),
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plan.json");
    std::fs::write(&path, plan.to_json()).unwrap();
    let back = Plan::read(&path).unwrap();
    let bits = |b: &WorldBox| [b.min, b.max].map(|c| c.map(f64::to_bits));
    let mut differ = 0;
    for (a, b) in plan.tiles.iter().zip(&back.tiles) {
        differ += usize::from(bits(&a.bounds) != bits(&b.bounds));
        differ += usize::from(bits(&a.buffered) != bits(&b.buffered));
    }
    assert_eq!(differ, 0, "tile boxes changed by the JSON round trip");
    assert_eq!(bits(&plan.bounds), bits(&back.bounds));
    assert_eq!(
        plan.grid.anchor.map(f64::to_bits),
        back.grid.anchor.map(f64::to_bits)
    );
    assert_eq!(plan.grid.size.to_bits(), back.grid.size.to_bits());
    assert_eq!(plan.grid.buffer.to_bits(), back.grid.buffer.to_bits());
    assert_eq!(plan, back);
}
