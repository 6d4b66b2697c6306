//! A direct reader for the most common binary PLY point-cloud layout, tried first by
//! [`load_point_cloud`](crate::load_point_cloud) on `.ply` files.
//!
//! Input: the file's bytes. Output: the same [`LoadedPointCloud`] that the general PLY
//! reader ([`load_ply_points`](super::ply::load_ply_points)) gives (same points, origin,
//! colours, normals, dropped count and warnings), faster for the layout scanners and our own
//! tools write most:
//! `format binary_little_endian 1.0` or `ascii 1.0`, a `vertex` element first, with
//! properties `float x y z`, optionally `float nx ny nz`, optionally `uchar red green blue
//! [alpha]`, in any order, then nothing or other elements (a raw scan's `range_grid`), which
//! are left unread as the general reader leaves them once it has the vertices. Such a file is
//! read in one piece and its records decoded in parallel; every other file (big-endian,
//! doubles, other vertex properties, an element before the vertices, a malformed property
//! line, a short body, bytes after the vertices of a binary file that declares nothing
//! after them, no finite point) goes to the general reader, which also gives the errors.
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

use std::io::Read;
use std::path::Path;

use super::PlyScalar;
use crate::{LoadedPointCloud, PointCloud};
use glam::Vec3;
use rayon::prelude::*;

/// How far into a file the header's `end_header` line may start.
const HEADER_LIMIT: usize = 64 * 1024;

/// Most properties a record of the simple layout has: x y z, nx ny nz, red green blue alpha
/// (each name at most once).
const MAX_PROPERTIES: usize = 10;

/// The line that ends a PLY header.
const END_HEADER: &[u8] = b"end_header\n";

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

/// The body encodings the direct reader takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Encoding {
    /// `binary_little_endian 1.0`: fixed-size records; elements after the vertices (a raw
    /// scan's `range_grid`) are left unread.
    Binary,
    /// `ascii 1.0`: one line of numbers per vertex; elements after the vertices (a raw
    /// scan's `range_grid`) are left unread.
    Ascii,
}

/// What the header of a file in the simple layout says.
#[derive(Clone, Debug, PartialEq)]
struct SimpleHeader {
    encoding: Encoding,
    /// Vertices.
    count: usize,
    /// Byte offsets in a binary record (used for binary bodies).
    layout: RecordLayout,
    /// Token indices in an ASCII line, in the same shape (used for ASCII bodies).
    tokens: RecordLayout,
    /// Offset of the body.
    start: usize,
    /// Elements follow the vertices (their bytes are not read).
    more_elements: bool,
}

/// The header, when it describes the simple layout; `None` for anything else.
fn parse_simple_header(bytes: &[u8]) -> Option<SimpleHeader> {
    let head_len = bytes
        .windows(END_HEADER.len())
        .take(HEADER_LIMIT)
        .position(|w| w == END_HEADER)?
        + END_HEADER.len();
    let text = std::str::from_utf8(&bytes[..head_len]).ok()?;
    let mut lines = text.split('\n');
    if lines.next()? != "ply" {
        return None;
    }
    let encoding = match lines.next()? {
        "format binary_little_endian 1.0" => Encoding::Binary,
        "format ascii 1.0" => Encoding::Ascii,
        _ => return None,
    };
    let mut count = None;
    // (name, byte offset, token index) of the float and uchar properties, in file order.
    let mut floats: Vec<(&str, usize, usize)> = Vec::new();
    let mut bytes_: Vec<(&str, usize, usize)> = Vec::new();
    let (mut stride, mut tokens) = (0usize, 0usize);
    let mut after_vertices = false;
    for line in lines {
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        match words.as_slice() {
            ["comment", ..] | ["obj_info", ..] => {}
            ["element", "vertex", n] if count.is_none() => count = Some(n.parse::<usize>().ok()?),
            // Later elements: left unread, as the general reader leaves them.
            ["element", _, n] if count.is_some() && n.parse::<usize>().is_ok() => {
                after_vertices = true;
            }
            ["property", ty, _] if after_vertices && PlyScalar::parse(ty).is_some() => {}
            ["property", "list", a, b, _]
                if after_vertices
                    && PlyScalar::parse(a).is_some()
                    && PlyScalar::parse(b).is_some() => {}
            ["property", "float", name] if count.is_some() => {
                floats.push((name, stride, tokens));
                (stride, tokens) = (stride + 4, tokens + 1);
            }
            ["property", "uchar", name] if count.is_some() => {
                bytes_.push((name, stride, tokens));
                (stride, tokens) = (stride + 1, tokens + 1);
            }
            ["end_header"] => break,
            _ => return None,
        }
    }
    let count = count?;
    let layout = simple_layout(&floats, &bytes_, |p| p.1, stride)?;
    let tokens = simple_layout(&floats, &bytes_, |p| p.2, tokens)?;
    Some(SimpleHeader {
        encoding,
        count,
        layout,
        tokens,
        start: head_len,
        more_elements: after_vertices,
    })
}

