//! The shared real scans: the two raw bunny range scans (alone, and registered together with
//! the poses of `bun.conf`) and Hoppe's distcap. Skipped when ../shared/data is missing.

use glam::{DQuat, DVec3, Vec3};
use spatch_cloud::CloudOptions;
use spatch_mesh::{load_point_cloud, PointCloud};

use crate::clouds::{assert_targets, convert_and_measure};

fn check_file(relative: &str) {
    let path = spatch_fixtures::require_shared!(relative);
    let loaded = load_point_cloud(&path).expect("the scan loads");
    assert_eq!(loaded.dropped_non_finite, 0);
    let (conversion, error) = convert_and_measure(&loaded.cloud, &CloudOptions::default());
    assert_targets(relative, &loaded.cloud, &conversion, &error);
}

#[test]
fn bun000_meets_the_targets() {
    check_file("bunny/data/bun000.ply");
}

#[test]
fn bun045_meets_the_targets() {
    check_file("bunny/data/bun045.ply");
}

#[test]
fn hoppe_distcap_meets_the_targets() {
    check_file("pointcloud/hoppe_distcap.ply");
}

/// The pose of a scan in `bun.conf`: translation and quaternion (x, y, z, w).
fn pose(conf: &str, scan: &str) -> (DVec3, DQuat) {
    let line = conf
        .lines()
        .find(|l| l.starts_with("bmesh") && l.contains(scan))
        .expect("the scan has a pose");
    let v: Vec<f64> = line
        .split_whitespace()
        .skip(2)
        .map(|t| t.parse().unwrap())
        .collect();
    // SOURCES.md: the quaternion must be conjugated to put the scans in one frame.
    (
        DVec3::new(v[0], v[1], v[2]),
        DQuat::from_xyzw(-v[3], -v[4], -v[5], v[6]),
    )
}

#[test]
fn two_registered_bunny_scans_meet_the_targets() {
    let conf = spatch_fixtures::require_shared!("bunny/data/bun.conf");
    let conf = std::fs::read_to_string(conf).unwrap();
    let mut world = Vec::new();
    for scan in ["bun000.ply", "bun045.ply"] {
        let path = spatch_fixtures::require_shared!(&format!("bunny/data/{scan}"));
        let cloud = load_point_cloud(&path).unwrap().cloud;
        let (t, q) = pose(&conf, scan);
        world.extend((0..cloud.len()).map(|i| q * cloud.world_position(i) + t));
    }
    let origin = world.iter().fold(DVec3::ZERO, |a, p| a + *p) / world.len() as f64;
    let merged = PointCloud {
        origin,
        positions: world
            .iter()
            .map(|p| (*p - origin).as_vec3())
            .collect::<Vec<Vec3>>(),
        colours: None,
        normals: None,
    };
    let (conversion, error) = convert_and_measure(&merged, &CloudOptions::default());
    assert_targets("bun000+bun045", &merged, &conversion, &error);
}
