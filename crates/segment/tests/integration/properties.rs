use glam::Vec3;
use proptest::prelude::*;
use spatch_fixtures::shapes;
use spatch_mesh::{build_face_adjacency, TriangleMesh};
use spatch_segment::{segment, SegmentOptions};

use crate::assert_valid;

fn options_strategy() -> impl Strategy<Value = SegmentOptions> {
    (
        5.0f32..60.0,
        5.0f32..80.0,
        0usize..40,
        prop_oneof![Just(f32::INFINITY), 0.1f32..3.0],
    )
        .prop_map(|(cone, merge, min_faces, extent)| {
            SegmentOptions::default()
                .with_cone_angle_deg(cone)
                .with_merge_angle_deg(merge)
                .with_min_region_faces(min_faces)
                .with_max_extent(extent)
        })
}

fn check(mesh: &TriangleMesh, options: &SegmentOptions) {
    let adjacency = build_face_adjacency(mesh);
    let (seg, stats) = segment(mesh, &adjacency, options).expect("segments");
    let bound = options
        .cone_angle_deg
        .max(options.merge_angle_deg)
        .to_radians();
    assert_valid(mesh, &adjacency, &seg, bound);
    assert!(stats.after_merge <= stats.after_secondary);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Triangle soups over few vertices: many shared, non-manifold and degenerate faces.
    #[test]
    fn random_soups_partition_every_face(
        points in prop::collection::vec(prop::array::uniform3(-2i8..3), 3..24),
        picks in prop::collection::vec(prop::array::uniform3(0usize..1000), 1..120),
        options in options_strategy(),
    ) {
        let positions: Vec<Vec3> = points.iter().map(|p| Vec3::new(p[0].into(), p[1].into(), p[2].into())).collect();
        let n = positions.len();
        let triangles = picks.iter().map(|t| t.map(|i| (i % n) as u32)).collect();
        let mesh = TriangleMesh::new(positions, triangles).expect("valid");
        check(&mesh, &options);
    }

    /// Closed shapes with jittered vertices: realistic meshes with noisy normals.
    #[test]
    fn perturbed_shapes_partition_every_face(
        which in 0usize..3,
        jitter in prop::collection::vec(prop::array::uniform3(-1.0f32..1.0), 16),
        amount in 0.0f32..0.2,
        options in options_strategy(),
    ) {
        let shape = match which {
            0 => shapes::icosphere(1.0, 2),
            1 => shapes::torus(1.5, 0.5, 24, 12),
            _ => shapes::cylinder(1.0, 2.0, 24),
        };
        let positions: Vec<Vec3> = shape
            .positions
            .iter()
            .enumerate()
            .map(|(i, &p)| Vec3::from(p) + Vec3::from(jitter[i % jitter.len()]) * amount * (1.0 + (i % 7) as f32) / 7.0)
            .collect();
        let mesh = TriangleMesh::new(positions, shape.triangles).expect("valid");
        check(&mesh, &options);
    }
}
