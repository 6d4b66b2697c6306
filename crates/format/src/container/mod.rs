//! The `.spatch` container, version 1 (see `docs/format.md`).
//!
//! A 16-byte file header, then sections, each a 20-byte section header and a
//! payload protected by a CRC-32: `SCNE` (scene fields), `FRAM` (frames and
//! per-patch fields), `DISP` (displacement codes), and `COLR` (per-node
//! colours, only when the scene stores them), then, from minor version 1,
//! the optional `ORGR` (origin residuals, only when a frame has one), `SIDE`
//! (per-patch visible sides, only when a patch is not front-only) and `OPEN`
//! (the openings of an open surface), from minor version 2 `CGRD`
//! (colour grids finer than the nodes, only when a patch has one), from 3 `CGRX`
//! (colour grids that may share), and from 4 `INSD` (the box the backs of two-sided
//! patches show inside, only for a surface that may be meant to be seen from inside).

mod atomic;
mod bounded;
mod colour_grids;
mod layout;
mod merge_writer;
mod predictive;
mod range_coder;
mod read;
mod read_frames;
mod read_nodes;
mod read_sides;
mod records;
mod scratch;
mod sections;
mod shape;
mod shared_colour_grids;
mod stream;
mod write;

pub use atomic::{abandon_pending_writes, write_file_atomically, write_file_atomically_with};
pub use colour_grids::colour_grid_section_len;
pub use merge_writer::MergeWriter;
pub use read::{decode_scene, inspect, read_scene, ContainerInfo, SectionInfo};
pub use stream::read_container_bytes;
pub use write::{encode_scene, write_scene, Compression, WriteOptions};

/// The first six bytes of every `.spatch` file.
pub const MAGIC: [u8; 6] = *b"SPATCH";
/// The major version this crate writes and reads. Readers refuse other majors.
pub const VERSION_MAJOR: u8 = 1;
/// The newest minor version this crate writes: 1 adds the optional `ORGR`,
/// `SIDE` and `OPEN` sections, 2 the optional `CGRD` (colour grids), 3 `CGRX` (colour
/// grids that may reuse another patch's, with a finer context model; writers write it
/// instead of CGRD), 4 `INSD` (the inside box of two-sided patches). A file
/// is written with the lowest minor that describes it, so one that needs none
/// of them is 1.0, byte for byte as before.
/// Readers accept any minor of their major.
pub const VERSION_MINOR: u8 = 4;

/// The lowest minor version that describes a file holding `tags`.
pub(crate) fn minor_for(tags: &[[u8; 4]]) -> u8 {
    use layout::{
        TAG_COLOUR_GRIDS, TAG_INSIDE_BOX, TAG_OPENINGS, TAG_ORIGIN_RESIDUALS,
        TAG_SHARED_COLOUR_GRIDS, TAG_SIDES,
    };
    if tags.contains(&TAG_INSIDE_BOX) {
        4
    } else if tags.contains(&TAG_SHARED_COLOUR_GRIDS) {
        3
    } else if tags.contains(&TAG_COLOUR_GRIDS) {
        2
    } else if tags
        .iter()
        .any(|t| [TAG_ORIGIN_RESIDUALS, TAG_SIDES, TAG_OPENINGS].contains(t))
    {
        1
    } else {
        0
    }
}
