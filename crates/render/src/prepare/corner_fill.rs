//! Filling the empty corners of a halved mip level.
//!
//! A coarse cell draws only with four filled corners. Along a patch's
//! outline (its empty nodes) a coarse cell often holds drawable finer
//! cells while one of its corners falls on an empty node. Such a corner is
//! filled when the coarse cell holds at least [`MIN_FINER_CELLS`] of its
//! four finer cells at level 1 ([`MIN_FINER_CELLS_ABOVE`] above), in two
//! steps:
//!
//! 1. **Extrapolation** (the prior): the mean of the linear extrapolations
//!    from its filled neighbours along the grid's eight directions (the
//!    nearer one repeated when the farther is empty or outside).
//! 2. **Fit to the finer level**: the value that brings the coarse cells
//!    it is a corner of closest (least squares) to the finer level's filled
//!    nodes inside them, the other corners held, with the prior as a weak
//!    pull (weight [`PRIOR_WEIGHT`], that of one node at a cell's centre):
//!    two sweeps over the filled corners, so neighbouring filled corners
//!    settle together.
//!
//! Why not every coarse cell holding a finer cell: a coarse cell drawn over
//! one finer cell covers three finer cells' area past the patch's data, on
//! a continuation of the surface. Where the patch's outline is seen against
//! a farther surface, those cells widen the silhouette by up to a coarse
//! cell, and where a neighbouring patch overlaps them they compete with
//! its real surface in the depth test. The finer cells of coarse cells
//! below the threshold are left to the neighbouring patches (on a closed
//! surface, which overlap them) or open a hole. Measured on the bunny
//! (bun_zipper, default convert; `spatch eval --mip-limit 3`, 14 views at
//! 500²; the default limit, see [`crate::RenderOptions::mip_limit`]):
//!
//! | coarse cells filled | PSNR | holes |
//! |---|---|---|
//! | holding 1 finer cell or more, extrapolated corners (before) | 23.25 dB | 0.0011 % |
//! | 1 or more, fitted corners | 23.97 dB | 0.0012 % |
//! | 2 or more, fitted | 24.37 dB | 0.0028 % |
//! | **3 or more, fitted** | **24.74 dB** | 0.0174 % |
//! | 3 or more, extrapolated | 24.44 dB | 0.0175 % |
//! | 4 (no filling) | 24.78 dB | 0.0533 % |
//!
//! (the rows apply the rule at every level; the bunny at 500² draws
//! level 1 almost only.) Above level 1 the dropped cells add up: Spot
//! (`spot_triangulated.obj`, default conversion, eval at 128²) with
//! three or more at every level opened 0.37 % holes; with two or more
//! above level 1, 0.017 % (19.57 dB; one or more: 0.0019 %, 19.18 dB; the
//! bunny at 500² then 24.74 and 24.72 dB; before, 19.01 dB, no holes).
//!
//! The fit keeps the coarse cell on the finer nodes it holds: an
//! extrapolated corner continues the tangent plane of the coarse nodes a
//! whole coarse cell away, which on a curved or rough scan leaves the finer
//! surface by a large fraction of a cell.

use spatch_format::EMPTY;

use crate::grid::CELL_DRAW;

/// The level a halved grid comes from, as the filling reads it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FinerLevel<'a> {
    /// Nodes per row.
    pub(crate) cols: usize,
    /// Rows of nodes.
    pub(crate) rows: usize,
    /// Its displacement codes, row by row ([`EMPTY`] for no node).
    pub(crate) displacements: &'a [u16],
    /// Per cell, row by row, [`CELL_DRAW`] when it is drawable.
    pub(crate) cell_flags: &'a [u8],
    /// Its node spacing in level-0 nodes (1 at level 0).
    pub(crate) spacing: u32,
}

/// Level-0 cells a level-1 cell must hold (of four) for its empty corners
/// to be filled; a coarse cell at a padded side, which spans fewer finer
/// cells, must hold all of them ([`fills_cell`]).
pub(crate) const MIN_FINER_CELLS: u8 = 3;

/// The same for the cells of level 2 and above.
pub(crate) const MIN_FINER_CELLS_ABOVE: u8 = 2;

