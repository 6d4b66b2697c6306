//! A section written by hand, for tests that splice sections into a container.

/// Section `tag` with `payload` stored raw (stored length = raw length) under `codec`: its
/// 20-byte header (tag, codec, three reserved bytes, both lengths, CRC-32 of the header's
/// first 16 bytes and the payload) followed by the payload (docs/format.md §3.2).
pub(crate) fn section_bytes(tag: &[u8; 4], codec: u8, payload: &[u8]) -> Vec<u8> {
    let mut section = tag.to_vec();
    section.extend_from_slice(&[codec, 0, 0, 0]);
    section.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    section.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&section);
    crc.update(payload);
    section.extend_from_slice(&crc.finalize().to_le_bytes());
    section.extend_from_slice(payload);
    section
}
