//! Colour grids (container 1.2 `CGRD`, 1.3 `CGRX`): round trip, byte layout, version,
//! shared grids, merge, files without grids unchanged, 1.2 files still read, lying sections.

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
            assert_eq!(bytes[7], 3, "a file with a colour grid is version 1.3");
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
    // docs/format.md §6.7: one kind byte per patch (the factor of an own grid), then the
    // samples, 3 bytes each (RGB).
    let scene = with_grid(minimal_scene(), 2);
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let at = bytes.windows(4).position(|w| w == b"CGRX").unwrap();
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
        "CGRX is the last section"
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
    let at = bytes.windows(4).position(|w| w == b"CGRX").unwrap();
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
    assert!(err.contains("CGRX"), "{err}");
}

/// Three patches of 4 × 4 nodes: patch 1's grid is patch 0's turned by `orientation`, patch 2
/// has a grid of its own.
fn shared_scene(orientation: u8) -> Scene {
    let base = minimal_scene();
    let template = &base.patches()[0];
    let grid = spatch_format::GridSize::new(4, 4).unwrap();
    let n = grid.node_count();
    let plain = Patch::new(
        *template.frame(),
        grid,
        vec![0; n],
        Some(vec![[9, 9, 9, 255]; n]),
    )
    .unwrap();
    let (cols, rows) = ColourGrid::sample_size(grid, 3);
    let picture = |seed: usize| -> Vec<[u8; 4]> {
        (0..cols * rows)
            .map(|k| {
                let (s, t) = (k % cols, k / cols);
                [(s * 20 + seed) as u8, (t * 9) as u8, (s * t) as u8, 255]
            })
            .collect()
    };
    let first = ColourGrid::new(grid, 3, picture(0)).unwrap();
    let second = first.oriented(orientation);
    let third = ColourGrid::new(grid, 3, picture(1)).unwrap();
    let patches = vec![
        plain.clone().with_colour_grid(first).unwrap(),
        plain.clone().with_colour_grid(second).unwrap(),
        plain.with_colour_grid(third).unwrap(),
    ];
    Scene::new(base.offset(), ColourChannel::Rgb8, patches).unwrap()
}

/// `bytes` with its last section (CGRX) replaced by a raw one holding `payload`.
fn with_raw_last_section(bytes: &[u8], payload: &[u8]) -> Vec<u8> {
    let at = bytes.windows(4).position(|w| w == b"CGRX").unwrap();
    let mut out = bytes[..at].to_vec();
    let mut header = b"CGRX".to_vec();
    header.extend_from_slice(&[0, 0, 0, 0]);
    header.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    header.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&header);
    crc.update(payload);
    header.extend_from_slice(&crc.finalize().to_le_bytes());
    out.extend_from_slice(&header);
    out.extend_from_slice(payload);
    out
}

#[test]
fn a_grid_equal_to_an_earlier_one_turned_is_stored_once_as_a_reference() {
    for orientation in 0..ColourGrid::ORIENTATIONS {
        let scene = shared_scene(orientation);
        for compression in [Compression::None, Compression::Predictive] {
            let bytes = encode_scene(&scene, &WriteOptions::with_compression(compression)).unwrap();
            assert_eq!(decode_scene(&bytes).unwrap(), scene);
            // Raw layout (§6.7): kinds [3, 128 + o, 3], one u32 source (0), two grids.
            let at = bytes.windows(4).position(|w| w == b"CGRX").unwrap();
            let raw_len = u32::from_le_bytes(bytes[at + 12..at + 16].try_into().unwrap());
            assert_eq!(raw_len as usize, 3 + 4 + 2 * 10 * 10 * 3);
        }
        // The raw form a writer would store decodes the same.
        let grids: Vec<&ColourGrid> = scene
            .patches()
            .iter()
            .filter_map(Patch::colour_grid)
            .collect();
        let mut payload = vec![3, 128 + orientation, 3, 0, 0, 0, 0];
        for g in [grids[0], grids[2]] {
            for s in g.samples() {
                payload.extend_from_slice(&s[..3]);
            }
        }
        let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
        let raw = with_raw_last_section(&bytes, &payload);
        assert_eq!(decode_scene(&raw).unwrap(), scene);
    }
}

