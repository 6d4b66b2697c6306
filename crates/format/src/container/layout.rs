//! Byte-level constants and the scene section's fields, shared by the reader
//! and the writer.

use crate::Corruption;

/// File header: magic (6), major (1), minor (1), section count (u32), CRC-32
/// of the first 12 bytes (u32).
pub(crate) const FILE_HEADER_LEN: usize = 16;
/// Section header: tag (4), codec (1), reserved (3), stored length (u32),
/// raw length (u32), CRC-32 of the first 16 header bytes and the payload (u32).
pub(crate) const SECTION_HEADER_LEN: usize = 20;
/// Bytes of the SCNE payload defined by version 1.0.
pub(crate) const SCENE_LEN: usize = 40;
/// Bytes of one frame: origin 3×f32, quaternion 4×f32, lengths 3×f32.
pub(crate) const FRAME_LEN: usize = 40;
/// A predictive section never expands by more than this factor (plus
/// [`MAX_EXPANSION_SLACK`]); readers refuse larger raw lengths before
/// allocating. The coder's clamped probabilities bound the real factor to
/// about 46.
pub(crate) const MAX_EXPANSION: usize = 64;
/// See [`MAX_EXPANSION`].
pub(crate) const MAX_EXPANSION_SLACK: usize = 64;

pub(crate) const TAG_SCENE: [u8; 4] = *b"SCNE";
pub(crate) const TAG_FRAMES: [u8; 4] = *b"FRAM";
pub(crate) const TAG_DISPLACEMENTS: [u8; 4] = *b"DISP";
pub(crate) const TAG_COLOURS: [u8; 4] = *b"COLR";
/// Optional (version 1.1): per-patch origin residuals, 3 × f32 each.
pub(crate) const TAG_ORIGIN_RESIDUALS: [u8; 4] = *b"ORGR";
/// Bytes of one ORGR record.
pub(crate) const RESIDUAL_LEN: usize = 12;
/// Per-patch visible sides (minor version 1): one byte per patch.
pub(crate) const TAG_SIDES: [u8; 4] = *b"SIDE";
/// The openings of an open surface (minor version 1).
pub(crate) const TAG_OPENINGS: [u8; 4] = *b"OPEN";
/// Bytes of one opening: centre 3×f32, radius f32, normal 3×f32, half thickness f32.
pub(crate) const OPENING_LEN: usize = 32;
/// The box two-sided patches show their backs inside (minor version 4).
pub(crate) const TAG_INSIDE_BOX: [u8; 4] = *b"INSD";
/// Bytes of the inside box: lower corner 3×f32, upper corner 3×f32.
pub(crate) const INSIDE_BOX_LEN: usize = 24;

/// Per-patch colour grids finer than the nodes (minor version 2).
pub(crate) const TAG_COLOUR_GRIDS: [u8; 4] = *b"CGRD";
/// Colour grids that may reuse another patch's (minor version 3; supersedes CGRD).
pub(crate) const TAG_SHARED_COLOUR_GRIDS: [u8; 4] = *b"CGRX";

pub(crate) const CODEC_RAW: u8 = 0;
pub(crate) const CODEC_PREDICTIVE: u8 = 1;

/// How colour is stored (SCNE byte 29).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ColourStorage {
    None = 0,
    Flat = 1,
    PerNode = 2,
}

/// How grid sizes are stored (SCNE byte 30).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum GridStorage {
    PerPatch = 0,
    Shared = 1,
}

/// How displacement widths are stored (SCNE byte 31).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum WidthStorage {
    PerPatch = 0,
    All8 = 1,
    All16 = 2,
}

/// The decoded SCNE payload.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SceneFields {
    pub(crate) offset: [f64; 3],
    pub(crate) patch_count: u32,
    /// 0 none, 1 RGB8, 2 RGBA8.
    pub(crate) channel: u8,
    pub(crate) colour_storage: ColourStorage,
    pub(crate) grid_storage: GridStorage,
    pub(crate) width_storage: WidthStorage,
    pub(crate) shared_cols: u16,
    pub(crate) shared_rows: u16,
    pub(crate) flat_colour: [u8; 4],
}

impl SceneFields {
    /// Bytes of one FRAM record.
    pub(crate) fn frame_record_len(&self) -> usize {
        FRAME_LEN
            + if self.grid_storage == GridStorage::PerPatch {
                4
            } else {
                0
            }
            + if self.width_storage == WidthStorage::PerPatch {
                1
            } else {
                0
            }
    }

    pub(crate) fn to_bytes(self) -> [u8; SCENE_LEN] {
        let mut b = [0u8; SCENE_LEN];
        for (k, v) in self.offset.iter().enumerate() {
            b[8 * k..8 * k + 8].copy_from_slice(&v.to_le_bytes());
        }
        b[24..28].copy_from_slice(&self.patch_count.to_le_bytes());
        b[28] = self.channel;
        b[29] = self.colour_storage as u8;
        b[30] = self.grid_storage as u8;
        b[31] = self.width_storage as u8;
        b[32..34].copy_from_slice(&self.shared_cols.to_le_bytes());
        b[34..36].copy_from_slice(&self.shared_rows.to_le_bytes());
        b[36..40].copy_from_slice(&self.flat_colour);
        b
    }

    /// Parses the first [`SCENE_LEN`] bytes; later minor versions may append
    /// fields, which a 1.0 reader ignores.
    pub(crate) fn from_bytes(b: &[u8]) -> Result<Self, Corruption> {
        if b.len() < SCENE_LEN {
            return Err(Corruption::Short {
                found: b.len(),
                needed: SCENE_LEN,
            });
        }
        let unknown = |field, value| Corruption::UnknownCode { field, value };
        let f64_at = |k: usize| f64::from_le_bytes(b[k..k + 8].try_into().unwrap_or([0; 8]));
        let u16_at = |k: usize| u16::from_le_bytes([b[k], b[k + 1]]);
        let colour_storage = match b[29] {
            0 => ColourStorage::None,
            1 => ColourStorage::Flat,
            2 => ColourStorage::PerNode,
            v => return Err(unknown("colour storage", v)),
        };
        let grid_storage = match b[30] {
            0 => GridStorage::PerPatch,
            1 => GridStorage::Shared,
            v => return Err(unknown("grid storage", v)),
        };
        let width_storage = match b[31] {
            0 => WidthStorage::PerPatch,
            1 => WidthStorage::All8,
            2 => WidthStorage::All16,
            v => return Err(unknown("displacement width storage", v)),
        };
        let channel = b[28];
        if channel > 2 {
            return Err(unknown("colour channel", channel));
        }
        if (channel == 0) != (colour_storage == ColourStorage::None) {
            return Err(Corruption::ChannelStorage);
        }
        Ok(Self {
            offset: [f64_at(0), f64_at(8), f64_at(16)],
            patch_count: u32::from_le_bytes([b[24], b[25], b[26], b[27]]),
            channel,
            colour_storage,
            grid_storage,
            width_storage,
            shared_cols: u16_at(32),
            shared_rows: u16_at(34),
            flat_colour: [b[36], b[37], b[38], b[39]],
        })
    }
}
