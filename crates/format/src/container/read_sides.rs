//! Readers of the version 1.1 visibility sections: SIDE (which sides of each
//! patch may be seen) and OPEN (the openings of an open surface).
//!
//! Input: the raw sections. Output: one [`Sides`] per patch, and the openings.
//! Checked (docs/format.md §10, step 9): both raw; SIDE one known code per
//! patch; OPEN whole 32-byte records of finite values. O(patches + openings).

use glam::Vec3;

use super::layout::OPENING_LEN;
use super::sections::{f32_at, require_raw, RawSection};
use crate::{Corruption, FormatError, Opening, Sides};

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
