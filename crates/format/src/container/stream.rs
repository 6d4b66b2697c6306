//! Reading one container from a stream (a pipe, a device, standard input)
//! without trusting the stream to end.
//!
//! The file header is read first and its magic checked, so a stream that is
//! not a container (`/dev/zero`, `/dev/urandom`) is refused after 16 bytes.
//! After that only what the headers announce is read — the section count,
//! then each section's stored length — plus one byte to notice trailing
//! data, and never more than a caller's limit. Memory grows with the bytes
//! that really arrive, not with the lengths announced. The bytes are then
//! decoded as usual ([`super::inspect`]), which checks every CRC.

use std::io::Read;

use super::layout::{FILE_HEADER_LEN, SECTION_HEADER_LEN};
use super::MAGIC;
use crate::FormatError;

/// Reads the bytes of one container from `reader`, no more than `limit`
/// bytes (plus one, to detect bytes after the last section). A stream that
/// does not start with the magic bytes is refused as soon as they are read;
/// a stream that ends early returns what it gave, for the decoder to report
/// as truncated.
pub fn read_container_bytes(reader: &mut impl Read, limit: u64) -> Result<Vec<u8>, FormatError> {
    let mut bytes = Vec::new();
    let io = |source| FormatError::Stream { source };
    read_up_to(reader, &mut bytes, FILE_HEADER_LEN as u64).map_err(io)?;
    if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        return Err(FormatError::NotSpatch);
    }
    if bytes.len() < FILE_HEADER_LEN {
        return Ok(bytes);
    }
    let count = u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]);
    for _ in 0..count {
        let at = bytes.len();
        read_bounded(reader, &mut bytes, SECTION_HEADER_LEN as u64, limit)?;
        if bytes.len() < at + SECTION_HEADER_LEN {
            return Ok(bytes);
        }
        let h = &bytes[at..];
        let stored_len = u32::from_le_bytes([h[8], h[9], h[10], h[11]]);
        let before = bytes.len();
        read_bounded(reader, &mut bytes, u64::from(stored_len), limit)?;
        if bytes.len() < before + stored_len as usize {
            return Ok(bytes);
        }
    }
    read_up_to(reader, &mut bytes, 1).map_err(io)?;
    Ok(bytes)
}

/// Appends up to `len` more bytes, refusing to pass `limit` in all.
fn read_bounded(
    reader: &mut impl Read,
    bytes: &mut Vec<u8>,
    len: u64,
    limit: u64,
) -> Result<(), FormatError> {
    if bytes.len() as u64 + len > limit {
        return Err(FormatError::TooLarge { limit });
    }
    read_up_to(reader, bytes, len).map_err(|source| FormatError::Stream { source })
}

/// Appends up to `len` bytes (fewer at the end of the stream).
fn read_up_to(reader: &mut impl Read, bytes: &mut Vec<u8>, len: u64) -> std::io::Result<()> {
    reader.take(len).read_to_end(bytes).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{decode_scene, encode_scene, ColourChannel, Scene, WriteOptions};

    fn small_container() -> Vec<u8> {
        let scene = Scene::new(glam::DVec3::ZERO, ColourChannel::None, Vec::new()).unwrap();
        encode_scene(&scene, &WriteOptions::default()).unwrap()
    }

    #[test]
    fn a_container_reads_back_whole_and_stops_at_its_end() {
        let bytes = small_container();
        let mut stream = bytes.clone();
        stream.extend_from_slice(&[7; 100]);
        let read = read_container_bytes(&mut stream.as_slice(), 1 << 20).unwrap();
        assert_eq!(
            read.len(),
            bytes.len() + 1,
            "one trailing byte, not all 100"
        );
        let exact = read_container_bytes(&mut bytes.as_slice(), 1 << 20).unwrap();
        assert_eq!(decode_scene(&exact).unwrap(), decode_scene(&bytes).unwrap());
    }

    #[test]
    fn endless_streams_are_refused_at_once() {
        let err = read_container_bytes(&mut std::io::repeat(0), u64::MAX).unwrap_err();
        assert!(matches!(err, FormatError::NotSpatch), "{err}");
        let mut endless = small_container()[..FILE_HEADER_LEN].to_vec();
        endless[8..12].copy_from_slice(&u32::MAX.to_le_bytes());
        let mut stream = endless.as_slice().chain(std::io::repeat(0xff));
        let err = read_container_bytes(&mut stream, 1 << 20).unwrap_err();
        assert!(matches!(err, FormatError::TooLarge { .. }), "{err}");
    }

    #[test]
    fn a_short_stream_gives_what_it_has() {
        let bytes = small_container();
        let read = read_container_bytes(&mut &bytes[..30], 1 << 20).unwrap();
        assert_eq!(read, &bytes[..30]);
    }
}
