//! Grid dimensions of a patch.

use crate::FormatError;

/// The number of nodes of a patch along its x axis (`cols`) and y axis
/// (`rows`).
///
/// # Guarantees
/// Each side is in 2..=257 (so a patch always has at least one cell, and a
/// 2^k + 1 grid halves evenly down a mip pyramid).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct GridSize {
    cols: u16,
    rows: u16,
}

impl GridSize {
    /// Smallest allowed side.
    pub const MIN_SIDE: u32 = 2;
    /// Largest allowed side.
    pub const MAX_SIDE: u32 = 257;

    /// A grid of `cols × rows` nodes; each side must be in 2..=257.
    pub fn new(cols: u32, rows: u32) -> Result<Self, FormatError> {
        let ok = |s: u32| (Self::MIN_SIDE..=Self::MAX_SIDE).contains(&s);
        if ok(cols) && ok(rows) {
            Ok(Self {
                cols: cols as u16,
                rows: rows as u16,
            })
        } else {
            Err(FormatError::InvalidGrid { cols, rows })
        }
    }

    /// Nodes along the x axis.
    pub fn cols(self) -> u16 {
        self.cols
    }

    /// Nodes along the y axis.
    pub fn rows(self) -> u16 {
        self.rows
    }

    /// Total number of nodes.
    pub fn node_count(self) -> usize {
        self.cols as usize * self.rows as usize
    }

    /// Index of node `(i, j)` in row-major order (`j * cols + i`).
    pub fn index(self, i: usize, j: usize) -> usize {
        j * self.cols as usize + i
    }
}

impl std::fmt::Display for GridSize {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.cols, self.rows)
    }
}
