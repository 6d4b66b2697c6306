//! Visible sides and openings (container 1.1, the `SIDE` and `OPEN` sections) and the inside
//! box of two-sided patches (1.4, `INSD`).

use glam::{DVec3, Vec3};
use spatch_format::{
    decode_scene, encode_scene, inspect, ColourChannel, InsideBox, Opening, Scene, Sides,
    WriteOptions,
};

use crate::scenes::{minimal_scene, mixed_scene};
use crate::section_bytes::section_bytes;

/// `scene` with patch `k` given `sides(k)` and the openings `openings`.
pub(crate) fn with_sides(
    scene: &Scene,
    sides: impl Fn(usize) -> Sides,
    openings: Vec<Opening>,
) -> Scene {
    let patches = scene
        .patches()
        .iter()
        .enumerate()
        .map(|(k, p)| p.clone().with_sides(sides(k)))
        .collect();
    Scene::new(scene.offset(), scene.channel(), patches)
        .unwrap()
        .with_openings(openings)
}

fn cycle(k: usize) -> Sides {
    [Sides::Front, Sides::ThroughOpenings, Sides::Both][k % 3]
}

fn two_openings() -> Vec<Opening> {
    vec![
        Opening::new(Vec3::new(1.0, 2.0, 3.0), 0.5, Vec3::Y, 0.1).unwrap(),
        Opening::new(Vec3::ZERO, 0.0, Vec3::Z, 0.0).unwrap(),
    ]
}

#[test]
fn sides_and_openings_round_trip_and_only_then_the_file_is_1_1() {
    let plain = mixed_scene(ColourChannel::Rgb8);
    let bytes = encode_scene(&plain, &WriteOptions::default()).unwrap();
    let (decoded, info) = inspect(&bytes).unwrap();
    assert_eq!(info.version_minor, 0, "nothing of 1.1 is needed");
    assert!(info
        .sections
        .iter()
        .all(|s| s.tag != "SIDE" && s.tag != "OPEN"));
    assert!(decoded.patches().iter().all(|p| p.sides() == Sides::Front));
    assert!(decoded.openings().is_empty());

    let marked = with_sides(&plain, cycle, two_openings());
    let bytes = encode_scene(&marked, &WriteOptions::default()).unwrap();
    let (decoded, info) = inspect(&bytes).unwrap();
    assert_eq!(info.version_minor, 1);
    let tags: Vec<&str> = info.sections.iter().map(|s| s.tag.as_str()).collect();
    assert_eq!(tags, ["SCNE", "FRAM", "DISP", "COLR", "SIDE", "OPEN"]);
    assert_eq!(info.sections[4].stored_len, marked.patches().len());
    assert_eq!(info.sections[5].stored_len, 64);
    assert_eq!(decoded, marked);
    assert!(decoded
        .patches()
        .iter()
        .enumerate()
        .all(|(k, p)| p.sides() == cycle(k)));
}

#[test]
fn merging_keeps_sides_and_moves_openings() {
    let a = with_sides(&minimal_scene(), |_| Sides::ThroughOpenings, two_openings());
    let moved = Scene::new(
        a.offset() + DVec3::new(10.0, 0.0, 0.0),
        a.channel(),
        minimal_scene().patches().to_vec(),
    )
    .unwrap()
    .with_openings(vec![Opening::new(Vec3::ONE, 2.0, Vec3::X, 0.0).unwrap()]);
    let merged = Scene::merge(vec![a, moved]).unwrap();
    let sides: Vec<Sides> = merged.patches().iter().map(|p| p.sides()).collect();
    assert_eq!(sides, [Sides::ThroughOpenings, Sides::Front]);
    assert_eq!(merged.openings().len(), 3);
    assert_eq!(merged.openings()[2].centre(), Vec3::new(11.0, 1.0, 1.0));
    assert_eq!(merged.openings()[2].radius(), 2.0);
}

/// Replaces the payload and codec of section `tag` of `bytes` and fixes its CRC.
fn with_payload(bytes: &[u8], tag: &str, payload: &[u8], codec: u8) -> Vec<u8> {
    let (_, info) = inspect(bytes).unwrap();
    let k = info.sections.iter().position(|s| s.tag == tag).unwrap();
    let s = &info.sections[k];
    let mut out = bytes[..s.offset].to_vec();
    let tag: &[u8; 4] = tag.as_bytes().try_into().unwrap();
    out.extend_from_slice(&section_bytes(tag, codec, payload));
    out.extend_from_slice(&bytes[s.offset + 20 + s.stored_len..]);
    out
}

