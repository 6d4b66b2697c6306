//! glTF 2.0 writing of patch meshes or points, as `.gltf` (JSON with the
//! buffer in a base64 data URI) or `.glb` (binary container).
//!
//! Layout: one glTF mesh and one node per patch, named `patch <index>`.
//! The node's `translation` is the patch origin minus the export origin,
//! written as f64 JSON numbers; the mesh's positions are f32 relative to it
//! and stay small, so precision does not depend on where the model lies.
//! Each primitive has `POSITION` (with its min/max), `NORMAL` (unit) and,
//! when the scene has colour, `COLOR_0` (f32 VEC3, or VEC4 for RGBA scenes,
//! converted from the stored sRGB to the linear values glTF expects).
//! Cells are mode 4 triangles with u32 `indices` (counter-clockwise front
//! faces, as glTF wants); points are mode 0. One material: white, not
//! metallic, fully rough (`BLEND` when some alpha is below 255), so viewers
//! show the vertex colours as they are. Every buffer view starts on a
//! 4-byte boundary. A non-zero export origin is recorded in
//! `asset.extras.origin`.
//!
//! Cost: one pass over the vertices and triangles; the JSON is about 700
//! bytes per patch.

use glam::{DVec3, Vec3};
use serde_json::{json, Value};

use crate::{ExportError, PatchMesh};

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const MODE_POINTS: u32 = 0;
const MODE_TRIANGLES: u32 = 4;

/// The JSON document and its binary buffer.
struct Document {
    json: Value,
    buffer: Vec<u8>,
}

/// Collects buffer views and accessors while the buffer grows.
#[derive(Default)]
struct Builder {
    buffer: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Builder {
    /// Appends `bytes` as a buffer view (4-byte aligned) and returns its index.
    fn push_view(&mut self, bytes: &[u8], target: u32) -> usize {
        let offset = self.buffer.len();
        self.buffer.extend_from_slice(bytes);
        while !self.buffer.len().is_multiple_of(4) {
            self.buffer.push(0);
        }
        self.views.push(json!({
            "buffer": 0,
            "byteOffset": offset,
            "byteLength": bytes.len(),
            "target": target,
        }));
        self.views.len() - 1
    }

    /// Appends an accessor over a whole view and returns its index.
    fn push_accessor(&mut self, mut accessor: Value) -> usize {
        accessor["byteOffset"] = json!(0);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// A float vector attribute of `width` components per vertex.
    fn push_floats(&mut self, values: &[f32], width: usize, extra: Value) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.push_view(&bytes, ARRAY_BUFFER);
        let mut accessor = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": values.len() / width,
            "type": format!("VEC{width}"),
        });
        if let (Value::Object(a), Value::Object(e)) = (&mut accessor, extra) {
            a.extend(e);
        }
        self.push_accessor(accessor)
    }
}

/// sRGB byte to linear value (the IEC 61966-2-1 curve).
fn linear(c: u8) -> f32 {
    let s = f32::from(c) / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// The primitive of one mesh, its data appended to `b`.
fn push_primitive(b: &mut Builder, mesh: &PatchMesh, rgba: bool, faces: bool) -> Value {
    let (lo, hi) = mesh
        .positions
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| {
            (lo.min(p), hi.max(p))
        });
    let flat = |v: &[Vec3]| -> Vec<f32> { v.iter().flat_map(|p| p.to_array()).collect() };
    let position = b.push_floats(
        &flat(&mesh.positions),
        3,
        json!({ "min": lo.to_array(), "max": hi.to_array() }),
    );
    let normal = b.push_floats(&flat(&mesh.normals), 3, json!({}));
    let mut attributes = json!({ "POSITION": position, "NORMAL": normal });
    if let Some(colours) = &mesh.colours {
        let width = if rgba { 4 } else { 3 };
        let values: Vec<f32> = colours
            .iter()
            .flat_map(|c| {
                let rgb = [linear(c[0]), linear(c[1]), linear(c[2])];
                let alpha = f32::from(c[3]) / 255.0;
                rgb.into_iter().chain(rgba.then_some(alpha))
            })
            .collect();
        attributes["COLOR_0"] = json!(b.push_floats(&values, width, json!({})));
    }
    let mut primitive = json!({
        "attributes": attributes,
        "material": 0,
        "mode": if faces { MODE_TRIANGLES } else { MODE_POINTS },
    });
    if faces {
        let bytes: Vec<u8> = mesh
            .triangles
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let view = b.push_view(&bytes, ELEMENT_ARRAY_BUFFER);
        primitive["indices"] = json!(b.push_accessor(json!({
            "bufferView": view,
            "componentType": UNSIGNED_INT,
            "count": mesh.triangles.len() * 3,
            "type": "SCALAR",
        })));
    }
    primitive
}