/// The layout of the named `floats` and `bytes_` properties with `place` (byte offset or
/// token index) and record size `stride`, when they are exactly x, y, z, optionally nx, ny,
/// nz, optionally red, green, blue and alpha, each once.
fn simple_layout(
    floats: &[(&str, usize, usize)],
    bytes_: &[(&str, usize, usize)],
    place: impl Fn(&(&str, usize, usize)) -> usize,
    stride: usize,
) -> Option<RecordLayout> {
    let float_at = |name: &str| floats.iter().find(|f| f.0 == name).map(&place);
    let byte_at = |name: &str| bytes_.iter().find(|f| f.0 == name).map(&place);
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
    Some(RecordLayout {
        stride,
        position,
        normal,
        colour,
    })
}

/// The cloud of the file at `path` when it is in the simple layout. Only the header is read
/// first, so a file in another layout (which the general reader then reads) is not read
/// whole twice.
pub(crate) fn read_simple_ply_file(path: &Path) -> Option<LoadedPointCloud> {
    let mut head = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take((HEADER_LIMIT + END_HEADER.len()) as u64)
        .read_to_end(&mut head)
        .ok()?;
    parse_simple_header(&head)?;
    read_simple_ply(&std::fs::read(path).ok()?)
}

/// The cloud of a file in the simple layout, given its bytes, or `None` when the file is not
/// in it (or has no finite point, which the general reader reports).
pub(crate) fn read_simple_ply(bytes: &[u8]) -> Option<LoadedPointCloud> {
    let header = parse_simple_header(bytes)?;
    let body = &bytes[header.start..];
    let count = header.count;
    if count == 0 || count >= u32::MAX as usize {
        return None;
    }
    let (positions, normals, colours) = match header.encoding {
        Encoding::Binary => decode_binary(body, count, &header.layout, header.more_elements)?,
        Encoding::Ascii => decode_ascii(body, count, &header.tokens)?,
    };
    finish(count, positions, normals, colours)
}

/// Positions, normals and colours as the file holds them.
type Columns = (Vec<Vec3>, Option<Vec<Vec3>>, Option<Vec<[u8; 4]>>);

/// Decodes `count` binary records of `layout`, when the body holds exactly that many (at
/// least that many when `more_elements` follow them).
fn decode_binary(
    body: &[u8],
    count: usize,
    layout: &RecordLayout,
    more_elements: bool,
) -> Option<Columns> {
    let size = count.checked_mul(layout.stride)?;
    if body.len() < size || (body.len() > size && !more_elements) {
        return None;
    }
    let body = &body[..size];
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
    let positions: Vec<Vec3> = records()
        .map(|r| Vec3::from_array(layout.position.map(|o| f32_at(r, o))))
        .collect();
    let normals: Option<Vec<Vec3>> = layout.normal.map(|offsets| {
        records()
            .map(|r| Vec3::from_array(offsets.map(|o| f32_at(r, o))))
            .collect()
    });
    let colours: Option<Vec<[u8; 4]>> = layout.colour.map(|(rgb, alpha)| {
        records()
            .map(|r| {
                let [red, green, blue] = rgb.map(|o| r[o]);
                [red, green, blue, alpha.map_or(255, |o| r[o])]
            })
            .collect()
    });
    Some((positions, normals, colours))
}

/// Decodes the first `count` lines of an ASCII body, each exactly `layout.stride` numbers, when
/// every line is in that form and every number is spelled as the PLY grammar allows (digits,
/// sign, point, exponent: no `nan` or `inf`, which the general reader refuses).
fn decode_ascii(body: &[u8], count: usize, layout: &RecordLayout) -> Option<Columns> {
    let lines = first_lines(body, count)?;
    let records = parse_ascii_records(&lines, layout)?;
    Some(record_columns(&records, layout))
}

