//! Merging scenes into one file with memory bounded by one input: [`MergeWriter`].
//!
//! Each pushed scene is moved into the first one's offset (as [`Scene::merge`] does) and
//! its patches' bytes are appended to one scratch file per section (FRAM with every
//! optional field, DISP, COLR, ORGR, SIDE); then the scene is dropped. What SCNE says and
//! which optional sections exist depend on every patch, so the file is written at the
//! end, section by section from the scratch files (compressed then, patch by patch, when
//! asked). The bytes are those of [`super::encode_scene`] on the scene [`Scene::merge`]
//! returns: both choose through the same `SceneShape` and per-patch record functions.

use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};

use glam::DVec3;

use super::layout::{
    ColourStorage, GridStorage, SceneFields, WidthStorage, CODEC_PREDICTIVE, CODEC_RAW, FRAME_LEN,
    TAG_COLOURS, TAG_DISPLACEMENTS, TAG_FRAMES, TAG_INSIDE_BOX, TAG_OPENINGS, TAG_ORIGIN_RESIDUALS,
    TAG_SCENE, TAG_SHARED_COLOUR_GRIDS, TAG_SIDES,
};
use super::predictive::{ColourEncoder, DisplacementEncoder};
use super::records::{
    file_header, inside_box_payload, layout_of_full_record, openings_payload, push_colours,
    push_displacements, push_frame_record, push_residual, section_header, FULL_FRAME_LEN,
};
use super::scratch::Scratch;
use super::shape::SceneShape;
use super::shared_colour_grids::shared_grids_section;
use super::{write_file_atomically_with, Compression, WriteOptions};
use crate::scene::{rebase_opening, rebase_patch, InsideBoxes};
use crate::{ColourChannel, ColourGrid, FormatError, MergeError, Opening, Scene};

/// Writes the merge of scenes given one at a time: memory holds one input scene and
/// small buffers; the output's sections wait in scratch files (about the output's size
/// on disk, removed when the writer is dropped).
///
/// ```
/// # use spatch_format::*;
/// # let frame = Frame::new(glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y, glam::Vec3::Z)?;
/// # let patch = Patch::new(frame, GridSize::new(2, 2)?, vec![0; 4], None)?;
/// # let scene = Scene::new(glam::DVec3::ZERO, ColourChannel::None, vec![patch])?;
/// let far = scene.clone().translated(glam::DVec3::X * 1e7)?;
/// let mut writer = MergeWriter::new(&std::env::temp_dir(), WriteOptions::default())?;
/// writer.push(scene.clone())?;
/// writer.push(far.clone())?;
/// let mut bytes = Vec::new();
/// writer.write_to(&mut bytes)?;
/// let merged = Scene::merge(vec![scene, far])?;
/// assert_eq!(bytes, encode_scene(&merged, &WriteOptions::default())?);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct MergeWriter {
    options: WriteOptions,
    folder: PathBuf,
    base: Option<(DVec3, ColourChannel)>,
    scenes: usize,
    shape: SceneShape,
    frames: Scratch,
    displacements: Scratch,
    colours: Scratch,
    residuals: Scratch,
    sides: Scratch,
    openings: Vec<Opening>,
    /// The inside boxes pushed so far ([`Scene::merge`]'s rule).
    inside: InsideBoxes,
    /// Patches pushed so far.
    patch_count: usize,
    /// The colour grids of the patches that have one, by patch index (kept in memory:
    /// CGRX is coded as a whole at the end).
    colour_grids: Vec<(usize, ColourGrid)>,
}

/// Where a section's payload comes from when the file is written.
enum Payload {
    Bytes(Vec<u8>),
    File(Scratch),
    /// Full FRAM records cut to the file's record layout.
    Frames {
        records: Scratch,
        grid: bool,
        width: bool,
    },
}

/// A section ready to write: its 20 header bytes and its payload.
struct Section {
    header: [u8; 20],
    payload: Payload,
}

impl MergeWriter {
    /// A writer whose scratch files go in `folder` (the output's folder is a good choice:
    /// it needs about the output's size).
    pub fn new(folder: &Path, options: WriteOptions) -> Result<Self, FormatError> {
        let scratch = || {
            Scratch::new(folder).map_err(|source| FormatError::Io {
                path: folder.to_path_buf(),
                source,
            })
        };
        Ok(Self {
            options,
            folder: folder.to_path_buf(),
            base: None,
            scenes: 0,
            shape: SceneShape::new(),
            frames: scratch()?,
            displacements: scratch()?,
            colours: scratch()?,
            residuals: scratch()?,
            sides: scratch()?,
            openings: Vec::new(),
            inside: InsideBoxes::default(),
            patch_count: 0,
            colour_grids: Vec::new(),
        })
    }

