//! The bytes behind a glTF file's buffers and buffer views.
//!
//! Buffers: the GLB `BIN` chunk (the first buffer with no URI), `data:` URIs (base64) and
//! relative files, resolved only inside the model's folder
//! (`local_reference`). A buffer with no URI that is the fallback
//! of `EXT_meshopt_compression` is not loaded (its views are decoded instead).
//!
//! Views: a plain view is a slice of its buffer; a view carrying `EXT_meshopt_compression` is
//! decoded with meshoptimizer's decoders (`ATTRIBUTES`, `TRIANGLES`, `INDICES` modes; `NONE`,
//! `OCTAHEDRAL`, `QUATERNION`, `EXPONENTIAL` and `COLOR` filters) into `count * byteStride`
//! bytes. A view whose range leaves its buffer, or whose compressed data does not decode, has
//! no bytes: an accessor reading it is refused then, naming its attribute.
//!
//! Bounds: a compressed view may claim at most [`MESHOPT_MAX_RATIO`] times its compressed
//! length (plus 64 KiB), so a small file cannot make the reader allocate without limit.
//!
//! Cost: O(buffer bytes) to read, O(decoded bytes) to decode.
//!
//! Based on: the glTF 2.0 specification (2021) section 3.6; the `EXT_meshopt_compression`
//! extension specification (Khronos glTF repository, 2021).

use std::borrow::Cow;
use std::path::Path;

use gltf::json::Value;

use super::local_reference::resolve_uri;
use crate::error::BufferProblem;
use crate::MeshError;

/// The largest ratio of decoded to compressed bytes a meshopt view may claim. meshoptimizer's
/// vertex codec stores a constant byte channel of a 256-vertex block in a few bits, so real
/// files reach a few hundred; beyond this a file is refused as hostile.
pub(crate) const MESHOPT_MAX_RATIO: usize = 1024;

/// Name of the meshopt extension.
const MESHOPT: &str = "EXT_meshopt_compression";

/// Loads every buffer of `document` (the GLB blob taken for the first one without a URI).
pub(crate) fn load_buffers(
    path: &Path,
    base: &Path,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, MeshError> {
    let mut out = Vec::with_capacity(document.buffers().len());
    for buffer in document.buffers() {
        let fail = |problem| MeshError::GltfBuffer {
            path: path.to_path_buf(),
            buffer: buffer.index(),
            problem,
        };
        let data = match buffer.source() {
            gltf::buffer::Source::Bin => match blob.take() {
                Some(bytes) => bytes,
                None if is_meshopt_fallback(&buffer) => Vec::new(),
                None => return Err(fail(BufferProblem::NoData)),
            },
            gltf::buffer::Source::Uri(uri) => read_uri(path, base, uri)
                .map_err(|e| e.unwrap_or_else(|| fail(BufferProblem::BadDataUri)))?,
        };
        if data.len() < buffer.length() && !is_meshopt_fallback(&buffer) {
            return Err(fail(BufferProblem::TooShort {
                declared: buffer.length(),
                actual: data.len(),
            }));
        }
        out.push(data);
    }
    Ok(out)
}

/// Reads a buffer or image URI: a `data:` URI decoded, or a file inside `base`.
/// `Err(None)` is a malformed `data:` URI; `Err(Some(_))` any other failure.
pub(crate) fn read_uri(path: &Path, base: &Path, uri: &str) -> Result<Vec<u8>, Option<MeshError>> {
    if uri.starts_with("data:") {
        // The gltf crate decodes the base64 payload; `base` is not needed for data URIs.
        return gltf::buffer::Data::from_source(gltf::buffer::Source::Uri(uri), None)
            .map(|d| d.0)
            .map_err(|_| None);
    }
    let file = resolve_uri(base, uri).map_err(|reason| {
        Some(MeshError::ReferenceOutsideFolder {
            path: path.to_path_buf(),
            reference: uri.to_owned(),
            reason,
        })
    })?;
    std::fs::read(&file).map_err(|source| Some(MeshError::Io { path: file, source }))
}

fn is_meshopt_fallback(buffer: &gltf::Buffer) -> bool {
    buffer
        .extension_value(MESHOPT)
        .and_then(|v| v.get("fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// Bytes of each buffer view, resolved (meshopt views decoded); `None` when unreadable.
pub(crate) type Views<'a> = [Option<Cow<'a, [u8]>>];

/// The bytes of each buffer view (`None`: out of range or undecodable).
pub(crate) fn resolve_views<'a>(
    document: &gltf::Document,
    buffers: &'a [Vec<u8>],
) -> Vec<Option<Cow<'a, [u8]>>> {
    document
        .views()
        .map(|view| match view.extension_value(MESHOPT) {
            Some(ext) => decode_meshopt_view(ext, buffers).map(Cow::Owned),
            None => slice(buffers, view.buffer().index(), view.offset(), view.length())
                .map(Cow::Borrowed),
        })
        .collect()
}

fn slice(buffers: &[Vec<u8>], buffer: usize, offset: usize, length: usize) -> Option<&[u8]> {
    buffers
        .get(buffer)?
        .get(offset..offset.checked_add(length)?)
}

/// The fields of a view's `EXT_meshopt_compression` object.
struct MeshoptView<'a> {
    source: &'a [u8],
    stride: usize,
    count: usize,
    mode: &'a str,
    filter: &'a str,
}

fn parse_meshopt_view<'a>(ext: &'a Value, buffers: &'a [Vec<u8>]) -> Option<MeshoptView<'a>> {
    let number = |key: &str| ext.get(key)?.as_u64().and_then(|v| usize::try_from(v).ok());
    let source = slice(
        buffers,
        number("buffer")?,
        number("byteOffset").unwrap_or(0),
        number("byteLength")?,
    )?;
    Some(MeshoptView {
        source,
        stride: number("byteStride")?,
        count: number("count")?,
        mode: ext.get("mode")?.as_str()?,
        filter: ext.get("filter").and_then(Value::as_str).unwrap_or("NONE"),
    })
}

