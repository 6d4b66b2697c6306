//! Encoding a [`Scene`] into container bytes.
//!
//! Deterministic: the bytes depend only on the scene and the options (no
//! timestamps, no hash-map order, no thread-dependent work).

use std::path::Path;

use super::layout::{
    ColourStorage, GridStorage, SceneFields, WidthStorage, CODEC_PREDICTIVE, CODEC_RAW,
    TAG_COLOURS, TAG_DISPLACEMENTS, TAG_FRAMES, TAG_OPENINGS, TAG_ORIGIN_RESIDUALS, TAG_SCENE,
    TAG_SIDES,
};
use super::predictive::{encode_colours, encode_displacements, DisplacementLayout};
use super::{write_file_atomically, MAGIC, VERSION_MAJOR, VERSION_MINOR};
use crate::{ColourChannel, DisplacementWidth, FormatError, Scene, EMPTY};

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

fn push_section(out: &mut Vec<u8>, tag: [u8; 4], codec: u8, raw_len: usize, payload: &[u8]) {
    let start = out.len();
    out.extend_from_slice(&tag);
    out.push(codec);
    out.extend_from_slice(&[0, 0, 0]);
    out.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    out.extend_from_slice(&(raw_len as u32).to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&out[start..start + 16]);
    crc.update(payload);
    out.extend_from_slice(&crc.finalize().to_le_bytes());
    out.extend_from_slice(payload);
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

/// Encodes a scene as `.spatch` bytes.
pub fn encode_scene(scene: &Scene, options: &WriteOptions) -> Result<Vec<u8>, FormatError> {
    let patches = scene.patches();
    let patch_count =
        u32::try_from(patches.len()).map_err(|_| FormatError::Bug("more than 2^32 patches"))?;
    let widths: Vec<DisplacementWidth> = patches.iter().map(|p| p.displacement_width()).collect();
    let first_grid = patches.first().map(|p| p.grid());
    let grid_storage = match first_grid {
        Some(g) if patches.iter().all(|p| p.grid() == g) => GridStorage::Shared,
        _ => GridStorage::PerPatch,
    };
    let width_storage = if widths.iter().all(|&w| w == DisplacementWidth::Bits8) {
        WidthStorage::All8
    } else if widths.iter().all(|&w| w == DisplacementWidth::Bits16) {
        WidthStorage::All16
    } else {
        WidthStorage::PerPatch
    };
    let flat = scene.flat_colour();
    let (channel, colour_storage) = match scene.channel() {
        ColourChannel::None => (0, ColourStorage::None),
        ColourChannel::Rgb8 => (
            1,
            if flat.is_some() {
                ColourStorage::Flat
            } else {
                ColourStorage::PerNode
            },
        ),
        ColourChannel::Rgba8 => (
            2,
            if flat.is_some() {
                ColourStorage::Flat
            } else {
                ColourStorage::PerNode
            },
        ),
    };
    let shared = if grid_storage == GridStorage::Shared {
        first_grid
    } else {
        None
    };
    let fields = SceneFields {
        offset: scene.offset().to_array(),
        patch_count,
        channel,
        colour_storage,
        grid_storage,
        width_storage,
        shared_cols: shared.map_or(0, |g| g.cols()),
        shared_rows: shared.map_or(0, |g| g.rows()),
        flat_colour: flat.unwrap_or([0; 4]),
    };

    let mut frames = Vec::new();
    let mut layouts = Vec::new();
    let mut displacements = Vec::new();
    let mut colours = Vec::new();
    let colour_bytes = scene.channel().bytes_per_node();
    for (patch, &width) in patches.iter().zip(&widths) {
        let frame = patch.frame();
        let q = frame.rotation();
        let numbers = frame
            .origin()
            .to_array()
            .into_iter()
            .chain([q.x, q.y, q.z, q.w])
            .chain(frame.lengths());
        for v in numbers {
            frames.extend_from_slice(&v.to_le_bytes());
        }
        if grid_storage == GridStorage::PerPatch {
            frames.extend_from_slice(&patch.grid().cols().to_le_bytes());
            frames.extend_from_slice(&patch.grid().rows().to_le_bytes());
        }
        if width_storage == WidthStorage::PerPatch {
            frames.push(width.bits());
        }
        let bytes_per_code = usize::from(width.bits() / 8);
        layouts.push(DisplacementLayout {
            cols: usize::from(patch.grid().cols()),
            rows: usize::from(patch.grid().rows()),
            bytes_per_code,
        });
        for &d in patch.displacements() {
            match width {
                DisplacementWidth::Bits8 => {
                    displacements.push(if d == EMPTY { 0xFF } else { d as u8 })
                }
                DisplacementWidth::Bits16 => displacements.extend_from_slice(&d.to_le_bytes()),
            }
        }
        if colour_storage == ColourStorage::PerNode {
            let node_colours = patch
                .colours()
                .ok_or(FormatError::Bug("coloured scene with a colourless patch"))?;
            for (c, &d) in node_colours.iter().zip(patch.displacements()) {
                if d != EMPTY {
                    colours.extend_from_slice(&c[..colour_bytes]);
                }
            }
        }
    }

    let compression = options.compression;
    let disp = choose_codec(displacements, compression, |raw| {
        encode_displacements(raw, &layouts)
    });
    let colr = (colour_storage == ColourStorage::PerNode).then(|| {
        choose_codec(colours, compression, |raw| {
            encode_colours(raw, colour_bytes)
        })
    });

    let residuals = encode_residuals(scene);
    let sides = encode_sides(scene);
    let openings = encode_openings(scene);
    let section_count = 3
        + u32::from(colr.is_some())
        + u32::from(residuals.is_some())
        + u32::from(sides.is_some())
        + u32::from(openings.is_some());
    let mut out = Vec::new();
    out.extend_from_slice(&MAGIC);
    out.push(VERSION_MAJOR);
    // The lowest minor version that describes the file.
    let needs_1_1 = residuals.is_some() || sides.is_some() || openings.is_some();
    out.push(if needs_1_1 { VERSION_MINOR } else { 0 });
    out.extend_from_slice(&section_count.to_le_bytes());
    let header_crc = crc32fast::hash(&out[..12]);
    out.extend_from_slice(&header_crc.to_le_bytes());
    let scene_bytes = fields.to_bytes();
    push_section(
        &mut out,
        TAG_SCENE,
        CODEC_RAW,
        scene_bytes.len(),
        &scene_bytes,
    );
    push_section(&mut out, TAG_FRAMES, CODEC_RAW, frames.len(), &frames);
    push_section(&mut out, TAG_DISPLACEMENTS, disp.0, disp.1, &disp.2);
    if let Some((codec, raw_len, payload)) = colr {
        push_section(&mut out, TAG_COLOURS, codec, raw_len, &payload);
    }
    if let Some(payload) = residuals {
        push_section(
            &mut out,
            TAG_ORIGIN_RESIDUALS,
            CODEC_RAW,
            payload.len(),
            &payload,
        );
    }
    if let Some(sides) = sides {
        push_section(&mut out, TAG_SIDES, CODEC_RAW, sides.len(), &sides);
    }
    if let Some(openings) = openings {
        push_section(&mut out, TAG_OPENINGS, CODEC_RAW, openings.len(), &openings);
    }
    Ok(out)
}

/// The ORGR payload (every patch's origin residual, 3 × f32), or `None`
/// when no frame has a residual (the file is then version 1.0).
fn encode_residuals(scene: &Scene) -> Option<Vec<u8>> {
    let patches = scene.patches();
    if patches
        .iter()
        .all(|p| p.frame().origin_residual() == glam::Vec3::ZERO)
    {
        return None;
    }
    let mut out = Vec::new();
    for patch in patches {
        for v in patch.frame().origin_residual().to_array() {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    Some(out)
}

/// The SIDE payload (one [`crate::Sides`] code per patch), or `None` when every patch is
/// front-only.
fn encode_sides(scene: &Scene) -> Option<Vec<u8>> {
    let codes: Vec<u8> = scene.patches().iter().map(|p| p.sides().code()).collect();
    codes.iter().any(|&c| c != 0).then_some(codes)
}

/// The OPEN payload (centre and radius of each opening), or `None` when there is none.
fn encode_openings(scene: &Scene) -> Option<Vec<u8>> {
    let openings = scene.openings();
    (!openings.is_empty()).then(|| {
        openings
            .iter()
            .flat_map(|o| {
                let [x, y, z] = o.centre().to_array();
                let [nx, ny, nz] = o.normal().to_array();
                [x, y, z, o.radius(), nx, ny, nz, o.half_thickness()]
            })
            .flat_map(f32::to_le_bytes)
            .collect()
    })
}

/// Encodes `scene` and writes it to `path` atomically (see
/// [`write_file_atomically`]).
pub fn write_scene(path: &Path, scene: &Scene, options: &WriteOptions) -> Result<(), FormatError> {
    let bytes = encode_scene(scene, options)?;
    write_file_atomically(path, &bytes)
}