/// Whether a coarse cell of a level halved from a `fc × fr`-cell level of
/// node spacing `spacing`, at `[i, j]`, holding `drawn` drawable finer
/// cells, gets its empty corners filled (see [`MIN_FINER_CELLS`]).
pub(crate) fn fills_cell(
    [fc, fr]: [usize; 2],
    [i, j]: [usize; 2],
    drawn: u8,
    spacing: u32,
) -> bool {
    let spanned = (fc - 2 * i).min(2) * (fr - 2 * j).min(2);
    let min = match spacing {
        1 => MIN_FINER_CELLS,
        _ => MIN_FINER_CELLS_ABOVE,
    };
    drawn > 0 && drawn >= min.min(spanned as u8)
}

/// Weight of the extrapolated value in the fit, against a finer node's
/// squared bilinear weight (1/16 for the node at a cell's centre). Why
/// not zero: a corner seen only through one finer node far from it would
/// be placed by that node's noise alone.
const PRIOR_WEIGHT: f32 = 1.0 / 16.0;

/// Sweeps of the fit over the filled corners.
const FIT_SWEEPS: usize = 2;

/// Fills the empty nodes of the halved grid `d` (`hc × hr`, every other
/// node of `fine`) that are a corner of a coarse cell holding enough
/// drawable cells of `fine` ([`fills_cell`]; see the module header). Each
/// such corner has a filled neighbour (a finer cell's corner at even
/// coordinates is a node of `d`), so each such coarse cell becomes
/// drawable.
pub(crate) fn fill_corners(fine: FinerLevel<'_>, size: [usize; 2], d: &mut [u16]) {
    fill_corners_with(fine, size, d, FIT_SWEEPS);
}

/// [`fill_corners`] with `sweeps` sweeps of the fit (0: the prior alone).
fn fill_corners_with(fine: FinerLevel<'_>, size: [usize; 2], d: &mut [u16], sweeps: usize) {
    let wanted = wanted_corners(fine, size);
    fill_wanted(fine, size, d, &wanted, sweeps);
}

/// Fills the empty nodes of `d` that `wanted` marks, as [`fill_corners`]
/// does (the nodes already filled are held): the corners of the level-1
/// cells drawn by quarters ([`crate::prepare::quarters`]).
pub(crate) fn fill_wanted_corners(
    fine: FinerLevel<'_>,
    size: [usize; 2],
    d: &mut [u16],
    wanted: &[bool],
) {
    fill_wanted(fine, size, d, wanted, FIT_SWEEPS);
}

/// The two steps of [`fill_corners`] over the empty nodes `wanted` marks.
fn fill_wanted(
    fine: FinerLevel<'_>,
    [hc, hr]: [usize; 2],
    d: &mut [u16],
    wanted: &[bool],
    sweeps: usize,
) {
    let holes: Vec<(usize, u16)> = (0..d.len())
        .filter(|&k| wanted[k] && d[k] == EMPTY)
        .filter_map(|k| extrapolated(d, [hc, hr], k).map(|prior| (k, prior)))
        .collect();
    for &(k, prior) in &holes {
        d[k] = prior;
    }
    for _ in 0..sweeps {
        for &(k, prior) in &holes {
            d[k] = fitted(fine, d, [hc, hr], k, prior);
        }
    }
}

/// Per node of the halved grid, whether it is a corner of a coarse cell
/// that [`fills_cell`] fills.
fn wanted_corners(fine: FinerLevel<'_>, [hc, hr]: [usize; 2]) -> Vec<bool> {
    let (fc, fr) = (fine.cols - 1, fine.rows - 1);
    let mut count = vec![0u8; (hc - 1) * (hr - 1)];
    for (k, &f) in fine.cell_flags.iter().enumerate() {
        if f & CELL_DRAW != 0 {
            let (i, j) = ((k % fc) / 2, (k / fc) / 2);
            count[j * (hc - 1) + i] += 1;
        }
    }
    let mut wanted = vec![false; hc * hr];
    for (k, &n) in count.iter().enumerate() {
        let (i, j) = (k % (hc - 1), k / (hc - 1));
        if fills_cell([fc, fr], [i, j], n, fine.spacing) {
            for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                wanted[(j + dj) * hc + i + di] = true;
            }
        }
    }
    wanted
}

