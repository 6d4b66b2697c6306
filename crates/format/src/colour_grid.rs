//! A patch's colour grid: colour samples finer than its nodes (container 1.2, `CGRD`).
//!
//! A node carries one colour, so per-node colour keeps a texture's detail only down to the
//! node spacing. A colour grid cuts every cell of its patch into `factor × factor` colour
//! cells: sample `(s, t)` lies at grid position `(s / factor, t / factor)` of the patch, so
//! there are `(cols − 1)·factor + 1` samples per row and `(rows − 1)·factor + 1` rows, and
//! sample `(i·factor, j·factor)` sits on node `(i, j)`. A renderer reads the albedo at a point
//! `(x, y)` of the patch (grid units, `0 <= x <= cols − 1`) bilinearly from the four samples
//! around `(x·factor, y·factor)` ([`ColourGrid::albedo_at`]).
//!
//! Samples outside every drawable cell are never read; producers fill them with whatever
//! codes best (a copy of a neighbour).

use crate::{FormatError, GridSize};

/// Colour samples of one patch at `factor` per cell side (module docs).
///
/// # Guarantees
/// `2 <= factor <= MAX_FACTOR`; `samples.len() == sample_cols × sample_rows` of the patch's
/// grid; in an RGB scene every alpha is 255 ([`crate::Scene::new`] sets it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ColourGrid {
    factor: u8,
    cols: usize,
    rows: usize,
    samples: Vec<[u8; 4]>,
}

impl ColourGrid {
    /// Largest number of colour cells per node cell side.
    pub const MAX_FACTOR: u8 = 64;

    /// Samples per row and rows of a colour grid of `factor` over `grid`.
    pub fn sample_size(grid: GridSize, factor: u8) -> (usize, usize) {
        let f = usize::from(factor);
        (
            (usize::from(grid.cols()) - 1) * f + 1,
            (usize::from(grid.rows()) - 1) * f + 1,
        )
    }

    /// A colour grid of `factor` (2..=[`Self::MAX_FACTOR`]) over a patch of `grid`, with its
    /// samples in row-major order (RGBA, straight alpha).
    pub fn new(grid: GridSize, factor: u8, samples: Vec<[u8; 4]>) -> Result<Self, FormatError> {
        if !(2..=Self::MAX_FACTOR).contains(&factor) {
            return Err(FormatError::InvalidColourGrid {
                reason: "the factor must be in 2..=64 colour cells per node cell",
            });
        }
        let (cols, rows) = Self::sample_size(grid, factor);
        if samples.len() != cols * rows {
            return Err(FormatError::NodeCountMismatch {
                what: "colour grid samples",
                found: samples.len(),
                expected: cols * rows,
                cols: grid.cols(),
                rows: grid.rows(),
            });
        }
        Ok(Self {
            factor,
            cols,
            rows,
            samples,
        })
    }

    /// Colour cells per node cell side.
    pub fn factor(&self) -> u8 {
        self.factor
    }

    /// Samples per row.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Rows of samples.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The samples, row-major.
    pub fn samples(&self) -> &[[u8; 4]] {
        &self.samples
    }

    pub(crate) fn samples_mut(&mut self) -> &mut [[u8; 4]] {
        &mut self.samples
    }

    /// The same colours at a coarser `factor` over `grid` (the patch's grid size): each new
    /// sample takes [`Self::albedo_at`] at its position (rounded to bytes) and the alpha of
    /// the nearest old sample. `None` when `factor` is below 2 (the patch then keeps its node
    /// colours only) or not coarser than this grid's.
    pub fn resampled(&self, grid: GridSize, factor: u8) -> Option<ColourGrid> {
        if factor < 2 || factor >= self.factor {
            return None;
        }
        let (cols, rows) = Self::sample_size(grid, factor);
        let f = f32::from(factor);
        let ratio = f32::from(self.factor) / f;
        let mut samples = Vec::new();
        for t in 0..rows {
            for s in 0..cols {
                let [r, g, b] = self.albedo_at(s as f32 / f, t as f32 / f);
                let near_s = ((s as f32 * ratio).round() as usize).min(self.cols - 1);
                let near_t = ((t as f32 * ratio).round() as usize).min(self.rows - 1);
                let alpha = self.samples[near_t * self.cols + near_s][3];
                let byte = |v: f32| v.round().clamp(0.0, 255.0) as u8;
                samples.push([byte(r), byte(g), byte(b), alpha]);
            }
        }
        ColourGrid::new(grid, factor, samples).ok()
    }

    /// Number of orientations of a grid of samples (the symmetries of a square).
    pub const ORIENTATIONS: u8 = 8;

