//! docs/format.md against the reader (issue 20, item 7): the raw-length rule of §3.2 in
//! every section, and the exact f32 evaluation of node positions of §1.1.

use glam::{DVec3, Quat, Vec3};
use spatch_format::{
    decode_scene, encode_scene, inspect, ColourChannel, Corruption, FormatError, Opening, Scene,
    Sides, WriteOptions,
};

use crate::corruption::with_section_lengths;
use crate::scenes::mixed_scene;

/// A scene whose file holds all seven known sections: colours (COLR), a far part
/// (ORGR), two-sided patches (SIDE) and an opening (OPEN).
fn every_section_scene() -> Scene {
    let near = mixed_scene(ColourChannel::Rgb8);
    let far = mixed_scene(ColourChannel::Rgb8)
        .translated(DVec3::new(1.0e7 + 0.3, -2.5e6, 0.125))
        .unwrap();
    let merged = Scene::merge(vec![near, far]).unwrap();
    let patches = merged
        .patches()
        .iter()
        .enumerate()
        .map(|(k, p)| p.clone().with_sides([Sides::Front, Sides::Both][k % 2]))
        .collect();
    Scene::new(merged.offset(), merged.channel(), patches)
        .unwrap()
        .with_openings(vec![Opening::new(Vec3::ONE, 1.0, Vec3::Z, 0.2).unwrap()])
}

#[test]
fn the_test_file_holds_every_section() {
    let bytes = encode_scene(&every_section_scene(), &WriteOptions::default()).unwrap();
    let (_, info) = inspect(&bytes).unwrap();
    let tags: Vec<&str> = info.sections.iter().map(|s| s.tag.as_str()).collect();
    assert_eq!(
        tags,
        ["SCNE", "FRAM", "DISP", "COLR", "ORGR", "SIDE", "OPEN"]
    );
}

#[test]
fn a_raw_section_whose_raw_length_is_not_its_stored_length_is_refused_in_every_section() {
    let bytes = encode_scene(&every_section_scene(), &WriteOptions::default()).unwrap();
    let (_, info) = inspect(&bytes).unwrap();
    for section in &info.sections {
        assert_eq!(section.codec, 0, "{}", section.tag);
        for raw in [section.raw_len + 1, section.raw_len.saturating_sub(1), 0] {
            if raw == section.raw_len {
                continue;
            }
            let damaged = with_section_lengths(&bytes, &section.tag, None, Some(raw as u32));
            let err = decode_scene(&damaged).expect_err(&section.tag);
            match (&err, section.tag.as_str()) {
                // The node data's raw length is first checked against what the frames need.
                (
                    FormatError::Corrupt {
                        kind: Corruption::RawLength { .. },
                        section: s,
                    },
                    "DISP" | "COLR",
                ) => assert_eq!(s, &section.tag),
                (
                    FormatError::Corrupt {
                        kind: Corruption::RawLengthNotStored { stored, raw: r },
                        section: s,
                    },
                    _,
                ) => {
                    assert_eq!(s, &section.tag);
                    assert_eq!((*stored, *r), (section.stored_len, raw));
                }
                _ => panic!("{}: raw length {raw}: {err}", section.tag),
            }
        }
    }
}

#[test]
fn a_section_that_must_be_raw_names_its_codec() {
    let bytes = encode_scene(&every_section_scene(), &WriteOptions::default()).unwrap();
    let (_, info) = inspect(&bytes).unwrap();
    for tag in ["SCNE", "FRAM", "ORGR", "SIDE", "OPEN"] {
        let section = info.sections.iter().find(|s| s.tag == tag).unwrap();
        let mut damaged = bytes.clone();
        damaged[section.offset + 4] = 1;
        let at = section.offset;
        let mut crc = crc32fast::Hasher::new();
        crc.update(&damaged[at..at + 16]);
        crc.update(&damaged[at + 20..at + 20 + section.stored_len]);
        damaged[at + 16..at + 20].copy_from_slice(&crc.finalize().to_le_bytes());
        let err = decode_scene(&damaged).unwrap_err();
        assert!(
            matches!(&err, FormatError::Corrupt { kind: Corruption::NotRaw(1), section } if section == tag),
            "{tag}: {err}"
        );
    }
}

/// docs/format.md §1.1, steps 1 and 2, written from the text alone.
fn unit_axes_as_written(q: Quat) -> [[f32; 3]; 3] {
    let (qx, qy, qz, qw) = (q.x, q.y, q.z, q.w);
    let n = ((qx * qx + qz * qz) + (qy * qy + qw * qw)).sqrt();
    let (x, y, z, w) = (qx / n, qy / n, qz / n, qw / n);
    let b = [x, y, z];
    let basis = [[1.0f32, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    basis.map(|v| {
        let bb = (x * x + y * y) + z * z;
        let c = w * w - bb;
        let s = ((v[0] * x + v[1] * y) + v[2] * z) * 2.0;
        let t = w * 2.0;
        let cross = [
            y * v[2] - v[1] * z,
            z * v[0] - v[2] * x,
            x * v[1] - v[0] * y,
        ];
        [0, 1, 2].map(|k| (v[k] * c + b[k] * s) + cross[k] * t)
    })
}

#[test]
fn node_positions_follow_the_written_expression() {
    let scene = every_section_scene();
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let read = decode_scene(&bytes).unwrap();
    let mut nodes = 0;
    for patch in read.patches() {
        let frame = patch.frame();
        let lengths = frame.lengths();
        let units = unit_axes_as_written(frame.rotation());
        // Step 3: the scaled axes.
        let axes: [[f32; 3]; 3] = [0, 1, 2].map(|a| units[a].map(|c| c * lengths[a]));
        let origin = frame.precise_origin();
        for (i, j, _) in patch.filled_nodes() {
            let d = f32::from(patch.displacement(i, j).unwrap());
            let (fi, fj) = (i as f32, j as f32);
            // Step 4, per component.
            let local =
                [0, 1, 2].map(|k| ((axes[0][k] * fi) + (axes[1][k] * fj)) + (axes[2][k] * d));
            // Step 5, in f64.
            let expected = (read.offset() + origin) + DVec3::from_array(local.map(f64::from));
            let got = patch.model_position(read.offset(), i, j).unwrap();
            assert_eq!(
                got.to_array().map(f64::to_bits),
                expected.to_array().map(f64::to_bits),
                "node ({i}, {j})"
            );
            assert_eq!(
                patch.node_local(i, j).unwrap().to_array().map(f32::to_bits),
                local.map(f32::to_bits)
            );
            nodes += 1;
        }
    }
    assert!(nodes > 1000, "{nodes}");
}
