//! Splitting container bytes into CRC-checked sections, and the checks every
//! section reader shares: raw sections, node-data payloads (raw or codec 1).
//!
//! Input: the whole file. Output: the file's version and its sections in file
//! order, each a [`SectionInfo`] and a borrowed payload. Checked here
//! (docs/format.md §10, steps 1–3): magic, major version, header CRC, the
//! section count against the bytes present, each header and payload inside
//! the file, each CRC, reserved bytes, no trailing bytes. Nothing is allocated
//! beyond one entry per section header actually present. O(file) for the CRCs.

use std::borrow::Cow;

use super::bounded::vec_for_count;
use super::layout::{
    CODEC_PREDICTIVE, CODEC_RAW, FILE_HEADER_LEN, MAX_EXPANSION, MAX_EXPANSION_SLACK,
    SECTION_HEADER_LEN,
};
use super::{MAGIC, VERSION_MAJOR};
use crate::{Corruption, FormatError};

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

/// A section's header fields and its stored payload.
pub(super) struct RawSection<'a> {
    pub(super) info: SectionInfo,
    pub(super) payload: &'a [u8],
}

impl RawSection<'_> {
    /// A corruption of this section.
    pub(super) fn corrupt(&self, kind: Corruption) -> FormatError {
        corrupt(&self.info.tag, kind)
    }
}

/// The file's version and its sections.
pub(super) struct Split<'a> {
    pub(super) major: u8,
    pub(super) minor: u8,
    pub(super) sections: Vec<RawSection<'a>>,
}

/// A corruption of section `tag`.
pub(super) fn corrupt(tag: &str, kind: Corruption) -> FormatError {
    FormatError::Corrupt {
        section: tag.to_owned(),
        kind,
    }
}

/// The section tag as text, non-printable bytes as `?`.
fn tag_name(tag: &[u8]) -> String {
    tag.iter()
        .map(|&b| if b.is_ascii_graphic() { b as char } else { '?' })
        .collect()
}

/// `len` bytes at `at`, or a truncation error naming `what`.
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

/// The little-endian u32 at `k` (the caller checked the length).
pub(super) fn u32_at(b: &[u8], k: usize) -> u32 {
    u32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]])
}

/// The little-endian f32 at `k` (the caller checked the length).
pub(super) fn f32_at(b: &[u8], k: usize) -> f32 {
    f32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]])
}

/// Checks the file header and splits the file into CRC-checked sections.
pub(super) fn split_sections(bytes: &[u8]) -> Result<Split<'_>, FormatError> {
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
        let section = read_section(bytes, at)?;
        at += SECTION_HEADER_LEN + section.info.stored_len;
        sections.push(section);
    }
    if at != bytes.len() {
        return Err(FormatError::TrailingBytes(bytes.len() - at));
    }
    Ok(Split {
        major,
        minor,
        sections,
    })
}

/// The section whose header starts at `at`, its CRC and reserved bytes checked.
fn read_section(bytes: &[u8], at: usize) -> Result<RawSection<'_>, FormatError> {
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
        return Err(corrupt(&tag, Corruption::ReservedBytes));
    }
    Ok(RawSection {
        info: SectionInfo {
            tag,
            codec: h[4],
            offset: at,
            stored_len,
            raw_len,
        },
        payload,
    })
}

/// Checks that a section is raw: codec 0, and its raw length equal to its
/// stored length (docs/format.md §3.2), as SCNE, FRAM, ORGR, SIDE and OPEN
/// must be.
pub(super) fn require_raw(section: &RawSection<'_>) -> Result<(), FormatError> {
    let info = &section.info;
    if info.codec != CODEC_RAW {
        return Err(section.corrupt(Corruption::NotRaw(info.codec)));
    }
    require_raw_length(section)
}

/// Checks that a raw-coded section's raw length equals its stored length.
pub(super) fn require_raw_length(section: &RawSection<'_>) -> Result<(), FormatError> {
    let info = &section.info;
    if info.raw_len != info.stored_len {
        return Err(section.corrupt(Corruption::RawLengthNotStored {
            stored: info.stored_len,
            raw: info.raw_len,
        }));
    }
    Ok(())
}

/// The raw payload of a node-data section (DISP, COLR) whose raw length must be
/// `expected_raw`: borrowed from the file's bytes when raw, decoded by `decode`
/// when codec 1 (with the raw length bounded by the coded length before
/// anything is allocated). Why borrowed: the readers copy the codes into each
/// patch anyway, and a copy of the bunny's DISP was 0.4 M instructions of a
/// one-frame render (callgrind, `spatch render bunny.spatch -o out.png
/// --threads 1`).
pub(super) fn node_data_payload<'a>(
    section: &RawSection<'a>,
    expected_raw: usize,
    decode: impl FnOnce(&[u8], Vec<u8>) -> Option<Vec<u8>>,
) -> Result<Cow<'a, [u8]>, FormatError> {
    let info = &section.info;
    if info.raw_len != expected_raw {
        return Err(section.corrupt(Corruption::RawLength {
            found: info.raw_len,
            expected: expected_raw,
        }));
    }
    match info.codec {
        CODEC_RAW => {
            require_raw_length(section)?;
            Ok(Cow::Borrowed(section.payload))
        }
        CODEC_PREDICTIVE => {
            let limit = info
                .stored_len
                .saturating_mul(MAX_EXPANSION)
                .saturating_add(MAX_EXPANSION_SLACK);
            if info.raw_len > limit {
                return Err(section.corrupt(Corruption::Expansion {
                    raw: info.raw_len,
                    stored: info.stored_len,
                }));
            }
            let buffer = vec_for_count(info.raw_len, 1, limit, "decoded bytes")?;
            decode(section.payload, buffer)
                .map(Cow::Owned)
                .ok_or_else(|| section.corrupt(Corruption::StreamEndsEarly))
        }
        other => Err(section.corrupt(Corruption::UnknownCodec(other))),
    }
}
