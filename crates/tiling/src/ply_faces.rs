//! Streamed PLY faces: the `face` element's `vertex_indices` (or `vertex_index`) lists,
//! one polygon at a time, ASCII or binary of either byte order.
//!
//! The elements before `face` are skipped: by lines in ASCII, by their fixed record size
//! in binary (an element with a list property before `face` is refused there). Other
//! properties of the face element (scalars or lists, e.g. texture coordinates) are read
//! past and ignored.

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use crate::ply_stream::{read_element_line, Encoding, Scalar};
use crate::TilingError;

/// A property: a scalar, or a list with its count and item types.
#[derive(Clone, Copy, Debug)]
enum Property {
    Scalar(Scalar),
    List(Scalar, Scalar),
}

/// An element of the header.
#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    /// The properties, and which one holds the face's vertex indices.
    properties: Vec<Property>,
    indices: Option<usize>,
}

/// Reads the header: the encoding and every element.
fn read_header(
    path: &Path,
    reader: &mut impl BufRead,
) -> Result<(Encoding, Vec<Element>), TilingError> {
    let bad = |reason: &str| TilingError::malformed(path, reason);
    let (mut encoding, mut elements) = (None, Vec::<Element>::new());
    let mut line = String::new();
    loop {
        line.clear();
        if reader
            .read_line(&mut line)
            .map_err(|e| TilingError::io(path, e))?
            == 0
        {
            return Err(bad("the header has no end_header line"));
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        let scalar = |w: &str| Scalar::parse(w).ok_or_else(|| bad("unknown property type"));
        match words.as_slice() {
            ["end_header"] => break,
            ["format", "ascii", _] => encoding = Some(Encoding::Ascii),
            ["format", "binary_little_endian", _] => encoding = Some(Encoding::Little),
            ["format", "binary_big_endian", _] => encoding = Some(Encoding::Big),
            ["element", name, n] => elements.push(Element {
                name: name.to_string(),
                count: n.parse().map_err(|_| bad("bad element count"))?,
                properties: Vec::new(),
                indices: None,
            }),
            ["property", "list", count, item, name] => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| bad("a property before any element"))?;
                if matches!(*name, "vertex_indices" | "vertex_index") {
                    e.indices = Some(e.properties.len());
                }
                e.properties
                    .push(Property::List(scalar(count)?, scalar(item)?));
            }
            ["property", ty, _] => {
                let e = elements
                    .last_mut()
                    .ok_or_else(|| bad("a property before any element"))?;
                e.properties.push(Property::Scalar(scalar(ty)?));
            }
            _ => {}
        }
    }
    Ok((encoding.ok_or_else(|| bad("no format line"))?, elements))
}

/// Streams the polygons of a PLY file's `face` element to `visit` (vertex indices as
/// given); returns how many were read. A file with no `face` element has no polygon.
pub(crate) fn stream_ply_faces(
    path: &Path,
    visit: &mut dyn FnMut(&[u32]) -> Result<(), TilingError>,
) -> Result<u64, TilingError> {
    let file = std::fs::File::open(path).map_err(|e| TilingError::io(path, e))?;
    let mut reader = BufReader::with_capacity(1 << 20, file);
    let (encoding, elements) = read_header(path, &mut reader)?;
    let Some(at) = elements.iter().position(|e| e.name == "face") else {
        return Ok(0);
    };
    let face = &elements[at];
    let indices = face
        .indices
        .ok_or_else(|| TilingError::malformed(path, "the face element has no vertex_indices"))?;
    match encoding {
        Encoding::Ascii => {
            let before: u64 = elements[..at].iter().map(|e| e.count).sum();
            skip_lines(path, &mut reader, before)?;
            read_ascii_faces(path, &mut reader, face, indices, visit)
        }
        e => {
            for skipped in &elements[..at] {
                skip_binary(path, &mut reader, skipped)?;
            }
            let big = e == Encoding::Big;
            read_binary_faces(path, &mut reader, face, indices, big, visit)
        }
    }
}

/// Reads past `n` lines.
fn skip_lines(path: &Path, reader: &mut impl BufRead, n: u64) -> Result<(), TilingError> {
    let mut line = Vec::new();
    for _ in 0..n {
        line.clear();
        if reader
            .read_until(b'\n', &mut line)
            .map_err(|e| TilingError::io(path, e))?
            == 0
        {
            return Err(TilingError::malformed(
                path,
                "the file ends before its faces",
            ));
        }
    }
    Ok(())
}