/// The mean of the linear extrapolations into node `k` of `d` from its
/// filled neighbours (rounded, clamped to the codes' range), or `None`
/// when it has none.
fn extrapolated(d: &[u16], [hc, hr]: [usize; 2], k: usize) -> Option<u16> {
    let at = |i: isize, j: isize| -> Option<i32> {
        if i < 0 || j < 0 || i >= hc as isize || j >= hr as isize {
            return None;
        }
        let v = d[j as usize * hc + i as usize];
        (v != EMPTY).then_some(v as i32)
    };
    let (i, j) = ((k % hc) as isize, (k / hc) as isize);
    let (mut sum, mut n) = (0i32, 0i32);
    for (di, dj) in [
        (-1, 0),
        (1, 0),
        (0, -1),
        (0, 1),
        (-1, -1),
        (1, -1),
        (-1, 1),
        (1, 1),
    ] {
        if let Some(a) = at(i + di, j + dj) {
            sum += at(i + 2 * di, j + 2 * dj).map_or(a, |b| 2 * a - b);
            n += 1;
        }
    }
    (n > 0).then(|| ((sum + n / 2).div_euclid(n)).clamp(0, EMPTY as i32 - 1) as u16)
}

/// The value of filled corner `k` of `d` that fits the coarse cells around
/// it to `fine`'s filled nodes inside them (see the module header), pulled
/// toward `prior`; rounded and clamped to the codes' range.
fn fitted(fine: FinerLevel<'_>, d: &[u16], [hc, hr]: [usize; 2], k: usize, prior: u16) -> u16 {
    let (i, j) = (k % hc, k / hc);
    let (mut num, mut den) = (PRIOR_WEIGHT * prior as f32, PRIOR_WEIGHT);
    for cj in j.saturating_sub(1)..=j.min(hr - 2) {
        for ci in i.saturating_sub(1)..=i.min(hc - 2) {
            let corner = |a: usize, b: usize| d[(cj + b) * hc + ci + a];
            let corners = [corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1)];
            if corners.contains(&EMPTY) {
                continue;
            }
            let own = (j - cj) * 2 + (i - ci);
            let [n, dd] = cell_terms(fine, [ci, cj], corners.map(f32::from), own);
            num += n;
            den += dd;
        }
    }
    (num / den).round().clamp(0.0, EMPTY as f32 - 1.0) as u16
}

