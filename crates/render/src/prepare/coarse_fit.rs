//! How far a mip level's surface strays from the level below it: the
//! per-patch tests behind [`crate::RenderOptions::geometry_tolerance`],
//! [`crate::RenderOptions::mip_tolerance`] and
//! [`crate::RenderOptions::level_one_limit`].
//!
//! Coarse geometry ([`crate::RenderOptions::geometry_limit`]) draws level
//! `g`'s cells, bilinear between every other node of level `g - 1`. Each
//! filled node of level `g - 1` inside a drawn cell of level `g` then sits
//! off that surface by `|d − bilinear(d of the cell's corners)|` codes
//! along the patch's height axis. The largest such gap, measured once per
//! scene, says whether the coarse surface moves samples enough to change
//! which patch wins or to let a thin rim's back show through; the root
//! mean square, how far the surface moves as a whole.
//!
//! Cost: O(nodes of level `g - 1`), once per patch and level.

use spatch_format::EMPTY;

use crate::prepare::mip::MipLevel;

/// The largest gap, in displacement codes, between a filled node of
/// `fine` and the bilinear surface of the cell of `coarse` (the level
/// above `fine`) that holds it; nodes in cells of `coarse` with an empty
/// corner (not drawn) are skipped. 0 when no node is compared.
pub(crate) fn coarse_gap(fine: &MipLevel, coarse: &MipLevel) -> f32 {
    grid_gap(
        &fine.displacements,
        [fine.cols, fine.rows],
        &coarse.displacements,
        [coarse.cols, coarse.rows],
    )
}

/// [`coarse_gap`] on bare grids of displacement codes: `fine` of
/// `fine_size` (columns, rows) nodes and `coarse`, every other node of it
/// (with filled or padded nodes), of `coarse_size`.
pub(crate) fn grid_gap(
    fine: &[u16],
    fine_size: [usize; 2],
    coarse: &[u16],
    coarse_size: [usize; 2],
) -> f32 {
    let mut worst = 0f32;
    for_each_gap(fine, fine_size, coarse, coarse_size, |g| {
        worst = worst.max(g)
    });
    worst
}

/// How far the filled nodes of a level lie from the bilinear surface of
/// the level above as a whole, in displacement codes (both 0 when no node
/// is compared): [`coarse_gaps`]. The largest distance is
/// [`coarse_gap`]'s: a crease or a step the coarse level cuts off, but
/// also a scan's noise, which puts some node of nearly every patch far
/// from the coarser surface.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Gaps {
    /// The root mean square distance: how far the surface moves as a
    /// whole.
    pub rms: f32,
    /// The distance that all but the farthest 2 % of the nodes stay
    /// within: a crease level 1 cuts off moves a row of nodes, a scan's
    /// noise a few scattered ones.
    pub most: f32,
}

/// The share of the compared nodes that [`Gaps::most`] bounds.
const MOST_NODES: f32 = 0.98;

/// The gaps [`coarse_gap`] takes the largest of, summed up as [`Gaps`]
/// ([`crate::RenderOptions::level_one_limit`]'s test). Why apart from
/// [`coarse_gap`]: the percentile keeps every gap in a vector, which the
/// mip tolerance's first frame, asking every full grid for its largest
/// gap, paid for in time (the sphere's one-image command 1.05-1.07 times
/// as long).
pub(crate) fn coarse_gaps(fine: &MipLevel, coarse: &MipLevel) -> Gaps {
    let mut gaps = Vec::new();
    let (f, c) = (&fine.displacements, &coarse.displacements);
    for_each_gap(
        f,
        [fine.cols, fine.rows],
        c,
        [coarse.cols, coarse.rows],
        |g| gaps.push(g),
    );
    if gaps.is_empty() {
        return Gaps::default();
    }
    let sum: f64 = gaps.iter().map(|&g| f64::from(g * g)).sum();
    let rms = (sum / gaps.len() as f64).sqrt() as f32;
    let k = ((gaps.len() as f32 * MOST_NODES) as usize).min(gaps.len() - 1);
    let (_, &mut most, _) = gaps.select_nth_unstable_by(k, f32::total_cmp);
    Gaps { rms, most }
}

