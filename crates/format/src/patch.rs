//! One spatial patch: a frame, a grid of displacements and optional colours.

use glam::{DVec3, Vec3};

use crate::{ColourGrid, FormatError, Frame, GridSize, Sides};

/// The displacement code of an empty node (no surface there).
///
/// In memory every displacement is a `u16`; real codes are `0..=65534`.
/// In a file, 8-bit patches store an empty node as 255 and 16-bit patches as
/// 65535.
pub const EMPTY: u16 = u16::MAX;

/// Width of the stored displacement codes of one patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DisplacementWidth {
    /// One byte per node: codes 0..=254, 255 = empty.
    Bits8,
    /// Two bytes per node (little-endian): codes 0..=65534, 65535 = empty.
    Bits16,
}

impl DisplacementWidth {
    /// Number of bits per stored code.
    pub fn bits(self) -> u8 {
        match self {
            Self::Bits8 => 8,
            Self::Bits16 => 16,
        }
    }

    /// Largest real (non-empty) code.
    pub fn max_code(self) -> u16 {
        match self {
            Self::Bits8 => 254,
            Self::Bits16 => 65534,
        }
    }
}

/// A spatial patch. Node `(i, j)` is `P + i·ax + j·ay + d·az`.
///
/// # Guarantees
/// `displacements.len() == grid.node_count()`; colours, when present, have
/// the same length; the colour of an empty node is `[0, 0, 0, 0]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    frame: Frame,
    grid: GridSize,
    displacements: Vec<u16>,
    colours: Option<Vec<[u8; 4]>>,
    colour_grid: Option<ColourGrid>,
    sides: Sides,
}

impl Patch {
    /// Builds a patch. `displacements` and `colours` are in row-major node
    /// order (`j * cols + i`); [`EMPTY`] marks a node with no surface.
    pub fn new(
        frame: Frame,
        grid: GridSize,
        displacements: Vec<u16>,
        colours: Option<Vec<[u8; 4]>>,
    ) -> Result<Self, FormatError> {
        let expected = grid.node_count();
        let mismatch = |what, found| FormatError::NodeCountMismatch {
            what,
            found,
            expected,
            cols: grid.cols(),
            rows: grid.rows(),
        };
        if displacements.len() != expected {
            return Err(mismatch("displacements", displacements.len()));
        }
        let colours = match colours {
            Some(mut c) => {
                if c.len() != expected {
                    return Err(mismatch("colours", c.len()));
                }
                for (colour, &d) in c.iter_mut().zip(&displacements) {
                    if d == EMPTY {
                        *colour = [0; 4];
                    }
                }
                Some(c)
            }
            None => None,
        };
        Ok(Self {
            frame,
            grid,
            displacements,
            colours,
            colour_grid: None,
            sides: Sides::Front,
        })
    }

    /// The patch with a colour grid finer than its nodes (container 1.2, `CGRD`). The grid
    /// must have been made for this patch's grid size, and the patch must have node colours
    /// (the grid refines them; readers that do not know grids use the nodes').
    pub fn with_colour_grid(mut self, grid: ColourGrid) -> Result<Self, FormatError> {
        let (cols, rows) = ColourGrid::sample_size(self.grid, grid.factor());
        if (grid.cols(), grid.rows()) != (cols, rows) {
            return Err(FormatError::InvalidColourGrid {
                reason: "its size does not match the patch's grid",
            });
        }
        if self.colours.is_none() {
            return Err(FormatError::InvalidColourGrid {
                reason: "the patch has no node colours",
            });
        }
        self.colour_grid = Some(grid);
        Ok(self)
    }

    /// The patch without its colour grid (node colours only).
    #[must_use]
    pub fn without_colour_grid(mut self) -> Self {
        self.colour_grid = None;
        self
    }

    /// The colour grid, if the patch has one ([`ColourGrid`]): albedo finer than its nodes.
    pub fn colour_grid(&self) -> Option<&ColourGrid> {
        self.colour_grid.as_ref()
    }

    pub(crate) fn colour_grid_mut(&mut self) -> Option<&mut ColourGrid> {
        self.colour_grid.as_mut()
    }

    /// The patch with its visible sides set to `sides` (see [`Patch::sides`]).
    #[must_use]
    pub fn with_sides(mut self, sides: Sides) -> Self {
        self.sides = sides;
        self
    }

    /// Which sides of this patch an eye outside the model may see. [`Sides::Front`] (the
    /// default, and every patch of a 1.0 file) lets a renderer cull its back;
    /// [`Sides::ThroughOpenings`] only where no opening of the scene lies between the eye and
    /// the patch; [`Sides::Both`] never. Stored in the `SIDE` section (container 1.1).
    pub fn sides(&self) -> Sides {
        self.sides
    }

    /// The frame.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The grid size.
    pub fn grid(&self) -> GridSize {
        self.grid
    }

    /// Displacement codes in row-major order; [`EMPTY`] marks empty nodes.
    pub fn displacements(&self) -> &[u16] {
        &self.displacements
    }

    /// Per-node colours (RGBA; alpha is 255 in RGB scenes), if the patch has any.
    pub fn colours(&self) -> Option<&[[u8; 4]]> {
        self.colours.as_deref()
    }

    /// Consumes the patch, returning its displacement codes and per-node
    /// colours (as [`Self::displacements`] and [`Self::colours`]), so a
    /// reader that keeps them need not copy them.
    pub fn into_nodes(self) -> (Vec<u16>, Option<Vec<[u8; 4]>>) {
        (self.displacements, self.colours)
    }

