//! Decoding container bytes into a [`Scene`].
//!
//! Every count read from the file is checked against the bytes that hold it
//! before anything is allocated for it; every section's CRC is checked before
//! its payload is parsed; nothing here panics on any input.

use std::path::Path;

use glam::{DVec3, Quat, Vec3};

use super::bounded::vec_for_count;
use super::layout::{
    ColourStorage, GridStorage, SceneFields, WidthStorage, CODEC_PREDICTIVE, CODEC_RAW,
    FILE_HEADER_LEN, MAX_EXPANSION, MAX_EXPANSION_SLACK, OPENING_LEN, RESIDUAL_LEN,
    SECTION_HEADER_LEN, TAG_COLOURS, TAG_DISPLACEMENTS, TAG_FRAMES, TAG_OPENINGS,
    TAG_ORIGIN_RESIDUALS, TAG_SCENE, TAG_SIDES,
};
use super::predictive::{decode_colours, decode_displacements, DisplacementLayout};
use super::{MAGIC, VERSION_MAJOR};
use crate::{ColourChannel, FormatError, Frame, GridSize, Opening, Patch, Scene, Sides, EMPTY};

/// One section as found in a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SectionInfo {
    /// The four-letter tag, e.g. `"DISP"`.
    pub tag: String,
    /// 0 = raw, 1 = predictive.
    pub codec: u8,
    /// Byte offset of the section header in the file.
    pub offset: usize,
    /// Payload bytes as stored.
    pub stored_len: usize,
    /// Payload bytes once decoded.
    pub raw_len: usize,
}

/// What a file holds besides the scene itself (for `spatch stats`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ContainerInfo {
    /// Major version in the header.
    pub version_major: u8,
    /// Minor version in the header.
    pub version_minor: u8,
    /// Every section, in file order, including ones this reader skipped.
    pub sections: Vec<SectionInfo>,
    /// Total file length.
    pub file_len: usize,
    /// Whether the scene stores one flat colour instead of per-node colours.
    pub flat_colour: bool,
}

struct RawSection<'a> {
    info: SectionInfo,
    payload: &'a [u8],
}

fn tag_name(tag: &[u8]) -> String {
    tag.iter()
        .map(|&b| if b.is_ascii_graphic() { b as char } else { '?' })
        .collect()
}

fn corrupt(section: &str, problem: impl Into<String>) -> FormatError {
    FormatError::Corrupt {
        section: section.to_owned(),
        problem: problem.into(),
    }
}

fn take<'a>(bytes: &'a [u8], at: usize, len: usize, what: &str) -> Result<&'a [u8], FormatError> {
    let available = bytes.len().saturating_sub(at);
    if len > available {
        return Err(FormatError::Truncated {
            what: what.to_owned(),
            offset: at,
            needed: len,
            available,
        });
    }
    Ok(&bytes[at..at + len])
}

fn u32_at(b: &[u8], k: usize) -> u32 {
    u32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]])
}

fn f32_at(b: &[u8], k: usize) -> f32 {
    f32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]])
}

/// Splits the file into CRC-checked sections.
fn split_sections(bytes: &[u8]) -> Result<(u8, u8, Vec<RawSection<'_>>), FormatError> {
    if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        return Err(FormatError::NotSpatch);
    }
    let header = take(bytes, 0, FILE_HEADER_LEN, "file header")?;
    let (major, minor) = (header[6], header[7]);
    if major != VERSION_MAJOR {
        return Err(FormatError::UnsupportedVersion {
            found: major,
            supported: VERSION_MAJOR,
        });
    }
    if crc32fast::hash(&header[..12]) != u32_at(header, 12) {
        return Err(FormatError::ChecksumMismatch {
            section: "header".to_owned(),
            offset: 0,
        });
    }
    let count = u32_at(header, 8) as usize;
    let remaining = bytes.len() - FILE_HEADER_LEN;
    if count > remaining / SECTION_HEADER_LEN {
        return Err(FormatError::Truncated {
            what: format!("{count} section headers"),
            offset: FILE_HEADER_LEN,
            needed: count.saturating_mul(SECTION_HEADER_LEN),
            available: remaining,
        });
    }
    let mut sections = vec_for_count(count, SECTION_HEADER_LEN, remaining, "sections")?;
    let mut at = FILE_HEADER_LEN;
    for _ in 0..count {
        let h = take(bytes, at, SECTION_HEADER_LEN, "section header")?;
        let tag = tag_name(&h[..4]);
        let stored_len = u32_at(h, 8) as usize;
        let raw_len = u32_at(h, 12) as usize;
        let payload = take(
            bytes,
            at + SECTION_HEADER_LEN,
            stored_len,
            &format!("{tag} payload"),
        )?;
        let mut crc = crc32fast::Hasher::new();
        crc.update(&h[..16]);
        crc.update(payload);
        if crc.finalize() != u32_at(h, 16) {
            return Err(FormatError::ChecksumMismatch {
                section: tag,
                offset: at,
            });
        }
        if h[5..8] != [0, 0, 0] {
            return Err(corrupt(&tag, "reserved header bytes are not zero"));
        }
        sections.push(RawSection {
            info: SectionInfo {
                tag,
                codec: h[4],
                offset: at,
                stored_len,
                raw_len,
            },
            payload,
        });
        at += SECTION_HEADER_LEN + stored_len;
    }
    if at != bytes.len() {
        return Err(FormatError::TrailingBytes(bytes.len() - at));
    }
    Ok((major, minor, sections))
}

