//! What can be wrong in a glTF file's structure and buffers, as carried by
//! [`MeshError`](crate::MeshError).

use std::fmt;

/// What is wrong with a glTF buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum BufferProblem {
    /// No URI, and no GLB binary chunk left to fill it.
    NoData,
    /// A `data:` URI whose payload is not valid base64.
    BadDataUri,
    /// Fewer bytes than its `byteLength`.
    TooShort {
        /// `byteLength`.
        declared: usize,
        /// Bytes read.
        actual: usize,
    },
}

impl fmt::Display for BufferProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BufferProblem::NoData => f.write_str("it has no URI and there is no GLB binary chunk"),
            BufferProblem::BadDataUri => f.write_str("its data: URI is not valid base64"),
            BufferProblem::TooShort { declared, actual } => {
                write!(f, "it declares {declared} bytes but holds {actual}")
            }
        }
    }
}

/// What is wrong with a glTF primitive's data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum GltfProblem {
    /// The primitive has no `POSITION` attribute.
    NoPositions,
    /// An attribute's accessor has a different count than `POSITION`.
    AttributeCountMismatch {
        /// Which attribute.
        attribute: GltfAttribute,
        /// Its count.
        count: usize,
        /// The `POSITION` count.
        expected: usize,
    },
    /// An accessor's element type, component type, count or byte range is invalid for its
    /// attribute (or reaches past its buffer).
    BadAccessor {
        /// Which attribute.
        attribute: GltfAttribute,
    },
    /// An index is not below the vertex count.
    IndexOutOfRange {
        /// The index.
        index: u32,
        /// The vertex count.
        vertex_count: usize,
    },
    /// An attribute or the index list names an accessor the file does not have.
    MissingAccessor {
        /// Which attribute.
        attribute: GltfAttribute,
        /// The accessor index as written.
        index: usize,
        /// How many accessors there are.
        accessor_count: usize,
    },
}

/// A glTF vertex attribute, for [`GltfProblem`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum GltfAttribute {
    /// `POSITION`.
    Position,
    /// The index accessor.
    Indices,
    /// `NORMAL`.
    Normal,
    /// `TEXCOORD_n` of the base colour texture.
    TexCoord,
    /// `COLOR_0`.
    Colour,
}

impl fmt::Display for GltfAttribute {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            GltfAttribute::Position => "POSITION",
            GltfAttribute::Indices => "index",
            GltfAttribute::Normal => "NORMAL",
            GltfAttribute::TexCoord => "TEXCOORD",
            GltfAttribute::Colour => "COLOR_0",
        })
    }
}

impl fmt::Display for GltfProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GltfProblem::NoPositions => f.write_str("no POSITION attribute"),
            GltfProblem::AttributeCountMismatch {
                attribute,
                count,
                expected,
            } => write!(
                f,
                "{} has {count} values for {expected} positions",
                attribute
            ),
            GltfProblem::BadAccessor { attribute } => write!(
                f,
                "the {attribute} accessor has a type, count or range the specification forbids"
            ),
            GltfProblem::IndexOutOfRange {
                index,
                vertex_count,
            } => write!(f, "index {index} is out of range ({vertex_count} vertices)"),
            GltfProblem::MissingAccessor {
                attribute,
                index,
                accessor_count,
            } => write!(
                f,
                "the {attribute} attribute names accessor {index}, but there are \
                 {accessor_count} accessors"
            ),
        }
    }
}
