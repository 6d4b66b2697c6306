//! Readers of the visibility sections: SIDE (which sides of each patch may be
//! seen) and OPEN (the openings of an open surface), version 1.1, and INSD
//! (the box the backs of two-sided patches show inside), version 1.4.
//!
//! Input: the raw sections. Output: one [`Sides`] per patch, the openings and
//! the inside box. Checked (docs/format.md §10, step 9): all raw; SIDE one
//! known code per patch; OPEN whole 32-byte records of finite values; INSD 24
//! bytes, finite corners, the lower not above the upper. O(patches + openings).

use glam::Vec3;

use super::layout::{INSIDE_BOX_LEN, OPENING_LEN};
use super::sections::{f32_at, require_raw, RawSection};
use crate::{Corruption, FormatError, InsideBox, Opening, Sides};

/// The checked SIDE payload: raw, one known code per patch.
pub(super) fn read_sides(
    section: &RawSection<'_>,
    patch_count: usize,
) -> Result<Vec<Sides>, FormatError> {
    require_raw(section)?;
    let codes = section.payload;
    if codes.len() != patch_count {
        return Err(section.corrupt(Corruption::RecordCount {
            bytes: codes.len(),
            count: patch_count,
            record: 1,
        }));
    }
    codes
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            Sides::from_code(c)
                .ok_or_else(|| section.corrupt(Corruption::SideCode { patch: k, code: c }))
        })
        .collect()
}

/// The checked OPEN payload: raw, whole records of a finite centre and a radius >= 0.
pub(super) fn read_openings(section: &RawSection<'_>) -> Result<Vec<Opening>, FormatError> {
    require_raw(section)?;
    let bytes = section.payload;
    if !bytes.len().is_multiple_of(OPENING_LEN) {
        return Err(section.corrupt(Corruption::PartialRecord {
            bytes: bytes.len(),
            record: OPENING_LEN,
        }));
    }
    bytes
        .chunks_exact(OPENING_LEN)
        .enumerate()
        .map(|(index, r)| {
            let centre = Vec3::new(f32_at(r, 0), f32_at(r, 4), f32_at(r, 8));
            let normal = Vec3::new(f32_at(r, 16), f32_at(r, 20), f32_at(r, 24));
            Opening::new(centre, f32_at(r, 12), normal, f32_at(r, 28)).map_err(|e| {
                section.corrupt(Corruption::Opening {
                    index,
                    error: Box::new(e),
                })
            })
        })
        .collect()
}

/// The checked INSD payload: raw, one 24-byte box with finite, ordered corners.
pub(super) fn read_inside_box(section: &RawSection<'_>) -> Result<InsideBox, FormatError> {
    require_raw(section)?;
    let r = section.payload;
    if r.len() != INSIDE_BOX_LEN {
        return Err(section.corrupt(Corruption::RecordCount {
            bytes: r.len(),
            count: 1,
            record: INSIDE_BOX_LEN,
        }));
    }
    let min = Vec3::new(f32_at(r, 0), f32_at(r, 4), f32_at(r, 8));
    let max = Vec3::new(f32_at(r, 12), f32_at(r, 16), f32_at(r, 20));
    InsideBox::new(min, max).map_err(|e| section.corrupt(Corruption::InsideBox(Box::new(e))))
}
