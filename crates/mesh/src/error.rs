//! The error type of this crate.
//!
//! Errors are split by party at fault: the file ([`MeshError::NonFinite`],
//! [`MeshError::IndexOutOfRange`], syntax problems, ...), the environment ([`MeshError::Io`]),
//! the caller ([`MeshError::InvalidMesh`] from constructors) and this crate
//! ([`MeshError::Internal`], always a bug). Every file error names the file and, where there
//! is one, the element (vertex, face, line) at fault. The glTF and PLY problems are in
//! `error/`; the warnings loaders collect are in `warning.rs`.

mod gltf_problem;
mod ply_problem;

use std::fmt;
use std::path::PathBuf;

pub use gltf_problem::{BufferProblem, GltfAttribute, GltfProblem};
pub use ply_problem::PlyProblem;

/// Everything that can go wrong loading or building a mesh or point cloud.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The file could not be opened or read.
    #[error("{}: cannot read the file: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// The file name's extension names no format this crate reads.
    #[error(
        "{}: unknown file type (expected .obj, .gltf, .glb, .ply, .off or .stl for meshes; \
         .ply, .xyz, .txt or .pts for point clouds)",
        path.display()
    )]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file holds no bytes (or only whitespace and comments).
    #[error("{}: the file is empty", path.display())]
    EmptyFile {
        /// The file.
        path: PathBuf,
    },
    /// The file holds vertices but no triangles (faces, or glTF triangle primitives).
    #[error("{}: the file has no faces (a point cloud? `spatch from-cloud` converts those)", path.display())]
    NoFaces {
        /// The file.
        path: PathBuf,
    },
    /// The file holds no points (a point cloud with no vertices).
    #[error("{}: the file has no points", path.display())]
    NoPoints {
        /// The file.
        path: PathBuf,
    },
    /// A coordinate, normal, texture coordinate, colour or transform is NaN or infinite.
    #[error("{}: {element} is not finite (NaN or infinity)", path.display())]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Which element holds the value.
        element: Element,
    },
    /// A vertex lies so far from the model's centre that f32 geometry would overflow.
    #[error(
        "{}: vertex {vertex} lies {distance:e} from the model's centre (at most 1e15 is \
         supported: is the file's unit or scale wrong?)",
        path.display()
    )]
    ExtentTooLarge {
        /// The file.
        path: PathBuf,
        /// Index of the farthest vertex (0-based, in file order).
        vertex: u64,
        /// Its largest per-axis distance from the centre of the bounding box.
        distance: f64,
    },
    /// A face refers to a vertex that does not exist.
    #[error(
        "{}: face {face} refers to vertex {index}, but there are {vertex_count} vertices",
        path.display()
    )]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// Index of the face in the file (0-based, before triangulation).
        face: u64,
        /// The offending vertex index as written (after resolving relative OBJ indices).
        index: i64,
        /// How many vertices there are.
        vertex_count: u64,
    },
    /// More elements than 32-bit indices can address.
    #[error("{}: {count} {kind} do not fit in 32-bit indices", path.display())]
    TooManyElements {
        /// The file.
        path: PathBuf,
        /// What kind of element overflowed.
        kind: ElementKind,
        /// How many there were (or would be).
        count: u64,
    },
    /// The glTF reader rejected the file (syntax, validation, missing buffer, ...).
    #[error("{}: not a readable glTF file: {source}", path.display())]
    Gltf {
        /// The file.
        path: PathBuf,
        /// The reader's reason.
        #[source]
        source: gltf::Error,
    },
    /// The glTF file requires an extension that this crate cannot decode (Draco, meshopt,
    /// quantized attributes, ...).
    #[error(
        "{}: the glTF file requires extension {extension}, which spatch cannot decode \
         (re-export the model without it, e.g. with `gltf-transform` or Blender)",
        path.display()
    )]
    GltfExtensionRequired {
        /// The file.
        path: PathBuf,
        /// The extension's name, as written in `extensionsRequired`.
        extension: String,
    },
    /// A glTF buffer's bytes cannot be had.
    #[error("{}: glTF buffer {buffer}: {problem}", path.display())]
    GltfBuffer {
        /// The file.
        path: PathBuf,
        /// Index of the buffer in the file.
        buffer: usize,
        /// What is wrong.
        problem: BufferProblem,
    },
    /// A file reference inside the model (glTF URI, OBJ `mtllib`) points outside the model's
    /// folder, or in a way this crate does not follow.
    #[error("{}: refusing to read {reference:?}: {reason}", path.display())]
    ReferenceOutsideFolder {
        /// The model file.
        path: PathBuf,
        /// The reference as written in the file.
        reference: String,
        /// Why it was refused.
        reason: OutsideReason,
    },
    /// A glTF accessor's data is not what the specification allows for its attribute.
    #[error("{}: mesh {mesh} primitive {primitive}: {problem}", path.display())]
    GltfPrimitive {
        /// The file.
        path: PathBuf,
        /// Index of the mesh in the file.
        mesh: usize,
        /// Index of the primitive in the mesh.
        primitive: usize,
        /// What is wrong.
        problem: GltfProblem,
    },
    /// The PLY reader (ply-rs-bw) rejected the header or body (truncated data, bad numbers,
    /// unknown format line, ...).
    #[error("{}: not a readable PLY file: {reason}", path.display())]
    Ply {
        /// The file.
        path: PathBuf,
        /// The reader's reason on one line (its message is nested over several lines).
        reason: String,
    },
    /// The PLY file parsed but does not describe a mesh or cloud this crate understands.
    #[error("{}: {problem}", path.display())]
    PlyStructure {
        /// The file.
        path: PathBuf,
        /// What is missing or malformed.
        problem: PlyProblem,
    },
    /// A binary STL's triangle count does not match its length (and the file does not start
    /// with `solid`, so it is not ASCII STL either).
    #[error(
        "{}: not a readable STL file: the binary header declares {declared} triangles \
         ({} bytes), but the file holds {length} bytes",
        path.display(),
        84 + 50 * *declared
    )]
    StlLength {
        /// The file.
        path: PathBuf,
        /// The triangle count in the binary header.
        declared: u64,
        /// The file's length in bytes.
        length: u64,
    },
    /// A line of a text format (OFF, XYZ) could not be parsed.
    #[error("{}: line {line}: {problem}", path.display())]
    Syntax {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong on that line.
        problem: SyntaxProblem,
    },
    /// A mesh handed to a constructor breaks an invariant (the caller's fault).
    #[error("invalid mesh: {problem}")]
    InvalidMesh {
        /// The broken invariant.
        problem: MeshProblem,
    },
    /// A texture handed to [`Texture::new`](crate::Texture::new) has the wrong byte count.
    #[error("texture of {width}x{height} needs {expected} RGBA bytes, got {actual}")]
    InvalidTexture {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// `width * height * 4`.
        expected: u64,
        /// Bytes given.
        actual: u64,
    },
}