/// Returns the raw payload of a node-data section, decoding codec 1.
fn section_payload(
    section: &RawSection<'_>,
    expected_raw: usize,
    decode: impl FnOnce(&[u8], Vec<u8>) -> Option<Vec<u8>>,
) -> Result<Vec<u8>, FormatError> {
    let info = &section.info;
    if info.raw_len != expected_raw {
        return Err(corrupt(
            &info.tag,
            format!(
                "raw length {} but the frames need {expected_raw}",
                info.raw_len
            ),
        ));
    }
    match info.codec {
        CODEC_RAW => {
            if info.stored_len != info.raw_len {
                return Err(corrupt(
                    &info.tag,
                    "raw section whose stored and raw lengths differ",
                ));
            }
            Ok(section.payload.to_vec())
        }
        CODEC_PREDICTIVE => {
            let limit = info
                .stored_len
                .saturating_mul(MAX_EXPANSION)
                .saturating_add(MAX_EXPANSION_SLACK);
            if info.raw_len > limit {
                return Err(corrupt(
                    &info.tag,
                    format!(
                        "raw length {} is impossible for {} coded bytes",
                        info.raw_len, info.stored_len
                    ),
                ));
            }
            let buffer = vec_for_count(info.raw_len, 1, limit, "decoded bytes")?;
            decode(section.payload, buffer)
                .ok_or_else(|| corrupt(&info.tag, "compressed stream ends early"))
        }
        other => Err(corrupt(&info.tag, format!("unknown codec {other}"))),
    }
}

