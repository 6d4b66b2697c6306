//! Spatial patches and the `.spatch` container.
//!
//! A spatial patch is a small range image of a piece of surface: a [`Frame`]
//! (origin and three orthogonal axes whose lengths are the node spacing and the
//! displacement step) and a grid of nodes, each a displacement along the frame's
//! z axis and, when the scene has colour, a colour. A [`Scene`] is a set of
//! patches with no connectivity, placed in model space by an `f64` offset.
//!
//! Node `(i, j)` of a patch is the point `P + i·ax + j·ay + d[i][j]·az`.
//!
//! The container (`.spatch`, see `docs/format.md`) is written by
//! [`write_scene`] / [`encode_scene`] and read by [`read_scene`] /
//! [`decode_scene`].
//!
//! ```
//! use glam::Vec3;
//! use spatch_format::{
//!     decode_scene, encode_scene, ColourChannel, Frame, GridSize, Patch, Scene, WriteOptions,
//! };
//!
//! let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01)?;
//! let grid = GridSize::new(3, 3)?;
//! let patch = Patch::new(frame, grid, vec![0; 9], None)?;
//! let scene = Scene::new(glam::DVec3::ZERO, ColourChannel::None, vec![patch])?;
//! let bytes = encode_scene(&scene, &WriteOptions::default())?;
//! assert_eq!(decode_scene(&bytes)?, scene);
//! # Ok::<(), spatch_format::FormatError>(())
//! ```
#![forbid(unsafe_code)]

mod axes;
mod colour_grid;
mod container;
mod error;
mod frame;
mod grid;
mod patch;
mod quantize;
mod scene;
mod sides;
mod summary;

pub use colour_grid::ColourGrid;
pub use container::{
    abandon_pending_writes, colour_grid_section_len, decode_scene, encode_scene, inspect,
    read_container_bytes, read_scene, write_file_atomically, write_file_atomically_with,
    write_scene, Compression, ContainerInfo, MergeWriter, SectionInfo, WriteOptions, MAGIC,
    VERSION_MAJOR, VERSION_MINOR,
};
pub use error::{Corruption, FormatError};
pub use frame::{Frame, ORTHOGONALITY_TOLERANCE};
pub use grid::GridSize;
pub use patch::{DisplacementWidth, Patch, EMPTY};
pub use quantize::{Quantizer, QuantizerPolicy};
pub use scene::{ColourChannel, MergeError, Scene};
pub use sides::{InsideBox, Opening, Sides};
pub use summary::{Range, SceneSummary};
