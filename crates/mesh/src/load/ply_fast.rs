//! A direct reader for the most common binary PLY point-cloud layout, tried first by
//! [`load_point_cloud`](crate::load_point_cloud) on `.ply` files.
//!
//! Input: the file's bytes. Output: the same [`LoadedPointCloud`] that the general PLY
//! reader ([`load_ply_points`](super::ply::load_ply_points)) gives (same points, origin,
//! colours, normals, dropped count and warnings), faster for the layout scanners and our own
//! tools write most:
//! `format binary_little_endian 1.0`, one `vertex` element and nothing else, with properties
//! `float x y z`, optionally `float nx ny nz`, optionally `uchar red green blue [alpha]`, in
//! any order. Such a file is read in one piece and its records decoded in parallel; every
//! other file (ASCII, big-endian, doubles, other properties or elements, trailing bytes, no
//! finite point) goes to the general reader, which also gives the errors.
//!
//! Why: the general reader (ply-rs-bw) decodes each property through a name lookup and
//! stores f64 records: 124 ms of the 1.4 s a 1M-point `spatch from-cloud` took, all
//! sequential, against about 15 ms here. The tests check this path against the general
//! reader field by field.
//!
//! Invariants: the result equals the general reader's on every file the fast path accepts
//! (positions are read as f32, widened to f64 exactly as the general reader does, centred on
//! the f64 bounding-box centre of the finite points, then narrowed).
//!
//! Cost: one read of the file, O(n) decoding; memory the file plus the cloud.

use crate::{LoadedPointCloud, PointCloud};
use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// Records decoded per parallel task at least.
const RECORDS_PER_TASK: usize = 16_384;

/// Byte offsets of the properties of a record, and its size.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RecordLayout {
    stride: usize,
    position: [usize; 3],
    normal: Option<[usize; 3]>,
    /// Red, green, blue and (if present) alpha.
    colour: Option<([usize; 3], Option<usize>)>,
}

/// The vertex count, the record layout and the offset of the first record, when the header
/// describes the simple layout; `None` for anything else.
fn parse_simple_header(bytes: &[u8]) -> Option<(usize, RecordLayout, usize)> {
    const END: &[u8] = b"end_header\n";
    let head_len = bytes
        .windows(END.len())
        .take(64 * 1024)
        .position(|w| w == END)?
        + END.len();
    let text = std::str::from_utf8(&bytes[..head_len]).ok()?;
    let mut lines = text.split('\n');
    if lines.next()? != "ply" || lines.next()? != "format binary_little_endian 1.0" {
        return None;
    }
    let mut count = None;
    // (name, offset) of the float and uchar properties, in file order.
    let mut floats: Vec<(&str, usize)> = Vec::new();
    let mut bytes_: Vec<(&str, usize)> = Vec::new();
    let mut stride = 0usize;
    for line in lines {
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        match words.as_slice() {
            ["comment", ..] | ["obj_info", ..] => {}
            ["element", "vertex", n] if count.is_none() => count = Some(n.parse::<usize>().ok()?),
            ["property", "float", name] if count.is_some() => {
                floats.push((name, stride));
                stride += 4;
            }
            ["property", "uchar", name] if count.is_some() => {
                bytes_.push((name, stride));
                stride += 1;
            }
            ["end_header"] => break,
            _ => return None,
        }
    }
    let float_at = |name: &str| floats.iter().find(|f| f.0 == name).map(|f| f.1);
    let byte_at = |name: &str| bytes_.iter().find(|f| f.0 == name).map(|f| f.1);
    let known_floats = ["x", "y", "z", "nx", "ny", "nz"];
    let known_bytes = ["red", "green", "blue", "alpha"];
    let names = floats.iter().map(|f| f.0).chain(bytes_.iter().map(|f| f.0));
    let mut seen: Vec<&str> = Vec::new();
    for name in names {
        if seen.contains(&name) {
            return None;
        }
        seen.push(name);
    }
    if floats.iter().any(|f| !known_floats.contains(&f.0))
        || bytes_.iter().any(|f| !known_bytes.contains(&f.0))
    {
        return None;
    }
    let position = [float_at("x")?, float_at("y")?, float_at("z")?];
    let normal = match (float_at("nx"), float_at("ny"), float_at("nz")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        (None, None, None) => None,
        _ => return None,
    };
    let colour = match (byte_at("red"), byte_at("green"), byte_at("blue")) {
        (Some(r), Some(g), Some(b)) => Some(([r, g, b], byte_at("alpha"))),
        (None, None, None) if byte_at("alpha").is_none() => None,
        _ => return None,
    };
    let layout = RecordLayout {
        stride,
        position,
        normal,
        colour,
    };
    Some((count?, layout, head_len))
}

