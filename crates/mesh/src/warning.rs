//! The warnings loaders collect: what they noticed and worked around.

use std::fmt;
use std::path::PathBuf;

/// Something a loader noticed and worked around; the mesh is still usable.
///
/// Callers (the CLI) show these to the user; nothing here is printed by the library.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum LoadWarning {
    /// The OBJ names a material library that could not be read; the model has no colour.
    MissingMaterialLibrary {
        /// The library as named in the OBJ.
        path: PathBuf,
        /// Why it could not be read (the reader's message).
        reason: String,
    },
    /// A texture file could not be found or decoded; that material keeps its base colour.
    TextureUnreadable {
        /// The texture file.
        path: PathBuf,
        /// Why (the decoder's message).
        reason: String,
    },
    /// An OBJ with texture coordinates but no material library: a lone image beside it
    /// (named like the OBJ, or `*_texture.*`) was taken as its texture.
    TextureGuessed {
        /// The image used.
        path: PathBuf,
    },
    /// An MTL texture option this crate does not apply (`-s`, `-o`, `-blendu`, ...).
    TextureOptionIgnored {
        /// The material.
        material: String,
        /// The option as written (for example `-s 2 2 1`).
        option: String,
    },
    /// A face uses a material that no library defines; it is drawn white.
    UnknownMaterial {
        /// The material's name, when known.
        name: String,
    },
    /// A material's transparency was ignored (spatch stores opaque colours); kept so a
    /// `Tr 1.0` written by MeshLab as "opaque" never makes a model invisible.
    TransparencyIgnored {
        /// The material.
        material: String,
    },
    /// Polygons with more than three vertices were split into triangles (convex ones as a fan
    /// from their first corner, others by ear clipping in their plane).
    PolygonsTriangulated {
        /// How many polygons.
        count: u64,
    },
    /// Polygons that cross or touch themselves: some of their triangles overlap.
    PolygonsNotSimple {
        /// How many polygons.
        count: u64,
    },
    /// glTF primitives that are not triangles (points, lines) were skipped.
    NonTrianglePrimitivesSkipped {
        /// How many primitives.
        count: u64,
    },
    /// Some faces have texture coordinates and others do not; the others get `(0, 0)`.
    PartialTexCoords {
        /// Faces without texture coordinates.
        faces_without: u64,
    },
    /// Vertex normals were dropped because only some vertices had them (or counts differed).
    NormalsDropped,
    /// Vertex colours were dropped because only some vertices had them.
    ColoursDropped,
}

impl fmt::Display for LoadWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadWarning::MissingMaterialLibrary { path, reason } => write!(
                f,
                "material library {} could not be read ({reason}); the model has no colour",
                path.display()
            ),
            LoadWarning::TextureUnreadable { path, reason } => write!(
                f,
                "texture {} could not be read ({reason}); its material keeps a flat colour",
                path.display()
            ),
            LoadWarning::TextureGuessed { path } => write!(
                f,
                "no material library; using {} beside the model as its texture",
                path.display()
            ),
            LoadWarning::TextureOptionIgnored { material, option } => write!(
                f,
                "material {material}: texture option '{option}' is not supported and was ignored"
            ),
            LoadWarning::UnknownMaterial { name } => {
                write!(f, "material '{name}' is not defined; its faces are white")
            }
            LoadWarning::TransparencyIgnored { material } => write!(
                f,
                "material {material}: transparency ignored (colours are stored opaque)"
            ),
            LoadWarning::PolygonsTriangulated { count } => {
                write!(
                    f,
                    "{count} polygons with more than 3 vertices were split into triangles"
                )
            }
            LoadWarning::PolygonsNotSimple { count } => write!(
                f,
                "{count} polygons cross or touch themselves; some of their triangles overlap"
            ),
            LoadWarning::NonTrianglePrimitivesSkipped { count } => {
                write!(f, "{count} point or line primitives were skipped")
            }
            LoadWarning::PartialTexCoords { faces_without } => write!(
                f,
                "{faces_without} faces have no texture coordinates and use (0, 0)"
            ),
            LoadWarning::NormalsDropped => {
                f.write_str("vertex normals were incomplete and were dropped")
            }
            LoadWarning::ColoursDropped => {
                f.write_str("vertex colours were incomplete and were dropped")
            }
        }
    }
}
