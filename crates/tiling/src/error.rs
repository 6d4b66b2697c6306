//! The one error type of the crate.

use std::path::PathBuf;

/// Why a plan, a tile's points or an index could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TilingError {
    /// The file system refused.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The input is not a readable point file.
    #[error("{}: {reason}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The file ends before the points it declares.
    #[error("{}: truncated: {read} of {declared} points", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// Points the header declares.
        declared: u64,
        /// Points read.
        read: u64,
    },
    /// The extension names no point format this crate streams.
    #[error("{}: cannot stream this format (PLY, LAS, LAZ, XYZ, TXT, PTS, E57 and .conf scan sets can be)", path.display())]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
    },
    /// The input holds no finite point.
    #[error("{}: no finite point", path.display())]
    NoPoints {
        /// The file.
        path: PathBuf,
    },
    /// A scan file's reader refused it (the message names the file).
    #[error(transparent)]
    Scan(#[from] spatch_scan::ScanError),
    /// A plan or index option is out of range.
    #[error("invalid {option}: {reason}")]
    InvalidOption {
        /// The option.
        option: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A plan or index file is not what this version writes.
    #[error("{}: {reason}", path.display())]
    BadJson {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// The tile asked for is not in the plan.
    #[error("tile {tile} is not in the plan (it has {tiles} tiles)")]
    NoSuchTile {
        /// The index asked for.
        tile: usize,
        /// Tiles the plan has.
        tiles: usize,
    },
}

impl TilingError {
    /// An I/O error on `path`.
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> TilingError {
        TilingError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// A malformed-input error on `path`.
    pub(crate) fn malformed(path: &std::path::Path, reason: impl Into<String>) -> TilingError {
        TilingError::Malformed {
            path: path.to_path_buf(),
            reason: reason.into(),
        }
    }
}
