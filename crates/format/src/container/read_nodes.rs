//! Readers of the node-data sections: DISP (displacement codes) and COLR
//! (per-node colours), raw or codec 1.
//!
//! Input: the sections and the per-patch layouts from FRAM. Output: each
//! patch's codes, and each patch's colours (flat, per node, or none).
//! Checked (docs/format.md §10, steps 6 and 7): raw lengths against what the
//! frames and the filled nodes imply, the codec-1 expansion bound, COLR present
//! exactly when the scene stores per-node colour. O(nodes).

use super::bounded::vec_for_count;
use super::layout::{ColourStorage, SceneFields};
use super::predictive::{decode_colours, decode_displacements, DisplacementLayout};
use super::sections::{node_data_payload, RawSection};
use crate::{Corruption, FormatError, EMPTY};

/// Each patch's displacement codes, and how many are filled over all patches.
pub(super) struct Codes {
    pub(super) per_patch: Vec<Vec<u16>>,
    pub(super) filled: usize,
}

/// Reads DISP: the codes of every patch laid out as `layouts` says
/// (`0xFF` is empty in an 8-bit patch, `0xFFFF` in a 16-bit one).
pub(super) fn read_displacements(
    section: &RawSection<'_>,
    layouts: &[DisplacementLayout],
) -> Result<Codes, FormatError> {
    let raw_len: usize = layouts.iter().map(DisplacementLayout::raw_len).sum();
    let disp = node_data_payload(section, raw_len, |coded, buffer| {
        decode_displacements(coded, layouts, buffer).ok()
    })?;
    // One Vec per patch; each layout came from a FRAM record actually present.
    let mut per_patch: Vec<Vec<u16>> = vec_for_count(layouts.len(), 1, layouts.len(), "patches")?;
    let mut at = 0;
    let mut filled = 0usize;
    for layout in layouts {
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
        filled += n - count_empty(&codes);
        per_patch.push(codes);
    }
    Ok(Codes { per_patch, filled })
}

/// The [`EMPTY`] codes in `codes`. Why a sum of comparisons rather than a
/// filtered count: the compiler runs the sum in vector lanes and left the
/// count scalar (1.9 M of the 3.3 M instructions reading the bunny's DISP;
/// callgrind, `spatch render bunny.spatch -o out.png --threads 1`).
/// Why in `u32`: eight lanes of 16-bit compares widen to two vectors, not
/// four (a grid has at most 257² nodes).
fn count_empty(codes: &[u16]) -> usize {
    codes.iter().map(|&d| u32::from(d == EMPTY)).sum::<u32>() as usize
}

/// Reads COLR when the scene stores per-node colour: `filled` colours of
/// `bytes_per_colour` bytes. `None` when the scene has no per-node colour.
pub(super) fn read_colours(
    section: Option<&RawSection<'_>>,
    fields: &SceneFields,
    bytes_per_colour: usize,
    filled: usize,
) -> Result<Option<Vec<u8>>, FormatError> {
    match (fields.colour_storage, section) {
        (ColourStorage::PerNode, Some(section)) => {
            let raw_len = filled * bytes_per_colour;
            Ok(Some(
                node_data_payload(section, raw_len, |coded, buffer| {
                    decode_colours(coded, bytes_per_colour, raw_len, buffer).ok()
                })?
                .into_owned(),
            ))
        }
        (ColourStorage::PerNode, None) => Err(FormatError::MissingSection("COLR")),
        (_, Some(section)) => Err(section.corrupt(Corruption::UnexpectedColours)),
        (_, None) => Ok(None),
    }
}

/// Hands out each patch's colours from the scene's colour storage, in patch order.
pub(super) struct ColourSource<'a> {
    storage: ColourStorage,
    flat: [u8; 4],
    per_node: &'a [u8],
    bytes_per_colour: usize,
    at: usize,
}

impl<'a> ColourSource<'a> {
    /// The colours of a scene with `fields`, and COLR's raw bytes when it has them.
    pub(super) fn new(fields: &SceneFields, per_node: Option<&'a [u8]>, bytes: usize) -> Self {
        Self {
            storage: fields.colour_storage,
            flat: fields.flat_colour,
            per_node: per_node.unwrap_or_default(),
            bytes_per_colour: bytes,
            at: 0,
        }
    }

    /// The next patch's colours (`[0; 4]` at empty nodes), `None` without colour.
    pub(super) fn next_patch(&mut self, codes: &[u16]) -> Option<Vec<[u8; 4]>> {
        match self.storage {
            ColourStorage::None => None,
            ColourStorage::Flat => Some(
                codes
                    .iter()
                    .map(|&d| if d == EMPTY { [0; 4] } else { self.flat })
                    .collect(),
            ),
            ColourStorage::PerNode => {
                let n = self.bytes_per_colour;
                Some(
                    codes
                        .iter()
                        .map(|&d| {
                            if d == EMPTY {
                                return [0; 4];
                            }
                            let c = &self.per_node[self.at..self.at + n];
                            self.at += n;
                            [c[0], c[1], c[2], if n == 4 { c[3] } else { 255 }]
                        })
                        .collect(),
                )
            }
        }
    }
}
