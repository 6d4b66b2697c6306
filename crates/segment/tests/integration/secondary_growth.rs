use spatch_fixtures::{shapes, Shape};
use spatch_segment::{grow_cones, grow_secondary, SegmentError, SegmentOptions, Segmentation};

use crate::{assert_valid, isoperimetric_ratio, mesh_of};

/// The area-weighted mean and the largest `perimeter² / area` over regions of 20 faces or more.
fn compactness(
    mesh: &spatch_mesh::TriangleMesh,
    adjacency: &spatch_mesh::FaceAdjacency,
    seg: &Segmentation,
) -> (f32, f32) {
    let (mut sum, mut area, mut worst) = (0.0, 0.0, 0.0f32);
    for (r, region) in seg.regions.iter().enumerate() {
        let ratio = isoperimetric_ratio(mesh, adjacency, seg, r);
        sum += ratio * region.area;
        area += region.area;
        if region.faces.len() >= 20 {
            worst = worst.max(ratio);
        }
    }
    (sum / area, worst)
}

#[test]
fn secondary_regions_are_more_compact_than_preliminary_ones() {
    // On a sphere cone-growing already grows geodesic discs (deviation is proportional to
    // distance there); on a wavy terrain it follows ridges, and secondary growth must fix that.
    for shape in [wavy_terrain(96, 0.9), wavy_terrain(64, 0.5)] {
        let (mesh, adjacency) = mesh_of(&shape);
        let options = SegmentOptions::default();
        let first = grow_cones(&mesh, &adjacency, &options).expect("stage 1");
        let second = grow_secondary(&mesh, &adjacency, &first, &options).expect("stage 2");
        assert_valid(
            &mesh,
            &adjacency,
            &second,
            options.cone_angle_deg.to_radians(),
        );
        let (before, after) = (
            compactness(&mesh, &adjacency, &first),
            compactness(&mesh, &adjacency, &second),
        );
        eprintln!("perimeter²/area (mean, worst) {before:?} -> {after:?}");
        assert!(
            after.0 < before.0,
            "mean perimeter²/area {before:?} -> {after:?}"
        );
        assert!(
            after.1 < 80.0,
            "worst perimeter²/area {before:?} -> {after:?}"
        );
    }
}

/// A square grid of `n × n` quads over `[0, 4π]²` with height `amplitude · sin x · cos y`.
fn wavy_terrain(n: u32, amplitude: f32) -> Shape {
    let mut shape = Shape::default();
    let step = 4.0 * std::f32::consts::PI / n as f32;
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 * step, j as f32 * step);
            shape.positions.push([x, y, amplitude * x.sin() * y.cos()]);
        }
    }
    let v = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
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
fn seeds_are_interior_faces() {
    let (mesh, adjacency) = mesh_of(&shapes::icosphere(1.0, 4));
    let options = SegmentOptions::default();
    let first = grow_cones(&mesh, &adjacency, &options).expect("stage 1");
    let second = grow_secondary(&mesh, &adjacency, &first, &options).expect("stage 2");
    for region in second.regions.iter().filter(|r| r.faces.len() > 40) {
        let id = second.face_region[region.seed.index()];
        assert!(
            adjacency
                .neighbours(region.seed)
                .iter()
                .all(|g| second.face_region[g.index()] == id),
            "central face {:?} on the border",
            region.seed
        );
    }
}

#[test]
fn a_segmentation_of_another_mesh_is_refused() {
    let (mesh, adjacency) = mesh_of(&shapes::cube(1.0));
    let (small, small_adjacency) = mesh_of(&shapes::single_triangle());
    let options = SegmentOptions::default();
    let other = grow_cones(&small, &small_adjacency, &options).expect("stage 1");
    let err = grow_secondary(&mesh, &adjacency, &other, &options).expect_err("mismatch");
    assert!(
        matches!(err, SegmentError::SegmentationMismatch { .. }),
        "{err}"
    );
}