/// The first `count` lines of `body` (without their LFs), or `None` when it has fewer.
fn first_lines(body: &[u8], count: usize) -> Option<Vec<&[u8]>> {
    let mut lines: Vec<&[u8]> = Vec::new();
    let mut rest = body;
    while lines.len() < count {
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        if end == 0 && rest.is_empty() {
            return None;
        }
        lines.push(&rest[..end]);
        rest = rest.get(end + 1..).unwrap_or_default();
    }
    Some(lines)
}

/// The numbers of each of `lines` in file order, as f32 (floats) or u8 (uchars), when every
/// line holds exactly `layout.stride` of them, each spelled as the PLY grammar allows.
fn parse_ascii_records(
    lines: &[&[u8]],
    layout: &RecordLayout,
) -> Option<Vec<[f32; MAX_PROPERTIES]>> {
    let number = |token: &str| {
        token
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E'))
    };
    // Colour tokens are read as u8, as the general reader reads `uchar` (digits only).
    let mut is_byte = vec![false; layout.stride];
    if let Some((rgb, alpha)) = layout.colour {
        for k in rgb.into_iter().chain(alpha) {
            is_byte[k] = true;
        }
    }
    let parse = |k: usize, token: &str| {
        if is_byte[k] {
            token.parse::<u8>().ok().map(f32::from)
        } else {
            number(token).then(|| token.parse::<f32>().ok()).flatten()
        }
    };
    // A fixed array per line (the layout has at most ten properties: x y z, three normal
    // components, four colour channels), so a million lines make no million allocations.
    lines
        .par_iter()
        .with_min_len(RECORDS_PER_TASK / 4)
        .map(|line| {
            let text = std::str::from_utf8(line).ok()?;
            let mut values = [0.0f32; MAX_PROPERTIES];
            let mut n = 0;
            for token in text.split_ascii_whitespace() {
                if n == layout.stride {
                    return None;
                }
                values[n] = parse(n, token)?;
                n += 1;
            }
            (n == layout.stride).then_some(values)
        })
        .collect::<Option<_>>()
}

/// Positions, normals and colours gathered from parsed ASCII `records` of `layout`.
fn record_columns(records: &[[f32; MAX_PROPERTIES]], layout: &RecordLayout) -> Columns {
    // Exact: colour values were parsed as u8.
    let byte = |v: f32| v as u8;
    let positions = records
        .iter()
        .map(|r| Vec3::from_array(layout.position.map(|k| r[k])))
        .collect();
    let normals = layout.normal.map(|ks| {
        records
            .iter()
            .map(|r| Vec3::from_array(ks.map(|k| r[k])))
            .collect()
    });
    let colours = layout.colour.map(|(rgb, alpha)| {
        records
            .iter()
            .map(|r| {
                let [red, green, blue] = rgb.map(|k| byte(r[k]));
                [red, green, blue, alpha.map_or(255, |k| byte(r[k]))]
            })
            .collect()
    });
    (positions, normals, colours)
}

