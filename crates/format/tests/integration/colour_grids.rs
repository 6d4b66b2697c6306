//! Colour grids (container 1.2, `CGRD`): round trip, byte layout, version, merge, and
//! files without grids unchanged.

use spatch_format::{
    decode_scene, encode_scene, ColourChannel, ColourGrid, Compression, MergeWriter, Patch, Scene,
    WriteOptions,
};

use crate::scenes::{minimal_scene, mixed_scene};

/// `scene` with a colour grid of `factor` on its first patch: a gradient with a flat block.
fn with_grid(scene: Scene, factor: u8) -> Scene {
    let channel = scene.channel();
    let offset = scene.offset();
    let mut patches = scene.into_patches();
    let grid = patches[0].grid();
    let (cols, rows) = ColourGrid::sample_size(grid, factor);
    let samples = (0..cols * rows)
        .map(|k| {
            let (s, t) = (k % cols, k / cols);
            if s < cols / 2 {
                [200, 100, 50, 128]
            } else {
                [(s * 7) as u8, (t * 11) as u8, 9, 255]
            }
        })
        .collect();
    let g = ColourGrid::new(grid, factor, samples).unwrap();
    patches[0] = patches[0].clone().with_colour_grid(g).unwrap();
    Scene::new(offset, channel, patches).unwrap()
}

#[test]
fn colour_grids_round_trip_in_every_channel_and_compression() {
    for channel in [ColourChannel::Rgb8, ColourChannel::Rgba8] {
        for compression in [Compression::None, Compression::Predictive] {
            let scene = with_grid(mixed_scene(channel), 5);
            let bytes = encode_scene(&scene, &WriteOptions::with_compression(compression)).unwrap();
            assert_eq!(bytes[7], 2, "a file with a colour grid is version 1.2");
            let back = decode_scene(&bytes).unwrap();
            assert_eq!(back, scene);
            let g = back.patches()[0].colour_grid().unwrap();
            let alpha = if channel == ColourChannel::Rgb8 {
                255
            } else {
                128
            };
            assert_eq!(g.samples()[0], [200, 100, 50, alpha]);
        }
    }
}

#[test]
fn the_raw_section_has_the_documented_layout() {
    // docs/format.md §6.6: one factor byte per patch, then the samples, 3 bytes each (RGB).
    let scene = with_grid(minimal_scene(), 2);
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let at = bytes.windows(4).position(|w| w == b"CGRD").unwrap();
    let header = &bytes[at..at + 20];
    let raw_len = u32::from_le_bytes(header[12..16].try_into().unwrap()) as usize;
    // 3 × 2 nodes at factor 2: 5 × 3 samples.
    assert_eq!(raw_len, 1 + 15 * 3);
    let payload = &bytes[at + 20..];
    match header[4] {
        0 => {
            assert_eq!(payload[0], 2);
            assert_eq!(&payload[1..4], &[200, 100, 50]);
        }
        codec => assert_eq!(codec, 1),
    }
    assert_eq!(
        at + 20 + payload.len(),
        bytes.len(),
        "CGRD is the last section"
    );
}

#[test]
fn files_without_grids_are_unchanged_and_old_files_still_read() {
    // The 1.0 golden file is written byte for byte as before, and reads with no grid.
    let golden = std::fs::read(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../testdata/format/v1_minimal.spatch"),
    )
    .unwrap();
    let scene = decode_scene(&golden).unwrap();
    assert!(scene.patches().iter().all(|p| p.colour_grid().is_none()));
    assert_eq!(
        encode_scene(&scene, &WriteOptions::default()).unwrap(),
        golden
    );
    // Dropping a scene's grids gives exactly the bytes it had without them.
    let plain = mixed_scene(ColourChannel::Rgb8);
    let gridded = with_grid(plain.clone(), 3);
    let bare: Vec<Patch> = gridded
        .patches()
        .iter()
        .map(|p| p.clone().without_colour_grid())
        .collect();
    let bare = Scene::new(plain.offset(), plain.channel(), bare).unwrap();
    let options = WriteOptions::default();
    assert_eq!(
        encode_scene(&bare, &options).unwrap(),
        encode_scene(&plain, &options).unwrap()
    );
}

#[test]
fn the_merge_writer_keeps_colour_grids() {
    let a = with_grid(mixed_scene(ColourChannel::Rgb8), 4);
    let b = with_grid(minimal_scene(), 2);
    let folder = std::env::temp_dir();
    let mut writer = MergeWriter::new(&folder, WriteOptions::default()).unwrap();
    writer.push(a.clone()).unwrap();
    writer.push(b.clone()).unwrap();
    let mut bytes = Vec::new();
    writer.write_to(&mut bytes).unwrap();
    let merged = Scene::merge(vec![a, b]).unwrap();
    assert_eq!(
        bytes,
        encode_scene(&merged, &WriteOptions::default()).unwrap()
    );
    let back = decode_scene(&bytes).unwrap();
    assert_eq!(
        back.patches()
            .iter()
            .filter(|p| p.colour_grid().is_some())
            .count(),
        2
    );
}

#[test]
fn a_lying_colour_grid_section_is_an_error() {
    let scene = with_grid(minimal_scene(), 2);
    let mut bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let at = bytes.windows(4).position(|w| w == b"CGRD").unwrap();
    // Claim one more raw byte than the factors imply, and fix the CRC so only the
    // length is wrong.
    let raw = u32::from_le_bytes(bytes[at + 12..at + 16].try_into().unwrap()) + 1;
    bytes[at + 12..at + 16].copy_from_slice(&raw.to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&bytes[at..at + 16]);
    crc.update(&bytes[at + 20..]);
    let crc = crc.finalize();
    bytes[at + 16..at + 20].copy_from_slice(&crc.to_le_bytes());
    let err = decode_scene(&bytes).unwrap_err().to_string();
    assert!(err.contains("CGRD"), "{err}");
}
