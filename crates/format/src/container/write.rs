//! Encoding a [`Scene`] into container bytes.
//!
//! Deterministic: the bytes depend only on the scene and the options (no
//! timestamps, no hash-map order, no thread-dependent work).

use std::path::Path;

use super::colour_grids::grids_of;
use super::layout::{
    ColourStorage, SceneFields, CODEC_PREDICTIVE, CODEC_RAW, TAG_COLOURS, TAG_DISPLACEMENTS,
    TAG_FRAMES, TAG_INSIDE_BOX, TAG_OPENINGS, TAG_ORIGIN_RESIDUALS, TAG_SCENE,
    TAG_SHARED_COLOUR_GRIDS, TAG_SIDES,
};
use super::predictive::{encode_colours, encode_displacements, DisplacementLayout};
use super::records::{
    displacement_layout, file_header, inside_box_payload, openings_payload, push_colours,
    push_displacements, push_frame_record, push_residual, section_header,
};
use super::shape::SceneShape;
use super::shared_colour_grids::shared_grids_section;
use super::write_file_atomically;
use crate::{FormatError, Scene};

/// Whether node data (DISP and COLR) is compressed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Compression {
    /// Raw codes: fastest to read, the original work's layout.
    #[default]
    None,
    /// Grid prediction + range coding (codec 1). Smaller files (about 1–3
    /// bits per displacement on smooth surfaces instead of 8), a few ms per
    /// million nodes more to read and write. A section that would not get
    /// smaller is stored raw.
    Predictive,
}

/// Options of [`encode_scene`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub struct WriteOptions {
    /// Compression of node data. Default: [`Compression::None`].
    pub compression: Compression,
}

impl WriteOptions {
    /// Options with the given compression.
    pub fn with_compression(compression: Compression) -> Self {
        Self { compression }
    }
}

fn push_section(
    out: &mut Vec<u8>,
    tag: [u8; 4],
    codec: u8,
    raw_len: usize,
    payload: &[u8],
) -> Result<(), FormatError> {
    let header = section_header(tag, codec, payload.len() as u64, raw_len as u64)?;
    let mut crc = crc32fast::Hasher::new();
    crc.update(&header);
    crc.update(payload);
    out.extend_from_slice(&header);
    out.extend_from_slice(&crc.finalize().to_le_bytes());
    out.extend_from_slice(payload);
    Ok(())
}

/// Picks codec 1 when it is asked for and makes the payload smaller.
fn choose_codec(
    raw: Vec<u8>,
    compression: Compression,
    code: impl FnOnce(&[u8]) -> Vec<u8>,
) -> (u8, usize, Vec<u8>) {
    let raw_len = raw.len();
    if compression == Compression::Predictive && !raw.is_empty() {
        let coded = code(&raw);
        if coded.len() < raw_len {
            return (CODEC_PREDICTIVE, raw_len, coded);
        }
    }
    (CODEC_RAW, raw_len, raw)
}

/// A section's codec, raw length and payload.
type CodedPayload = (u8, usize, Vec<u8>);

/// A scene's node data: its FRAM payload, its DISP section and, when the colours are per
/// node, its COLR section.
struct NodeSections {
    frames: Vec<u8>,
    disp: CodedPayload,
    colr: Option<CodedPayload>,
}

/// Encodes a scene as `.spatch` bytes.
pub fn encode_scene(scene: &Scene, options: &WriteOptions) -> Result<Vec<u8>, FormatError> {
    let mut shape = SceneShape::new();
    for patch in scene.patches() {
        shape.add(patch);
    }
    let fields = shape.fields(scene.offset().to_array(), scene.channel())?;
    let nodes = node_sections(scene, &fields, options.compression)?;
    let optional = optional_sections(scene, &shape);
    let colour_grids = encode_grids(scene);
    let mut tags: Vec<[u8; 4]> = optional
        .iter()
        .filter(|(_, p)| p.is_some())
        .map(|(t, _)| *t)
        .collect();
    if colour_grids.is_some() {
        tags.push(TAG_SHARED_COLOUR_GRIDS);
    }
    let section_count = 3 + u32::from(nodes.colr.is_some()) + tags.len() as u32;
    let mut out = file_header(section_count, super::minor_for(&tags)).to_vec();
    push_leading_sections(&mut out, &fields, nodes)?;
    for (tag, payload) in optional {
        if let Some(payload) = payload {
            push_section(&mut out, tag, CODEC_RAW, payload.len(), &payload)?;
        }
    }
    if let Some((codec, raw_len, payload)) = colour_grids {
        push_section(&mut out, TAG_SHARED_COLOUR_GRIDS, codec, raw_len, &payload)?;
    }
    Ok(out)
}