#[test]
fn a_reference_that_cannot_stand_for_a_grid_is_a_typed_error() {
    let scene = shared_scene(0);
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let samples = |k: usize| -> Vec<u8> {
        scene.patches()[k]
            .colour_grid()
            .unwrap()
            .samples()
            .iter()
            .flat_map(|s| s[..3].to_vec())
            .collect()
    };
    // Patch 0 refers to patch 1 (not earlier); patch 1 refers to patch 1 itself; patch 2
    // refers to patch 1, which has no grid of its own; an unknown kind byte.
    let cases: [(Vec<u8>, &str); 4] = [
        (
            [vec![128, 3, 3, 1, 0, 0, 0], samples(1), samples(2)].concat(),
            "not an earlier patch",
        ),
        (
            [vec![3, 128, 3, 1, 0, 0, 0], samples(0), samples(2)].concat(),
            "not an earlier patch",
        ),
        (
            [vec![3, 128, 128, 0, 0, 0, 0, 1, 0, 0, 0], samples(0)].concat(),
            "no grid of its own",
        ),
        (
            [vec![3, 136, 3, 0, 0, 0, 0], samples(0), samples(2)].concat(),
            "unknown colour grid kind 136",
        ),
    ];
    for (payload, expected) in cases {
        let err = decode_scene(&with_raw_last_section(&bytes, &payload)).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("CGRX") && text.contains(expected), "{text}");
    }
    // The typed variant names both patches.
    let payload = [vec![3, 128, 3, 1, 0, 0, 0], samples(0), samples(2)].concat();
    match decode_scene(&with_raw_last_section(&bytes, &payload)).unwrap_err() {
        spatch_format::FormatError::Corrupt {
            kind:
                spatch_format::Corruption::GridReference {
                    patch,
                    source_patch,
                    ..
                },
            ..
        } => assert_eq!((patch, source_patch), (1, 1)),
        other => panic!("{other}"),
    }
}

#[test]
fn a_turned_grid_that_does_not_fit_its_patch_is_refused() {
    // Patch 0 is 4 × 4 nodes, patch 1 (of the mixed scene) another size: a reference
    // from one to the other cannot fit.
    let a = with_grid(mixed_scene(ColourChannel::Rgb8), 2);
    let bytes = encode_scene(&a, &WriteOptions::default()).unwrap();
    let own: Vec<u8> = a.patches()[0]
        .colour_grid()
        .unwrap()
        .samples()
        .iter()
        .flat_map(|s| s[..3].to_vec())
        .collect();
    let count = a.patches().len();
    let mut payload = vec![0u8; count];
    payload[0] = 2;
    payload[1] = 128;
    payload.extend_from_slice(&[0, 0, 0, 0]);
    payload.extend_from_slice(&own);
    let err = decode_scene(&with_raw_last_section(&bytes, &payload)).unwrap_err();
    assert!(err.to_string().contains("does not fit"), "{err}");
}

#[test]
fn version_1_2_files_with_cgrd_still_read() {
    // Written by the 1.2 writer (BoxTextured.glb, `--colour-budget 2500`): six grids of
    // factor 2 in CGRD, codec 1.
    let golden = std::fs::read(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../testdata/format/v1_2_colour_grids.spatch"),
    )
    .unwrap();
    let (scene, info) = spatch_format::inspect(&golden).unwrap();
    assert_eq!((info.version_major, info.version_minor), (1, 2));
    assert!(info.sections.iter().any(|s| s.tag == "CGRD"));
    let grids: Vec<&ColourGrid> = scene
        .patches()
        .iter()
        .filter_map(Patch::colour_grid)
        .collect();
    assert_eq!(grids.len(), 6);
    assert!(grids.iter().all(|g| g.factor() == 2));
    // Written again it is a 1.3 file with CGRX, and reads back the same.
    let again = encode_scene(&scene, &WriteOptions::default()).unwrap();
    assert_eq!(again[7], 3);
    assert_eq!(decode_scene(&again).unwrap(), scene);
}