impl MeshError {
    /// A syntax `problem` at `line` (1-based) of the file at `path`.
    pub(crate) fn syntax(path: &std::path::Path, line: usize, problem: SyntaxProblem) -> Self {
        Self::Syntax {
            path: path.to_path_buf(),
            line,
            problem,
        }
    }
}

/// The element of a file that holds a bad value, as printed in errors (`vertex 17`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Element {
    /// A vertex position (0-based index in the file).
    Vertex(u64),
    /// A vertex normal.
    Normal(u64),
    /// A texture coordinate.
    TexCoord(u64),
    /// A vertex colour.
    Colour(u64),
    /// A glTF node's transform.
    Node(u64),
}

impl fmt::Display for Element {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Element::Vertex(i) => write!(f, "vertex {i}"),
            Element::Normal(i) => write!(f, "normal {i}"),
            Element::TexCoord(i) => write!(f, "texture coordinate {i}"),
            Element::Colour(i) => write!(f, "colour of vertex {i}"),
            Element::Node(i) => write!(f, "the transform of node {i}"),
        }
    }
}

/// A kind of element, for counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ElementKind {
    /// Vertices.
    Vertices,
    /// Triangles (after fanning polygons).
    Triangles,
    /// Materials.
    Materials,
}

impl fmt::Display for ElementKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ElementKind::Vertices => "vertices",
            ElementKind::Triangles => "triangles",
            ElementKind::Materials => "materials",
        })
    }
}

/// Why a reference was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum OutsideReason {
    /// An absolute path (or a `file:` URI, or a Windows drive or share).
    Absolute,
    /// A `..` component.
    ParentComponent,
    /// A URI scheme this crate does not read (`http:`, `https:`, ...).
    UnsupportedScheme,
    /// A percent-encoding that is malformed or decodes to bytes that are not UTF-8.
    BadEncoding,
    /// The reference is empty.
    Empty,
}

impl fmt::Display for OutsideReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            OutsideReason::Absolute => {
                "it is an absolute path (only files in the model's folder are read)"
            }
            OutsideReason::ParentComponent => {
                "it contains '..' (only files in the model's folder are read)"
            }
            OutsideReason::UnsupportedScheme => {
                "its URI scheme is not read (only data: URIs and relative paths)"
            }
            OutsideReason::BadEncoding => "its percent-encoding is malformed",
            OutsideReason::Empty => "it is empty",
        })
    }
}

