//! Decoding container bytes into a [`Scene`]: the file split into sections
//! (`sections`), then one reader per section, in the order of docs/format.md
//! §10: SCNE here, FRAM and ORGR (`read_frames`), DISP and COLR
//! (`read_nodes`), SIDE and OPEN (`read_sides`).
//!
//! Every count read from the file is checked against the bytes that hold it
//! before anything is allocated for it; every section's CRC is checked before
//! its payload is parsed; nothing here panics on any input. Each refusal is a
//! [`FormatError`] naming the section, with a typed [`crate::Corruption`].

use std::path::Path;

use glam::DVec3;

use super::colour_grids::read_colour_grids;
use super::layout::{
    ColourStorage, SceneFields, TAG_COLOURS, TAG_COLOUR_GRIDS, TAG_DISPLACEMENTS, TAG_FRAMES,
    TAG_INSIDE_BOX, TAG_OPENINGS, TAG_ORIGIN_RESIDUALS, TAG_SCENE, TAG_SHARED_COLOUR_GRIDS,
    TAG_SIDES,
};
use super::read_frames::{read_frames, read_residuals};
use super::read_nodes::{read_colours, read_displacements, ColourSource};
use super::read_sides::{read_inside_box, read_openings, read_sides};
pub use super::sections::SectionInfo;
use super::sections::{corrupt, require_raw, split_sections, RawSection};
use super::shared_colour_grids::read_shared_colour_grids;
use crate::{
    ColourChannel, ColourGrid, Corruption, FormatError, Frame, GridSize, InsideBox, Opening, Patch,
    Scene, Sides,
};

/// What a file holds besides the scene itself (for `spatch stats`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ContainerInfo {
    /// Major version in the header.
    pub version_major: u8,
    /// Minor version in the header.
    pub version_minor: u8,
    /// Every section, in file order, including ones this reader skipped.
    pub sections: Vec<SectionInfo>,
    /// Total file length.
    pub file_len: usize,
    /// Whether the scene stores one flat colour instead of per-node colours.
    pub flat_colour: bool,
}

/// The sections this reader knows, each found at most once and in this order.
struct Known<'s, 'a> {
    scene: &'s RawSection<'a>,
    frames: &'s RawSection<'a>,
    displacements: &'s RawSection<'a>,
    colours: Option<&'s RawSection<'a>>,
    residuals: Option<&'s RawSection<'a>>,
    sides: Option<&'s RawSection<'a>>,
    openings: Option<&'s RawSection<'a>>,
    inside_box: Option<&'s RawSection<'a>>,
    colour_grids: Option<&'s RawSection<'a>>,
    shared_colour_grids: Option<&'s RawSection<'a>>,
}

/// The known tags in the order a file must hold them.
const KNOWN_TAGS: [[u8; 4]; 10] = [
    TAG_SCENE,
    TAG_FRAMES,
    TAG_DISPLACEMENTS,
    TAG_COLOURS,
    TAG_ORIGIN_RESIDUALS,
    TAG_SIDES,
    TAG_OPENINGS,
    TAG_INSIDE_BOX,
    TAG_COLOUR_GRIDS,
    TAG_SHARED_COLOUR_GRIDS,
];

/// Finds the known sections, refusing a repeated or out-of-order one and a
/// missing required one; sections with other tags (a later minor version's)
/// are skipped.
fn find_known<'s, 'a>(sections: &'s [RawSection<'a>]) -> Result<Known<'s, 'a>, FormatError> {
    let mut found: [Option<&'s RawSection<'a>>; 10] = [None; 10];
    let mut last = None;
    for section in sections {
        let Some(k) = KNOWN_TAGS
            .iter()
            .position(|t| t[..] == *section.info.tag.as_bytes())
        else {
            continue;
        };
        if found[k].is_some() || last.is_some_and(|l| l >= k) {
            return Err(section.corrupt(Corruption::OutOfOrder));
        }
        found[k] = Some(section);
        last = Some(k);
    }
    let [scene, frames, displacements, colours, residuals, sides, openings, inside_box, colour_grids, shared_colour_grids] =
        found;
    if let (Some(_), Some(shared)) = (colour_grids, shared_colour_grids) {
        return Err(shared.corrupt(Corruption::OutOfOrder));
    }
    Ok(Known {
        scene: scene.ok_or(FormatError::MissingSection("SCNE"))?,
        frames: frames.ok_or(FormatError::MissingSection("FRAM"))?,
        displacements: displacements.ok_or(FormatError::MissingSection("DISP"))?,
        colours,
        residuals,
        sides,
        openings,
        inside_box,
        colour_grids,
        shared_colour_grids,
    })
}

/// The checked SCNE fields: raw, the first 40 bytes in range.
fn read_scene_fields(section: &RawSection<'_>) -> Result<SceneFields, FormatError> {
    require_raw(section)?;
    SceneFields::from_bytes(section.payload).map_err(|kind| section.corrupt(kind))
}

