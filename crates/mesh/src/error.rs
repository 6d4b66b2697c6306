//! The error type of this crate and the warnings loaders collect.
//!
//! Errors are split by party at fault: the file ([`MeshError::NonFinite`],
//! [`MeshError::IndexOutOfRange`], syntax problems, ...), the environment ([`MeshError::Io`]),
//! the caller ([`MeshError::InvalidMesh`] from constructors) and this crate
//! ([`MeshError::Internal`], always a bug). Every file error names the file and, where there
//! is one, the element (vertex, face, line) at fault.

use std::fmt;
use std::path::PathBuf;

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

/// What is wrong with a PLY file's structure.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum PlyProblem {
    /// No `vertex` element.
    NoVertexElement,
    /// The vertex element lacks a coordinate property (`x`, `y` or `z`).
    MissingCoordinate {
        /// `'x'`, `'y'` or `'z'`.
        axis: char,
    },
    /// A vertex property that must be a scalar is a list (or the reverse for face indices).
    WrongPropertyShape {
        /// The element.
        element: String,
        /// The property.
        property: String,
    },
    /// The face element has no `vertex_indices` / `vertex_index` list.
    NoFaceIndexList,
    /// A face lists fewer than three vertices.
    FaceTooSmall {
        /// Face index in the file.
        face: u64,
        /// Number of indices it lists.
        len: usize,
    },
    /// A `tristrips` list holds an index past the vertices (or a negative one other than the
    /// `-1` restart).
    StripIndexOutOfRange {
        /// Index of the strip list in the file.
        strip: u64,
        /// The index.
        index: i64,
        /// How many vertices there are.
        vertex_count: u64,
    },
    /// A `range_grid` element without both `obj_info num_cols` and `num_rows` lines.
    RangeGridWithoutSize,
    /// A `range_grid` element whose sample count is not `num_cols × num_rows`.
    RangeGridSize {
        /// `obj_info num_cols`.
        cols: u64,
        /// `obj_info num_rows`.
        rows: u64,
        /// Samples in the element.
        samples: u64,
    },
    /// A `range_grid` sample names a vertex past the vertices (or a negative one).
    RangeGridIndex {
        /// Index of the sample in the grid.
        sample: u64,
        /// The index.
        index: i64,
        /// How many vertices there are.
        vertex_count: u64,
    },
    /// A `range_grid` sample lists more than one vertex.
    RangeGridList {
        /// Index of the sample in the grid.
        sample: u64,
        /// Length of its list.
        len: u64,
    },
}

impl fmt::Display for PlyProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlyProblem::NoVertexElement => f.write_str("PLY has no vertex element"),
            PlyProblem::MissingCoordinate { axis } => {
                write!(f, "PLY vertex element has no '{axis}' property")
            }
            PlyProblem::WrongPropertyShape { element, property } => {
                write!(
                    f,
                    "PLY property {element}.{property} has an unexpected type"
                )
            }
            PlyProblem::NoFaceIndexList => {
                f.write_str("PLY face element has no vertex_indices (or vertex_index) list")
            }
            PlyProblem::FaceTooSmall { face, len } => {
                write!(f, "PLY face {face} has {len} vertices (at least 3 needed)")
            }
            PlyProblem::StripIndexOutOfRange {
                strip,
                index,
                vertex_count,
            } => write!(
                f,
                "PLY triangle strip {strip} refers to vertex {index}, but there are \
                 {vertex_count} vertices"
            ),
            PlyProblem::RangeGridWithoutSize => write!(
                f,
                "PLY range_grid without its size (obj_info num_cols and num_rows lines)"
            ),
            PlyProblem::RangeGridSize {
                cols,
                rows,
                samples,
            } => write!(
                f,
                "PLY range_grid of {samples} samples, but obj_info says {cols} × {rows}"
            ),
            PlyProblem::RangeGridIndex {
                sample,
                index,
                vertex_count,
            } => write!(
                f,
                "PLY range_grid sample {sample} refers to vertex {index}, but there are \
                 {vertex_count} vertices"
            ),
            PlyProblem::RangeGridList { sample, len } => write!(
                f,
                "PLY range_grid sample {sample} lists {len} vertices (0 or 1 expected)"
            ),
        }
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
