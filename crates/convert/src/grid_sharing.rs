//! Sharing colour grids between patches that show the same texture.
//!
//! The container stores a grid once and lets another patch refer to it in one of the 8
//! orientations of a square (CGRX, docs/format.md §6.7), but only when the two are equal
//! sample for sample. Patches cut from the same texture (the six faces of a textured box)
//! sample it at slightly different places and so differ by a level here and there. This step
//! replaces a patch's grid by an earlier patch's grid, turned, when the two are the same
//! picture: the same size once turned, a mean colour within [`MEAN_LEVELS`], an RMS
//! difference of at most [`RMS_LEVELS`] and at most [`OUTLIER_FRACTION`] of the samples off
//! by more than [`OUTLIER_LEVELS`] in some channel. A picture that differs in a small
//! region (another label) keeps its own grid as long as that region holds more samples than
//! the outlier fraction.
//!
//! Cost: per grid, its mean (one pass); per pair of same-sized grids whose means agree, up
//! to 8 turned copies compared (each stops at the first sign of a real difference). Grids of
//! unrelated textures differ in mean and cost one comparison of three numbers.

use spatch_format::{ColourGrid, Patch};

/// Largest difference of mean colour (per channel, levels of 255) between shared grids.
pub(crate) const MEAN_LEVELS: f64 = 2.0;
/// Largest RMS difference (levels of 255, over the channels) between shared grids.
pub(crate) const RMS_LEVELS: f64 = 3.0;
/// A sample differs outright when a channel is off by more than this many levels.
pub(crate) const OUTLIER_LEVELS: u8 = 24;
/// Largest fraction of samples that may differ outright between shared grids.
pub(crate) const OUTLIER_FRACTION: f64 = 0.01;

/// The mean RGB(A) of a grid.
fn mean_colour(grid: &ColourGrid) -> [f64; 4] {
    let mut sum = [0.0f64; 4];
    for s in grid.samples() {
        for (total, &v) in sum.iter_mut().zip(s) {
            *total += f64::from(v);
        }
    }
    let n = grid.samples().len().max(1) as f64;
    sum.map(|v| v / n)
}

/// True when `a` and `b` are the same picture within the module's tolerances.
fn same_picture(a: &ColourGrid, b: &ColourGrid) -> bool {
    if (a.factor(), a.cols(), a.rows()) != (b.factor(), b.cols(), b.rows()) {
        return false;
    }
    let n = a.samples().len();
    let max_outliers = (n as f64 * OUTLIER_FRACTION) as usize;
    let max_squares = RMS_LEVELS * RMS_LEVELS * (n * 4) as f64;
    let (mut outliers, mut squares) = (0usize, 0.0f64);
    for (x, y) in a.samples().iter().zip(b.samples()) {
        let mut worst = 0u8;
        for (&u, &v) in x.iter().zip(y) {
            let d = u.abs_diff(v);
            worst = worst.max(d);
            squares += f64::from(d) * f64::from(d);
        }
        outliers += usize::from(worst > OUTLIER_LEVELS);
        if outliers > max_outliers || squares > max_squares {
            return false;
        }
    }
    true
}

/// True when `source` turned by `orientation` has the factor and sides of `grid`. Why:
/// turning copies a whole grid, and most same-mean candidates differ in size.
fn turns_to_size_of(source: &ColourGrid, orientation: u8, grid: &ColourGrid) -> bool {
    let (cols, rows) = if orientation & 4 != 0 {
        (source.rows(), source.cols())
    } else {
        (source.cols(), source.rows())
    };
    (source.factor(), cols, rows) == (grid.factor(), grid.cols(), grid.rows())
}

/// Replaces the colour grid of every patch that shows the same picture as an earlier patch's
/// (module docs) by that grid turned to fit; returns how many patches now share a grid.
pub(crate) fn share_colour_grids(patches: &mut [Patch]) -> usize {
    // Patches that keep their own grid, with their grid's mean colour.
    let mut kept: Vec<(usize, [f64; 4])> = Vec::new();
    let mut shared = 0;
    for k in 0..patches.len() {
        let Some(grid) = patches[k].colour_grid() else {
            continue;
        };
        let mean = mean_colour(grid);
        let found = kept
            .iter()
            .filter(|(_, m)| (0..4).all(|ch| (m[ch] - mean[ch]).abs() <= MEAN_LEVELS))
            .find_map(|&(j, _)| {
                let source = patches[j].colour_grid()?;
                (0..ColourGrid::ORIENTATIONS)
                    .filter(|&o| turns_to_size_of(source, o, grid))
                    .map(|o| source.oriented(o))
                    .find(|turned| same_picture(turned, grid))
            });
        match found {
            Some(turned) => {
                let bare = patches[k].clone().without_colour_grid();
                if let Ok(p) = bare.with_colour_grid(turned) {
                    patches[k] = p;
                    shared += 1;
                }
            }
            None => kept.push((k, mean)),
        }
    }
    shared
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use spatch_format::{Frame, GridSize};

    fn patch_with(samples: Vec<[u8; 4]>) -> Patch {
        let grid = GridSize::new(3, 3).unwrap();
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let patch = Patch::new(frame, grid, vec![0; 9], Some(vec![[1, 2, 3, 255]; 9])).unwrap();
        patch
            .with_colour_grid(ColourGrid::new(grid, 10, samples).unwrap())
            .unwrap()
    }

    /// A 21 × 21 picture: a red disc on blue, off centre so that its turns differ.
    fn picture(jitter: u8) -> Vec<[u8; 4]> {
        (0..21 * 21i32)
            .map(|k| {
                let (s, t) = (k % 21, k / 21);
                let inside = (s - 7).pow(2) + (t - 12).pow(2) < 30;
                let j = if k % 7 == 0 { jitter } else { 0 };
                if inside {
                    [220 - j, 20, 20, 255]
                } else {
                    [20, 40 + j, 200, 255]
                }
            })
            .collect()
    }

    #[test]
    fn a_turned_copy_within_a_few_levels_shares_and_another_picture_does_not() {
        let first = patch_with(picture(0));
        let turned = first.colour_grid().unwrap().oriented(6);
        let mut jittered = turned.samples().to_vec();
        jittered.iter_mut().step_by(5).for_each(|s| s[1] += 4);
        let second = patch_with(jittered);
        let mut other = picture(0);
        other
            .iter_mut()
            .take(60)
            .for_each(|s| *s = [0, 255, 0, 255]);
        let third = patch_with(other);
        let mut patches = vec![first.clone(), second, third.clone()];
        assert_eq!(share_colour_grids(&mut patches), 1);
        assert_eq!(patches[1].colour_grid(), Some(&turned));
        assert_eq!(patches[2], third);
        assert_eq!(patches[0], first);
    }
}
