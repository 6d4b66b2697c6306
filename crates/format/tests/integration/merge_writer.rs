//! The streaming [`MergeWriter`] writes, byte for byte, what `encode_scene` writes for
//! `Scene::merge` of the same scenes, and leaves no scratch file behind.

use glam::{DVec3, Vec3};
use spatch_format::{
    decode_scene, encode_scene, ColourChannel, Compression, Frame, GridSize, InsideBox, MergeError,
    MergeWriter, Opening, Patch, Scene, Sides, WriteOptions,
};

use crate::scenes::{minimal_scene, mixed_scene};
use crate::two_sided::with_sides;

/// The bytes of the in-memory merge and of the streaming one.
fn both(scenes: &[Scene], options: WriteOptions) -> (Vec<u8>, Vec<u8>) {
    let merged = Scene::merge(scenes.to_vec()).unwrap();
    let expected = encode_scene(&merged, &options).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut writer = MergeWriter::new(dir.path(), options).unwrap();
    for scene in scenes {
        writer.push(scene.clone()).unwrap();
    }
    let mut streamed = Vec::new();
    let written = writer.write_to(&mut streamed).unwrap();
    assert_eq!(written, streamed.len() as u64);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    (expected, streamed)
}

/// Two 3 × 3 patches of one grid whose every filled node is `colour`.
fn flat_scene(offset: DVec3, colour: [u8; 4]) -> Scene {
    let frame = Frame::new(Vec3::ONE, Vec3::X, Vec3::Y, Vec3::Z * 0.01).unwrap();
    let grid = GridSize::new(3, 3).unwrap();
    let patch = |k: u16| {
        let d = (0..9u16)
            .map(|i| if i == k { spatch_format::EMPTY } else { i })
            .collect();
        Patch::new(frame, grid, d, Some(vec![colour; 9])).unwrap()
    };
    Scene::new(offset, ColourChannel::Rgba8, vec![patch(0), patch(4)]).unwrap()
}

fn options() -> [WriteOptions; 2] {
    [
        WriteOptions::default(),
        WriteOptions::with_compression(Compression::Predictive),
    ]
}

#[test]
fn streamed_merges_are_byte_identical_to_in_memory_ones() {
    let far = |s: Scene, d: f64| s.translated(DVec3::new(d, -0.5 * d, 3.0)).unwrap();
    for channel in [
        ColourChannel::None,
        ColourChannel::Rgb8,
        ColourChannel::Rgba8,
    ] {
        let mixed = mixed_scene(channel);
        let sets = [
            vec![mixed.clone()],
            vec![mixed.clone(), mixed.clone()],
            vec![
                mixed.clone(),
                far(mixed.clone(), 1e7),
                far(mixed.clone(), -3e4),
            ],
        ];
        for (k, scenes) in sets.iter().enumerate() {
            for options in options() {
                let (expected, streamed) = both(scenes, options);
                assert!(expected == streamed, "{channel:?}, set {k}, {options:?}");
            }
        }
    }
}

#[test]
fn shared_grids_flat_colours_sides_and_openings_are_chosen_alike() {
    let red = [255, 0, 0, 255];
    let opening = Opening::new(Vec3::new(1.0, 2.0, 3.0), 0.5, Vec3::Y, 0.1).unwrap();
    let sided = |s: Scene| with_sides(&s, |k| [Sides::Front, Sides::Both][k % 2], vec![opening]);
    let inside = InsideBox::new(Vec3::splat(-1.0), Vec3::new(1.0, 1.5, 2.0)).unwrap();
    let boxed = |s: Scene| sided(s).with_inside_box(Some(inside));
    let sets = [
        // One grid and one colour everywhere: shared grid, flat colour, no COLR.
        vec![
            flat_scene(DVec3::ZERO, red),
            flat_scene(DVec3::X * 1e6, red),
        ],
        // The colour changes in the second scene: per-node colours.
        vec![
            flat_scene(DVec3::ZERO, red),
            flat_scene(DVec3::ZERO, [0, 9, 0, 255]),
        ],
        // SIDE in one part only, OPEN moved by the offset difference.
        vec![
            minimal_scene(),
            sided(minimal_scene().translated(DVec3::Y * 7.0).unwrap()),
        ],
        vec![
            sided(flat_scene(DVec3::ZERO, red)),
            flat_scene(DVec3::Z * 2.5, red),
        ],
        // INSD: two boxes joined, the second moved by the offset difference.
        vec![
            boxed(flat_scene(DVec3::ZERO, red)),
            boxed(flat_scene(DVec3::Z * 2.5, red)),
        ],
        // A two-sided part without a box drops the box.
        vec![
            boxed(flat_scene(DVec3::ZERO, red)),
            sided(flat_scene(DVec3::Z * 2.5, red)),
        ],
    ];
    for (k, scenes) in sets.iter().enumerate() {
        for options in options() {
            let (expected, streamed) = both(scenes, options);
            assert!(expected == streamed, "set {k}, {options:?}");
            let decoded = decode_scene(&streamed).unwrap();
            assert_eq!(decoded, Scene::merge(scenes.clone()).unwrap(), "set {k}");
        }
    }
}

#[test]
fn a_file_is_written_atomically_and_a_channel_mismatch_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("all.spatch");
    let scenes = [mixed_scene(ColourChannel::Rgb8), minimal_scene()];
    let mut writer = MergeWriter::new(dir.path(), WriteOptions::default()).unwrap();
    for scene in &scenes {
        writer.push(scene.clone()).unwrap();
    }
    let bytes = writer.write_to_file(&path).unwrap();
    let expected = encode_scene(
        &Scene::merge(scenes.to_vec()).unwrap(),
        &WriteOptions::default(),
    )
    .unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), expected);
    assert_eq!(bytes, expected.len() as u64);
    let names: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
    assert_eq!(names.len(), 1, "scratch files left: {names:?}");

    let mut writer = MergeWriter::new(dir.path(), WriteOptions::default()).unwrap();
    writer.push(minimal_scene()).unwrap();
    let err = writer.push(mixed_scene(ColourChannel::None)).unwrap_err();
    assert!(
        matches!(err, MergeError::ChannelMismatch { index: 1, .. }),
        "{err}"
    );
}
