//! Export of spatch scenes to the formats other tools open: PLY, OBJ and
//! glTF 2.0 (`.gltf` or `.glb`).
//!
//! - [`extract_patch_meshes`]: per patch, either every filled node as a
//!   point, or the drawable cells as one welded triangle mesh (nodes shared
//!   by the cells that use them), with unit normals (reconstructed from
//!   displacement differences, [`spatch_format::Patch::node_normal`]) and
//!   colours when the scene has them. Vertices are relative to the patch's
//!   own f64 origin, so nothing is lost far from the model origin.
//! - [`export_scene`]: writes them in a [`Format`], positions shifted by
//!   [`ExportOptions::origin`] (recorded in the file when not zero). PLY
//!   writes `double` positions when `float` would lose more than 1e-5 of a
//!   median patch ([`PositionType`]); OBJ writes f64 text; glTF places each
//!   patch by an f64 node translation.
//! - [`encode_depth_tiff`]: a rendered depth image as a float TIFF
//!   (`spatch render --depth-format tiff`).
//! - [`encode_depth_exr`]: the same depth as an OpenEXR file with one float
//!   channel `Z` (`spatch render --depth-format exr`).
//!
//! ```
//! use spatch_export::{export_scene, Content, ExportOptions, Format};
//!
//! let scene = spatch_sphere::build_sphere(&Default::default())?.scene;
//! let options = ExportOptions::new(Format::Glb, Content::Cells);
//! let exported = export_scene(&scene, &options)?;
//! assert!(exported.bytes.starts_with(b"glTF"));
//! assert_eq!(exported.meshes, scene.patches().len());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod depth_exr;
mod depth_tiff;
mod float_depth;
mod gltf_writer;
mod obj;
mod patch_mesh;
mod ply;
mod precision;

use std::path::Path;

use glam::DVec3;
use spatch_format::{ColourChannel, Scene};

pub use depth_exr::{encode_depth_exr, DEPTH_EXR_CHANNEL};
pub use depth_tiff::encode_depth_tiff;
pub use gltf_writer::{write_glb, write_gltf};
pub use obj::write_obj;
pub use patch_mesh::{extract_patch_meshes, Content, PatchMesh};
pub use ply::write_ply;
pub use precision::{needs_f64, PositionType, F32_TOLERANCE};

/// A file format to export to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Format {
    /// Binary little-endian PLY.
    Ply,
    /// Wavefront OBJ (text).
    Obj,
    /// glTF 2.0 JSON with an embedded buffer.
    Gltf,
    /// glTF 2.0 binary container.
    Glb,
}

impl Format {
    /// The format a file name's extension names (case-insensitive), if any.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "ply" => Some(Self::Ply),
            "obj" => Some(Self::Obj),
            "gltf" => Some(Self::Gltf),
            "glb" => Some(Self::Glb),
            _ => None,
        }
    }

    /// `"ply"`, `"obj"`, `"gltf"` or `"glb"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Ply => "ply",
            Self::Obj => "obj",
            Self::Gltf => "gltf",
            Self::Glb => "glb",
        }
    }
}

/// What [`export_scene`] writes and how.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct ExportOptions {
    /// The file format.
    pub format: Format,
    /// Points or cells. Default: [`Content::Nodes`].
    pub content: Content,
    /// Model-space point subtracted from every position (f64), recorded in
    /// the file when not zero (PLY and OBJ comments, glTF
    /// `asset.extras.origin`). Default: zero. Choose one near the model to
    /// get full f32 precision in tools that read f32 only.
    pub origin: DVec3,
    /// PLY position type. Default: [`PositionType::Auto`]; OBJ and glTF
    /// ignore it (OBJ is f64 text, glTF f32 relative to f64 translations).
    pub positions: PositionType,
}

impl ExportOptions {
    /// Options for `format` and `content`, with the other defaults.
    pub fn new(format: Format, content: Content) -> Self {
        Self {
            format,
            content,
            origin: DVec3::ZERO,
            positions: PositionType::Auto,
        }
    }
}

/// An exported file and what it holds.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Exported {
    /// The file's bytes.
    pub bytes: Vec<u8>,
    /// Meshes (or point sets), one per patch with something to export.
    pub meshes: usize,
    /// Vertices in all meshes.
    pub vertices: usize,
    /// Triangles in all meshes (0 for points).
    pub triangles: usize,
    /// Whether positions were written as f64 (PLY `double`, OBJ text).
    pub f64_positions: bool,
}

/// Why a scene could not be exported.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportError {
    /// The origin shift is not finite.
    #[error("the export origin is not a finite point")]
    InvalidOrigin,
    /// A depth image's size does not match its values.
    #[error("a {width} x {height} depth image cannot hold {values} values")]
    DepthSize {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Values given.
        values: usize,
    },
    /// The TIFF encoder failed (a bug: it writes to memory).
    #[error("TIFF encoding failed (this is a bug): {0}")]
    Tiff(String),
    /// The EXR encoder failed (a bug: it writes to memory).
    #[error("EXR encoding failed (this is a bug): {0}")]
    Exr(String),
    /// The output would exceed a limit of the format.
    #[error("the {format} output would exceed the format's limit of {limit}")]
    TooLarge {
        /// The format's name.
        format: &'static str,
        /// The limit, in words.
        limit: &'static str,
    },
}

/// Writes `scene` as `options` say (see the crate overview).
pub fn export_scene(scene: &Scene, options: &ExportOptions) -> Result<Exported, ExportError> {
    if !options.origin.is_finite() {
        return Err(ExportError::InvalidOrigin);
    }
    let meshes = extract_patch_meshes(scene, options.content);
    let vertices: usize = meshes.iter().map(|m| m.positions.len()).sum();
    let triangles: usize = meshes.iter().map(|m| m.triangles.len()).sum();
    let faces = options.content == Content::Cells;
    let coloured = scene.channel() != ColourChannel::None;
    let origin = options.origin;
    let (bytes, f64_positions) = match options.format {
        Format::Ply => {
            if i32::try_from(vertices).is_err() {
                return Err(ExportError::TooLarge {
                    format: "ply",
                    limit: "2^31 vertices",
                });
            }
            let doubles = needs_f64(&meshes, origin, options.positions);
            (
                write_ply(&meshes, coloured, doubles, origin, faces),
                doubles,
            )
        }
        Format::Obj => (write_obj(&meshes, origin, faces), true),
        Format::Gltf | Format::Glb => {
            let rgba = scene.channel() == ColourChannel::Rgba8;
            let bytes = if options.format == Format::Gltf {
                write_gltf(&meshes, rgba, origin, faces)
            } else {
                write_glb(&meshes, rgba, origin, faces)?
            };
            (bytes, false)
        }
    };
    Ok(Exported {
        bytes,
        meshes: meshes.len(),
        vertices,
        triangles,
        f64_positions,
    })
}
