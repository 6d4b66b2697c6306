//! Lowering a colour grid's factor with a tent filter.
//!
//! A coarser grid's sample `(s, t)` lies at the fitted grid's position `(s·r, t·r)`, `r` =
//! fitted factor / coarser factor. Reading the fitted grid there bilinearly
//! (`ColourGrid::resampled`) keeps only the samples next to that position: detail between the
//! coarse samples aliases, which costs bytes (noise codes badly) and error. Here each coarse
//! sample is the mean of the fitted samples within `r` of it, each weighted by the tent
//! `(1 − |du| / r)(1 − |dv| / r)` (clamped at the grid's border): the bilinear
//! reconstruction's own kernel, so a smooth picture comes out as before and fine detail as
//! its local mean. Alpha is taken from the nearest fitted sample.
//!
//! Cost: O(coarse samples × (2r)²) = O(fitted samples × 4) per grid.

use spatch_format::{ColourGrid, GridSize};

/// `fitted` (over a patch of `grid` nodes) lowered to `factor` with the tent filter (module
/// docs), its colours not yet rounded; `None` unless `2 <= factor < fitted.factor()`.
pub(crate) fn tent_lowered(
    fitted: &ColourGrid,
    grid: GridSize,
    factor: u8,
) -> Option<Vec<[u8; 4]>> {
    if factor < 2 || factor >= fitted.factor() {
        return None;
    }
    let (cols, rows) = ColourGrid::sample_size(grid, factor);
    let r = f64::from(fitted.factor()) / f64::from(factor);
    let mut samples = Vec::with_capacity(cols * rows);
    for t in 0..rows {
        let ys = tent_weights(t as f64 * r, r, fitted.rows());
        for s in 0..cols {
            let xs = tent_weights(s as f64 * r, r, fitted.cols());
            samples.push(weighted_mean(fitted, &xs, &ys));
        }
    }
    Some(samples)
}

/// The fitted indices within `r` of position `centre` along an axis of `len` samples, with
/// their tent weights.
fn tent_weights(centre: f64, r: f64, len: usize) -> Vec<(usize, f64)> {
    let first = (centre - r).ceil().max(0.0) as usize;
    let last = ((centre + r).floor() as usize).min(len - 1);
    (first..=last)
        .map(|k| (k, 1.0 - (k as f64 - centre).abs() / r))
        .filter(|&(_, w)| w > 0.0)
        .collect()
}

/// The mean of `fitted`'s samples over the separable weights `xs` × `ys`; alpha of the
/// heaviest sample.
fn weighted_mean(fitted: &ColourGrid, xs: &[(usize, f64)], ys: &[(usize, f64)]) -> [u8; 4] {
    let cols = fitted.cols();
    let mut sum = [0.0f64; 3];
    let mut total = 0.0;
    let mut alpha = (0.0, 255);
    for &(j, wy) in ys {
        for &(i, wx) in xs {
            let c = fitted.samples()[j * cols + i];
            let w = wx * wy;
            for ch in 0..3 {
                sum[ch] += w * f64::from(c[ch]);
            }
            total += w;
            if w > alpha.0 {
                alpha = (w, c[3]);
            }
        }
    }
    let byte = |v: f64| (v / total).round().clamp(0.0, 255.0) as u8;
    [byte(sum[0]), byte(sum[1]), byte(sum[2]), alpha.1]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tent_keeps_a_ramp_and_averages_stripes() {
        let grid = GridSize::new(2, 2).unwrap();
        let (c, r) = ColourGrid::sample_size(grid, 4);
        // A ramp along s: bilinear, so the tent keeps it exactly (but at the clamped border).
        let ramp: Vec<[u8; 4]> = (0..c * r)
            .map(|k| [(k % c) as u8 * 10, 0, 0, 255])
            .collect();
        let g = ColourGrid::new(grid, 4, ramp).unwrap();
        let low = tent_lowered(&g, grid, 2).unwrap();
        assert_eq!(low.len(), 9);
        assert_eq!(low[1][0], 20);
        // Stripes one sample wide: their mean, not one stripe's colour.
        let stripes: Vec<[u8; 4]> = (0..c * r)
            .map(|k| {
                if k % 2 == 0 {
                    [200, 0, 0, 255]
                } else {
                    [0, 0, 0, 255]
                }
            })
            .collect();
        let g = ColourGrid::new(grid, 4, stripes).unwrap();
        let low = tent_lowered(&g, grid, 2).unwrap();
        assert!((90..=110).contains(&low[4][0]), "{:?}", low[4]);
        assert!(tent_lowered(&g, grid, 4).is_none() && tent_lowered(&g, grid, 1).is_none());
    }
}