    /// Appends a scene's patches and openings, placed relative to the first scene's
    /// offset at full precision (see [`Scene::merge`]). Scenes must share the first
    /// one's colour channel.
    pub fn push(&mut self, scene: Scene) -> Result<(), MergeError> {
        let (offset, channel) = *self.base.get_or_insert((scene.offset(), scene.channel()));
        if scene.channel() != channel {
            return Err(MergeError::ChannelMismatch {
                index: self.scenes,
                expected: channel,
                found: scene.channel(),
            });
        }
        self.scenes += 1;
        let shift = scene.offset() - offset;
        self.inside.add(&scene, shift)?;
        for opening in scene.openings() {
            self.openings
                .push(rebase_opening(opening, shift).map_err(MergeError::Format)?);
        }
        let colour_bytes = channel.bytes_per_node();
        let mut buffers: [Vec<u8>; 5] = Default::default();
        for patch in scene.into_patches() {
            let patch = rebase_patch(patch, shift).map_err(MergeError::Format)?;
            self.shape.add(&patch);
            let [frames, displacements, colours, residuals, sides] = &mut buffers;
            push_frame_record(
                frames,
                &patch,
                GridStorage::PerPatch,
                WidthStorage::PerPatch,
            );
            push_displacements(displacements, &patch);
            if colour_bytes > 0 {
                push_colours(colours, &patch, colour_bytes).map_err(MergeError::Format)?;
            }
            push_residual(residuals, &patch);
            sides.push(patch.sides().code());
            if let Some(grid) = patch.colour_grid() {
                self.colour_grids.push((self.patch_count, grid.clone()));
            }
            self.patch_count += 1;
        }
        self.append(&buffers).map_err(MergeError::Format)
    }

    /// Appends one scene's section bytes to the scratch files.
    fn append(&mut self, buffers: &[Vec<u8>; 5]) -> Result<(), FormatError> {
        let scratches = [
            &mut self.frames,
            &mut self.displacements,
            &mut self.colours,
            &mut self.residuals,
            &mut self.sides,
        ];
        for (scratch, bytes) in scratches.into_iter().zip(buffers) {
            scratch.append(bytes).map_err(|source| FormatError::Io {
                path: self.folder.clone(),
                source,
            })?;
        }
        if self.displacements.len() > u64::from(u32::MAX) {
            return Err(FormatError::SectionTooLong {
                tag: "DISP".into(),
                bytes: self.displacements.len(),
            });
        }
        Ok(())
    }

    /// Writes the merged scene to `path` atomically; returns its size in bytes.
    pub fn write_to_file(self, path: &Path) -> Result<u64, FormatError> {
        let mut sections = self.into_sections()?;
        let total = file_len(&sections);
        write_file_atomically_with(path, |out| write_sections(&mut sections, out))?;
        Ok(total)
    }

    /// Writes the merged scene into `out`; returns its size in bytes.
    pub fn write_to(self, out: &mut dyn Write) -> Result<u64, FormatError> {
        let folder = self.folder.clone();
        let mut sections = self.into_sections()?;
        let total = file_len(&sections);
        write_sections(&mut sections, out).map_err(|source| FormatError::Io {
            path: folder,
            source,
        })?;
        Ok(total)
    }

    /// Every section of the file, headers computed, in file order. Errors (a section
    /// past u32, a failing disk) come here, before any byte of the output is written.
    fn into_sections(self) -> Result<Vec<Section>, FormatError> {
        let (offset, channel) = self.base.ok_or(FormatError::Bug("merge of no scene"))?;
        let fields = self.shape.fields(offset.to_array(), channel)?;
        let Self {
            options,
            folder,
            shape,
            frames,
            displacements,
            colours,
            residuals,
            sides,
            openings,
            inside,
            patch_count,
            colour_grids,
            base: _,
            scenes: _,
        } = self;
        let compress = options.compression == Compression::Predictive;
        let mut payloads = vec![(
            TAG_SCENE,
            CODEC_RAW,
            0,
            Payload::Bytes(fields.to_bytes().to_vec()),
        )];
        let node_data = NodeData {
            frames,
            displacements,
            colours,
        };
        payloads.extend(node_data.payloads(&fields, channel, compress, &folder)?);
        let tail = Tail {
            shape,
            residuals,
            sides,
            openings,
            inside,
            patch_count,
            colour_grids,
        };
        payloads.extend(tail.payloads(channel.bytes_per_node()));
        let sections = payloads
            .into_iter()
            .map(|(tag, codec, raw, payload)| section(tag, codec, raw, payload, &folder))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(sections)
    }
}