#[test]
fn side_and_open_sections_that_lie_are_refused() {
    let scene = with_sides(
        &mixed_scene(ColourChannel::None),
        |_| Sides::Both,
        two_openings(),
    );
    let n = scene.patches().len();
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let good = vec![1u8; n];
    assert!(decode_scene(&with_payload(&bytes, "SIDE", &good, 0)).is_ok());
    let mut unknown = good.clone();
    unknown[n - 1] = 3;
    for (payload, codec, what) in [
        (
            &[good.clone(), vec![0]].concat()[..],
            0,
            "one byte too many",
        ),
        (&good[..n - 1], 0, "one byte too few"),
        (&unknown[..], 0, "an unknown code"),
        (&good[..], 1, "a codec"),
    ] {
        let err = decode_scene(&with_payload(&bytes, "SIDE", payload, codec)).expect_err(what);
        assert!(err.to_string().contains("SIDE"), "{what}: {err}");
    }
    let negative: Vec<u8> = [0.0f32, 0.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    for (payload, what) in [
        (&negative[..], "a negative radius"),
        (&[0u8; 31][..], "a short record"),
    ] {
        let err = decode_scene(&with_payload(&bytes, "OPEN", payload, 0)).expect_err(what);
        assert!(err.to_string().contains("OPEN"), "{what}: {err}");
    }
}

fn unit_box() -> InsideBox {
    InsideBox::new(Vec3::new(-1.0, -2.0, -3.0), Vec3::new(1.0, 2.0, 3.0)).unwrap()
}

#[test]
fn an_inside_box_round_trips_as_insd_after_open_and_makes_the_file_1_4() {
    let scene = with_sides(
        &mixed_scene(ColourChannel::Rgb8),
        |_| Sides::Both,
        two_openings(),
    )
    .with_inside_box(Some(unit_box()));
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let (decoded, info) = inspect(&bytes).unwrap();
    assert_eq!(info.version_minor, 4);
    let tags: Vec<&str> = info.sections.iter().map(|s| s.tag.as_str()).collect();
    assert_eq!(
        tags,
        ["SCNE", "FRAM", "DISP", "COLR", "SIDE", "OPEN", "INSD"]
    );
    let insd = &info.sections[6];
    assert_eq!(insd.stored_len, 24);
    let payload = &bytes[insd.offset + 20..insd.offset + 44];
    let floats: Vec<f32> = payload
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    assert_eq!(floats, [-1.0, -2.0, -3.0, 1.0, 2.0, 3.0]);
    assert_eq!(decoded, scene);
    assert_eq!(decoded.inside_box(), Some(unit_box()));
}

#[test]
fn merging_joins_inside_boxes_only_when_every_two_sided_part_has_one() {
    let boxed = |shift: f64| {
        let s = with_sides(&minimal_scene(), |_| Sides::Both, Vec::new())
            .with_inside_box(Some(unit_box()));
        s.translated(DVec3::new(shift, 0.0, 0.0)).unwrap()
    };
    let merged = Scene::merge(vec![boxed(0.0), boxed(10.0)]).unwrap();
    let b = merged.inside_box().expect("both parts have a box");
    assert_eq!(b.min(), Vec3::new(-1.0, -2.0, -3.0));
    assert_eq!(b.max(), Vec3::new(11.0, 2.0, 3.0));
    // A front-only part without a box leaves the union as it is.
    let merged = Scene::merge(vec![boxed(0.0), minimal_scene()]).unwrap();
    assert_eq!(merged.inside_box(), Some(unit_box()));
    // A two-sided part without one (a point cloud: its backs show from anywhere) drops it.
    let cloud = with_sides(&minimal_scene(), |_| Sides::Both, Vec::new());
    let merged = Scene::merge(vec![boxed(0.0), cloud]).unwrap();
    assert_eq!(merged.inside_box(), None);
}

#[test]
fn insd_sections_that_lie_are_refused() {
    let scene = with_sides(
        &mixed_scene(ColourChannel::None),
        |_| Sides::Both,
        Vec::new(),
    )
    .with_inside_box(Some(unit_box()));
    let bytes = encode_scene(&scene, &WriteOptions::default()).unwrap();
    let floats = |v: [f32; 6]| -> Vec<u8> { v.iter().flat_map(|x| x.to_le_bytes()).collect() };
    let good = floats([0.0, 0.0, 0.0, 1.0, 1.0, 1.0]);
    assert!(decode_scene(&with_payload(&bytes, "INSD", &good, 0)).is_ok());
    for (payload, codec, what) in [
        (
            floats([2.0, 0.0, 0.0, 1.0, 1.0, 1.0]),
            0,
            "a lower corner above the upper",
        ),
        (floats([0.0, 0.0, f32::NAN, 1.0, 1.0, 1.0]), 0, "a NaN"),
        (good[..20].to_vec(), 0, "a short box"),
        ([good.clone(), good.clone()].concat(), 0, "two boxes"),
        (good.clone(), 1, "a codec"),
    ] {
        let err = decode_scene(&with_payload(&bytes, "INSD", &payload, codec)).expect_err(what);
        assert!(err.to_string().contains("INSD"), "{what}: {err}");
    }
}
