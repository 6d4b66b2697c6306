//! Integration tests of spatch-tiling: the streamed readers against each other, plans,
//! and per-tile conversion joining into the untiled conversion.

mod join;
mod readers;

use std::path::Path;

use spatch_fixtures::Cityscape;

/// Writes `city` as binary little-endian PLY (float xyz, uchar rgb).
pub(crate) fn write_city_ply(city: &Cityscape, path: &Path) {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n",
        city.len()
    )
    .into_bytes();
    city.for_each_chunk(4096, &mut |p, c| {
        for (p, c) in p.iter().zip(c) {
            for v in p {
                bytes.extend_from_slice(&(*v as f32).to_le_bytes());
            }
            bytes.extend_from_slice(c);
        }
    });
    std::fs::write(path, bytes).unwrap();
}