/// A section before its header is computed: tag, codec, raw length (0: the stored length)
/// and payload.
type PendingSection = ([u8; 4], u8, u64, Payload);

/// The scratch files of the node data: full FRAM records, DISP and COLR.
struct NodeData {
    frames: Scratch,
    displacements: Scratch,
    colours: Scratch,
}

impl NodeData {
    /// FRAM, DISP and (when the colours are per node) COLR, in file order; DISP and COLR
    /// coded when `compress` asks and it makes them smaller.
    fn payloads(
        mut self,
        fields: &SceneFields,
        channel: ColourChannel,
        compress: bool,
        folder: &Path,
    ) -> Result<Vec<PendingSection>, FormatError> {
        let io_error = |source| FormatError::Io {
            path: folder.to_path_buf(),
            source,
        };
        let displacements = if compress {
            let coded = code_displacements(&mut self.frames, &mut self.displacements, folder)
                .map_err(io_error)?;
            smaller(self.displacements, coded)
        } else {
            (
                CODEC_RAW,
                self.displacements.len(),
                Payload::File(self.displacements),
            )
        };
        let colours = if fields.colour_storage != ColourStorage::PerNode {
            None
        } else if compress {
            let coded = code_colours(&mut self.colours, channel.bytes_per_node(), folder)
                .map_err(io_error)?;
            Some(smaller(self.colours, coded))
        } else {
            Some((CODEC_RAW, self.colours.len(), Payload::File(self.colours)))
        };
        let frames = Payload::Frames {
            records: self.frames,
            grid: fields.grid_storage == GridStorage::PerPatch,
            width: fields.width_storage == WidthStorage::PerPatch,
        };
        let (codec, raw, payload) = displacements;
        let mut payloads = vec![
            (TAG_FRAMES, CODEC_RAW, 0, frames),
            (TAG_DISPLACEMENTS, codec, raw, payload),
        ];
        if let Some((codec, raw, payload)) = colours {
            payloads.push((TAG_COLOURS, codec, raw, payload));
        }
        Ok(payloads)
    }
}

/// What the sections after the node data are made of.
struct Tail {
    shape: SceneShape,
    residuals: Scratch,
    sides: Scratch,
    openings: Vec<Opening>,
    inside: InsideBoxes,
    patch_count: usize,
    colour_grids: Vec<(usize, ColourGrid)>,
}

impl Tail {
    /// The optional sections the scene has (ORGR, SIDE, OPEN, IBOX, CGRX), in file order;
    /// `bytes_per_node` is the colour channel's.
    fn payloads(self, bytes_per_node: usize) -> Vec<PendingSection> {
        let mut payloads = Vec::new();
        if self.shape.has_residuals() {
            payloads.push((
                TAG_ORIGIN_RESIDUALS,
                CODEC_RAW,
                0,
                Payload::File(self.residuals),
            ));
        }
        if self.shape.has_sides() {
            payloads.push((TAG_SIDES, CODEC_RAW, 0, Payload::File(self.sides)));
        }
        if !self.openings.is_empty() {
            let bytes = openings_payload(&self.openings);
            payloads.push((TAG_OPENINGS, CODEC_RAW, 0, Payload::Bytes(bytes)));
        }
        if let Some(b) = self.inside.merged() {
            let bytes = inside_box_payload(&b);
            payloads.push((TAG_INSIDE_BOX, CODEC_RAW, 0, Payload::Bytes(bytes)));
        }
        if !self.colour_grids.is_empty() {
            let mut grids: Vec<Option<&ColourGrid>> = vec![None; self.patch_count];
            for (k, grid) in &self.colour_grids {
                grids[*k] = Some(grid);
            }
            let (codec, raw, bytes) = shared_grids_section(&grids, bytes_per_node);
            payloads.push((
                TAG_SHARED_COLOUR_GRIDS,
                codec,
                raw as u64,
                Payload::Bytes(bytes),
            ));
        }
        payloads
    }
}

/// The raw payload, or the coded one when it is smaller (codec 1), as `encode_scene`
/// chooses: `(codec, raw length, payload)`.
fn smaller(raw: Scratch, coded: Scratch) -> (u8, u64, Payload) {
    let raw_len = raw.len();
    if raw_len > 0 && coded.len() < raw_len {
        (CODEC_PREDICTIVE, raw_len, Payload::File(coded))
    } else {
        (CODEC_RAW, raw_len, Payload::File(raw))
    }
}