fn decode_meshopt_view(ext: &Value, buffers: &[Vec<u8>]) -> Option<Vec<u8>> {
    let view = parse_meshopt_view(ext, buffers)?;
    let decoded_len = view.count.checked_mul(view.stride)?;
    if decoded_len > view.source.len().saturating_mul(MESHOPT_MAX_RATIO) + (1 << 16) {
        return None;
    }
    // meshoptimizer asserts (aborting the process in builds with debug info) on a triangle
    // index count that is not a multiple of three: refuse it here.
    if view.mode == "TRIANGLES" && view.count % 3 != 0 {
        return None;
    }
    match (view.mode, view.stride) {
        ("ATTRIBUTES", _) => {
            let mut bytes = decode_vertices(view.source, view.count, view.stride)?;
            apply_filter(view.filter, view.stride, &mut bytes)?;
            Some(bytes)
        }
        ("TRIANGLES", 2) => meshopt::decode_index_buffer::<u16>(view.source, view.count)
            .ok()
            .map(|v| v.iter().flat_map(|i| i.to_le_bytes()).collect()),
        ("TRIANGLES", 4) => meshopt::decode_index_buffer::<u32>(view.source, view.count)
            .ok()
            .map(|v| v.iter().flat_map(|i| i.to_le_bytes()).collect()),
        ("INDICES", 2) => meshopt::decode_index_sequence::<u16>(view.source, view.count)
            .ok()
            .map(|v| v.iter().flat_map(|i| i.to_le_bytes()).collect()),
        ("INDICES", 4) => meshopt::decode_index_sequence::<u32>(view.source, view.count)
            .ok()
            .map(|v| v.iter().flat_map(|i| i.to_le_bytes()).collect()),
        _ => None,
    }
}

/// Decodes a vertex stream of `count` elements of `stride` bytes (a multiple of 4, at most
/// 256, as the extension requires).
fn decode_vertices(source: &[u8], count: usize, stride: usize) -> Option<Vec<u8>> {
    fn run<const N: usize>(source: &[u8], count: usize) -> Option<Vec<u8>> {
        meshopt::decode_vertex_buffer::<VertexBytes<N>>(source, count)
            .ok()
            .map(|v| v.iter().flat_map(|b| b.0).collect())
    }
    macro_rules! by_stride {
        ($($n:literal)*) => {
            match stride {
                $($n => run::<$n>(source, count),)*
                _ => None,
            }
        };
    }
    by_stride!(4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64 68 72 76 80 84 88 92 96 100 104
        108 112 116 120 124 128 132 136 140 144 148 152 156 160 164 168 172 176 180 184 188
        192 196 200 204 208 212 216 220 224 228 232 236 240 244 248 252 256)
}

/// One vertex of `N` bytes, as meshopt's decoder fills it (arrays past 32 have no `Default`).
#[derive(Clone, Copy)]
struct VertexBytes<const N: usize>([u8; N]);

impl<const N: usize> Default for VertexBytes<N> {
    fn default() -> Self {
        VertexBytes([0; N])
    }
}

/// Undoes a meshopt filter in place; `None` for an unknown filter or a stride it forbids.
fn apply_filter(filter: &str, stride: usize, bytes: &mut [u8]) -> Option<()> {
    match (filter, stride) {
        ("NONE", _) => {}
        ("OCTAHEDRAL", 4) => with_i8x4(bytes, meshopt::decode_filter_oct::<i8>),
        ("OCTAHEDRAL", 8) => with_i16x4(bytes, meshopt::decode_filter_oct::<i16>),
        ("COLOR", 4) => with_i8x4(bytes, meshopt::decode_filter_color::<i8>),
        ("COLOR", 8) => with_i16x4(bytes, meshopt::decode_filter_color::<i16>),
        ("QUATERNION", 8) => with_i16x4(bytes, meshopt::decode_filter_quat),
        ("EXPONENTIAL", s) if s % 4 == 0 => {
            let mut words: Vec<[u32; 1]> = bytes
                .chunks_exact(4)
                .map(|c| [u32::from_le_bytes([c[0], c[1], c[2], c[3]])])
                .collect();
            meshopt::decode_filter_exp(&mut words);
            for (c, w) in bytes.chunks_exact_mut(4).zip(&words) {
                c.copy_from_slice(&w[0].to_le_bytes());
            }
        }
        _ => return None,
    }
    Some(())
}

fn with_i8x4(bytes: &mut [u8], filter: impl FnOnce(&mut [[i8; 4]])) {
    let mut items: Vec<[i8; 4]> = bytes
        .chunks_exact(4)
        .map(|c| [c[0] as i8, c[1] as i8, c[2] as i8, c[3] as i8])
        .collect();
    filter(&mut items);
    for (c, v) in bytes.chunks_exact_mut(4).zip(&items) {
        c.copy_from_slice(&v.map(|x| x as u8));
    }
}

fn with_i16x4(bytes: &mut [u8], filter: impl FnOnce(&mut [[i16; 4]])) {
    let mut items: Vec<[i16; 4]> = bytes
        .chunks_exact(8)
        .map(|c| std::array::from_fn(|k| i16::from_le_bytes([c[2 * k], c[2 * k + 1]])))
        .collect();
    filter(&mut items);
    for (c, v) in bytes.chunks_exact_mut(8).zip(&items) {
        for k in 0..4 {
            c[2 * k..2 * k + 2].copy_from_slice(&v[k].to_le_bytes());
        }
    }
}
