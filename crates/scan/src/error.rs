//! The error type of this crate.
//!
//! Split by party at fault: the files ([`ScanError::Conf`], [`ScanError::Mesh`] for the scans
//! the mesh crate reads, the LAS and E57 readers' refusals, ...), the caller
//! ([`ScanError::NoInputs`], [`ScanError::ColumnSpec`]), the environment ([`ScanError::Io`])
//! and this crate ([`ScanError::Bug`]). Every file error names the file.

use std::fmt;
use std::path::PathBuf;

use spatch_mesh::MeshError;

use crate::PoseProblem;

/// Everything that can go wrong reading scans.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScanError {
    /// A file could not be opened or read.
    #[error("{}: cannot read the file: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        #[source]
        source: std::io::Error,
    },
    /// A scan read by the mesh crate's loaders (PLY, XYZ, PTS) was refused; the message names
    /// the file.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// A line of a `.conf` pose file is malformed.
    #[error("{}: line {line}: {problem}", path.display())]
    Conf {
        /// The pose file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        problem: ConfProblem,
    },
    /// A `.conf` pose file lists no scan (`bmesh` line).
    #[error("{}: the pose file lists no scans (no `bmesh FILE ...` line)", path.display())]
    NoScans {
        /// The pose file.
        path: PathBuf,
    },
    /// A pose file names a scan through another pose file.
    #[error("{}: a scan set cannot list another scan set ({})", path.display(), nested.display())]
    NestedScanSet {
        /// The pose file.
        path: PathBuf,
        /// The scan-set file it names.
        nested: PathBuf,
    },
    /// The LAS/LAZ reader refused the file (bad signature, header, VLRs or compressed data).
    #[error("{}: not a readable LAS/LAZ file: {source}", path.display())]
    Las {
        /// The file.
        path: PathBuf,
        /// The `las` crate's reason (its message includes the cause, so it is not chained).
        source: Box<las::Error>,
    },
    /// The E57 reader refused the file (bad header, XML, checksum or binary section).
    /// A LAS header whose sizes the `las` crate's own arithmetic overflows on: point
    /// records ending past the largest file offset, or a header size smaller than the
    /// version's fields.
    #[error(
        "{}: not a readable LAS/LAZ file: its header sizes are impossible ({points} points \
         of {record_len} bytes after byte {offset}, or a header shorter than its version's)",
        path.display()
    )]
    LasSize {
        /// The file.
        path: PathBuf,
        /// Points the header declares.
        points: u64,
        /// Bytes per point record.
        record_len: u16,
        /// Offset of the point data.
        offset: u32,
    },
    /// A LAS 1.4 extended variable-length record reaches past the end of the file.
    #[error(
        "{}: an extended variable-length record at byte {start} declares {length} bytes, \
         past the end of the {file_len}-byte file",
        path.display()
    )]
    LasExtendedRecord {
        /// The file.
        path: PathBuf,
        /// Where the record starts.
        start: u64,
        /// Bytes the record declares after its 60-byte header.
        length: u64,
        /// The file's length.
        file_len: u64,
    },
    /// The E57 reader refused the file.
    #[error("{}: not a readable E57 file: {source}", path.display())]
    E57 {
        /// The file.
        path: PathBuf,
        /// The `e57` crate's reason.
        source: Box<e57::Error>,
    },
    /// An E57 scan's pose is not a rigid transform (a NaN, or a zero quaternion).
    #[error("{}: scan `{scan}`: {problem}", path.display())]
    BadScanPose {
        /// The file.
        path: PathBuf,
        /// The scan's name in the file (empty when it has none).
        scan: String,
        /// What is wrong.
        problem: PoseProblem,
    },
    /// The file ends before the points its header declares.
    #[error("{}: the file is truncated: {read} of {declared} declared points read", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Points the header declares.
        declared: u64,
        /// Points present.
        read: u64,
    },
    /// The file holds no (valid) points.
    #[error("{}: the file has no points", path.display())]
    NoPoints {
        /// The file.
        path: PathBuf,
    },
    /// The file name's extension names no format this crate (or the mesh crate) reads.
    #[error(
        "{}: unknown point cloud type (expected .ply, .xyz, .txt, .pts, .las, .laz, .e57 \
         or a .conf scan set)",
        path.display()
    )]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
    },
    /// Together the inputs hold more points than 32-bit point ids can address.
    #[error("{count} points in all: more than spatch can index (4294967294)")]
    TooManyPoints {
        /// Points read so far.
        count: u64,
    },
    /// No input file was given.
    #[error("no input files")]
    NoInputs,
    /// A `--columns` layout could not be understood.
    #[error("column layout `{spec}`: {problem}")]
    ColumnSpec {
        /// The layout as given.
        spec: String,
        /// What is wrong with it.
        problem: ColumnSpecProblem,
    },
    /// An internal invariant failed: this is a bug in spatch-scan.
    #[error("internal error in spatch-scan (this is a bug): {0}")]
    Bug(String),
}

/// What is wrong with a line of a `.conf` file.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ConfProblem {
    /// The line starts with a keyword other than `camera`, `bmesh` or `mesh`.
    UnknownKeyword {
        /// The keyword (at most 40 characters of it).
        keyword: String,
    },
    /// A `bmesh` line without its file name.
    MissingFile,
    /// A pose does not have its seven values `tx ty tz qx qy qz qw`.
    PoseValues {
        /// Values found.
        found: usize,
    },
    /// A pose value is not a number.
    NotANumber {
        /// 1-based position among the seven values.
        value: usize,
    },
    /// The values name no rigid pose.
    BadPose(PoseProblem),
}

impl fmt::Display for ConfProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConfProblem::UnknownKeyword { keyword } => write!(
                f,
                "unknown keyword `{keyword}` (expected camera, bmesh or mesh)"
            ),
            ConfProblem::MissingFile => write!(f, "the scan file name is missing"),
            ConfProblem::PoseValues { found } => write!(
                f,
                "expected 7 pose values (tx ty tz qx qy qz qw), found {found}"
            ),
            ConfProblem::NotANumber { value } => write!(f, "pose value {value} is not a number"),
            ConfProblem::BadPose(problem) => write!(f, "{problem}"),
        }
    }
}

/// What is wrong with a `--columns` layout.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ColumnSpecProblem {
    /// A name that is not a column kind.
    UnknownName {
        /// The name as given.
        name: String,
    },
    /// A column kind named twice (only `skip` may repeat).
    Repeated {
        /// The name as given.
        name: String,
    },
    /// `x`, `y` or `z` is missing, or only some of a group (`nx ny nz`, `r g b`) are named.
    Incomplete {
        /// What is missing, e.g. `z` or `g`.
        missing: &'static str,
    },
}

impl fmt::Display for ColumnSpecProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ColumnSpecProblem::UnknownName { name } => write!(
                f,
                "unknown column `{name}` (expected x, y, z, nx, ny, nz, r, g, b, a, \
                 intensity or skip)"
            ),
            ColumnSpecProblem::Repeated { name } => write!(f, "column `{name}` appears twice"),
            ColumnSpecProblem::Incomplete { missing } => {
                write!(f, "column `{missing}` is missing")
            }
        }
    }
}
