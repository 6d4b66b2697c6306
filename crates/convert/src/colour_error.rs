//! How far a coarser colour grid is from the grid the fitter sampled.
//!
//! The error of a grid of factor `f'` against the fitted grid of factor `f` (both over the
//! same patch) is the RMS difference, in levels of 255 over the three colour channels, between
//! every fitted sample and the coarser grid read bilinearly at that sample's position: what
//! the renderer would show at the fitted grid's resolution. A patch without a grid shows its
//! node colours, bilinearly between nodes; [`node_colour_error`] measures that.
//!
//! Cost: O(samples of the fitted grid) per comparison.

use spatch_format::{ColourGrid, Patch};

/// Squared differences summed over colour channels of samples, in levels of 255.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SquaredError {
    sum: f64,
    count: usize,
}

impl SquaredError {
    /// The root mean square (0 over no sample).
    pub(crate) fn rms(self) -> f64 {
        (self.sum / self.count.max(1) as f64).sqrt()
    }
}

impl std::ops::AddAssign for SquaredError {
    fn add_assign(&mut self, other: Self) {
        self.sum += other.sum;
        self.count += other.count;
    }
}

/// Error of `coarse` against `fitted`, over `fitted`'s samples.
pub(crate) fn grid_error(fitted: &ColourGrid, coarse: &ColourGrid) -> SquaredError {
    error_against(fitted, |x, y| coarse.albedo_at(x, y))
}

/// Error of `patch`'s node colours, read bilinearly, against `fitted` (as black when the
/// patch has none).
pub(crate) fn node_colour_error(patch: &Patch, fitted: &ColourGrid) -> SquaredError {
    let Some(colours) = patch.colours() else {
        return error_against(fitted, |_, _| [0.0; 3]);
    };
    let grid = patch.grid();
    let (cols, rows) = (grid.cols() as usize, grid.rows() as usize);
    let at = |i: usize, j: usize, ch: usize| f32::from(colours[j * cols + i][ch]);
    error_against(fitted, |x, y| {
        let (i, j) = (
            (x as usize).min(cols.saturating_sub(2)),
            (y as usize).min(rows.saturating_sub(2)),
        );
        let (a, b) = (x - i as f32, y - j as f32);
        std::array::from_fn(|ch| {
            let top = at(i, j, ch) * (1.0 - a) + at(i + 1, j, ch) * a;
            let bottom = at(i, j + 1, ch) * (1.0 - a) + at(i + 1, j + 1, ch) * a;
            top * (1.0 - b) + bottom * b
        })
    })
}

/// Error over `fitted`'s samples of `shown` at their patch positions.
fn error_against(fitted: &ColourGrid, shown: impl Fn(f32, f32) -> [f32; 3]) -> SquaredError {
    let f = f32::from(fitted.factor());
    let cols = fitted.cols();
    let mut sum = 0.0f64;
    for (k, sample) in fitted.samples().iter().enumerate() {
        let (s, t) = (k % cols, k / cols);
        let got = shown(s as f32 / f, t as f32 / f);
        for ch in 0..3 {
            let d = f64::from(got[ch] - f32::from(sample[ch]));
            sum += d * d;
        }
    }
    SquaredError {
        sum,
        count: 3 * fitted.samples().len(),
    }
}