/// Decodes `.spatch` bytes, returning the scene and what the file holds.
pub fn inspect(bytes: &[u8]) -> Result<(Scene, ContainerInfo), FormatError> {
    let split = split_sections(bytes)?;
    let known = find_known(&split.sections)?;
    let fields = read_scene_fields(known.scene)?;
    let channel = colour_channel(fields.channel);
    let patch_count = fields.patch_count as usize;
    let residuals = read_residuals(known.residuals, patch_count)?;
    let records = read_frames(known.frames, &fields, known.residuals.zip(residuals))?;
    let codes = read_displacements(known.displacements, &records.layouts)?;
    let bytes_per_colour = channel.bytes_per_node();
    let node_colours = read_colours(known.colours, &fields, bytes_per_colour, codes.filled)?;
    let visibility = read_visibility(&known, patch_count)?;
    let sizes: Vec<_> = records.frames.iter().map(|(_, g)| *g).collect();
    let grids = read_grids(&known, &sizes, bytes_per_colour)?;
    let patches = assemble_patches(PatchParts {
        frames: records.frames,
        codes: codes.per_patch,
        colours: ColourSource::new(&fields, node_colours.as_deref(), bytes_per_colour),
        sides: visibility.sides.as_deref(),
        grids,
        displacements: known.displacements,
    })?;
    let scene = Scene::new(DVec3::from_array(fields.offset), channel, patches)
        .map_err(|e| corrupt("SCNE", Corruption::Scene(Box::new(e))))?
        .with_openings(visibility.openings)
        .with_inside_box(visibility.inside_box);
    let info = ContainerInfo {
        version_major: split.major,
        version_minor: split.minor,
        sections: split.sections.into_iter().map(|s| s.info).collect(),
        file_len: bytes.len(),
        flat_colour: fields.colour_storage == ColourStorage::Flat,
    };
    Ok((scene, info))
}

/// The colour channel of SCNE's channel code.
fn colour_channel(code: u8) -> ColourChannel {
    match code {
        0 => ColourChannel::None,
        1 => ColourChannel::Rgb8,
        _ => ColourChannel::Rgba8,
    }
}

/// Which sides of the patches may show: SIDE, OPEN and the inside box, each optional.
struct Visibility {
    sides: Option<Vec<Sides>>,
    openings: Vec<Opening>,
    inside_box: Option<InsideBox>,
}

/// Reads SIDE (one entry per patch), OPEN and the inside box, in that order.
fn read_visibility(known: &Known<'_, '_>, patch_count: usize) -> Result<Visibility, FormatError> {
    let sides = match known.sides {
        Some(section) => Some(read_sides(section, patch_count)?),
        None => None,
    };
    let openings = match known.openings {
        Some(section) => read_openings(section)?,
        None => Vec::new(),
    };
    let inside_box = known.inside_box.map(read_inside_box).transpose()?;
    Ok(Visibility {
        sides,
        openings,
        inside_box,
    })
}

/// The patches' colour grids, one entry per patch, and the tag of the section they
/// came from (named by a refused grid's error).
struct PatchGrids {
    grids: std::vec::IntoIter<Option<ColourGrid>>,
    tag: &'static str,
}

/// Reads CGRD or CGRX (a file holds at most one), or no grid for any patch.
fn read_grids(
    known: &Known<'_, '_>,
    sizes: &[GridSize],
    bytes_per_colour: usize,
) -> Result<PatchGrids, FormatError> {
    let tag = if known.shared_colour_grids.is_some() {
        "CGRX"
    } else {
        "CGRD"
    };
    let grids = match (known.colour_grids, known.shared_colour_grids) {
        (Some(section), _) => read_colour_grids(section, sizes, bytes_per_colour)?,
        (None, Some(section)) => read_shared_colour_grids(section, sizes, bytes_per_colour)?,
        (None, None) => Vec::new(),
    }
    .into_iter();
    Ok(PatchGrids { grids, tag })
}

/// Everything read for the patches, in file order, before they are joined.
struct PatchParts<'p, 'a> {
    frames: Vec<(Frame, GridSize)>,
    codes: Vec<Vec<u16>>,
    colours: ColourSource<'p>,
    sides: Option<&'p [Sides]>,
    grids: PatchGrids,
    /// DISP, named by a refused patch's error.
    displacements: &'p RawSection<'a>,
}

/// Joins each patch's frame, grid, codes, colours, colour grid and sides into patches.
fn assemble_patches(parts: PatchParts<'_, '_>) -> Result<Vec<Patch>, FormatError> {
    let PatchParts {
        frames,
        codes,
        mut colours,
        sides,
        mut grids,
        displacements,
    } = parts;
    let mut patches = Vec::new();
    for (k, ((frame, grid), codes)) in frames.into_iter().zip(codes).enumerate() {
        let patch_colours = colours.next_patch(&codes);
        let side = sides.map_or(Sides::Front, |s| s[k]);
        let patch = Patch::new(frame, grid, codes, patch_colours).map_err(|e| {
            displacements.corrupt(Corruption::Patch {
                patch: k,
                error: Box::new(e),
            })
        })?;
        let patch = match grids.grids.next().flatten() {
            Some(g) => patch.with_colour_grid(g).map_err(|e| {
                corrupt(
                    grids.tag,
                    Corruption::Patch {
                        patch: k,
                        error: Box::new(e),
                    },
                )
            })?,
            None => patch,
        };
        patches.push(patch.with_sides(side));
    }
    Ok(patches)
}

/// Decodes `.spatch` bytes into a scene.
pub fn decode_scene(bytes: &[u8]) -> Result<Scene, FormatError> {
    inspect(bytes).map(|(scene, _)| scene)
}

/// Reads and decodes a `.spatch` file.
pub fn read_scene(path: &Path) -> Result<Scene, FormatError> {
    let bytes = std::fs::read(path).map_err(|source| FormatError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_scene(&bytes)
}