    pub(crate) fn colours_mut(&mut self) -> Option<&mut Vec<[u8; 4]>> {
        self.colours.as_mut()
    }

    pub(crate) fn set_frame(&mut self, frame: Frame) {
        self.frame = frame;
    }

    /// The displacement code of node `(i, j)`, or `None` when it is empty.
    pub fn displacement(&self, i: usize, j: usize) -> Option<u16> {
        let d = self.displacements[self.grid.index(i, j)];
        (d != EMPTY).then_some(d)
    }

    /// Number of non-empty nodes.
    pub fn filled_count(&self) -> usize {
        self.displacements.iter().filter(|&&d| d != EMPTY).count()
    }

    /// The narrowest width that stores every code of this patch exactly.
    pub fn displacement_width(&self) -> DisplacementWidth {
        let widest = self
            .displacements
            .iter()
            .filter(|&&d| d != EMPTY)
            .max()
            .copied()
            .unwrap_or(0);
        if widest <= DisplacementWidth::Bits8.max_code() {
            DisplacementWidth::Bits8
        } else {
            DisplacementWidth::Bits16
        }
    }

    /// Position of node `(i, j)` relative to the scene offset, or `None`
    /// when it is empty.
    pub fn node_position(&self, i: usize, j: usize) -> Option<Vec3> {
        let d = self.displacement(i, j)?;
        let [ax, ay, az] = self.frame.axes();
        Some(self.frame.origin() + ax * i as f32 + ay * j as f32 + az * d as f32)
    }

    /// Position of node `(i, j)` relative to the patch origin `P`
    /// (`i·ax + j·ay + d·az`, small whatever the scene's placement), or
    /// `None` when it is empty.
    pub fn node_local(&self, i: usize, j: usize) -> Option<Vec3> {
        let d = self.displacement(i, j)?;
        let [ax, ay, az] = self.frame.axes();
        Some(ax * i as f32 + ay * j as f32 + az * d as f32)
    }

    /// Position of node `(i, j)` relative to the scene offset in f64:
    /// [`Frame::precise_origin`] plus [`Self::node_local`], so a patch far
    /// from the offset (a merged scene's far part) keeps the precision of
    /// its own frame. `None` when the node is empty.
    pub fn precise_node_position(&self, i: usize, j: usize) -> Option<DVec3> {
        Some(self.frame.precise_origin() + self.node_local(i, j)?.as_dvec3())
    }

    /// Model-space position of node `(i, j)` in a scene with offset `offset`:
    /// `(offset + (P + r)) + local` in f64, the exact expression of
    /// docs/format.md §1.1 (what `spatch export` writes). `None` when the node
    /// is empty.
    pub fn model_position(&self, offset: DVec3, i: usize, j: usize) -> Option<DVec3> {
        Some((offset + self.frame.precise_origin()) + self.node_local(i, j)?.as_dvec3())
    }

    /// Positions of all non-empty nodes, in node order, with their `(i, j)`.
    pub fn filled_nodes(&self) -> impl Iterator<Item = (usize, usize, Vec3)> + '_ {
        let [ax, ay, az] = self.frame.axes();
        let origin = self.frame.origin();
        let cols = self.grid.cols() as usize;
        self.displacements
            .iter()
            .enumerate()
            .filter(|(_, &d)| d != EMPTY)
            .map(move |(k, &d)| {
                let (i, j) = (k % cols, k / cols);
                (i, j, origin + ax * i as f32 + ay * j as f32 + az * d as f32)
            })
    }

    /// The surface normal at node `(i, j)`, reconstructed from displacement
    /// differences: central differences along each grid direction where
    /// both neighbours are filled, one-sided where only one is, and no slope
    /// where neither is. Unit length; `None` for an empty node.
    pub fn node_normal(&self, i: usize, j: usize) -> Option<Vec3> {
        let centre = f32::from(self.displacement(i, j)?);
        let (cols, rows) = (usize::from(self.grid.cols()), usize::from(self.grid.rows()));
        let height = |a: usize, b: usize| self.displacement(a, b).map(f32::from);
        // Slope in displacement codes per node step along one grid direction.
        let slope = |before: Option<f32>, after: Option<f32>| match (before, after) {
            (Some(b), Some(a)) => (a - b) * 0.5,
            (Some(b), None) => centre - b,
            (None, Some(a)) => a - centre,
            (None, None) => 0.0,
        };
        let di = slope(
            (i > 0).then(|| height(i - 1, j)).flatten(),
            (i + 1 < cols).then(|| height(i + 1, j)).flatten(),
        );
        let dj = slope(
            (j > 0).then(|| height(i, j - 1)).flatten(),
            (j + 1 < rows).then(|| height(i, j + 1)).flatten(),
        );
        let [ax, ay, az] = self.frame.axes();
        let normal = (ax + az * di).cross(ay + az * dj);
        Some(normal.normalize_or(self.frame.unit_axes()[2]))
    }

    /// True when all four corners of cell `(i, j)` (nodes `i..=i+1`,
    /// `j..=j+1`) are filled, so the cell is drawn.
    pub fn cell_is_drawable(&self, i: usize, j: usize) -> bool {
        let g = self.grid;
        [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)]
            .iter()
            .all(|&(a, b)| self.displacements[g.index(a, b)] != EMPTY)
    }

    /// Axis-aligned bounds `(min, max)` of the filled nodes relative to the
    /// scene offset, or `None` when every node is empty.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.filled_nodes().fold(None, |acc, (_, _, p)| match acc {
            None => Some((p, p)),
            Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
        })
    }
}
