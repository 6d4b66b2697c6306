//! What can be wrong in a PLY file's structure, as carried by
//! [`MeshError`](crate::MeshError).

use std::fmt;

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