/// The cloud of a file in the simple layout, or `None` when the file is not in it (or has
/// no finite point, which the general reader reports).
pub(crate) fn read_simple_binary_ply(bytes: &[u8]) -> Option<LoadedPointCloud> {
    let (count, layout, start) = parse_simple_header(bytes)?;
    let body = &bytes[start..];
    if count == 0 || count >= u32::MAX as usize || body.len() != count.checked_mul(layout.stride)? {
        return None;
    }
    let f32_at = |record: &[u8], offset: usize| {
        f32::from_le_bytes([
            record[offset],
            record[offset + 1],
            record[offset + 2],
            record[offset + 3],
        ])
    };
    let records = || {
        body.par_chunks_exact(layout.stride)
            .with_min_len(RECORDS_PER_TASK)
    };
    let mut positions: Vec<Vec3> = records()
        .map(|r| Vec3::from_array(layout.position.map(|o| f32_at(r, o))))
        .collect();
    let mut normals: Option<Vec<Vec3>> = layout.normal.map(|offsets| {
        records()
            .map(|r| Vec3::from_array(offsets.map(|o| f32_at(r, o))))
            .collect()
    });
    let mut colours: Option<Vec<[u8; 4]>> = layout.colour.map(|(rgb, alpha)| {
        records()
            .map(|r| {
                let [red, green, blue] = rgb.map(|o| r[o]);
                [red, green, blue, alpha.map_or(255, |o| r[o])]
            })
            .collect()
    });
    // The general reader drops points with a non-finite position or normal.
    let is_finite =
        |i: usize| positions[i].is_finite() && normals.as_ref().is_none_or(|n| n[i].is_finite());
    let keep: Vec<bool> = (0..count).into_par_iter().map(is_finite).collect();
    let kept = keep.iter().filter(|&&k| k).count();
    if kept == 0 {
        return None;
    }
    if kept < count {
        let mut index = 0;
        positions.retain(|_| (keep[index], index += 1).0);
        if let Some(n) = normals.as_mut() {
            index = 0;
            n.retain(|_| (keep[index], index += 1).0);
        }
        if let Some(c) = colours.as_mut() {
            index = 0;
            c.retain(|_| (keep[index], index += 1).0);
        }
    }
    let dropped_non_finite = (count - kept) as u64;
    let (lo, hi) = positions
        .par_iter()
        .with_min_len(RECORDS_PER_TASK)
        .map(|p| (p.as_dvec3(), p.as_dvec3()))
        .reduce(
            || (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    let centre = (lo + hi) * 0.5;
    let origin = if centre.is_finite() {
        centre
    } else {
        DVec3::ZERO
    };
    // Centred in f64 and narrowed, as the general reader does.
    positions
        .par_iter_mut()
        .with_min_len(RECORDS_PER_TASK)
        .for_each(|p| *p = (p.as_dvec3() - origin).as_vec3());
    let cloud = PointCloud {
        origin,
        positions,
        colours,
        normals,
    };
    Some(LoadedPointCloud {
        cloud,
        dropped_non_finite,
        warnings: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_outside_the_simple_layout_are_refused() {
        let header = |props: &str| {
            format!(
                "ply\nformat binary_little_endian 1.0\ncomment c\nelement vertex 2\n{props}end_header\n"
            )
            .into_bytes()
        };
        let xyz = "property float x\nproperty float y\nproperty float z\n";
        let (n, layout, start) = parse_simple_header(&header(xyz)).unwrap();
        assert_eq!((n, layout.stride, layout.position), (2, 12, [0, 4, 8]));
        assert_eq!(start, header(xyz).len());
        let rgb = "property uchar red\nproperty uchar green\nproperty uchar blue\n";
        let layout = parse_simple_header(&header(&format!("{rgb}{xyz}")))
            .unwrap()
            .1;
        assert_eq!((layout.stride, layout.position), (15, [3, 7, 11]));
        assert_eq!(layout.colour, Some(([0, 1, 2], None)));
        for other in [
            format!("{xyz}property double w\n"),
            format!("{xyz}property float nx\n"),
            format!("{xyz}property float intensity\n"),
            format!("{xyz}property uchar red\n"),
            format!("{xyz}property float x\n"),
            "property double x\nproperty double y\nproperty double z\n".to_owned(),
            format!("{xyz}element face 1\nproperty list uchar int vertex_indices\n"),
        ] {
            assert_eq!(parse_simple_header(&header(&other)), None, "{other}");
        }
        let ascii = String::from_utf8(header(xyz))
            .unwrap()
            .replace("binary_little_endian", "ascii");
        assert_eq!(parse_simple_header(ascii.as_bytes()), None);
    }

    #[test]
    fn the_simple_layout_is_read_directly() {
        let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nend_header\n".to_vec();
        for p in [
            [1.0f32, 2.0, 3.0],
            [f32::NAN, 0.0, 0.0],
            [3.0, 2.0, 1.0],
            [2.0, 2.0, 2.0],
        ] {
            for v in p {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        let loaded = read_simple_binary_ply(&bytes).expect("the simple layout");
        assert_eq!(loaded.dropped_non_finite, 1);
        assert_eq!(loaded.cloud.origin, DVec3::new(2.0, 2.0, 2.0));
        assert_eq!(
            loaded.cloud.positions,
            vec![
                Vec3::new(-1.0, 0.0, 1.0),
                Vec3::new(1.0, 0.0, -1.0),
                Vec3::ZERO
            ]
        );
        // A body one byte short is left to the general reader.
        assert!(read_simple_binary_ply(&bytes[..bytes.len() - 1]).is_none());
    }
}
