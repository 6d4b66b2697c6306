//! The one error type of the format crate.

use std::path::PathBuf;

/// Everything that can go wrong while building, encoding or decoding a scene.
///
/// Variants are split by who is at fault: the caller's values
/// (`Invalid*`), the bytes of a file (`Corrupt*`, `Truncated`, ...), the
/// operating system (`Io`), or this crate (`Bug`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FormatError {
    /// A frame was built from non-finite numbers, zero lengths, or axes that
    /// are not orthogonal and right-handed.
    #[error("invalid frame: {reason}")]
    InvalidFrame {
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A grid side is outside 2..=257 nodes.
    #[error("invalid grid {cols}x{rows}: each side must have 2..=257 nodes")]
    InvalidGrid {
        /// Nodes along the x axis.
        cols: u32,
        /// Nodes along the y axis.
        rows: u32,
    },
    /// The displacement or colour arrays do not match the grid.
    #[error("patch data has {found} {what}, the {cols}x{rows} grid needs {expected}")]
    NodeCountMismatch {
        /// `"displacements"` or `"colours"`.
        what: &'static str,
        /// Number of values given.
        found: usize,
        /// Number of nodes in the grid.
        expected: usize,
        /// Grid columns.
        cols: u16,
        /// Grid rows.
        rows: u16,
    },
    /// Colour presence on a patch disagrees with the scene's colour channel.
    #[error("patch {patch} {problem}")]
    ColourMismatch {
        /// Index of the patch in the scene.
        patch: usize,
        /// `"has colours but the scene has no colour channel"` or the reverse.
        problem: &'static str,
    },
    /// The scene offset is not finite.
    #[error("scene offset is not finite")]
    InvalidOffset,
    /// A colour grid's values are out of range.
    #[error("invalid colour grid: {reason}")]
    InvalidColourGrid {
        /// Which rule is broken.
        reason: &'static str,
    },
    /// An opening has a non-finite centre or a negative or non-finite radius.
    #[error(
        "an opening needs a finite centre, radius and thickness (not below 0) and a unit normal"
    )]
    InvalidOpening,
    /// An inside box with a non-finite corner or a lower corner above the upper one.
    #[error("an inside box needs finite corners, the lower not above the upper")]
    InvalidInsideBox,
    /// A quantizer was given a non-finite or non-positive step.
    #[error("invalid quantizer: {reason}")]
    InvalidQuantizer {
        /// What is wrong with it.
        reason: &'static str,
    },
    /// The file does not start with the spatch magic bytes.
    #[error("not a .spatch file (magic bytes missing)")]
    NotSpatch,
    /// The file's major version is one this reader does not know.
    #[error("unsupported .spatch major version {found} (this reader supports {supported}.x); a newer spatch wrote it")]
    UnsupportedVersion {
        /// Major version in the file.
        found: u8,
        /// Major version this reader supports.
        supported: u8,
    },
    /// The file ends before a structure it announces.
    #[error(
        "file truncated: {what} needs {needed} bytes at offset {offset}, only {available} remain"
    )]
    Truncated {
        /// The structure being read.
        what: String,
        /// Byte offset where it starts.
        offset: usize,
        /// Bytes it needs.
        needed: usize,
        /// Bytes left in the file.
        available: usize,
    },
    /// A CRC-32 does not match: the bytes were changed after writing.
    #[error("checksum mismatch in {section} section at offset {offset}: the file is corrupt")]
    ChecksumMismatch {
        /// Section tag (or `"header"`).
        section: String,
        /// Byte offset of the section header.
        offset: usize,
    },
    /// A structural value in the file is impossible.
    #[error("corrupt {section} section: {kind}")]
    Corrupt {
        /// Section tag.
        section: String,
        /// What is wrong.
        kind: Corruption,
    },
    /// A required section is absent.
    #[error("missing required {0} section")]
    MissingSection(&'static str),
    /// Bytes follow the last section.
    #[error("{0} unexpected bytes after the last section")]
    TrailingBytes(usize),
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Reading a stream (a pipe, a device) failed.
    #[error("cannot read: {source}")]
    Stream {
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A stream announces more bytes than the reader accepts from it.
    #[error("the input passes the {limit}-byte limit for a stream (a pipe or a device)")]
    TooLarge {
        /// The largest number of bytes accepted.
        limit: u64,
    },
    /// A section would pass the container's u32 length field (4 GiB − 1 bytes): split
    /// the scene into several files (tiles).
    #[error("the {tag} section would hold {bytes} bytes, past the 4 GiB limit of a .spatch section: split the scene into tiles")]
    SectionTooLong {
        /// Section tag.
        tag: String,
        /// Bytes it would hold.
        bytes: u64,
    },
    /// A scene would pass the container's u32 patch count.
    #[error(
        "{count} patches pass the 2^32 - 1 limit of a .spatch file: split the scene into tiles"
    )]
    TooManyPatches {
        /// Patches it would hold.
        count: u64,
    },
    /// An internal invariant failed; this is a bug in spatch.
    #[error("internal error (this is a bug in spatch): {0}")]
    Bug(&'static str),
}

