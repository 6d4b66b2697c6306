//! Damaged files give errors, never panics or huge allocations.

use spatch_format::{
    decode_scene, encode_scene, inspect, ColourChannel, Compression, FormatError, WriteOptions,
};

use crate::scenes::{minimal_scene, mixed_scene};
use crate::section_bytes::section_bytes;

fn files() -> Vec<Vec<u8>> {
    let mut out = vec![encode_scene(&minimal_scene(), &WriteOptions::default()).unwrap()];
    for compression in [Compression::None, Compression::Predictive] {
        out.push(
            encode_scene(
                &mixed_scene(ColourChannel::Rgba8),
                &WriteOptions::with_compression(compression),
            )
            .unwrap(),
        );
    }
    // A 1.1 file: the SIDE section is checked like the others.
    let marked = crate::two_sided::with_sides(
        &mixed_scene(ColourChannel::Rgb8),
        |k| [spatch_format::Sides::Front, spatch_format::Sides::Both][k % 2],
        vec![spatch_format::Opening::new(glam::Vec3::ONE, 1.0, glam::Vec3::Z, 0.2).unwrap()],
    );
    out.push(encode_scene(&marked, &WriteOptions::default()).unwrap());
    out
}

#[test]
fn every_truncation_is_an_error() {
    for bytes in files() {
        for len in 0..bytes.len() {
            assert!(
                decode_scene(&bytes[..len]).is_err(),
                "prefix of {len} bytes decoded"
            );
        }
    }
}

#[test]
fn a_flipped_byte_in_any_section_is_caught() {
    for bytes in files() {
        let (_, info) = inspect(&bytes).unwrap();
        for section in &info.sections {
            // First header byte, a payload byte in the middle, and the last byte.
            let end = section.offset + 20 + section.stored_len;
            for at in [
                section.offset,
                section.offset + 9,
                section.offset + 20 + section.stored_len / 2,
                end - 1,
            ] {
                let mut damaged = bytes.clone();
                damaged[at] ^= 0x10;
                assert!(
                    decode_scene(&damaged).is_err(),
                    "flip at {at} in {} went unnoticed",
                    section.tag
                );
            }
        }
        // Every byte of the file header too.
        for at in 0..16 {
            let mut damaged = bytes.clone();
            damaged[at] ^= 0x01;
            assert!(
                decode_scene(&damaged).is_err(),
                "flip at header byte {at} went unnoticed"
            );
        }
    }
}

/// Rewrites a section's stored/raw length fields and fixes its CRC, so the
/// lie reaches the structural checks.
pub(crate) fn with_section_lengths(
    bytes: &[u8],
    tag: &str,
    stored: Option<u32>,
    raw: Option<u32>,
) -> Vec<u8> {
    let (_, info) = inspect(bytes).unwrap();
    let section = info.sections.iter().find(|s| s.tag == tag).unwrap();
    let mut out = bytes.to_vec();
    let at = section.offset;
    if let Some(stored) = stored {
        out[at + 8..at + 12].copy_from_slice(&stored.to_le_bytes());
    }
    if let Some(raw) = raw {
        out[at + 12..at + 16].copy_from_slice(&raw.to_le_bytes());
    }
    let mut crc = crc32fast::Hasher::new();
    crc.update(&out[at..at + 16]);
    let stored_len = u32::from_le_bytes(out[at + 8..at + 12].try_into().unwrap()) as usize;
    let end = (at + 20 + stored_len).min(out.len());
    crc.update(&out[(at + 20).min(end)..end]);
    out[at + 16..at + 20].copy_from_slice(&crc.finalize().to_le_bytes());
    out
}

#[test]
fn counts_larger_than_the_file_are_refused_before_allocating() {
    let bytes = files().remove(2);
    // A section claiming 4 GiB of payload.
    let damaged = with_section_lengths(&bytes, "DISP", Some(u32::MAX), None);
    assert!(matches!(
        decode_scene(&damaged),
        Err(FormatError::Truncated { .. })
    ));
    // A compressed section claiming an impossible expansion.
    let damaged = with_section_lengths(&bytes, "DISP", None, Some(u32::MAX));
    assert!(matches!(
        decode_scene(&damaged),
        Err(FormatError::Corrupt { .. })
    ));
    // A header claiming a billion sections.
    let mut damaged = bytes.clone();
    damaged[8..12].copy_from_slice(&1_000_000_000u32.to_le_bytes());
    let crc = crc32fast::hash(&damaged[..12]);
    damaged[12..16].copy_from_slice(&crc.to_le_bytes());
    assert!(matches!(
        decode_scene(&damaged),
        Err(FormatError::Truncated { .. })
    ));
}

#[test]
fn a_patch_count_that_disagrees_with_the_frames_is_refused() {
    let bytes = files().remove(0);
    let (_, info) = inspect(&bytes).unwrap();
    let scne = &info.sections[0];
    let mut damaged = bytes.clone();
    let at = scne.offset + 20 + 24;
    damaged[at..at + 4].copy_from_slice(&4_000_000_000u32.to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&damaged[scne.offset..scne.offset + 16]);
    crc.update(&damaged[scne.offset + 20..scne.offset + 20 + scne.stored_len]);
    damaged[scne.offset + 16..scne.offset + 20].copy_from_slice(&crc.finalize().to_le_bytes());
    let err = decode_scene(&damaged).unwrap_err();
    assert!(err.to_string().contains("FRAM"), "{err}");
}

#[test]
fn an_unknown_major_version_is_refused_clearly() {
    let mut bytes = files().remove(0);
    bytes[6] = 2;
    let err = decode_scene(&bytes).unwrap_err();
    assert!(matches!(
        err,
        FormatError::UnsupportedVersion {
            found: 2,
            supported: 1
        }
    ));
    assert!(err.to_string().contains("newer spatch"), "{err}");
}

#[test]
fn a_newer_minor_version_with_an_extra_section_still_reads() {
    let mut bytes = files().remove(0);
    // Minor 7 and one more section "xtra" that a 1.0 reader skips.
    bytes[7] = 7;
    let count = u32::from_le_bytes(bytes[8..12].try_into().unwrap()) + 1;
    bytes[8..12].copy_from_slice(&count.to_le_bytes());
    let crc = crc32fast::hash(&bytes[..12]);
    bytes[12..16].copy_from_slice(&crc.to_le_bytes());
    bytes.extend_from_slice(&section_bytes(b"xtra", 0, b"future"));
    let (scene, info) = inspect(&bytes).unwrap();
    assert_eq!(scene, minimal_scene());
    assert_eq!(info.version_minor, 7);
    assert_eq!(info.sections.last().unwrap().tag, "xtra");
}

#[test]
fn trailing_bytes_and_foreign_files_are_refused() {
    let mut bytes = files().remove(0);
    bytes.push(0);
    assert!(matches!(
        decode_scene(&bytes),
        Err(FormatError::TrailingBytes(1))
    ));
    assert!(matches!(
        decode_scene(b"ply\nformat ascii 1.0\n"),
        Err(FormatError::NotSpatch)
    ));
    assert!(matches!(decode_scene(b""), Err(FormatError::NotSpatch)));
}
