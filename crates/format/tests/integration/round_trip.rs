//! Write → read round trips.

use glam::{DVec3, Quat, Vec3};
use proptest::prelude::*;
use spatch_format::{
    decode_scene, encode_scene, inspect, ColourChannel, Compression, Frame, GridSize, Patch, Scene,
    WriteOptions, EMPTY,
};

use crate::scenes::mixed_scene;

const COMPRESSIONS: [Compression; 2] = [Compression::None, Compression::Predictive];

#[test]
fn mixed_scenes_round_trip_in_every_channel_and_codec() {
    for channel in [
        ColourChannel::None,
        ColourChannel::Rgb8,
        ColourChannel::Rgba8,
    ] {
        let scene = mixed_scene(channel);
        for compression in COMPRESSIONS {
            let bytes = encode_scene(&scene, &WriteOptions::with_compression(compression)).unwrap();
            let (decoded, info) = inspect(&bytes).unwrap();
            assert_eq!(decoded, scene, "{channel:?} {compression:?}");
            let tags: Vec<&str> = info.sections.iter().map(|s| s.tag.as_str()).collect();
            let expected: &[&str] = if channel == ColourChannel::None {
                &["SCNE", "FRAM", "DISP"]
            } else {
                &["SCNE", "FRAM", "DISP", "COLR"]
            };
            assert_eq!(tags, expected);
        }
    }
}

#[test]
fn one_flat_colour_is_stored_once() {
    let base = mixed_scene(ColourChannel::Rgb8);
    let patches = base
        .patches()
        .iter()
        .map(|p| {
            let colours = vec![[10, 20, 30, 255]; p.grid().node_count()];
            Patch::new(
                *p.frame(),
                p.grid(),
                p.displacements().to_vec(),
                Some(colours),
            )
            .unwrap()
        })
        .collect();
    let flat = Scene::new(base.offset(), ColourChannel::Rgb8, patches).unwrap();
    let bytes = encode_scene(&flat, &WriteOptions::default()).unwrap();
    let (decoded, info) = inspect(&bytes).unwrap();
    assert!(info.flat_colour);
    assert!(info.sections.iter().all(|s| s.tag != "COLR"));
    assert_eq!(decoded, flat);
}

#[test]
fn compression_shrinks_smooth_grids() {
    let sphere = spatch_format_test_sphere();
    let raw = encode_scene(&sphere, &WriteOptions::default()).unwrap();
    let packed = encode_scene(
        &sphere,
        &WriteOptions::with_compression(Compression::Predictive),
    )
    .unwrap();
    assert!(
        packed.len() * 2 < raw.len(),
        "{} vs {}",
        packed.len(),
        raw.len()
    );
    assert_eq!(decode_scene(&packed).unwrap(), sphere);
}

/// A smooth dome without the sphere crate (format has no internal deps).
fn spatch_format_test_sphere() -> Scene {
    let grid = GridSize::new(33, 33).unwrap();
    let displacements: Vec<u16> = (0..grid.node_count())
        .map(|k| {
            let (i, j) = ((k % 33) as f32 - 16.0, (k / 33) as f32 - 16.0);
            (400.0 - (i * i + j * j) * 0.6) as u16
        })
        .collect();
    let patches = (0..20)
        .map(|k| {
            let frame =
                Frame::new(Vec3::splat(k as f32), Vec3::X, Vec3::Y, Vec3::Z * 0.01).unwrap();
            Patch::new(frame, grid, displacements.clone(), None).unwrap()
        })
        .collect();
    Scene::new(DVec3::ZERO, ColourChannel::None, patches).unwrap()
}

#[test]
fn output_is_deterministic() {
    let scene = mixed_scene(ColourChannel::Rgba8);
    for compression in COMPRESSIONS {
        let options = WriteOptions::with_compression(compression);
        assert_eq!(
            encode_scene(&scene, &options).unwrap(),
            encode_scene(&scene.clone(), &options).unwrap()
        );
    }
}

fn arbitrary_patch(channel: ColourChannel) -> impl Strategy<Value = Patch> {
    (
        2u32..12,
        2u32..12,
        any::<bool>(),
        -1e3f32..1e3,
        0.0f32..std::f32::consts::TAU,
        0.0f32..std::f32::consts::PI,
        1e-3f32..10.0,
        1e-4f32..1.0,
        any::<u64>(),
    )
        .prop_map(
            move |(cols, rows, wide, shift, yaw, pitch, spacing, step, seed)| {
                let rotation = Quat::from_rotation_z(yaw) * Quat::from_rotation_x(pitch);
                let frame = Frame::new(
                    Vec3::new(shift, -shift, shift * 0.5),
                    rotation * Vec3::X * spacing,
                    rotation * Vec3::Y * spacing * 1.5,
                    rotation * Vec3::Z * step,
                )
                .unwrap();
                let grid = GridSize::new(cols, rows).unwrap();
                let mut state = seed | 1;
                let mut next = move || {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    state
                };
                let max = if wide { 65534 } else { 254 };
                let displacements: Vec<u16> = (0..grid.node_count())
                    .map(|_| {
                        let r = next();
                        if r % 5 == 0 {
                            EMPTY
                        } else {
                            (r % (max + 1)) as u16
                        }
                    })
                    .collect();
                let colours = (channel != ColourChannel::None).then(|| {
                    (0..grid.node_count())
                        .map(|_| next().to_le_bytes()[..4].try_into().unwrap())
                        .collect()
                });
                Patch::new(frame, grid, displacements, colours).unwrap()
            },
        )
}

fn arbitrary_scene() -> impl Strategy<Value = Scene> {
    prop_oneof![
        Just(ColourChannel::None),
        Just(ColourChannel::Rgb8),
        Just(ColourChannel::Rgba8)
    ]
    .prop_flat_map(|channel| {
        (
            prop::collection::vec(arbitrary_patch(channel), 0..6),
            -1e9f64..1e9,
        )
            .prop_map(move |(patches, offset)| {
                Scene::new(DVec3::new(offset, 1.0, -offset), channel, patches).unwrap()
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_scenes_round_trip_exactly(scene in arbitrary_scene(), compress in any::<bool>()) {
        let compression = if compress { Compression::Predictive } else { Compression::None };
        let bytes = encode_scene(&scene, &WriteOptions::with_compression(compression)).unwrap();
        prop_assert_eq!(decode_scene(&bytes).unwrap(), scene);
    }

    #[test]
    fn merging_adds_patch_counts(a in arbitrary_scene(), b in arbitrary_scene()) {
        let (na, nb) = (a.patches().len(), b.patches().len());
        match Scene::merge(vec![a.clone(), b.clone()]) {
            Ok(merged) => {
                prop_assert_eq!(merged.patches().len(), na + nb);
                prop_assert_eq!(merged.filled_node_count(), a.filled_node_count() + b.filled_node_count());
            }
            Err(_) => prop_assert_ne!(a.channel(), b.channel()),
        }
    }
}
