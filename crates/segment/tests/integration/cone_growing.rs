use spatch_fixtures::shapes;
use spatch_segment::{grow_cones, SegmentOptions};

use crate::{assert_valid, mesh_of};

#[test]
fn cube_faces_become_six_regions() {
    let (mesh, adjacency) = mesh_of(&shapes::cube(2.0));
    let seg = grow_cones(&mesh, &adjacency, &SegmentOptions::default()).expect("segments");
    assert_valid(&mesh, &adjacency, &seg, 30f32.to_radians());
    assert_eq!(seg.len(), 6);
    assert!(seg
        .regions
        .iter()
        .all(|r| r.half_angle < 1e-3 && r.faces.len() == 2));
}

#[test]
fn every_cone_is_within_theta1_for_several_angles() {
    let (mesh, adjacency) = mesh_of(&shapes::icosphere(1.0, 3));
    let mut previous = usize::MAX;
    for degrees in [10.0, 20.0, 30.0, 45.0, 60.0] {
        let options = SegmentOptions::default().with_cone_angle_deg(degrees);
        let seg = grow_cones(&mesh, &adjacency, &options).expect("segments");
        assert_valid(&mesh, &adjacency, &seg, f32::to_radians(degrees));
        // A wider cone never needs more regions on a sphere.
        assert!(seg.len() <= previous, "{degrees}°: {} regions", seg.len());
        previous = seg.len();
    }
}

#[test]
fn the_first_region_on_a_sphere_fills_its_cone() {
    // The first seed sees an untouched sphere: a tight cone lets its region grow to nearly
    // the whole cap of half-angle θ1 (a loose cone would stop early).
    let (mesh, adjacency) = mesh_of(&shapes::icosphere(1.0, 4));
    let seg = grow_cones(&mesh, &adjacency, &SegmentOptions::default()).expect("segments");
    let cap_area = std::f32::consts::TAU * (1.0 - 30f32.to_radians().cos());
    let largest = seg.regions.iter().map(|r| r.area).fold(0.0, f32::max);
    assert!(
        largest > 0.85 * cap_area,
        "largest region {largest}, cap {cap_area}"
    );
}
