//! Filling of small sampling gaps in a range image by interpolating depths across them.
//!
//! Input: a [`RangeImage`], the widest gap `max_gap` (pixels) and the discontinuity threshold
//! `jump` (model units per pixel step). Output: the same image with gap pixels filled.
//!
//! Method: for every empty pixel, look along four lines (the row, the column and both
//! diagonals) for the nearest filled pixel on each side. A line is used when the run of
//! empty pixels it crosses is at most `max_gap` long and the two end depths differ by at most
//! `jump` per step, so a gap is never bridged across a depth discontinuity (the edge of a
//! surface over a farther one). The pixel gets the mean of the linear interpolations of the
//! usable lines, weighted by the inverse of their span; colours are interpolated the same
//! way. Only pixels that were filled before the pass serve as ends, so the result does not
//! depend on the scan order.
//!
//! Invariants: filled pixels are never changed; an empty pixel stays empty when no line
//! qualifies (openings wider than `max_gap`, silhouettes).
//!
//! Cost: O(w·h·max_gap) time, one copy of the heights.
//!
//! Based on: the gap interpolation of the spatial-patch paper's range images; the
//! line-wise interpolation is the usual scan-line hole filling of range scanners.

use crate::range_image::{RangeImage, EMPTY_DEPTH};

/// The four line directions (row, column, two diagonals).
const LINES: [(isize, isize); 4] = [(1, 0), (0, 1), (1, 1), (1, -1)];

/// Fills gaps of at most `max_gap` pixels (see the module documentation). Returns how many
/// pixels were filled.
pub(crate) fn fill_gaps(image: &mut RangeImage, max_gap: u32, jump: f32) -> usize {
    if max_gap == 0 {
        return 0;
    }
    let (w, h) = (image.geometry.width, image.geometry.height);
    let source = image.depth.clone();
    let source_colour = image.colour.clone();
    let max_gap = max_gap as isize;
    let mut filled = 0;
    let at = |i: isize, j: isize| -> Option<(usize, f32)> {
        if i < 0 || j < 0 || i >= w as isize || j >= h as isize {
            return None;
        }
        let k = j as usize * w + i as usize;
        let d = source[k];
        d.is_finite().then_some((k, d))
    };
    for j in 0..h as isize {
        for i in 0..w as isize {
            let k = j as usize * w + i as usize;
            if source[k].is_finite() {
                continue;
            }
            let (mut weight, mut depth) = (0.0f32, 0.0f32);
            let mut colour = [0.0f32; 4];
            for (di, dj) in LINES {
                let step_length = if di != 0 && dj != 0 {
                    std::f32::consts::SQRT_2
                } else {
                    1.0
                };
                let find = |sign: isize| {
                    (1..=max_gap)
                        .find_map(|s| at(i + sign * s * di, j + sign * s * dj).map(|f| (s, f)))
                };
                // One side first: most empty pixels are background with nothing on it.
                let Some((sa, (ka, ha))) = find(-1) else {
                    continue;
                };
                let Some((sb, (kb, hb))) = find(1) else {
                    continue;
                };
                let span = sa + sb;
                if span - 1 > max_gap || (ha - hb).abs() > jump * step_length * span as f32 {
                    continue;
                }
                let t = sa as f32 / span as f32;
                let wgt = 1.0 / span as f32;
                weight += wgt;
                depth += wgt * (ha + (hb - ha) * t);
                if let Some(c) = source_colour.as_ref() {
                    for (acc, (&a, &b)) in colour.iter_mut().zip(c[ka].iter().zip(&c[kb])) {
                        *acc += wgt * (f32::from(a) + (f32::from(b) - f32::from(a)) * t);
                    }
                }
            }
            if weight > 0.0 {
                image.depth[k] = depth / weight;
                if let Some(c) = image.colour.as_mut() {
                    c[k] = colour.map(|v| (v / weight).round().clamp(0.0, 255.0) as u8);
                }
                filled += 1;
            } else {
                image.depth[k] = EMPTY_DEPTH;
            }
        }
    }
    filled
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::directions::ViewBasis;
    use crate::range_image::ImageGeometry;
    use glam::Vec3;

    fn image(w: usize, h: usize, depth: impl Fn(usize, usize) -> f32) -> RangeImage {
        let geometry = ImageGeometry {
            basis: ViewBasis::new(Vec3::Z),
            x0: 0.0,
            y0: 0.0,
            pixel: 1.0,
            width: w,
            height: h,
        };
        RangeImage {
            geometry,
            depth: (0..w * h).map(|k| depth(k % w, k / w)).collect(),
            colour: None,
        }
    }

    #[test]
    fn small_holes_are_filled_on_a_slope() {
        let mut img = image(10, 10, |i, j| {
            if (i, j) == (4, 4) || (i, j) == (5, 4) {
                EMPTY_DEPTH
            } else {
                0.5 * i as f32 + 0.25 * j as f32
            }
        });
        assert_eq!(fill_gaps(&mut img, 2, 1.0), 2);
        assert!((img.depth[4 * 10 + 4] - 3.0).abs() < 1e-5);
        assert!((img.depth[4 * 10 + 5] - 3.5).abs() < 1e-5);
    }

    #[test]
    fn gaps_across_a_discontinuity_and_wide_gaps_stay_open() {
        // Left half at depth 0, right half at depth 10, a one-pixel empty column between.
        let mut img = image(9, 5, |i, _| match i {
            4 => EMPTY_DEPTH,
            0..4 => 0.0,
            _ => 10.0,
        });
        assert_eq!(fill_gaps(&mut img, 2, 1.0), 0);
        // A 4-wide empty band is wider than max_gap.
        let mut img = image(12, 5, |i, _| {
            if (4..8).contains(&i) {
                EMPTY_DEPTH
            } else {
                1.0
            }
        });
        assert_eq!(fill_gaps(&mut img, 2, 1.0), 0);
    }
}