/// A section's header for `payload` (`raw_len` 0: the stored length), its CRC computed by
/// reading the payload once.
fn section(
    tag: [u8; 4],
    codec: u8,
    raw_len: u64,
    mut payload: Payload,
    folder: &Path,
) -> Result<Section, FormatError> {
    let mut sink = CrcSink::default();
    write_payload(&mut payload, &mut sink).map_err(|source| FormatError::Io {
        path: folder.to_path_buf(),
        source,
    })?;
    let raw_len = if codec == CODEC_RAW {
        sink.len
    } else {
        raw_len
    };
    let first = section_header(tag, codec, sink.len, raw_len)?;
    let mut crc = crc32fast::Hasher::new();
    crc.update(&first);
    crc.combine(&sink.crc);
    let mut header = [0u8; 20];
    header[..16].copy_from_slice(&first);
    header[16..].copy_from_slice(&crc.finalize().to_le_bytes());
    Ok(Section { header, payload })
}

/// The file's size: its header and every section.
fn file_len(sections: &[Section]) -> u64 {
    let payloads: u64 = sections
        .iter()
        .map(|s| {
            u64::from(u32::from_le_bytes([
                s.header[8],
                s.header[9],
                s.header[10],
                s.header[11],
            ]))
        })
        .sum();
    16 + 20 * sections.len() as u64 + payloads
}

/// Writes the file: its header, then every section's header and payload.
fn write_sections(sections: &mut [Section], out: &mut dyn Write) -> io::Result<()> {
    let tags: Vec<[u8; 4]> = sections
        .iter()
        .map(|s| [s.header[0], s.header[1], s.header[2], s.header[3]])
        .collect();
    out.write_all(&file_header(sections.len() as u32, super::minor_for(&tags)))?;
    for section in sections {
        out.write_all(&section.header)?;
        write_payload(&mut section.payload, out)?;
    }
    out.flush()
}

/// Writes a section's payload.
fn write_payload(payload: &mut Payload, out: &mut dyn Write) -> io::Result<()> {
    match payload {
        Payload::Bytes(bytes) => out.write_all(bytes),
        Payload::File(scratch) => scratch.copy_to(out),
        Payload::Frames {
            records,
            grid,
            width,
        } => {
            let mut reader = records.reader()?;
            let mut record = [0u8; FULL_FRAME_LEN];
            for _ in 0..records.len() / FULL_FRAME_LEN as u64 {
                reader.read_exact(&mut record)?;
                out.write_all(&record[..FRAME_LEN])?;
                if *grid {
                    out.write_all(&record[FRAME_LEN..FRAME_LEN + 4])?;
                }
                if *width {
                    out.write_all(&record[FRAME_LEN + 4..])?;
                }
            }
            Ok(())
        }
    }
}

/// Codes the DISP scratch patch by patch (layouts from the full FRAM records).
fn code_displacements(
    frames: &mut Scratch,
    raw: &mut Scratch,
    folder: &Path,
) -> io::Result<Scratch> {
    let (mut records, mut codes) = (frames.reader()?, raw.reader()?);
    let mut coded = Scratch::new(folder)?;
    let mut encoder = DisplacementEncoder::new();
    let mut record = [0u8; FULL_FRAME_LEN];
    let mut patch = Vec::new();
    for _ in 0..frames.len() / FULL_FRAME_LEN as u64 {
        records.read_exact(&mut record)?;
        let layout = layout_of_full_record(&record);
        patch.resize(layout.raw_len(), 0);
        codes.read_exact(&mut patch)?;
        encoder.push_patch(&patch, &layout);
        coded.append(&encoder.take_output())?;
    }
    coded.append(&encoder.finish())?;
    Ok(coded)
}

/// Codes the COLR scratch in pieces of whole colours.
fn code_colours(raw: &mut Scratch, bytes_per_node: usize, folder: &Path) -> io::Result<Scratch> {
    let mut reader = raw.reader()?;
    let mut coded = Scratch::new(folder)?;
    let mut encoder = ColourEncoder::new(bytes_per_node);
    let mut piece = vec![0u8; bytes_per_node << 14];
    let mut left = raw.len();
    while left > 0 {
        let n = piece.len().min(left as usize);
        reader.read_exact(&mut piece[..n])?;
        encoder.push(&piece[..n]);
        coded.append(&encoder.take_output())?;
        left -= n as u64;
    }
    coded.append(&encoder.finish())?;
    Ok(coded)
}

/// A writer that keeps only the CRC-32 and the length of what it is given.
#[derive(Default)]
struct CrcSink {
    crc: crc32fast::Hasher,
    len: u64,
}

impl Write for CrcSink {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.crc.update(bytes);
        self.len += bytes.len() as u64;
        Ok(bytes.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}
