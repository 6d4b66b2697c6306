//! Streamed PLY vertices: the header, then the `vertex` element (which must come first)
//! read [`CHUNK_POINTS`] records at a time, ASCII or binary of either byte order.
//!
//! Properties read: `x y z` (required), `nx ny nz`, `red green blue` (and `alpha`); any
//! other scalar property is skipped. Colours of type `uchar` are taken as they are,
//! `ushort` by their high byte, floats as `0..1`. A list property in the vertex element is
//! refused (its records have no fixed size).

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use glam::{DVec3, Vec3};

use crate::stream::{PointChunk, Visit, CHUNK_POINTS};
use crate::TilingError;

/// How the records are stored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Encoding {
    Ascii,
    Little,
    Big,
}

/// A property's scalar type (shared with the mesh crate's PLY readers).
pub(crate) use spatch_mesh::load::PlyScalar as Scalar;

/// A colour channel value of type `scalar` as a byte.
fn colour_byte(scalar: Scalar, v: f64) -> u8 {
    match scalar {
        Scalar::F32 | Scalar::F64 => (v * 255.0).round().clamp(0.0, 255.0) as u8,
        Scalar::U16 | Scalar::I16 => (v / 256.0).clamp(0.0, 255.0) as u8,
        _ => v.clamp(0.0, 255.0) as u8,
    }
}

/// The vertex element's layout.
#[derive(Debug)]
struct Header {
    encoding: Encoding,
    count: u64,
    /// Each property's type and byte offset in a binary record.
    properties: Vec<(String, Scalar, usize)>,
    record: usize,
}

impl Header {
    fn find(&self, name: &str) -> Option<usize> {
        self.properties.iter().position(|p| p.0 == name)
    }
}

/// Reads the header up to `end_header`.
fn read_header(path: &Path, reader: &mut impl BufRead) -> Result<Header, TilingError> {
    let mut line = String::new();
    let mut next = |line: &mut String| -> Result<bool, TilingError> {
        line.clear();
        let n = reader
            .read_line(line)
            .map_err(|e| TilingError::io(path, e))?;
        Ok(n > 0)
    };
    if !next(&mut line)? || line.trim() != "ply" {
        return Err(TilingError::malformed(
            path,
            "not a PLY file (no `ply` magic line)",
        ));
    }
    let mut so_far = HeaderSoFar::default();
    loop {
        if !next(&mut line)? {
            return Err(TilingError::malformed(
                path,
                "the header has no end_header line",
            ));
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        if words == ["end_header"] {
            break;
        }
        so_far
            .read(&words)
            .map_err(|e| TilingError::malformed(path, e))?;
    }
    so_far.finish().map_err(|e| TilingError::malformed(path, e))
}

/// What the header's lines have said so far.
#[derive(Default)]
struct HeaderSoFar {
    encoding: Option<Encoding>,
    count: Option<u64>,
    in_vertex: bool,
    seen_element: bool,
    properties: Vec<(String, Scalar, usize)>,
    record: usize,
}

impl HeaderSoFar {
    /// Takes in one header line's `words` (other than `end_header`); lines
    /// the reader does not need (comments, other elements' properties) are
    /// passed over.
    fn read(&mut self, words: &[&str]) -> Result<(), &'static str> {
        match words {
            ["format", f, _] => {
                self.encoding = Some(match *f {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    _ => return Err("unknown PLY format"),
                })
            }
            ["element", name, n] => {
                if !self.seen_element && *name != "vertex" {
                    return Err("the vertex element must come first");
                }
                self.in_vertex = !self.seen_element;
                self.seen_element = true;
                if self.in_vertex {
                    self.count = Some(n.parse::<u64>().map_err(|_| "bad vertex count")?);
                }
            }
            ["property", "list", ..] if self.in_vertex => {
                return Err("a list property in the vertex element")
            }
            ["property", ty, name] if self.in_vertex => {
                let scalar = Scalar::parse(ty).ok_or("unknown property type")?;
                self.properties
                    .push((name.to_string(), scalar, self.record));
                self.record += scalar.size();
            }
            _ => {}
        }
        Ok(())
    }

    /// The header, once it has a format, a vertex element and x, y, z.
    fn finish(self) -> Result<Header, &'static str> {
        let header = Header {
            encoding: self.encoding.ok_or("no format line")?,
            count: self.count.ok_or("no vertex element")?,
            properties: self.properties,
            record: self.record,
        };
        for axis in ["x", "y", "z"] {
            header
                .find(axis)
                .ok_or("the vertex element has no x, y, z")?;
        }
        Ok(header)
    }
}

/// Where each wanted property sits (indices into the header's properties).
struct Fields {
    xyz: [usize; 3],
    normal: Option<[usize; 3]>,
    colour: Option<[usize; 3]>,
    alpha: Option<usize>,
}

impl Fields {
    fn of(h: &Header) -> Fields {
        let three = |a: &str, b: &str, c: &str| Some([h.find(a)?, h.find(b)?, h.find(c)?]);
        Fields {
            xyz: three("x", "y", "z").unwrap_or([0; 3]),
            normal: three("nx", "ny", "nz"),
            colour: three("red", "green", "blue"),
            alpha: h.find("alpha"),
        }
    }