/// Decodes `.spatch` bytes, returning the scene and what the file holds.
pub fn inspect(bytes: &[u8]) -> Result<(Scene, ContainerInfo), FormatError> {
    let (major, minor, sections) = split_sections(bytes)?;
    let known = [
        TAG_SCENE,
        TAG_FRAMES,
        TAG_DISPLACEMENTS,
        TAG_COLOURS,
        TAG_ORIGIN_RESIDUALS,
        TAG_SIDES,
        TAG_OPENINGS,
    ];
    let mut found: [Option<&RawSection<'_>>; 7] = [None; 7];
    let mut last_known = None;
    for section in &sections {
        let Some(k) = known
            .iter()
            .position(|t| t[..] == *section.info.tag.as_bytes())
        else {
            continue; // a section from a later minor version: skipped
        };
        if found[k].is_some() || last_known.is_some_and(|l| l >= k) {
            return Err(corrupt(
                &section.info.tag,
                "section repeated or out of order",
            ));
        }
        found[k] = Some(section);
        last_known = Some(k);
    }
    let scene_section = found[0].ok_or(FormatError::MissingSection("SCNE"))?;
    let frame_section = found[1].ok_or(FormatError::MissingSection("FRAM"))?;
    let disp_section = found[2].ok_or(FormatError::MissingSection("DISP"))?;
    if scene_section.info.codec != CODEC_RAW || frame_section.info.codec != CODEC_RAW {
        return Err(corrupt("SCNE", "scene and frame sections must be raw"));
    }
    let fields = SceneFields::from_bytes(scene_section.payload).map_err(|p| corrupt("SCNE", p))?;
    let channel = match fields.channel {
        0 => ColourChannel::None,
        1 => ColourChannel::Rgb8,
        _ => ColourChannel::Rgba8,
    };
    let offset = DVec3::from_array(fields.offset);

    // FRAM: its exact length bounds the patch count before any allocation.
    let record_len = fields.frame_record_len();
    let patch_count = fields.patch_count as usize;
    if frame_section.payload.len() != patch_count.saturating_mul(record_len) {
        return Err(corrupt(
            "FRAM",
            format!(
                "{} bytes for {patch_count} patches of {record_len} bytes",
                frame_section.payload.len()
            ),
        ));
    }
    let shared_grid = match fields.grid_storage {
        GridStorage::Shared => Some(
            GridSize::new(fields.shared_cols.into(), fields.shared_rows.into())
                .map_err(|e| corrupt("SCNE", e.to_string()))?,
        ),
        GridStorage::PerPatch => None,
    };
    let frame_bytes = frame_section.payload.len();
    let residuals = read_residuals(found[4], patch_count)?;
    let mut frames = vec_for_count(patch_count, record_len, frame_bytes, "frames")?;
    let mut layouts = vec_for_count(patch_count, record_len, frame_bytes, "frames")?;
    for (k, record) in frame_section.payload.chunks_exact(record_len).enumerate() {
        let origin = Vec3::new(f32_at(record, 0), f32_at(record, 4), f32_at(record, 8));
        let rotation = Quat::from_xyzw(
            f32_at(record, 12),
            f32_at(record, 16),
            f32_at(record, 20),
            f32_at(record, 24),
        );
        let lengths = [f32_at(record, 28), f32_at(record, 32), f32_at(record, 36)];
        let mut frame = Frame::from_parts(origin, rotation, lengths)
            .map_err(|e| corrupt("FRAM", format!("patch {k}: {e}")))?;
        if let Some(r) = residuals {
            let at = k * RESIDUAL_LEN;
            let residual = Vec3::new(f32_at(r, at), f32_at(r, at + 4), f32_at(r, at + 8));
            frame = frame
                .with_residual(residual)
                .map_err(|e| corrupt("ORGR", format!("patch {k}: {e}")))?;
        }
        let mut at = 40;
        let grid = match shared_grid {
            Some(g) => g,
            None => {
                let cols = u16::from_le_bytes([record[at], record[at + 1]]);
                let rows = u16::from_le_bytes([record[at + 2], record[at + 3]]);
                at += 4;
                GridSize::new(cols.into(), rows.into())
                    .map_err(|e| corrupt("FRAM", format!("patch {k}: {e}")))?
            }
        };
        let bytes_per_code = match fields.width_storage {
            WidthStorage::All8 => 1,
            WidthStorage::All16 => 2,
            WidthStorage::PerPatch => match record[at] {
                8 => 1,
                16 => 2,
                bits => {
                    return Err(corrupt(
                        "FRAM",
                        format!("patch {k}: displacement width {bits} bits"),
                    ))
                }
            },
        };
        frames.push((frame, grid));
        layouts.push(DisplacementLayout {
            cols: grid.cols().into(),
            rows: grid.rows().into(),
            bytes_per_code,
        });
    }

    let disp_raw_len: usize = layouts.iter().map(DisplacementLayout::raw_len).sum();
    let disp = section_payload(disp_section, disp_raw_len, |coded, buffer| {
        decode_displacements(coded, &layouts, buffer).ok()
    })?;
    let mut displacements: Vec<Vec<u16>> =
        vec_for_count(patch_count, record_len, frame_bytes, "patches")?;
    let mut at = 0;
    let mut filled = 0usize;
    for layout in &layouts {
        let n = layout.cols * layout.rows;
        let codes: Vec<u16> = if layout.bytes_per_code == 1 {
            disp[at..at + n]
                .iter()
                .map(|&b| if b == 0xFF { EMPTY } else { u16::from(b) })
                .collect()
        } else {
            disp[at..at + 2 * n]
                .chunks_exact(2)
                .map(|c| u16::from_le_bytes([c[0], c[1]]))
                .collect()
        };
        at += n * layout.bytes_per_code;
        filled += codes.iter().filter(|&&d| d != EMPTY).count();
        displacements.push(codes);
    }

    let colour_bytes = channel.bytes_per_node();
    let node_colours: Option<Vec<u8>> = match (fields.colour_storage, found[3]) {
        (ColourStorage::PerNode, Some(section)) => {
            let raw_len = filled * colour_bytes;
            Some(section_payload(section, raw_len, |coded, buffer| {
                decode_colours(coded, colour_bytes, raw_len, buffer).ok()
            })?)
        }
        (ColourStorage::PerNode, None) => return Err(FormatError::MissingSection("COLR")),
        (_, Some(_)) => {
            return Err(corrupt(
                "COLR",
                "colour section in a scene without per-node colour",
            ))
        }
        (_, None) => None,
    };

    let sides = match found[5] {
        Some(section) => Some(read_sides(section, patch_count)?),
        None => None,
    };
    let mut patches = vec_for_count(patch_count, record_len, frame_bytes, "patches")?;
    let mut colour_at = 0;
    for (k, ((frame, grid), codes)) in frames.into_iter().zip(displacements).enumerate() {
        let colours = match fields.colour_storage {
            ColourStorage::None => None,
            ColourStorage::Flat => Some(
                codes
                    .iter()
                    .map(|&d| {
                        if d == EMPTY {
                            [0; 4]
                        } else {
                            fields.flat_colour
                        }
                    })
                    .collect(),
            ),
            ColourStorage::PerNode => {
                let raw = node_colours.as_deref().unwrap_or_default();
                Some(
                    codes
                        .iter()
                        .map(|&d| {
                            if d == EMPTY {
                                return [0; 4];
                            }
                            let c = &raw[colour_at..colour_at + colour_bytes];
                            colour_at += colour_bytes;
                            [c[0], c[1], c[2], if colour_bytes == 4 { c[3] } else { 255 }]
                        })
                        .collect(),
                )
            }
        };
        let side = sides.as_deref().map_or(Sides::Front, |s| s[k]);
        patches.push(
            Patch::new(frame, grid, codes, colours)
                .map_err(|e| corrupt("DISP", format!("patch {k}: {e}")))?
                .with_sides(side),
        );
    }
    let openings = match found[6] {
        Some(section) => read_openings(section)?,
        None => Vec::new(),
    };
    let scene = Scene::new(offset, channel, patches)
        .map_err(|e| corrupt("SCNE", e.to_string()))?
        .with_openings(openings);
    let info = ContainerInfo {
        version_major: major,
        version_minor: minor,
        sections: sections.into_iter().map(|s| s.info).collect(),
        file_len: bytes.len(),
        flat_colour: fields.colour_storage == ColourStorage::Flat,
    };
    Ok((scene, info))
}

/// The ORGR payload, checked to hold one record per patch (a raw section).
fn read_residuals<'a>(
    section: Option<&RawSection<'a>>,
    patch_count: usize,
) -> Result<Option<&'a [u8]>, FormatError> {
    let Some(section) = section else {
        return Ok(None);
    };
    require_raw(section)?;
    if section.payload.len() != patch_count.saturating_mul(RESIDUAL_LEN) {
        return Err(corrupt(
            "ORGR",
            format!(
                "{} bytes for {patch_count} patches of {RESIDUAL_LEN} bytes",
                section.payload.len()
            ),
        ));
    }
    Ok(Some(section.payload))
}

