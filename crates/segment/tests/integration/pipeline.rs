use spatch_fixtures::shapes;
use spatch_mesh::{build_face_adjacency, load_mesh, prepare_mesh, PrepareOptions};
use spatch_segment::{segment, SegmentError, SegmentOption, SegmentOptions};

use crate::{assert_valid, isoperimetric_ratio, mesh_of};

#[test]
fn cube_gives_six_regions() {
    let (mesh, adjacency) = mesh_of(&shapes::cube(2.0).translated([1e3, -5.0, 7.0]));
    let (seg, stats) = segment(&mesh, &adjacency, &SegmentOptions::default()).expect("segments");
    assert_valid(&mesh, &adjacency, &seg, 40f32.to_radians());
    assert_eq!(seg.len(), 6);
    assert_eq!(
        (
            stats.preliminary_regions,
            stats.after_secondary,
            stats.after_merge
        ),
        (6, 6, 6)
    );
    let mut axes: Vec<[i32; 3]> = seg
        .regions
        .iter()
        .map(|r| r.axis.round().as_ivec3().to_array())
        .collect();
    axes.sort();
    assert_eq!(
        axes,
        [
            [-1, 0, 0],
            [0, -1, 0],
            [0, 0, -1],
            [0, 0, 1],
            [0, 1, 0],
            [1, 0, 0]
        ]
    );
}

#[test]
fn sphere_regions_are_compact() {
    let (mesh, adjacency) = mesh_of(&shapes::icosphere(10.0, 5));
    let (seg, stats) = segment(&mesh, &adjacency, &SegmentOptions::default()).expect("segments");
    assert_valid(&mesh, &adjacency, &seg, 40f32.to_radians());
    eprintln!("icosphere(5): {stats:?}");
    for r in 0..seg.len() {
        let ratio = isoperimetric_ratio(&mesh, &adjacency, &seg, r);
        assert!(
            ratio < 45.0,
            "region {r} ({} faces): perimeter²/area = {ratio}",
            seg.regions[r].faces.len()
        );
    }
}

#[test]
fn results_do_not_depend_on_the_run_or_the_thread() {
    let (mesh, adjacency) = mesh_of(&shapes::torus(3.0, 1.0, 48, 24));
    let options = SegmentOptions::default();
    let (first, _) = segment(&mesh, &adjacency, &options).expect("segments");
    let others: Vec<_> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..3)
            .map(|_| scope.spawn(|| segment(&mesh, &adjacency, &options).expect("segments").0))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("thread"))
            .collect()
    });
    assert!(others.iter().all(|s| *s == first));
}

#[test]
fn bad_options_and_mismatched_adjacency_are_errors() {
    let (mesh, adjacency) = mesh_of(&shapes::cube(1.0));
    for (options, option) in [
        (
            SegmentOptions::default().with_cone_angle_deg(0.0),
            SegmentOption::ConeAngle,
        ),
        (
            SegmentOptions::default().with_cone_angle_deg(f32::NAN),
            SegmentOption::ConeAngle,
        ),
        (
            SegmentOptions::default().with_merge_angle_deg(95.0),
            SegmentOption::MergeAngle,
        ),
        (
            SegmentOptions::default().with_max_extent(-1.0),
            SegmentOption::MaxExtent,
        ),
        (
            SegmentOptions::default().with_max_extent(f32::NAN),
            SegmentOption::MaxExtent,
        ),
    ] {
        match segment(&mesh, &adjacency, &options) {
            Err(SegmentError::InvalidOption { option: o, .. }) => assert_eq!(o, option),
            other => panic!("{options:?}: expected an invalid option, got {other:?}"),
        }
    }
    let (other, _) = mesh_of(&shapes::single_triangle());
    let wrong = build_face_adjacency(&other);
    let err = segment(&mesh, &wrong, &SegmentOptions::default()).expect_err("mismatch");
    assert!(
        matches!(err, SegmentError::AdjacencyMismatch { .. }),
        "{err}"
    );
}

#[test]
fn bunny_segments_and_reports_its_region_count() {
    let path = spatch_fixtures::require_shared!("bunny/reconstruction/bun_zipper.ply");
    let loaded = load_mesh(&path).expect("bunny loads");
    let (mesh, _) = prepare_mesh(&loaded.mesh, &PrepareOptions::default());
    let adjacency = build_face_adjacency(&mesh);
    let options = SegmentOptions::default();
    let (seg, stats) = segment(&mesh, &adjacency, &options).expect("segments");
    assert_valid(
        &mesh,
        &adjacency,
        &seg,
        options.merge_angle_deg.to_radians(),
    );
    eprintln!(
        "bunny: {} faces -> {} preliminary, {} after secondary, {} after merge; {:?}",
        mesh.face_count(),
        stats.preliminary_regions,
        stats.after_secondary,
        stats.after_merge,
        stats.seconds_per_stage
    );
    assert_eq!(stats.after_merge, seg.len());
    assert!(stats.after_merge <= stats.after_secondary);
    // Far fewer regions than the original's 1,526 patches: the fitter splits large ones.
    assert!(seg.len() < 1526, "{} regions", seg.len());
}
