//! Issue 22, item 5: far from the origin, exports keep node positions to
//! 1e-6 of the model's extent (PLY doubles, OBJ f64 text, glTF f64 node
//! translations, or an explicit origin), alone and after a far merge.

use glam::{DVec3, Vec3};
use spatch_export::{export_scene, Content, ExportOptions, Format, PositionType};
use spatch_format::Scene;

use crate::scenes::{extent, node_positions, sphere};

/// Positions of a PLY export (float or double), plus the recorded origin.
fn read_ply(bytes: &[u8]) -> (Vec<DVec3>, bool) {
    let end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    let doubles = header.contains("property double x");
    let origin = header
        .lines()
        .find_map(|l| l.strip_prefix("comment origin "))
        .map(|l| {
            let v: Vec<f64> = l.split(' ').take(3).map(|x| x.parse().unwrap()).collect();
            DVec3::new(v[0], v[1], v[2])
        })
        .unwrap_or(DVec3::ZERO);
    let count: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .unwrap()
        .parse()
        .unwrap();
    let width = if doubles { 8 } else { 4 };
    let record = 3 * width + 12;
    let positions = bytes[end..end + count * record]
        .chunks_exact(record)
        .map(|r| {
            let at = |k: usize| {
                let b = &r[k * width..(k + 1) * width];
                if doubles {
                    f64::from_le_bytes(b.try_into().unwrap())
                } else {
                    f64::from(f32::from_le_bytes(b.try_into().unwrap()))
                }
            };
            origin + DVec3::new(at(0), at(1), at(2))
        })
        .collect();
    (positions, doubles)
}

/// Positions of an OBJ export.
fn read_obj(bytes: &[u8]) -> Vec<DVec3> {
    std::str::from_utf8(bytes)
        .unwrap()
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let v: Vec<f64> = l.split(' ').take(3).map(|x| x.parse().unwrap()).collect();
            DVec3::new(v[0], v[1], v[2])
        })
        .collect()
}

/// Positions of a GLB export: node translations read as f64 from the JSON
/// chunk, plus the f32 positions the gltf crate reads.
fn read_glb(bytes: &[u8]) -> Vec<DVec3> {
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let (document, buffers, _) = gltf::import_slice(bytes).unwrap();
    let mut out = Vec::new();
    for node in document.nodes() {
        let t = &json["nodes"][node.index()]["translation"];
        let t = DVec3::new(
            t[0].as_f64().unwrap(),
            t[1].as_f64().unwrap(),
            t[2].as_f64().unwrap(),
        );
        let primitive = node.mesh().unwrap().primitives().next().unwrap();
        let reader = primitive.reader(|b| Some(&buffers[b.index()]));
        out.extend(
            reader
                .read_positions()
                .unwrap()
                .map(|p| t + Vec3::from(p).as_dvec3()),
        );
    }
    out
}

/// Largest distance between exported and expected positions, relative to
/// the extent.
fn relative_error(got: &[DVec3], expected: &[DVec3]) -> f64 {
    assert_eq!(got.len(), expected.len());
    let worst = got
        .iter()
        .zip(expected)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f64::max);
    worst / extent(expected)
}

fn nodes(format: Format) -> ExportOptions {
    ExportOptions::new(format, Content::Nodes)
}

#[test]
fn issue_22_far_scenes_export_within_1e_6_of_their_extent() {
    for distance in [1e4, 1e6, 1e7] {
        let shift = DVec3::new(distance, -0.7 * distance, 0.3 * distance);
        let scene = sphere().translated(shift).unwrap();
        let expected = node_positions(&scene);
        let ply = export_scene(&scene, &nodes(Format::Ply)).unwrap();
        let (got, doubles) = read_ply(&ply.bytes);
        assert!(
            doubles && ply.f64_positions,
            "at {distance}: doubles expected"
        );
        assert!(relative_error(&got, &expected) < 1e-6, "ply at {distance}");
        let obj = export_scene(&scene, &nodes(Format::Obj)).unwrap();
        assert!(
            relative_error(&read_obj(&obj.bytes), &expected) < 1e-6,
            "obj at {distance}"
        );
        let glb = export_scene(&scene, &nodes(Format::Glb)).unwrap();
        assert!(
            relative_error(&read_glb(&glb.bytes), &expected) < 1e-6,
            "glb at {distance}"
        );
        // An origin near the model gives f32 precision back in PLY float.
        let mut near = nodes(Format::Ply);
        near.origin = shift + DVec3::new(0.25, 0.5, 0.125);
        let ply = export_scene(&scene, &near).unwrap();
        let (got, doubles) = read_ply(&ply.bytes);
        assert!(!doubles);
        assert!(
            relative_error(&got, &expected) < 1e-6,
            "ply --origin at {distance}"
        );
    }
}

#[test]
fn forced_floats_at_1e7_lose_what_the_issue_reports() {
    let scene = sphere().translated(DVec3::new(1e7, 0.0, 0.0)).unwrap();
    let mut options = nodes(Format::Ply);
    options.positions = PositionType::F32;
    let (got, doubles) = read_ply(&export_scene(&scene, &options).unwrap().bytes);
    assert!(!doubles);
    assert!(relative_error(&got, &node_positions(&scene)) > 1e-4);
}

#[test]
fn near_scenes_keep_float_ply() {
    let scene = sphere();
    let (_, doubles) = read_ply(&export_scene(&scene, &nodes(Format::Ply)).unwrap().bytes);
    assert!(!doubles);
}

#[test]
fn issue_22_a_far_merged_part_exports_as_it_does_alone() {
    for distance in [1e4, 1e6, 1e7] {
        let far = sphere()
            .translated(DVec3::new(distance, distance, 0.0))
            .unwrap();
        let merged = Scene::merge(vec![sphere(), far.clone()]).unwrap();
        let alone = node_positions(&far);
        for format in [Format::Ply, Format::Obj, Format::Glb] {
            let exported = export_scene(&merged, &nodes(format)).unwrap();
            let all = match format {
                Format::Ply => read_ply(&exported.bytes).0,
                Format::Obj => read_obj(&exported.bytes),
                _ => read_glb(&exported.bytes),
            };
            let part = &all[all.len() - alone.len()..];
            let err = relative_error(part, &alone);
            assert!(err < 1e-6, "{format:?} at {distance}: {err}");
        }
    }
}
