//! Edge-preserving smoothing of a range image (a bilateral filter with a robust range
//! weight).
//!
//! Input: a [`RangeImage`], [`SmoothOptions`], the spacing and the discontinuity threshold
//! `jump`. Output: the image with every filled pixel replaced by a weighted mean of the filled
//! pixels in its `(2r+1)²` window; empty pixels stay empty.
//!
//! Weights: spatial `exp(−d²/(2σ²))` with `σ = 0.6·r` pixels (precomputed once per call)
//! times the Tukey biweight of the depth difference, `(1 − (Δ/c)²)²` for `|Δ| < c`, zero
//! beyond; a neighbour more than `jump` per step away gets no weight at all. So noise (small
//! differences) is averaged while edges, creases and the far side of a discontinuity are left
//! alone. The biweight needs no `exp` per neighbour, which keeps the filter at a few
//! multiply-adds per tap.
//!
//! The range scale adapts to the data: `c = range · σ̂`, where `σ̂` is the image's noise,
//! estimated robustly as `1.4826 · median |h − mean of its 4 neighbours| · √(4/5)` over the
//! pixels whose 4 neighbours are filled (the factor `√(4/5)` undoes the variance the
//! neighbour mean adds). Clean data has `σ̂ ≈ 0` and is left almost as it is; on noisy data the
//! filter averages differences of a few `σ̂` but not the larger height changes of curved
//! surface across the window, which a fixed scale would flatten (shrinking curved parts by
//! about `κ·σ²`).
//!
//! Invariants: empty pixels stay empty, filled stay filled; each iteration reads only the
//! previous one's output (order independent).
//!
//! Cost: O(filled pixels · (2r+1)² · iterations), one extra copy of the heights.
//!
//! Based on: C. Tomasi, R. Manduchi, "Bilateral filtering for gray and color images", ICCV
//! 1998; the biweight as in M. J. Black, G. Sapiro, D. Marimont, D. Heeger, "Robust
//! anisotropic diffusion", IEEE TIP 7(3), 1998.

use crate::range_image::RangeImage;
use crate::SmoothOptions;

/// Smooths `image` in place (see the module documentation).
pub(crate) fn smooth_range_image(
    image: &mut RangeImage,
    options: &SmoothOptions,
    spacing: f32,
    jump: f32,
) {
    let (w, h) = (image.geometry.width, image.geometry.height);
    let taps = filter_taps(options.radius, jump);
    // A floor far below any measurable noise keeps the weights finite on exact data.
    let c = (options.range * estimate_noise(image)).max(1e-6 * spacing);
    let inv_c2 = 1.0 / (c * c);
    let mut source = image.depth.clone();
    for _ in 0..options.iterations {
        source.copy_from_slice(&image.depth);
        for j in 0..h as isize {
            for i in 0..w as isize {
                let k = j as usize * w + i as usize;
                if source[k].is_finite() {
                    image.depth[k] = smoothed_height(&source, (w, h), (i, j), &taps, inv_c2);
                }
            }
        }
    }
}

/// One tap of the filter: its offset `(di, dj)` in pixels, its spatial (Gaussian) weight
/// and the largest height difference it takes (`jump` per pixel step, times 1.5).
type Tap = (isize, isize, f32, f32);

/// The taps of a `(2·radius + 1)²` window, row by row (the order of the sums).
fn filter_taps(radius: u32, jump: f32) -> Vec<Tap> {
    let r = radius as isize;
    let sigma = 0.6 * radius as f32;
    (-r..=r)
        .flat_map(|dj| (-r..=r).map(move |di| (di, dj)))
        .map(|(di, dj)| {
            let d2 = (di * di + dj * dj) as f32;
            let steps = di.abs().max(dj.abs()) as f32;
            (
                di,
                dj,
                (-d2 / (2.0 * sigma * sigma)).exp(),
                jump * steps * 1.5,
            )
        })
        .collect()
}

/// The filtered height of the filled pixel `(i, j)` of the `w × h` heights `source`: the
/// taps' neighbours within their jump limit, weighted by the spatial weight times the
/// biweight of the height difference (`inv_c2`: one over the biweight's scale squared).
#[inline(always)] // The per-pixel body of `smooth_range_image`'s loop.
fn smoothed_height(
    source: &[f32],
    (w, h): (usize, usize),
    (i, j): (isize, isize),
    taps: &[Tap],
    inv_c2: f32,
) -> f32 {
    let d = source[j as usize * w + i as usize];
    let (mut sum, mut weight) = (0.0f32, 0.0f32);
    for &(di, dj, spatial, limit) in taps {
        let (a, b) = (i + di, j + dj);
        if a < 0 || b < 0 || a >= w as isize || b >= h as isize {
            continue;
        }
        let n = source[b as usize * w + a as usize];
        let delta = n - d;
        // Empty neighbours are -inf: `delta.abs()` is then infinite.
        if delta.abs() > limit {
            continue;
        }
        let t = delta * delta * inv_c2;
        if t >= 1.0 {
            continue;
        }
        let wgt = spatial * (1.0 - t) * (1.0 - t);
        sum += wgt * n;
        weight += wgt;
    }
    // The centre tap always has weight 1, so `weight > 0`.
    sum / weight
}

/// Robust noise estimate of the heights (see the module documentation); 0 when fewer than
/// 16 pixels have 4 filled neighbours.
fn estimate_noise(image: &RangeImage) -> f32 {
    let (w, h) = (image.geometry.width, image.geometry.height);
    let d = &image.depth;
    let mut residuals = Vec::new();
    for j in 1..h.saturating_sub(1) {
        for i in 1..w - 1 {
            let k = j * w + i;
            let around = [d[k - 1], d[k + 1], d[k - w], d[k + w]];
            if d[k].is_finite() && around.iter().all(|v| v.is_finite()) {
                residuals.push((d[k] - around.iter().sum::<f32>() * 0.25).abs());
            }
        }
    }
    if residuals.len() < 16 {
        return 0.0;
    }
    let mid = residuals.len() / 2;
    let (_, median, _) = residuals.select_nth_unstable_by(mid, f32::total_cmp);
    1.4826 * *median * (4.0f32 / 5.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::range_image::EMPTY_DEPTH;

    #[test]
    fn noise_drops_and_a_step_survives() {
        // Left: noisy plane at 0; right: a plane at 20 (a discontinuity); one empty pixel.
        let noise = |i: usize, j: usize| (((i * 31 + j * 17) % 13) as f32 / 13.0 - 0.5) * 0.4;
        let mut img = RangeImage::from_fn(30, 20, |i, j| match (i, j) {
            (3, 3) => EMPTY_DEPTH,
            (0..15, _) => noise(i, j),
            _ => 20.0 + noise(i, j),
        });
        let rms = |img: &RangeImage| {
            let v: Vec<f32> = (0..20)
                .flat_map(|j| (3..12).map(move |i| (i, j)))
                .map(|(i, j)| img.depth[j * 30 + i])
                .filter(|d| d.is_finite())
                .collect();
            (v.iter().map(|d| d * d).sum::<f32>() / v.len() as f32).sqrt()
        };
        let before = rms(&img);
        let options = SmoothOptions::default();
        smooth_range_image(&mut img, &options, 1.0, 3.0);
        assert!(estimate_noise(&img) < 0.1);
        assert!(rms(&img) < 0.5 * before, "{} vs {before}", rms(&img));
        assert_eq!(img.depth[3 * 30 + 3], EMPTY_DEPTH);
        for j in 0..20 {
            assert!(img.depth[j * 30 + 14] < 1.0 && img.depth[j * 30 + 15] > 19.0);
        }
    }
}
