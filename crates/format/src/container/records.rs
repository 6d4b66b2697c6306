//! The bytes one patch contributes to each section, and the file and section headers:
//! shared by the in-memory encoder ([`super::encode_scene`]) and the streaming
//! [`super::MergeWriter`], so both write the same bytes.

use super::layout::{GridStorage, WidthStorage, FRAME_LEN};
use super::predictive::DisplacementLayout;
use super::{MAGIC, VERSION_MAJOR, VERSION_MINOR};
use crate::{DisplacementWidth, FormatError, InsideBox, Opening, Patch, EMPTY};

/// Bytes of a FRAM record with every optional field (grid and width).
pub(crate) const FULL_FRAME_LEN: usize = FRAME_LEN + 5;

/// Appends the patch's FRAM record: origin, rotation and lengths, then its grid when
/// grids are stored per patch, then its width when widths are.
pub(crate) fn push_frame_record(
    out: &mut Vec<u8>,
    patch: &Patch,
    grid_storage: GridStorage,
    width_storage: WidthStorage,
) {
    let frame = patch.frame();
    let q = frame.rotation();
    let numbers = frame
        .origin()
        .to_array()
        .into_iter()
        .chain([q.x, q.y, q.z, q.w])
        .chain(frame.lengths());
    for v in numbers {
        out.extend_from_slice(&v.to_le_bytes());
    }
    if grid_storage == GridStorage::PerPatch {
        out.extend_from_slice(&patch.grid().cols().to_le_bytes());
        out.extend_from_slice(&patch.grid().rows().to_le_bytes());
    }
    if width_storage == WidthStorage::PerPatch {
        out.push(patch.displacement_width().bits());
    }
}

/// What the displacement codec needs to know about a patch, from its full FRAM record
/// (see [`FULL_FRAME_LEN`]).
pub(crate) fn layout_of_full_record(record: &[u8; FULL_FRAME_LEN]) -> DisplacementLayout {
    let u16_at = |k: usize| usize::from(u16::from_le_bytes([record[k], record[k + 1]]));
    DisplacementLayout {
        cols: u16_at(FRAME_LEN),
        rows: u16_at(FRAME_LEN + 2),
        bytes_per_code: usize::from(record[FRAME_LEN + 4] / 8),
    }
}

/// What the displacement codec needs to know about `patch`.
pub(crate) fn displacement_layout(patch: &Patch) -> DisplacementLayout {
    DisplacementLayout {
        cols: usize::from(patch.grid().cols()),
        rows: usize::from(patch.grid().rows()),
        bytes_per_code: usize::from(patch.displacement_width().bits() / 8),
    }
}

/// Appends the patch's DISP codes (one byte each when 8-bit, u16 LE when 16-bit).
pub(crate) fn push_displacements(out: &mut Vec<u8>, patch: &Patch) {
    match patch.displacement_width() {
        DisplacementWidth::Bits8 => {
            out.extend(
                patch
                    .displacements()
                    .iter()
                    .map(|&d| if d == EMPTY { 0xFF } else { d as u8 }),
            )
        }
        DisplacementWidth::Bits16 => {
            for &d in patch.displacements() {
                out.extend_from_slice(&d.to_le_bytes());
            }
        }
    }
}

/// Appends the colours of the patch's filled nodes, `colour_bytes` (3 or 4) each.
pub(crate) fn push_colours(
    out: &mut Vec<u8>,
    patch: &Patch,
    colour_bytes: usize,
) -> Result<(), FormatError> {
    let node_colours = patch
        .colours()
        .ok_or(FormatError::Bug("coloured scene with a colourless patch"))?;
    for (c, &d) in node_colours.iter().zip(patch.displacements()) {
        if d != EMPTY {
            out.extend_from_slice(&c[..colour_bytes]);
        }
    }
    Ok(())
}

/// Appends the patch's ORGR record (its origin residual, 3 × f32).
pub(crate) fn push_residual(out: &mut Vec<u8>, patch: &Patch) {
    for v in patch.frame().origin_residual().to_array() {
        out.extend_from_slice(&v.to_le_bytes());
    }
}

/// The OPEN payload: centre, radius, normal and half thickness of each opening.
pub(crate) fn openings_payload(openings: &[Opening]) -> Vec<u8> {
    openings
        .iter()
        .flat_map(|o| {
            let [x, y, z] = o.centre().to_array();
            let [nx, ny, nz] = o.normal().to_array();
            [x, y, z, o.radius(), nx, ny, nz, o.half_thickness()]
        })
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// The INSD payload: the lower corner, then the upper one.
pub(crate) fn inside_box_payload(b: &InsideBox) -> Vec<u8> {
    [b.min().to_array(), b.max().to_array()]
        .into_iter()
        .flatten()
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// The 16-byte file header: the lowest minor version that describes the file.
pub(crate) fn file_header(section_count: u32, minor: u8) -> [u8; 16] {
    let mut out = [0u8; 16];
    out[..6].copy_from_slice(&MAGIC);
    out[6] = VERSION_MAJOR;
    out[7] = minor.min(VERSION_MINOR);
    out[8..12].copy_from_slice(&section_count.to_le_bytes());
    let crc = crc32fast::hash(&out[..12]);
    out[12..].copy_from_slice(&crc.to_le_bytes());
    out
}

/// A section's 16 header bytes before its CRC; lengths past `u32` are refused (a
/// section holds at most 4 GiB − 1 bytes).
pub(crate) fn section_header(
    tag: [u8; 4],
    codec: u8,
    stored_len: u64,
    raw_len: u64,
) -> Result<[u8; 16], FormatError> {
    let fits = |n: u64| u32::try_from(n).ok();
    let (Some(stored), Some(raw)) = (fits(stored_len), fits(raw_len)) else {
        return Err(FormatError::SectionTooLong {
            tag: String::from_utf8_lossy(&tag).into_owned(),
            bytes: stored_len.max(raw_len),
        });
    };
    let mut out = [0u8; 16];
    out[..4].copy_from_slice(&tag);
    out[4] = codec;
    out[8..12].copy_from_slice(&stored.to_le_bytes());
    out[12..].copy_from_slice(&raw.to_le_bytes());
    Ok(out)
}
