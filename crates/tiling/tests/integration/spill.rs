//! The single-pass spill gives every tile exactly the cloud that reading the tile alone
//! gives, whatever the memory budget (so a local run's tiles are byte-identical to tiles
//! converted one at a time).

use spatch_fixtures::Cityscape;
use spatch_tiling::{
    make_plan, read_spilled_tile, read_tile_points, spill_tiles, PlanOptions, SPILL_BUDGET,
};

use crate::write_city_ply;

/// Spills `path` with `budget` and compares every tile with [`read_tile_points`].
fn spill_matches_tile_reads(path: &std::path::Path, tile: f64, budget: usize) {
    let plan = make_plan(
        path,
        &PlanOptions {
            tile,
            buffer: Some(0.8),
            spacing: None,
            pixel_factor: 2.0,
        },
    )
    .unwrap();
    assert!(plan.tiles.len() >= 4, "{} tiles", plan.tiles.len());
    let grid = plan.grid.tile_grid().unwrap();
    let keys: Vec<_> = plan.tiles.iter().map(|t| t.key).collect();
    let dir = tempfile::tempdir().unwrap();
    let spill = spill_tiles(path, &grid, &keys, dir.path(), budget).unwrap();
    let mut records = 0;
    for (i, tile) in plan.tiles.iter().enumerate() {
        let (alone, own) = read_tile_points(path, &grid, tile.key).unwrap();
        let (spilled, spilled_own) = read_spilled_tile(&spill, i).unwrap();
        assert_eq!(spilled_own, own, "tile {i}");
        assert_eq!(own, tile.points, "tile {i}");
        assert!(alone.len() as u64 > own, "tile {i} has no buffer point");
        assert!(spilled == alone, "tile {i}: the spilled cloud differs");
        records += spill.tiles[i].points;
    }
    // Buffer points are spilled to every tile that needs them.
    assert!(
        records > plan.points,
        "{records} records for {} points",
        plan.points
    );
}

#[test]
fn spilled_tiles_equal_tiles_read_alone_with_colours_and_a_tiny_budget() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    // More than one chunk, and a budget that flushes after every chunk.
    let city = Cityscape::new(70_000, 2);
    write_city_ply(&city, &path);
    spill_matches_tile_reads(&path, city.side() / 3.0, 1);
    spill_matches_tile_reads(&path, city.side() / 2.0 + 0.01, SPILL_BUDGET);
}

#[test]
fn spilled_tiles_equal_tiles_read_alone_without_colours_with_normals() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    let city = Cityscape::new(20_000, 6);
    let mut text = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nend_header\n",
        city.len()
    );
    city.for_each_chunk(4096, &mut |p, _| {
        for (i, p) in p.iter().enumerate() {
            let ny = (i % 3) as f32 / 3.0;
            text.push_str(&format!("{} {} {} 0 {ny} 1\n", p[0], p[1], p[2]));
        }
    });
    std::fs::write(&path, text).unwrap();
    spill_matches_tile_reads(&path, city.side() / 2.0 + 0.01, 1000);
}