/// Reads past a binary element of fixed-size records.
fn skip_binary(path: &Path, reader: &mut impl Read, e: &Element) -> Result<(), TilingError> {
    let mut record = 0u64;
    for p in &e.properties {
        match p {
            Property::Scalar(s) => record += s.size() as u64,
            Property::List(..) => {
                return Err(TilingError::malformed(
                    path,
                    format!("element {} has a list and comes before the faces", e.name),
                ))
            }
        }
    }
    let bytes = record * e.count;
    let copied = std::io::copy(&mut reader.take(bytes), &mut std::io::sink())
        .map_err(|e| TilingError::io(path, e))?;
    if copied < bytes {
        return Err(TilingError::malformed(
            path,
            "the file ends before its faces",
        ));
    }
    Ok(())
}

/// A vertex index read from the file, refused when negative or past u32.
fn index(path: &Path, v: f64) -> Result<u32, TilingError> {
    if v >= 0.0 && v <= f64::from(u32::MAX - 1) && v.fract() == 0.0 {
        Ok(v as u32)
    } else {
        Err(TilingError::malformed(
            path,
            format!("bad vertex index {v}"),
        ))
    }
}

/// The ASCII face lines.
fn read_ascii_faces(
    path: &Path,
    reader: &mut impl BufRead,
    face: &Element,
    indices: usize,
    visit: &mut dyn FnMut(&[u32]) -> Result<(), TilingError>,
) -> Result<u64, TilingError> {
    let (mut line, mut polygon) = (String::new(), Vec::new());
    for read in 0..face.count {
        read_element_line(reader, path, &mut line, face.count, read)?;
        let mut words = line.split_whitespace().map(|w| {
            w.parse::<f64>()
                .map_err(|_| TilingError::malformed(path, format!("face {read}: `{w}`")))
        });
        let mut next = || {
            words
                .next()
                .unwrap_or_else(|| Err(TilingError::malformed(path, format!("face {read}: short"))))
        };
        polygon.clear();
        for (k, p) in face.properties.iter().enumerate() {
            let n = match p {
                Property::Scalar(_) => 0,
                Property::List(..) => next()? as usize,
            };
            if matches!(p, Property::Scalar(_)) {
                next()?;
            }
            for _ in 0..n {
                let v = next()?;
                if k == indices {
                    polygon.push(index(path, v)?);
                }
            }
        }
        visit(&polygon)?;
    }
    Ok(face.count)
}

/// The binary face records.
fn read_binary_faces(
    path: &Path,
    reader: &mut impl Read,
    face: &Element,
    indices: usize,
    big: bool,
    visit: &mut dyn FnMut(&[u32]) -> Result<(), TilingError>,
) -> Result<u64, TilingError> {
    let (mut buf, mut polygon) = (vec![0u8; 8], Vec::new());
    for read in 0..face.count {
        let truncated = |e: std::io::Error| match e.kind() {
            std::io::ErrorKind::UnexpectedEof => TilingError::Truncated {
                path: path.to_path_buf(),
                declared: face.count,
                read,
            },
            _ => TilingError::io(path, e),
        };
        let mut value = |s: Scalar, buf: &mut Vec<u8>| -> Result<f64, TilingError> {
            reader.read_exact(&mut buf[..s.size()]).map_err(truncated)?;
            Ok(s.read(buf, big))
        };
        polygon.clear();
        for (k, p) in face.properties.iter().enumerate() {
            match *p {
                Property::Scalar(s) => {
                    value(s, &mut buf)?;
                }
                Property::List(count, item) => {
                    let n = value(count, &mut buf)?;
                    if !(0.0..=1e6).contains(&n) {
                        return Err(TilingError::malformed(
                            path,
                            format!("face {read}: {n} items"),
                        ));
                    }
                    for _ in 0..n as usize {
                        let v = value(item, &mut buf)?;
                        if k == indices {
                            polygon.push(index(path, v)?);
                        }
                    }
                }
            }
        }
        visit(&polygon)?;
    }
    Ok(face.count)
}