/// Calls `gap` with the distance of each filled node of `fine` from the
/// bilinear surface of the drawn cell of `coarse` that holds it.
fn for_each_gap(
    fine: &[u16],
    [fine_cols, fine_rows]: [usize; 2],
    coarse: &[u16],
    coarse_size: [usize; 2],
    mut gap: impl FnMut(f32),
) {
    for j in 0..fine_rows {
        for i in 0..fine_cols {
            let d = fine[j * fine_cols + i];
            if d == EMPTY {
                continue;
            }
            if let Some(b) = bilinear_at(coarse, coarse_size, i, j) {
                gap((d as f32 - b).abs());
            }
        }
    }
}

/// The bilinear displacement of `coarse` (`cols × rows` nodes) at the
/// point of fine node `(i, j)` (coarse node units `(i / 2, j / 2)`),
/// `None` when the cell holding it has an empty corner or lies outside
/// the grid.
fn bilinear_at(coarse: &[u16], [cols, rows]: [usize; 2], i: usize, j: usize) -> Option<f32> {
    let (ci, cj) = ((i / 2).min(cols - 2), (j / 2).min(rows - 2));
    let (fu, fv) = ((i as f32 / 2.0) - ci as f32, (j as f32 / 2.0) - cj as f32);
    if fu > 1.0 || fv > 1.0 {
        return None;
    }
    let at = |di: usize, dj: usize| {
        let v = coarse[(cj + dj) * cols + ci + di];
        (v != EMPTY).then_some(v as f32)
    };
    let (d00, d10, d01, d11) = (at(0, 0)?, at(1, 0)?, at(0, 1)?, at(1, 1)?);
    let bottom = d00 + (d10 - d00) * fu;
    let top = d01 + (d11 - d01) * fu;
    Some(bottom + (top - bottom) * fv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prepare::mip::{base_level, halve_level};
    use glam::Vec3;
    use spatch_format::{Frame, GridSize, Patch};

    /// Level 0 of a patch of `cols × rows` filled nodes with
    /// displacements `f(i, j)`.
    fn level(cols: u32, rows: u32, f: impl Fn(u32, u32) -> u16) -> MipLevel {
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let d: Vec<u16> = (0..cols * rows).map(|k| f(k % cols, k / cols)).collect();
        let patch = Patch::new(frame, GridSize::new(cols, rows).unwrap(), d, None).unwrap();
        base_level(&patch).unwrap()
    }

    #[test]
    fn a_plane_has_no_gap() {
        let fine = level(9, 7, |i, j| (1000 + 30 * i + 7 * j) as u16);
        let coarse = halve_level(&fine).unwrap();
        assert_eq!(coarse_gap(&fine, &coarse), 0.0);
        assert_eq!(coarse_gaps(&fine, &coarse), Gaps::default());
    }

    #[test]
    fn a_bump_at_an_odd_node_is_the_gap() {
        let fine = level(9, 9, |i, j| if (i, j) == (3, 5) { 1250 } else { 1000 });
        let coarse = halve_level(&fine).unwrap();
        let gaps = coarse_gaps(&fine, &coarse);
        assert_eq!(coarse_gap(&fine, &coarse), 250.0);
        // One node of 81 off by 250: the root mean square is 250 / 9, and
        // 98 % of the nodes lie on the surface.
        assert!((gaps.rms - 250.0 / 9.0).abs() < 1e-3);
        assert_eq!(gaps.most, 0.0);
    }

    #[test]
    fn a_ridge_moves_most_nodes_and_a_spike_does_not() {
        // A ridge along the odd column 3 (a crease level 1 cuts off) moves
        // 9 of 81 nodes: more than 2 %.
        let ridge = level(9, 9, |i, _| if i == 3 { 1100 } else { 1000 });
        let coarse = halve_level(&ridge).unwrap();
        assert_eq!(coarse_gap(&ridge, &coarse), 100.0);
        assert_eq!(coarse_gaps(&ridge, &coarse).most, 100.0);
    }
}