/// The node data of `scene` laid out as `fields` says, DISP and COLR coded when
/// `compression` asks and it makes them smaller.
fn node_sections(
    scene: &Scene,
    fields: &SceneFields,
    compression: Compression,
) -> Result<NodeSections, FormatError> {
    let patches = scene.patches();
    let (grid_storage, width_storage) = (fields.grid_storage, fields.width_storage);
    let colour_storage = fields.colour_storage;
    let mut frames = Vec::new();
    let mut displacements = Vec::new();
    let mut colours = Vec::new();
    let colour_bytes = scene.channel().bytes_per_node();
    for patch in patches {
        push_frame_record(&mut frames, patch, grid_storage, width_storage);
        push_displacements(&mut displacements, patch);
        if colour_storage == ColourStorage::PerNode {
            push_colours(&mut colours, patch, colour_bytes)?;
        }
    }
    let layouts: Vec<DisplacementLayout> = patches.iter().map(displacement_layout).collect();
    let disp = choose_codec(displacements, compression, |raw| {
        encode_displacements(raw, &layouts)
    });
    let colr = (colour_storage == ColourStorage::PerNode).then(|| {
        choose_codec(colours, compression, |raw| {
            encode_colours(raw, colour_bytes)
        })
    });
    Ok(NodeSections { frames, disp, colr })
}

/// The optional sections before CGRX (ORGR, SIDE, OPEN, IBOX), in file order, each with
/// its payload when the scene has it.
fn optional_sections(scene: &Scene, shape: &SceneShape) -> [([u8; 4], Option<Vec<u8>>); 4] {
    let residuals = shape.has_residuals().then(|| encode_residuals(scene));
    let sides = shape
        .has_sides()
        .then(|| scene.patches().iter().map(|p| p.sides().code()).collect());
    let openings = (!scene.openings().is_empty()).then(|| openings_payload(scene.openings()));
    let inside_box = scene.inside_box().map(|b| inside_box_payload(&b));
    [
        (TAG_ORIGIN_RESIDUALS, residuals),
        (TAG_SIDES, sides),
        (TAG_OPENINGS, openings),
        (TAG_INSIDE_BOX, inside_box),
    ]
}

/// Appends SCNE (from `fields`), FRAM, DISP and, when there is one, COLR.
fn push_leading_sections(
    out: &mut Vec<u8>,
    fields: &SceneFields,
    nodes: NodeSections,
) -> Result<(), FormatError> {
    let scene_bytes = fields.to_bytes();
    push_section(out, TAG_SCENE, CODEC_RAW, scene_bytes.len(), &scene_bytes)?;
    let frames = nodes.frames;
    push_section(out, TAG_FRAMES, CODEC_RAW, frames.len(), &frames)?;
    let disp = nodes.disp;
    push_section(out, TAG_DISPLACEMENTS, disp.0, disp.1, &disp.2)?;
    if let Some((codec, raw_len, payload)) = nodes.colr {
        push_section(out, TAG_COLOURS, codec, raw_len, &payload)?;
    }
    Ok(())
}

/// The CGRX section of a scene where some patch has a colour grid
/// ([`shared_grids_section`]; writers no longer write CGRD).
fn encode_grids(scene: &Scene) -> Option<(u8, usize, Vec<u8>)> {
    let grids = grids_of(scene.patches());
    if grids.iter().all(Option::is_none) {
        return None;
    }
    Some(shared_grids_section(
        &grids,
        scene.channel().bytes_per_node(),
    ))
}

/// The ORGR payload (every patch's origin residual, 3 × f32), written when some frame
/// has a residual (else the file can be version 1.0).
fn encode_residuals(scene: &Scene) -> Vec<u8> {
    let mut out = Vec::new();
    for patch in scene.patches() {
        push_residual(&mut out, patch);
    }
    out
}

/// Encodes `scene` and writes it to `path` atomically (see
/// [`write_file_atomically`]).
pub fn write_scene(path: &Path, scene: &Scene, options: &WriteOptions) -> Result<(), FormatError> {
    let bytes = encode_scene(scene, options)?;
    write_file_atomically(path, &bytes)
}