/// One coarse cell's terms of the fit of its corner `own` (0..4, in the
/// order `(0, 0), (1, 0), (0, 1), (1, 1)`): over `fine`'s filled nodes in
/// the cell `[ci, cj]`, the sums of `w · (node − rest)` and `w²`, where `w`
/// is the corner's bilinear weight at the node and `rest` the other
/// corners' share of the cell's value there. Only the four finer nodes on
/// the corner's half of each axis have `w > 0` (row by row, as the sums
/// run). Why only those: the other five weigh nothing, and skipping them
/// took the one-frame bunny render from 127.3 to 126.1 M instructions
/// (callgrind, `spatch render bunny.spatch -o out.png --threads 1`; images
/// identical).
fn cell_terms(
    fine: FinerLevel<'_>,
    [ci, cj]: [usize; 2],
    corners: [f32; 4],
    own: usize,
) -> [f32; 2] {
    let (mut num, mut den) = (0.0, 0.0);
    let half = |k: usize| if k == 0 { [0, 1] } else { [1, 2] };
    for b in half(own / 2) {
        for a in half(own % 2) {
            let (fi, fj) = (2 * ci + a, 2 * cj + b);
            if fi >= fine.cols || fj >= fine.rows {
                continue;
            }
            let node = fine.displacements[fj * fine.cols + fi];
            if node == EMPTY {
                continue;
            }
            let (s, t) = (a as f32 / 2.0, b as f32 / 2.0);
            let w = [(1.0 - s) * (1.0 - t), s * (1.0 - t), (1.0 - s) * t, s * t];
            let value: f32 = w.iter().zip(&corners).map(|(w, c)| w * c).sum();
            let rest = value - w[own] * corners[own];
            num += w[own] * (node as f32 - rest);
            den += w[own] * w[own];
        }
    }
    [num, den]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::drawn_cells;
    use crate::prepare::coarse_fit::grid_gap;

    /// A `side × side` grid (`side` odd) on the bowl `400 + 2.5 r²` around
    /// node (8, 8), with the nodes outside a disc of `radius` nodes around
    /// `(cx, cy)` empty, and its drawable cells.
    fn bowl_with_outline(side: usize, (cx, cy, radius): (f32, f32, f32)) -> (Vec<u16>, Vec<u8>) {
        let d: Vec<u16> = (0..side * side)
            .map(|k| {
                let (i, j) = ((k % side) as f32, (k / side) as f32);
                let bowl = 400.0 + 2.5 * ((i - 8.0).powi(2) + (j - 8.0).powi(2));
                match (i - cx).powi(2) + (j - cy).powi(2) <= radius * radius {
                    true => bowl.round() as u16,
                    false => EMPTY,
                }
            })
            .collect();
        let flags = drawn_cells(&d, side, side);
        (d, flags)
    }

    /// A 17 × 17 level-0 grid `d` with its drawable cells, as the fill reads it.
    fn level_zero<'a>(d: &'a [u16], flags: &'a [u8]) -> FinerLevel<'a> {
        FinerLevel {
            cols: 17,
            rows: 17,
            displacements: d,
            cell_flags: flags,
            spacing: 1,
        }
    }

    /// Every other node of a `side × side` grid (`side` odd).
    fn halved(d: &[u16], side: usize) -> Vec<u16> {
        let h = side / 2 + 1;
        (0..h * h)
            .map(|k| d[2 * (k / h) * side + 2 * (k % h)])
            .collect()
    }

    /// The largest gap over discs cutting coarse cells at several offsets,
    /// with `sweeps` sweeps of the fit.
    fn worst_gap(sweeps: usize) -> f32 {
        let mut worst = 0.0f32;
        for disc in [
            (8.0, 8.0, 6.3),
            (7.4, 8.9, 5.1),
            (9.2, 6.6, 7.7),
            (8.5, 8.0, 4.2),
        ] {
            let (d, flags) = bowl_with_outline(17, disc);
            let fine = level_zero(&d, &flags);
            let mut coarse = halved(&d, 17);
            fill_corners_with(fine, [9, 9], &mut coarse, sweeps);
            worst = worst.max(grid_gap(&d, [17, 17], &coarse, [9, 9]));
        }
        worst
    }

    #[test]
    fn filled_corners_keep_coarse_cells_on_the_finer_nodes_they_hold() {
        // A bowl curved like a scan over a few cells: the fitted corners
        // keep each coarse cell within 7 codes of the finer nodes it holds
        // (5 measured); the extrapolation alone (the prior) leaves 11.5.
        let (fitted, extrapolated) = (worst_gap(FIT_SWEEPS), worst_gap(0));
        assert!(fitted <= 7.0, "largest gap {fitted} codes");
        assert!(
            extrapolated > 2.0 * fitted,
            "{extrapolated} against {fitted}"
        );
    }

    #[test]
    fn coarse_cells_holding_too_few_finer_cells_are_not_filled() {
        // One coarse cell at each count of drawable finer cells, at level 1
        // and above, and a coarse cell at a padded side that spans two
        // finer cells.
        let full = [4u8, 3, 2, 1];
        let at_level_one = [true, true, false, false];
        let above = [true, true, true, false];
        for ((n, one), above) in full.iter().zip(at_level_one).zip(above) {
            assert_eq!(fills_cell([16, 16], [0, 0], *n, 1), one, "{n}");
            assert_eq!(
                fills_cell([16, 16], [0, 0], *n, 2),
                above,
                "{n} above level 1"
            );
        }
        assert!(fills_cell([15, 16], [7, 0], 2, 1));
        assert!(!fills_cell([15, 16], [7, 0], 1, 1));
        assert!(!fills_cell([16, 16], [0, 0], 0, 1));
        assert!(!fills_cell([16, 16], [0, 0], 0, 2));
    }

    #[test]
    fn on_a_plane_filled_corners_stay_on_the_plane() {
        let plane = |i: usize, j: usize| (300 + 4 * i + 7 * j) as u16;
        let d: Vec<u16> = (0..17 * 17)
            .map(|k| match k % 17 + k / 17 <= 21 {
                true => plane(k % 17, k / 17),
                false => EMPTY,
            })
            .collect();
        let flags = drawn_cells(&d, 17, 17);
        let fine = level_zero(&d, &flags);
        let mut coarse = halved(&d, 17);
        let before = coarse.iter().filter(|&&v| v == EMPTY).count();
        fill_corners(fine, [9, 9], &mut coarse);
        assert!(coarse.iter().filter(|&&v| v == EMPTY).count() < before);
        for (k, &v) in coarse.iter().enumerate() {
            if v != EMPTY {
                assert_eq!(v, plane(2 * (k % 9), 2 * (k / 9)), "node {k}");
            }
        }
    }
}