/// What is wrong on one line of a text file (OFF, XYZ).
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SyntaxProblem {
    /// The OFF header line (`OFF`, `COFF`, `NOFF`, ...) is missing.
    MissingOffHeader,
    /// An OBJ face refers to a texture coordinate or normal that does not exist.
    AttributeIndexOutOfRange {
        /// The index as resolved (0-based).
        index: i64,
        /// How many texture coordinates or normals there are at that point.
        count: u64,
    },
    /// An OBJ face index is zero (OBJ indices start at 1; negative ones count back).
    ZeroIndex,
    /// The binary variant of a text format (`OFF BINARY`), which is not supported.
    BinaryVariant,
    /// The OFF counts line (`vertices faces edges`) is missing or malformed.
    BadOffCounts,
    /// The file ended before all declared elements were read.
    UnexpectedEnd {
        /// What was being read.
        expected: ElementKind,
        /// How many had been read.
        read: u64,
        /// How many were declared.
        declared: u64,
    },
    /// A token is not a number.
    NotANumber {
        /// 1-based column (token) on the line.
        column: usize,
    },
    /// A line has fewer values than its element needs.
    TooFewValues {
        /// Values needed.
        expected: usize,
        /// Values found.
        found: usize,
    },
    /// An XYZ line has a number of columns with no agreed meaning (see the loader's docs).
    UnsupportedColumnCount {
        /// Columns found.
        found: usize,
    },
    /// A face lists fewer than three vertices.
    FaceTooSmall {
        /// Vertices listed.
        len: usize,
    },
    /// An ASCII STL `vertex` or `endloop` outside an `outer loop`.
    StlVertexOutsideLoop,
    /// An ASCII STL ends inside an `outer loop`.
    StlUnclosedLoop,
}

impl fmt::Display for SyntaxProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SyntaxProblem::MissingOffHeader => f.write_str("expected an OFF header line"),
            SyntaxProblem::AttributeIndexOutOfRange { index, count } => write!(
                f,
                "texture coordinate or normal index {index} is out of range ({count} defined)"
            ),
            SyntaxProblem::ZeroIndex => f.write_str("index 0 (OBJ indices start at 1)"),
            SyntaxProblem::BinaryVariant => f.write_str("binary OFF is not supported"),
            SyntaxProblem::BadOffCounts => {
                f.write_str("expected the counts line 'vertices faces edges'")
            }
            SyntaxProblem::UnexpectedEnd {
                expected,
                read,
                declared,
            } => write!(
                f,
                "the file ends after {read} of {declared} declared {expected}"
            ),
            SyntaxProblem::NotANumber { column } => write!(f, "value {column} is not a number"),
            SyntaxProblem::TooFewValues { expected, found } => {
                write!(f, "expected {expected} values, found {found}")
            }
            SyntaxProblem::UnsupportedColumnCount { found } => write!(
                f,
                "{found} columns (expected 3: x y z, 6: x y z r g b or x y z nx ny nz, \
                 7: x y z r g b a, 9: x y z r g b nx ny nz)"
            ),
            SyntaxProblem::FaceTooSmall { len } => {
                write!(f, "a face lists {len} vertices (at least 3 needed)")
            }
            SyntaxProblem::StlVertexOutsideLoop => {
                f.write_str("'vertex' or 'endloop' outside an 'outer loop'")
            }
            SyntaxProblem::StlUnclosedLoop => {
                f.write_str("the file ends inside an 'outer loop' (no 'endloop')")
            }
        }
    }
}

/// An invariant of [`TriangleMesh`](crate::TriangleMesh) that a mesh breaks.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeshProblem {
    /// A triangle refers to a vertex past the end of `positions`.
    IndexOutOfRange {
        /// The face.
        face: u32,
        /// The index.
        index: u32,
        /// `positions.len()`.
        vertex_count: usize,
    },
    /// A position, normal or UV is NaN or infinite.
    NonFinite {
        /// Where.
        element: Element,
    },
    /// A per-vertex or per-face array has the wrong length.
    LengthMismatch {
        /// Which array.
        array: MeshArray,
        /// Its length.
        len: usize,
        /// The length it must have.
        expected: usize,
    },
    /// A face names a material past the end of `materials`.
    MaterialOutOfRange {
        /// The face.
        face: u32,
        /// The material index.
        material: u32,
    },
    /// More vertices or faces than `u32` ids can address.
    TooLarge,
}

/// An array of a [`TriangleMesh`](crate::TriangleMesh), for [`MeshProblem::LengthMismatch`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum MeshArray {
    /// `face_uvs`.
    FaceUvs,
    /// `vertex_colours`.
    VertexColours,
    /// `vertex_normals`.
    VertexNormals,
    /// `face_materials`.
    FaceMaterials,
}

impl fmt::Display for MeshProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshProblem::IndexOutOfRange {
                face,
                index,
                vertex_count,
            } => write!(f, "face {face} refers to vertex {index} of {vertex_count}"),
            MeshProblem::NonFinite { element } => write!(f, "{element} is not finite"),
            MeshProblem::LengthMismatch {
                array,
                len,
                expected,
            } => write!(f, "{array:?} has {len} entries, expected {expected}"),
            MeshProblem::MaterialOutOfRange { face, material } => {
                write!(
                    f,
                    "face {face} names material {material}, which does not exist"
                )
            }
            MeshProblem::TooLarge => f.write_str("more than 2^32 - 1 vertices or faces"),
        }
    }
}