/// The glTF document of `meshes` (see the module header).
fn build_document(meshes: &[PatchMesh], rgba: bool, origin: DVec3, faces: bool) -> Document {
    let mut b = Builder::default();
    let mut gltf_meshes = Vec::new();
    let mut nodes = Vec::new();
    for (k, mesh) in meshes.iter().enumerate() {
        let primitive = push_primitive(&mut b, mesh, rgba, faces);
        let name = format!("patch {}", mesh.patch);
        gltf_meshes.push(json!({ "name": name, "primitives": [primitive] }));
        let mut node = json!({ "name": name, "mesh": k });
        let t = mesh.origin - origin;
        if t != DVec3::ZERO {
            node["translation"] = json!(t.to_array());
        }
        nodes.push(node);
    }
    let translucent = meshes
        .iter()
        .filter_map(|m| m.colours.as_ref())
        .flatten()
        .any(|c| c[3] < 255);
    let mut asset = json!({
        "version": "2.0",
        "generator": format!("spatch {}", env!("CARGO_PKG_VERSION")),
    });
    if origin != DVec3::ZERO {
        asset["extras"] = json!({ "origin": origin.to_array() });
    }
    let mut json = json!({
        "asset": asset,
        "materials": [{
            "name": "spatch",
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 1.0, 1.0, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 1.0,
            },
            "alphaMode": if translucent { "BLEND" } else { "OPAQUE" },
        }],
    });
    // An empty export has no scene at all (a scene's node list may not be
    // empty, and readers such as the gltf crate refuse a scene without one).
    if !meshes.is_empty() {
        json["scene"] = json!(0);
        json["scenes"] = json!([{
            "name": "spatch",
            "nodes": (0..nodes.len()).collect::<Vec<_>>(),
        }]);
        json["nodes"] = json!(nodes);
        json["meshes"] = json!(gltf_meshes);
        json["accessors"] = json!(b.accessors);
        json["bufferViews"] = json!(b.views);
        json["buffers"] = json!([{ "byteLength": b.buffer.len() }]);
    }
    Document {
        json,
        buffer: b.buffer,
    }
}

/// `meshes` as a `.gltf` file: JSON with the buffer embedded as a base64
/// data URI.
pub fn write_gltf(meshes: &[PatchMesh], rgba: bool, origin: DVec3, faces: bool) -> Vec<u8> {
    let mut doc = build_document(meshes, rgba, origin, faces);
    if let Some(buffer) = doc.json.get_mut("buffers").and_then(|b| b.get_mut(0)) {
        buffer["uri"] = json!(format!(
            "data:application/octet-stream;base64,{}",
            encode_base64(&doc.buffer)
        ));
    }
    let mut out = serde_json::to_vec_pretty(&doc.json).unwrap_or_default();
    out.push(b'\n');
    out
}

/// `meshes` as a `.glb` file: the 12-byte header, the JSON chunk (padded
/// with spaces) and the binary chunk (padded with zeros).
pub fn write_glb(
    meshes: &[PatchMesh],
    rgba: bool,
    origin: DVec3,
    faces: bool,
) -> Result<Vec<u8>, ExportError> {
    let doc = build_document(meshes, rgba, origin, faces);
    let mut json = serde_json::to_vec(&doc.json).unwrap_or_default();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let bin_len = if doc.buffer.is_empty() {
        0
    } else {
        8 + doc.buffer.len()
    };
    let total = 12 + 8 + json.len() + bin_len;
    let length = u32::try_from(total).map_err(|_| ExportError::TooLarge {
        format: "glb",
        limit: "4 GiB",
    })?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&length.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    if !doc.buffer.is_empty() {
        out.extend_from_slice(&(doc.buffer.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&doc.buffer);
    }
    Ok(out)
}

/// Standard base64 (RFC 4648, with `=` padding).
fn encode_base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let n = chunk
            .iter()
            .enumerate()
            .fold(0u32, |n, (k, &b)| n | u32::from(b) << (16 - 8 * k));
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(char::from(ALPHABET[(n >> (18 - 6 * k) & 63) as usize]));
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_the_rfc_examples() {
        for (input, expected) in [
            ("", ""),
            ("f", "Zg=="),
            ("fo", "Zm8="),
            ("foo", "Zm9v"),
            ("foob", "Zm9vYg=="),
            ("fooba", "Zm9vYmE="),
            ("foobar", "Zm9vYmFy"),
        ] {
            assert_eq!(encode_base64(input.as_bytes()), expected);
        }
    }

    #[test]
    fn srgb_decoding_keeps_the_ends_and_darkens_the_middle() {
        assert_eq!(linear(0), 0.0);
        assert!((linear(255) - 1.0).abs() < 1e-6);
        assert!((linear(128) - 0.2158).abs() < 1e-3);
    }
}