/// What is wrong with a section of a `.spatch` file ([`FormatError::Corrupt`]).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Corruption {
    /// Bytes 5..8 of the section header are not zero.
    #[error("reserved header bytes are not zero")]
    ReservedBytes,
    /// A known section appears twice, or before one that must precede it.
    #[error("section repeated or out of order")]
    OutOfOrder,
    /// A section that must be raw (SCNE, FRAM, ORGR, SIDE, OPEN) names a codec.
    #[error("this section must be raw, found codec {0}")]
    NotRaw(u8),
    /// A raw section whose raw length is not its stored length.
    #[error("raw section whose raw length {raw} differs from its stored length {stored}")]
    RawLengthNotStored {
        /// Stored length in the header.
        stored: usize,
        /// Raw length in the header.
        raw: usize,
    },
    /// A node-data section's raw length is not what the frames imply.
    #[error("raw length {found} but the frames need {expected}")]
    RawLength {
        /// Raw length in the header.
        found: usize,
        /// Length the frames (or the filled nodes) imply.
        expected: usize,
    },
    /// A codec-1 section announces more raw bytes than its coded bytes can hold.
    #[error("raw length {raw} is impossible for {stored} coded bytes")]
    Expansion {
        /// Raw length in the header.
        raw: usize,
        /// Stored (coded) length.
        stored: usize,
    },
    /// A CGRX reference (container 1.3) that cannot stand for a grid.
    #[error("patch {patch}'s colour grid refers to patch {source_patch}, but {reason}")]
    GridReference {
        /// The patch whose grid is a reference.
        patch: usize,
        /// The patch it refers to.
        source_patch: u32,
        /// What is wrong.
        reason: &'static str,
    },
    /// The coded stream runs out before the announced raw bytes are decoded.
    #[error("compressed stream ends early")]
    StreamEndsEarly,
    /// A codec number this reader does not know.
    #[error("unknown codec {0}")]
    UnknownCodec(u8),
    /// The payload is not one record of `record` bytes per patch.
    #[error("{bytes} bytes for {count} patches of {record} bytes")]
    RecordCount {
        /// Payload bytes.
        bytes: usize,
        /// Patches in the scene.
        count: usize,
        /// Bytes per patch record.
        record: usize,
    },
    /// The payload is not a whole number of records.
    #[error("{bytes} bytes is not a whole number of {record}-byte records")]
    PartialRecord {
        /// Payload bytes.
        bytes: usize,
        /// Bytes per record.
        record: usize,
    },
    /// The SCNE payload is shorter than its fields.
    #[error("payload is {found} bytes, needs {needed}")]
    Short {
        /// Payload bytes.
        found: usize,
        /// Bytes of the fields.
        needed: usize,
    },
    /// A field holds a value outside its list of codes.
    #[error("unknown {field} {value}")]
    UnknownCode {
        /// The field, e.g. `colour storage`.
        field: &'static str,
        /// The value found.
        value: u8,
    },
    /// The colour channel and the colour storage of SCNE disagree.
    #[error("colour channel and colour storage disagree")]
    ChannelStorage,
    /// A COLR section in a scene without per-node colour.
    #[error("colour section in a scene without per-node colour")]
    UnexpectedColours,
    /// A frame record's displacement width is neither 8 nor 16 bits.
    #[error("patch {patch}: displacement width {bits} bits")]
    Width {
        /// Patch index.
        patch: usize,
        /// The width found.
        bits: u8,
    },
    /// A SIDE code is not one of the known sides (0..=2).
    #[error("patch {patch}: unknown code {code}")]
    SideCode {
        /// Patch index.
        patch: usize,
        /// The code found.
        code: u8,
    },
    /// A patch's stored values are refused (its frame, grid, residual or
    /// node data).
    #[error("patch {patch}: {error}")]
    Patch {
        /// Patch index.
        patch: usize,
        /// Why.
        error: Box<FormatError>,
    },
    /// An opening's stored values are refused.
    #[error("opening {index}: {error}")]
    Opening {
        /// Opening index.
        index: usize,
        /// Why.
        error: Box<FormatError>,
    },
    /// The inside box's stored values are refused.
    #[error("inside box: {0}")]
    InsideBox(Box<FormatError>),
    /// The scene's stored values are refused (its shared grid, its offset).
    #[error("{0}")]
    Scene(Box<FormatError>),
}
