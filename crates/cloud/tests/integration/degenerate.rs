//! Degenerate input and options: clear errors, never a panic.

use glam::{DVec3, Vec3};
use spatch_cloud::{cloud_to_scene, CloudError, CloudOptions};

use crate::clouds::{cloud, sphere};

#[test]
fn empty_cloud_is_refused() {
    let err =
        cloud_to_scene(&cloud(DVec3::ZERO, Vec::new()), &CloudOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            CloudError::EmptyCloud {
                dropped_non_finite: 0
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("empty"));
}

#[test]
fn single_point_is_refused() {
    let err = cloud_to_scene(
        &cloud(DVec3::ZERO, vec![Vec3::ONE]),
        &CloudOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            CloudError::TooFewPoints {
                found: 1,
                needed: 3
            }
        ),
        "{err}"
    );
}

#[test]
fn only_non_finite_points_is_an_empty_cloud_with_the_count() {
    let c = cloud(
        DVec3::ZERO,
        vec![Vec3::NAN, Vec3::new(f32::INFINITY, 0.0, 0.0)],
    );
    let err = cloud_to_scene(&c, &CloudOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            CloudError::EmptyCloud {
                dropped_non_finite: 2
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("2 non-finite"), "{err}");
}

#[test]
fn non_finite_points_are_dropped_and_counted() {
    let mut points = sphere(5_000, 1.0);
    for k in (0..points.len()).step_by(500) {
        points[k] = Vec3::new(f32::NAN, 0.0, 1.0);
    }
    let c = cloud(DVec3::ZERO, points);
    let conversion = cloud_to_scene(&c, &CloudOptions::default()).unwrap();
    assert_eq!(conversion.report.dropped_non_finite, 10);
    assert_eq!(conversion.report.points, 4_990);
    assert_eq!(conversion.report.input_points, 5_000);
    for patch in conversion.scene.patches() {
        assert!(patch.filled_nodes().all(|(_, _, p)| p.is_finite()));
    }
}

#[test]
fn coincident_points_have_no_extent() {
    let err = cloud_to_scene(
        &cloud(DVec3::ZERO, vec![Vec3::ONE; 50]),
        &CloudOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(err, CloudError::NoExtent { points: 50, .. }),
        "{err}"
    );
}

#[test]
fn collinear_points_have_no_surface() {
    let line = (0..500)
        .map(|k| Vec3::new(k as f32 * 0.01, 0.0, 0.0))
        .collect();
    let err = cloud_to_scene(&cloud(DVec3::ZERO, line), &CloudOptions::default()).unwrap_err();
    assert!(
        matches!(err, CloudError::NoSurface { points: 500 }),
        "{err}"
    );
}

#[test]
fn mismatched_attributes_and_bad_options_are_refused() {
    let mut c = cloud(DVec3::ZERO, sphere(100, 1.0));
    c.colours = Some(vec![[0; 4]; 3]);
    let err = cloud_to_scene(&c, &CloudOptions::default()).unwrap_err();
    assert!(
        matches!(
            err,
            CloudError::MismatchedAttribute {
                what: "colours",
                ..
            }
        ),
        "{err}"
    );

    let c = cloud(DVec3::ZERO, sphere(100, 1.0));
    let with = |change: fn(&mut CloudOptions)| {
        let mut options = CloudOptions::default();
        change(&mut options);
        options
    };
    for (field, options) in [
        ("views", with(|o| o.views = 0)),
        ("grid", with(|o| o.grid = 1)),
        ("spacing", with(|o| o.spacing = Some(-1.0))),
        ("pixel_factor", with(|o| o.pixel_factor = f32::NAN)),
    ] {
        let err = cloud_to_scene(&c, &options).unwrap_err();
        assert!(
            matches!(err, CloudError::InvalidOption { option, .. } if option == field),
            "{field}: {err}"
        );
    }
}

#[test]
fn a_few_far_outliers_do_not_blow_up_the_images() {
    let mut points = sphere(20_000, 1.0);
    points.push(Vec3::splat(5_000.0));
    points.push(Vec3::splat(-5_000.0));
    let conversion = cloud_to_scene(&cloud(DVec3::ZERO, points), &CloudOptions::default()).unwrap();
    assert!(!conversion.report.warnings.is_empty());
    assert!(conversion.report.counts.patches > 0);
}
