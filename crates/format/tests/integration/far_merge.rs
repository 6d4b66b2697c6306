//! Issue 22, item 5: merging scenes far apart keeps every part's precision,
//! through the container too.

use glam::{DVec3, Quat, Vec3};
use spatch_format::{
    decode_scene, encode_scene, ColourChannel, Frame, GridSize, Patch, Scene, WriteOptions,
};

use crate::scenes::mixed_scene;

/// A unit-sized curved patch set near its own offset.
fn small_scene(offset: DVec3) -> Scene {
    let patches = (0..4u16)
        .map(|k| {
            let r = Quat::from_rotation_z(0.4 * f32::from(k)) * Quat::from_rotation_x(0.3);
            let frame = Frame::new(
                Vec3::new(0.1 * f32::from(k), -0.05, 0.02),
                r * Vec3::X * 0.013,
                r * Vec3::Y * 0.011,
                r * Vec3::Z * 0.0007,
            )
            .unwrap();
            let grid = GridSize::new(17, 17).unwrap();
            let d = (0..grid.node_count())
                .map(|i| (i * 13 % 251) as u16)
                .collect();
            Patch::new(frame, grid, d, None).unwrap()
        })
        .collect();
    Scene::new(offset, ColourChannel::None, patches).unwrap()
}

/// Largest distance between the model-space nodes of `part` (alone) and
/// of the patches of `merged` from `first` on.
fn worst_node_error(part: &Scene, merged: &Scene, first: usize) -> f64 {
    let mut worst = 0.0f64;
    for (alone, moved) in part.patches().iter().zip(&merged.patches()[first..]) {
        for (i, j, _) in alone.filled_nodes() {
            let a = part.offset() + alone.precise_node_position(i, j).unwrap();
            let b = merged.offset() + moved.precise_node_position(i, j).unwrap();
            worst = worst.max((a - b).length());
        }
    }
    worst
}

#[test]
fn issue_22_far_parts_keep_their_node_positions() {
    let near = small_scene(DVec3::new(0.25, -0.5, 1.0));
    for distance in [1e4, 1e6, 1e7] {
        let far = small_scene(DVec3::new(distance, -0.3 * distance, 0.7));
        let merged = Scene::merge(vec![near.clone(), far.clone()]).unwrap();
        let decoded = decode_scene(&encode_scene(&merged, &WriteOptions::default()).unwrap())
            .expect("the merged scene decodes");
        assert_eq!(decoded, merged, "ORGR carries the residuals");
        let n = near.patches().len();
        // The scene is about 0.5 units wide: 1e-6 relative is 5e-7 units.
        let err = worst_node_error(&far, &decoded, n);
        assert!(err < 5e-7, "at {distance}: far part moved by {err}");
        assert!(worst_node_error(&near, &decoded, 0) == 0.0);
        // Without the residual (what the plain f32 origin holds) the far
        // part is off by far more: the test can fail.
        if distance >= 1e6 {
            let err_f32 =
                far.patches()
                    .iter()
                    .zip(&decoded.patches()[n..])
                    .fold(0.0f64, |w, (a, b)| {
                        let exact = far.offset() + a.frame().precise_origin();
                        let plain = decoded.offset() + b.frame().origin().as_dvec3();
                        w.max((exact - plain).length())
                    });
            assert!(err_f32 > 1e-3, "at {distance}: {err_f32}");
        }
    }
}

#[test]
fn a_scene_without_residuals_is_written_as_version_1_0() {
    let bytes = encode_scene(&mixed_scene(ColourChannel::Rgb8), &WriteOptions::default()).unwrap();
    assert_eq!(bytes[7], 0);
    let merged = Scene::merge(vec![
        small_scene(DVec3::ZERO),
        small_scene(DVec3::new(1e6 + 0.1, 0.0, 0.0)),
    ])
    .unwrap();
    let bytes = encode_scene(&merged, &WriteOptions::default()).unwrap();
    assert_eq!(bytes[7], 1);
    assert!(bytes.windows(4).any(|w| w == b"ORGR"));
}

#[test]
fn translating_moves_only_the_offset() {
    let scene = small_scene(DVec3::new(1.0, 2.0, 3.0));
    let moved = scene.clone().translated(DVec3::new(1e7, 0.5, 0.0)).unwrap();
    assert_eq!(moved.offset(), DVec3::new(1e7 + 1.0, 2.5, 3.0));
    assert_eq!(moved.patches(), scene.patches());
    assert!(scene
        .translated(DVec3::new(f64::INFINITY, 0.0, 0.0))
        .is_err());
}