    /// This grid turned or mirrored by `orientation` (0..[`Self::ORIENTATIONS`]; higher bits
    /// are ignored): sample `(s, t)` of the result is this grid's sample `(u, v)` where
    /// `(u, v) = (t, s)` when bit 2 is set, else `(s, t)`, then `u` is mirrored
    /// (`cols − 1 − u`) when bit 0 is set and `v` (`rows − 1 − v`) when bit 1 is
    /// (docs/format.md §6.7). With bit 2 the result is `rows` samples wide and `cols` tall.
    pub fn oriented(&self, orientation: u8) -> ColourGrid {
        let transpose = orientation & 4 != 0;
        let (cols, rows) = if transpose {
            (self.rows, self.cols)
        } else {
            (self.cols, self.rows)
        };
        let mut samples = Vec::new();
        for t in 0..rows {
            for s in 0..cols {
                let (mut u, mut v) = if transpose { (t, s) } else { (s, t) };
                if orientation & 1 != 0 {
                    u = self.cols - 1 - u;
                }
                if orientation & 2 != 0 {
                    v = self.rows - 1 - v;
                }
                samples.push(self.samples[v * self.cols + u]);
            }
        }
        ColourGrid {
            factor: self.factor,
            cols,
            rows,
            samples,
        }
    }

    /// The albedo (RGB in 0..=255) at patch grid position `(x, y)`: the samples around
    /// `(x·factor, y·factor)` interpolated bilinearly. Positions outside the grid are clamped
    /// to it. Always inlined: a renderer calls it per pixel from code
    /// compiled for the CPU at hand.
    #[inline(always)]
    pub fn albedo_at(&self, x: f32, y: f32) -> [f32; 3] {
        let f = f32::from(self.factor);
        let last = [(self.cols - 1) as f32, (self.rows - 1) as f32];
        let (u, v) = ((x * f).clamp(0.0, last[0]), (y * f).clamp(0.0, last[1]));
        let (s, t) = (
            (u as usize).min(self.cols.saturating_sub(2)),
            (v as usize).min(self.rows.saturating_sub(2)),
        );
        let (a, b) = (u - s as f32, v - t as f32);
        let k = t * self.cols + s;
        let [c00, c10, c01, c11] = [
            self.samples[k],
            self.samples[k + 1],
            self.samples[k + self.cols],
            self.samples[k + self.cols + 1],
        ];
        std::array::from_fn(|ch| {
            let top = f32::from(c00[ch]) * (1.0 - a) + f32::from(c10[ch]) * a;
            let bottom = f32::from(c01[ch]) * (1.0 - a) + f32::from(c11[ch]) * a;
            top * (1.0 - b) + bottom * b
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_follow_the_factor_and_interpolate_between_neighbours() {
        let grid = GridSize::new(3, 2).unwrap();
        assert_eq!(ColourGrid::sample_size(grid, 4), (9, 5));
        let samples: Vec<[u8; 4]> = (0..45).map(|k| [(k % 9) as u8 * 10, 0, 0, 255]).collect();
        let g = ColourGrid::new(grid, 4, samples).unwrap();
        // Node (1, 0) is sample (4, 0); a quarter cell further is sample 5.
        assert_eq!(g.albedo_at(1.0, 0.0)[0], 40.0);
        assert_eq!(g.albedo_at(1.125, 0.5)[0], 45.0);
        assert_eq!(g.albedo_at(2.0, 1.0)[0], 80.0);
        assert_eq!(g.albedo_at(9.0, -1.0)[0], 80.0);
        let coarse = g.resampled(grid, 2).unwrap();
        assert_eq!((coarse.cols(), coarse.rows()), (5, 3));
        assert_eq!(coarse.albedo_at(1.25, 0.5)[0], 50.0);
        assert!(g.resampled(grid, 4).is_none() && g.resampled(grid, 1).is_none());
        assert!(ColourGrid::new(grid, 1, vec![[0; 4]; 6]).is_err());
        assert!(ColourGrid::new(grid, 4, vec![[0; 4]; 44]).is_err());
    }

    #[test]
    fn the_eight_orientations_are_distinct_and_invert() {
        let grid = GridSize::new(3, 2).unwrap();
        let samples: Vec<[u8; 4]> = (0..15).map(|k| [k as u8, 0, 0, 255]).collect();
        let g = ColourGrid::new(grid, 2, samples).unwrap();
        let turned: Vec<ColourGrid> = (0..8).map(|o| g.oriented(o)).collect();
        for (o, a) in turned.iter().enumerate() {
            for b in &turned[o + 1..] {
                assert_ne!(a, b);
            }
        }
        // Transposed: 3 wide, 5 tall; sample (s, t) is the source's (t, s).
        let t = g.oriented(4);
        assert_eq!((t.cols(), t.rows()), (3, 5));
        assert_eq!(t.samples()[3 + 2][0], g.samples()[2 * 5 + 1][0]);
        // Mirrors are their own inverse; the transpose too.
        for o in [0, 1, 2, 3, 4] {
            assert_eq!(g.oriented(o).oriented(o), g);
        }
        // A quarter turn (mirror then transpose) four times is the identity.
        let quarter = |x: &ColourGrid| x.oriented(1).oriented(4);
        assert_eq!(quarter(&quarter(&quarter(&quarter(&g)))), g);
    }
}
