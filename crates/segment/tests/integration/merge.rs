use spatch_fixtures::shapes;
use spatch_segment::{grow_cones, merge_regions, SegmentOptions};

use crate::{assert_valid, mesh_of};

#[test]
fn small_regions_merge_within_theta3() {
    // A fine cone angle makes many small regions on a sphere; merging at θ3 = 25° must
    // reduce them and keep every union within 25°.
    let (mesh, adjacency) = mesh_of(&shapes::icosphere(1.0, 3));
    let options = SegmentOptions::default()
        .with_cone_angle_deg(8.0)
        .with_merge_angle_deg(25.0)
        .with_min_region_faces(40);
    let fine = grow_cones(&mesh, &adjacency, &options).expect("stage 1");
    let merged = merge_regions(&mesh, &adjacency, &fine, &options).expect("stage 3");
    assert_valid(&mesh, &adjacency, &merged, 25f32.to_radians());
    assert!(
        merged.len() * 2 < fine.len(),
        "{} -> {} regions",
        fine.len(),
        merged.len()
    );
}

#[test]
fn merged_regions_respect_max_extent() {
    let (mesh, adjacency) = mesh_of(&shapes::icosphere(1.0, 3));
    let max_extent = 0.6;
    let options = SegmentOptions::default()
        .with_cone_angle_deg(8.0)
        .with_merge_angle_deg(60.0)
        .with_min_region_faces(1000)
        .with_max_extent(max_extent);
    let fine = grow_cones(&mesh, &adjacency, &options).expect("stage 1");
    let merged = merge_regions(&mesh, &adjacency, &fine, &options).expect("stage 3");
    assert_valid(&mesh, &adjacency, &merged, 60f32.to_radians());
    assert!(merged.len() < fine.len());
    for (r, region) in merged.regions.iter().enumerate() {
        let first = fine.face_region[region.faces[0].index()];
        if region.faces == fine.regions[first.index()].faces {
            continue; // not merged: stage 1 made it, max_extent does not bind it
        }
        let corners: Vec<glam::Vec3> = region
            .faces
            .iter()
            .flat_map(|&f| mesh.face_positions(f))
            .collect();
        let diameter = corners
            .iter()
            .flat_map(|a| corners.iter().map(move |b| a.distance(*b)))
            .fold(0.0f32, f32::max);
        assert!(
            diameter <= max_extent * 1.0001,
            "region {r}: diameter {diameter}"
        );
    }
}

#[test]
fn zero_min_faces_merges_nothing_and_cube_edges_never_merge() {
    let (mesh, adjacency) = mesh_of(&shapes::icosphere(1.0, 2));
    let off = SegmentOptions::default()
        .with_cone_angle_deg(10.0)
        .with_min_region_faces(0);
    let fine = grow_cones(&mesh, &adjacency, &off).expect("stage 1");
    let same = merge_regions(&mesh, &adjacency, &fine, &off).expect("stage 3");
    assert_eq!(same, fine);

    // Cube sides are 90° apart: a union's cone is at least 45°, above θ3 = 40°.
    let (cube, cube_adjacency) = mesh_of(&shapes::cube(1.0));
    let options = SegmentOptions::default().with_min_region_faces(100);
    let sides = grow_cones(&cube, &cube_adjacency, &options).expect("stage 1");
    let merged = merge_regions(&cube, &cube_adjacency, &sides, &options).expect("stage 3");
    assert_eq!(merged.len(), 6);
}

/// A flat `n × n` grid of unit quads in `z = 0` with a strip of `n × 1` quads folded up by 20°
/// along its `x = n` side.
fn folded_grid(n: u32) -> spatch_fixtures::Shape {
    let mut shape = spatch_fixtures::Shape::default();
    let (s, c) = 20f32.to_radians().sin_cos();
    for j in 0..=n {
        for i in 0..=n + 1 {
            let p = if i <= n {
                [i as f32, j as f32, 0.0]
            } else {
                [n as f32 + c, j as f32, s]
            };
            shape.positions.push(p);
        }
    }
    let v = |i: u32, j: u32| j * (n + 2) + i;
    for j in 0..n {
        for i in 0..=n {
            shape
                .triangles
                .push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            shape
                .triangles
                .push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    shape
}

#[test]
fn a_small_region_joins_a_region_already_wider_than_a_patch() {
    let (mesh, adjacency) = mesh_of(&folded_grid(12));
    let options = SegmentOptions::default()
        .with_cone_angle_deg(5.0)
        .with_merge_angle_deg(40.0)
        .with_min_region_faces(30)
        .with_max_extent(4.0);
    let parts = grow_cones(&mesh, &adjacency, &options).expect("stage 1");
    assert_eq!(parts.len(), 2, "flat grid and folded strip");
    // The grid (288 faces, 17 units across) is tiled by the fitter anyway: the strip joins.
    let merged = merge_regions(&mesh, &adjacency, &parts, &options).expect("stage 3");
    assert_valid(&mesh, &adjacency, &merged, 40f32.to_radians());
    assert_eq!(merged.len(), 1);

    // Two regions that each fit a patch never merge into one that does not.
    let (mesh, adjacency) = mesh_of(&folded_grid(3));
    let options = options.with_max_extent(4.5);
    let parts = grow_cones(&mesh, &adjacency, &options).expect("stage 1");
    assert_eq!(parts.len(), 2);
    let merged = merge_regions(&mesh, &adjacency, &parts, &options).expect("stage 3");
    assert_eq!(merged.len(), 2, "union wider than max_extent");
    let wide = options.with_max_extent(10.0);
    let merged = merge_regions(&mesh, &adjacency, &parts, &wide).expect("stage 3");
    assert_eq!(merged.len(), 1, "union within max_extent");
}
