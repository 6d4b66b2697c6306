//! Per-tile conversion of a plan joins into the conversion of the whole cloud on the same
//! grid: the same patches to within the few that border effects move, no tile's points
//! lost, no duplicates.

use glam::Vec3;
use spatch_cloud::{cloud_to_scene, CloudOptions};
use spatch_fixtures::Cityscape;
use spatch_mesh::PointCloud;
use spatch_tiling::{is_member, make_plan, read_tile_points, stream_points, PlanOptions};

use crate::write_city_ply;

#[test]
fn tiles_converted_alone_add_up_to_the_whole_tiled_conversion() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.ply");
    let city = Cityscape::new(80_000, 9);
    write_city_ply(&city, &path);
    let plan = make_plan(
        &path,
        &PlanOptions {
            tile: city.side() / 2.0 + 0.01,
            buffer: None,
            spacing: None,
            pixel_factor: 2.0,
        },
    )
    .unwrap();
    let grid = plan.grid.tile_grid().unwrap();
    let mut options = CloudOptions::default();
    options.spacing = Some(plan.spacing);
    options.tile_grid = Some(grid);

    // The whole cloud on the plan's grid.
    let anchor = glam::DVec3::from_array(plan.grid.anchor);
    let mut whole = PointCloud {
        origin: anchor,
        positions: Vec::new(),
        colours: None,
        normals: None,
    };
    stream_points(&path, &mut |c| {
        whole
            .positions
            .extend(c.positions.iter().map(|p| (*p - anchor).as_vec3()));
        Ok(())
    })
    .unwrap();
    let all = cloud_to_scene(&whole, &options).unwrap();

    let (mut patches, mut nodes, mut own_total) = (0usize, 0usize, 0u64);
    for tile in &plan.tiles {
        let (cloud, own) = read_tile_points(&path, &grid, tile.key).unwrap();
        assert_eq!(own, tile.points);
        // Every point read is a member; the buffer adds points.
        assert!(cloud.positions.iter().all(|p| is_member(
            &grid,
            tile.key,
            cloud.origin + p.as_dvec3()
        )));
        assert!(cloud.positions.len() as u64 > own);
        own_total += own;
        let mut one = options.clone();
        one.only_tile = Some(tile.key);
        let Ok(conversion) = cloud_to_scene(&cloud, &one) else {
            assert!(
                own < 50,
                "tile {} with {own} points has no surface",
                tile.index
            );
            continue;
        };
        patches += conversion.scene.patches().len();
        nodes += conversion.scene.node_count();
        // No patch far outside the tile: each was cut for its own points.
        let (lo, hi) = conversion.scene.bounds().unwrap();
        let reach = Vec3::splat(2.0 * plan.grid.buffer as f32).as_dvec3();
        assert!(lo
            .cmpge(glam::DVec3::from_array(tile.bounds.min) - reach)
            .all());
        assert!(hi
            .cmple(glam::DVec3::from_array(tile.bounds.max) + reach)
            .all());
    }
    assert_eq!(own_total, 80_000);
    let (whole_patches, whole_nodes) = (all.scene.patches().len(), all.scene.node_count());
    let close = |a: usize, b: usize| (a as f64 - b as f64).abs() <= 0.03 * b as f64;
    assert!(
        close(patches, whole_patches),
        "{patches} patches vs {whole_patches}"
    );
    assert!(close(nodes, whole_nodes), "{nodes} nodes vs {whole_nodes}");
}