/// Drops non-finite points and centres the rest on their f64 bounding-box centre, as the
/// general reader does; `None` when no point is finite (the general reader reports that).
fn finish(
    count: usize,
    mut positions: Vec<Vec3>,
    mut normals: Option<Vec<Vec3>>,
    mut colours: Option<Vec<[u8; 4]>>,
) -> Option<LoadedPointCloud> {
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
    // The centre of the bulk, so a far outlier does not cost the real points their precision.
    let origin = crate::robust_centre(positions.len(), |k| positions[k].as_dvec3());
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
    use glam::DVec3;

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
        let parsed = parse_simple_header(&header(xyz)).unwrap();
        let (n, layout) = (parsed.count, parsed.layout);
        assert_eq!((n, layout.stride, layout.position), (2, 12, [0, 4, 8]));
        assert_eq!(parsed.start, header(xyz).len());
        assert_eq!(
            (parsed.tokens.stride, parsed.tokens.position),
            (3, [0, 1, 2])
        );
        let rgb = "property uchar red\nproperty uchar green\nproperty uchar blue\n";
        let layout = parse_simple_header(&header(&format!("{rgb}{xyz}")))
            .unwrap()
            .layout;
        assert_eq!((layout.stride, layout.position), (15, [3, 7, 11]));
        assert_eq!(layout.colour, Some(([0, 1, 2], None)));
        for other in [
            format!("{xyz}property double w\n"),
            format!("{xyz}property float nx\n"),
            format!("{xyz}property float intensity\n"),
            format!("{xyz}property uchar red\n"),
            format!("{xyz}property float x\n"),
            "property double x\nproperty double y\nproperty double z\n".to_owned(),
        ] {
            assert_eq!(parse_simple_header(&header(&other)), None, "{other}");
        }
        // Elements after the vertices are left unread, when their header lines are well
        // formed (a mesh's faces too: the general reader reads only its vertices for a cloud).
        for later in ["range_grid 4", "face 1"] {
            let scan = format!("{xyz}element {later}\nproperty list uchar int vertex_indices\n");
            let parsed = parse_simple_header(&header(&scan)).unwrap();
            let read = (parsed.encoding, parsed.more_elements);
            assert_eq!(read, (Encoding::Binary, true), "{later}");
        }
        for bad in [
            "element range_grid four\n",
            "element range_grid 4\nproperty list uchar blob vertex_indices\n",
            "element range_grid 4\nproperty quad q\n",
        ] {
            assert_eq!(parse_simple_header(&header(&format!("{xyz}{bad}"))), None);
        }
        let scan = format!("{xyz}element range_grid 4\nproperty list uchar int vertex_indices\n");
        let ascii = String::from_utf8(header(&scan))
            .unwrap()
            .replace("binary_little_endian", "ascii");
        let parsed = parse_simple_header(ascii.as_bytes()).unwrap();
        assert_eq!((parsed.encoding, parsed.count), (Encoding::Ascii, 2));
        let big = String::from_utf8(header(xyz))
            .unwrap()
            .replace("binary_little_endian", "binary_big_endian");
        assert_eq!(parse_simple_header(big.as_bytes()), None);
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
        let loaded = read_simple_ply(&bytes).expect("the simple layout");
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
        // A body one byte short is left to the general reader, and so are bytes after the
        // vertices when the header declares nothing after them.
        assert!(read_simple_ply(&bytes[..bytes.len() - 1]).is_none());
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(read_simple_ply(&longer).is_none());
        // A raw scan's grid after the vertices: its bytes are not read.
        let grid = b"element range_grid 2\nproperty list uchar int vertex_indices\n";
        let at = bytes.windows(10).position(|w| w == b"end_header").unwrap();
        let mut scan = [&bytes[..at], &grid[..], &bytes[at..]].concat();
        scan.extend_from_slice(&[1, 3, 0, 0, 0, 0]);
        let with_grid = read_simple_ply(&scan).expect("a binary scan with its grid");
        assert_eq!(with_grid.cloud, loaded.cloud);
    }

    #[test]
    fn ascii_scans_are_read_directly() {
        let text = "ply\nformat ascii 1.0\nobj_info x\nelement vertex 3\nproperty float x\n\
            property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n\
            property uchar blue\nelement range_grid 2\nproperty list uchar int vertex_indices\n\
            end_header\n0 0 0 1 2 3\n2 -4e0 2.5 255 0 7\n1 1 1 0 0 0\n1 0\n0\n";
        let loaded = read_simple_ply(text.as_bytes()).expect("the simple ASCII layout");
        assert_eq!(loaded.cloud.origin, DVec3::new(1.0, -1.5, 1.25));
        assert_eq!(loaded.cloud.positions[1], Vec3::new(1.0, -2.5, 1.25));
        assert_eq!(loaded.cloud.colours.unwrap()[1], [255, 0, 7, 255]);
        // A short line, a word, a colour out of range, or too few lines: not taken.
        for bad in [
            "2 -4e0 2.5 255 0\n",
            "2 -4e0 inf 255 0 7\n",
            "2 -4e0 2.5 256 0 7\n",
        ] {
            let broken = text.replace("2 -4e0 2.5 255 0 7\n", bad);
            assert!(read_simple_ply(broken.as_bytes()).is_none(), "{bad}");
        }
        let cut = &text[..text.find("1 1 1").unwrap()];
        assert!(read_simple_ply(cut.as_bytes()).is_none());
    }
}