/// Checks that a 1.1 section is raw (its stored and raw lengths equal).
fn require_raw(section: &RawSection<'_>) -> Result<(), FormatError> {
    let info = &section.info;
    if info.codec != CODEC_RAW || info.raw_len != section.payload.len() {
        return Err(corrupt(&info.tag, "this section must be raw"));
    }
    Ok(())
}

/// The checked SIDE payload: raw, one known code per patch.
fn read_sides(section: &RawSection<'_>, patch_count: usize) -> Result<Vec<Sides>, FormatError> {
    require_raw(section)?;
    let codes = section.payload;
    if codes.len() != patch_count {
        return Err(corrupt(
            "SIDE",
            format!("{} bytes for {patch_count} patches", codes.len()),
        ));
    }
    codes
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            Sides::from_code(c)
                .ok_or_else(|| corrupt("SIDE", format!("patch {k}: unknown code {c}")))
        })
        .collect()
}

/// The checked OPEN payload: raw, whole records of a finite centre and a radius >= 0.
fn read_openings(section: &RawSection<'_>) -> Result<Vec<Opening>, FormatError> {
    require_raw(section)?;
    let bytes = section.payload;
    if !bytes.len().is_multiple_of(OPENING_LEN) {
        return Err(corrupt(
            "OPEN",
            format!("{} bytes is not a whole number of openings", bytes.len()),
        ));
    }
    bytes
        .chunks_exact(OPENING_LEN)
        .enumerate()
        .map(|(k, r)| {
            let centre = Vec3::new(f32_at(r, 0), f32_at(r, 4), f32_at(r, 8));
            let normal = Vec3::new(f32_at(r, 16), f32_at(r, 20), f32_at(r, 24));
            Opening::new(centre, f32_at(r, 12), normal, f32_at(r, 28))
                .map_err(|e| corrupt("OPEN", format!("opening {k}: {e}")))
        })
        .collect()
}

/// Decodes `.spatch` bytes into a scene.
pub fn decode_scene(bytes: &[u8]) -> Result<Scene, FormatError> {
    inspect(bytes).map(|(scene, _)| scene)
}

/// Reads and decodes a `.spatch` file.
pub fn read_scene(path: &Path) -> Result<Scene, FormatError> {
    let bytes = std::fs::read(path).map_err(|source| FormatError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_scene(&bytes)
}