    fn empty_chunk(&self) -> PointChunk {
        PointChunk {
            positions: Vec::with_capacity(CHUNK_POINTS),
            colours: self.colour.map(|_| Vec::with_capacity(CHUNK_POINTS)),
            normals: self.normal.map(|_| Vec::with_capacity(CHUNK_POINTS)),
            scan: 0,
        }
    }

    /// Appends one record whose property values `value(k)` gives.
    fn push(&self, h: &Header, chunk: &mut PointChunk, value: impl Fn(usize) -> f64) {
        chunk
            .positions
            .push(DVec3::from_array(self.xyz.map(&value)));
        if let (Some(n), Some(out)) = (self.normal, &mut chunk.normals) {
            let v = n.map(|k| value(k) as f32);
            out.push(Vec3::from_array(v));
        }
        if let (Some(c), Some(out)) = (self.colour, &mut chunk.colours) {
            let byte = |k: usize| colour_byte(h.properties[k].1, value(k));
            let a = self.alpha.map_or(255, byte);
            out.push([byte(c[0]), byte(c[1]), byte(c[2]), a]);
        }
    }
}

/// Streams a PLY file's vertices (see the module documentation).
pub(crate) fn stream_ply(path: &Path, visit: &mut Visit<'_>) -> Result<u64, TilingError> {
    let file = std::fs::File::open(path).map_err(|e| TilingError::io(path, e))?;
    let mut reader = BufReader::with_capacity(1 << 20, file);
    let header = read_header(path, &mut reader)?;
    let fields = Fields::of(&header);
    let mut chunk = fields.empty_chunk();
    let read = match header.encoding {
        Encoding::Ascii => read_ascii(path, &mut reader, &header, &fields, &mut chunk, visit)?,
        e => read_binary(
            path,
            &mut reader,
            &header,
            &fields,
            &mut chunk,
            e == Encoding::Big,
            visit,
        )?,
    };
    Ok(read)
}

/// The binary records, a chunk at a time.
fn read_binary(
    path: &Path,
    reader: &mut impl Read,
    h: &Header,
    fields: &Fields,
    chunk: &mut PointChunk,
    big: bool,
    visit: &mut Visit<'_>,
) -> Result<u64, TilingError> {
    let mut bytes = vec![0u8; h.record * CHUNK_POINTS];
    let mut read = 0u64;
    while read < h.count {
        let n = (h.count - read).min(CHUNK_POINTS as u64) as usize;
        let buf = &mut bytes[..n * h.record];
        reader.read_exact(buf).map_err(|e| match e.kind() {
            std::io::ErrorKind::UnexpectedEof => TilingError::Truncated {
                path: path.to_path_buf(),
                declared: h.count,
                read,
            },
            _ => TilingError::io(path, e),
        })?;
        chunk.clear();
        for record in buf.chunks_exact(h.record) {
            let value = |k: usize| {
                let (_, scalar, offset) = &h.properties[k];
                scalar.read(&record[*offset..], big)
            };
            fields.push(h, chunk, value);
        }
        visit(chunk)?;
        read += n as u64;
    }
    Ok(read)
}

/// The ASCII records, one line each.
fn read_ascii(
    path: &Path,
    reader: &mut impl BufRead,
    h: &Header,
    fields: &Fields,
    chunk: &mut PointChunk,
    visit: &mut Visit<'_>,
) -> Result<u64, TilingError> {
    let mut line = String::new();
    let mut values = Vec::with_capacity(h.properties.len());
    let mut read = 0u64;
    chunk.clear();
    while read < h.count {
        read_element_line(reader, path, &mut line, h.count, read)?;
        values.clear();
        for word in line.split_whitespace() {
            let v: f64 = word.parse().map_err(|_| {
                TilingError::malformed(path, format!("vertex {read}: `{word}` is not a number"))
            })?;
            values.push(v);
        }
        if values.len() < h.properties.len() {
            return Err(TilingError::malformed(
                path,
                format!("vertex {read}: too few values"),
            ));
        }
        fields.push(h, chunk, |k| values[k]);
        read += 1;
        if chunk.len() == CHUNK_POINTS {
            visit(chunk)?;
            chunk.clear();
        }
    }
    if !chunk.is_empty() {
        visit(chunk)?;
    }
    Ok(read)
}

/// Reads the next line of an ASCII element into `line` (cleared first); the element
/// declared `declared` rows and `read` were read before, so an end of file is
/// [`TilingError::Truncated`].
pub(crate) fn read_element_line(
    reader: &mut impl BufRead,
    path: &Path,
    line: &mut String,
    declared: u64,
    read: u64,
) -> Result<(), TilingError> {
    line.clear();
    if reader
        .read_line(line)
        .map_err(|e| TilingError::io(path, e))?
        == 0
    {
        return Err(TilingError::Truncated {
            path: path.to_path_buf(),
            declared,
            read,
        });
    }
    Ok(())
}
