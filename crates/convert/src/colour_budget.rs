//! Holding the colour grids to a byte budget.
//!
//! The fitter gives each textured patch a colour grid at the texture's own resolution
//! (`spatch_fit::FitOptions::colour_grid_texels`); how many bytes that costs is known only
//! once the grids are coded (flat colours code to almost nothing, photographs do not). So the
//! pipeline first lets patches that show the same picture share one grid
//! ([`crate::grid_sharing`], stored once by the container), then codes the grid section
//! ([`colour_grid_section_len`]) and, while it exceeds the
//! budget, lowers the largest factor by a quarter (at least one) and resamples every grid
//! above it ([`ColourGrid::resampled`], rounded again to the fitter's step,
//! [`spatch_fit::COLOUR_GRID_STEP`]); below a factor of 2 a patch keeps its node colours
//! only, and the grids are shared again. The finest grids give up detail first.
//!
//! Cost: one coding of the grids per round; the factor drops geometrically, so at most about
//! 15 rounds from 64.

use serde::Serialize;
use spatch_fit::quantize_sample;
use spatch_format::{colour_grid_section_len, ColourChannel, ColourGrid, Patch};

use crate::grid_sharing::share_colour_grids;

/// How many bytes the colour grids may take.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum ColourBudget {
    /// At most this many times the bytes of the file without colour grids (`>= 0`), but at
    /// least [`ColourBudget::MIN_SCALED_BYTES`] when the scale is above 0.
    Scale(f32),
    /// At most this many bytes of CGRD section.
    Bytes(u64),
}

impl ColourBudget {
    /// Default scale: the grids may add 1 × the file without them (issue 22's target is
    /// at most 4 × the texture-blind bytes; the node spacing's texture budget takes the
    /// other 2 ×).
    pub const DEFAULT_SCALE: f32 = 1.0;
    /// The least a [`ColourBudget::Scale`] above 0 allows: 4 KiB. Why: a scale starves small
    /// files (the 12-triangle textured box is 1,552 bytes without grids, and its logo needs
    /// about 2-4 KB of grid to reach 30 dB: 33.3 dB in 5,554 bytes, against 27.9 dB with
    /// 1,497 bytes of grid), while 4 KiB is noise for anything larger (fuze's 1x is 89 KB).
    pub const MIN_SCALED_BYTES: usize = 4096;

    /// The budget in bytes for a file of `base` bytes without grids.
    pub fn bytes(self, base: usize) -> usize {
        match self {
            ColourBudget::Scale(k) if k > 0.0 => {
                ((f64::from(k) * base as f64) as usize).max(Self::MIN_SCALED_BYTES)
            }
            ColourBudget::Scale(_) => 0,
            ColourBudget::Bytes(b) => usize::try_from(b).unwrap_or(usize::MAX),
        }
    }
}

impl Default for ColourBudget {
    fn default() -> Self {
        ColourBudget::Scale(Self::DEFAULT_SCALE)
    }
}

/// What the colour grids kept (the convert report's `colour_grids`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct ColourGridReport {
    /// Patches with a colour grid.
    pub patches: usize,
    /// Colour samples over those grids.
    pub samples: usize,
    /// The largest factor kept (colour cells per node cell side).
    pub max_factor: u8,
    /// The largest factor the fitter asked for.
    pub wanted_factor: u8,
    /// Patches whose grid is another patch's, turned (stored once).
    pub shared: usize,
    /// Bytes of the colour grid section (CGRX).
    pub bytes: usize,
    /// The budget those bytes were held to.
    pub budget_bytes: usize,
    /// True when the budget lowered some grid's factor.
    pub budget_limited: bool,
}

/// Lowers the colour grids of `patches` (in a scene of `channel`) until their section fits
/// `budget` bytes (module docs); returns what was kept, or `None` when no patch has a grid.
pub(crate) fn hold_colour_budget(
    patches: &mut Vec<Patch>,
    channel: ColourChannel,
    budget: usize,
) -> Option<ColourGridReport> {
    let wanted = max_factor(patches)?;
    let mut shared = share_colour_grids(patches);
    let mut bytes = colour_grid_section_len(patches, channel);
    let mut limited = false;
    while bytes > budget {
        let Some(top) = max_factor(patches) else {
            break;
        };
        limited = true;
        let next = top - (top / 4).max(1);
        let lowered: Vec<Patch> = std::mem::take(patches)
            .into_iter()
            .map(|p| lower_grid(p, next))
            .collect();
        *patches = lowered;
        shared = share_colour_grids(patches);
        bytes = colour_grid_section_len(patches, channel);
    }
    let grids = patches.iter().filter_map(Patch::colour_grid);
    Some(ColourGridReport {
        patches: grids.clone().count(),
        samples: grids.map(|g| g.samples().len()).sum(),
        max_factor: max_factor(patches).unwrap_or(0),
        wanted_factor: wanted,
        shared,
        bytes,
        budget_bytes: budget,
        budget_limited: limited,
    })
}

/// The largest colour grid factor of `patches`, `None` without grids.
fn max_factor(patches: &[Patch]) -> Option<u8> {
    patches
        .iter()
        .filter_map(|p| p.colour_grid().map(ColourGrid::factor))
        .max()
}

/// `patch` with its colour grid at most `factor` (resampled; dropped below 2).
fn lower_grid(patch: Patch, factor: u8) -> Patch {
    let Some(grid) = patch.colour_grid() else {
        return patch;
    };
    if grid.factor() <= factor {
        return patch;
    }
    match grid.resampled(patch.grid(), factor) {
        Some(coarser) => {
            let samples = coarser
                .samples()
                .iter()
                .map(|&c| quantize_sample(c))
                .collect();
            let Ok(coarser) = ColourGrid::new(patch.grid(), factor, samples) else {
                return patch.without_colour_grid();
            };
            let bare = patch.clone().without_colour_grid();
            bare.with_colour_grid(coarser).unwrap_or(patch)
        }
        None => patch.without_colour_grid(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use spatch_format::{Frame, GridSize};

    fn noisy_patch(seed: u32) -> Patch {
        let grid = GridSize::new(5, 5).unwrap();
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let patch = Patch::new(frame, grid, vec![0; 25], Some(vec![[1, 2, 3, 255]; 25])).unwrap();
        let (c, r) = ColourGrid::sample_size(grid, 32);
        let mut state = seed;
        let samples = (0..c * r)
            .map(|_| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                let v = (state >> 24) as u8;
                [v, v / 2, 255 - v, 255]
            })
            .collect();
        patch
            .with_colour_grid(ColourGrid::new(grid, 32, samples).unwrap())
            .unwrap()
    }

    #[test]
    fn the_grids_shrink_until_they_fit_the_budget() {
        let mut patches = vec![noisy_patch(1), noisy_patch(2)];
        let full = colour_grid_section_len(&patches, ColourChannel::Rgb8);
        let report = hold_colour_budget(&mut patches, ColourChannel::Rgb8, full / 10).unwrap();
        assert!(
            report.budget_limited && report.bytes <= full / 10,
            "{report:?}"
        );
        assert!(
            report.max_factor < 32 && report.max_factor >= 2,
            "{report:?}"
        );
        assert_eq!(report.wanted_factor, 32);
        let mut patches = vec![noisy_patch(3)];
        let report = hold_colour_budget(&mut patches, ColourChannel::Rgb8, 0).unwrap();
        assert_eq!((report.patches, report.bytes), (0, 0));
        assert!(patches[0].colour_grid().is_none());
    }
}
