//! Isolated dark pixels ("specks") of a render, as ../shared/MEASURES.md defines them.
//!
//! Over the covered pixels eroded by 2 px ([`crate::interior_mask`] at
//! [`crate::MEASURES_RADIUS`]: the 5 × 5 square around the pixel is covered), a pixel is a
//! speck when its grey level (the mean of R, G and B) is more than [`SPECK_DARKER_BY`] below
//! the median grey of its 5 × 5 neighbourhood. The speck fraction is specks over those
//! counted pixels. A surface drawn cleanly scores about 0.2 % (shading detail such as a
//! crease's dark side makes a few); z-fighting between overlapping patches, pixels lit from
//! behind or background seen through cracks show as more.
//!
//! Cost: per counted pixel one selection of the median of 25 values, O(pixels) in all.

use crate::interior::{interior_mask, MEASURES_RADIUS};

/// Grey levels (0–255) by which a speck is darker than its neighbourhood's median.
pub const SPECK_DARKER_BY: i32 = 40;

/// The specks of one image.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Specks {
    /// Index (row-major) of every speck pixel.
    pub pixels: Vec<usize>,
    /// Pixels tested: the covered pixels whose 5 × 5 square is covered.
    pub counted: usize,
}

impl Specks {
    /// Specks over counted pixels (0 when none is counted).
    pub fn fraction(&self) -> f64 {
        if self.counted == 0 {
            0.0
        } else {
            self.pixels.len() as f64 / self.counted as f64
        }
    }
}

/// The specks of the `width × height` RGBA image `pixels` (row-major) whose covered pixels
/// are `covered`.
///
/// ```
/// // A flat grey field with one dark pixel in the middle.
/// let (w, h) = (9, 9);
/// let mut pixels = vec![[180u8, 180, 180, 255]; w * h];
/// pixels[4 * w + 4] = [60, 60, 60, 255];
/// let specks = spatch_eval::find_specks(&pixels, &vec![true; w * h], w, h);
/// assert_eq!((specks.pixels, specks.counted), (vec![4 * w + 4], 25));
/// ```
pub fn find_specks(pixels: &[[u8; 4]], covered: &[bool], width: usize, height: usize) -> Specks {
    assert_eq!(pixels.len(), width * height, "image of {width} × {height}");
    let interior = interior_mask(covered, width, height, MEASURES_RADIUS);
    specks_within(pixels, &interior, width)
}

/// [`find_specks`] over `interior`, the covered pixels' interior already found
/// ([`interior_mask`] at [`MEASURES_RADIUS`], so every 5 × 5 window lies in the image).
pub(crate) fn specks_within(pixels: &[[u8; 4]], interior: &[bool], width: usize) -> Specks {
    let r = MEASURES_RADIUS;
    let mut specks = Specks::default();
    let mut window = Vec::with_capacity((2 * r + 1) * (2 * r + 1));
    for (k, _) in interior.iter().enumerate().filter(|(_, &inside)| inside) {
        let (x, y) = (k % width, k / width);
        specks.counted += 1;
        window.clear();
        for row in pixels[(y - r) * width..(y + r + 1) * width].chunks_exact(width) {
            window.extend(row[x - r..=x + r].iter().map(|&p| grey(p)));
        }
        let middle = window.len() / 2;
        let median = *window.select_nth_unstable(middle).1;
        if grey(pixels[k]) < median - SPECK_DARKER_BY {
            specks.pixels.push(k);
        }
    }
    specks
}

/// The grey level of a pixel: the mean of R, G and B.
fn grey(pixel: [u8; 4]) -> i32 {
    (i32::from(pixel[0]) + i32::from(pixel[1]) + i32::from(pixel[2])) / 3
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_thin_dark_line_is_specks_and_a_smooth_ramp_or_a_dark_half_is_not() {
        let (w, h) = (20, 20);
        let covered = vec![true; w * h];
        // A ramp of 8 grey levels per pixel: nothing is 40 below its neighbourhood.
        let ramp: Vec<[u8; 4]> = (0..w * h).map(|k| [(40 + 8 * (k % w)) as u8; 4]).collect();
        assert!(find_specks(&ramp, &covered, w, h).pixels.is_empty());
        // A dark half (a crease's shadow): the median follows it.
        let half: Vec<[u8; 4]> = (0..w * h)
            .map(|k| if k % w < 10 { [40; 4] } else { [200; 4] })
            .collect();
        assert!(find_specks(&half, &covered, w, h).pixels.is_empty());
        // A dark column one pixel wide: every counted pixel of it is a speck.
        let mut line = vec![[200u8, 200, 200, 255]; w * h];
        for y in 0..h {
            line[y * w + 7] = [100, 100, 100, 255];
        }
        let specks = find_specks(&line, &covered, w, h);
        assert_eq!(specks.counted, 16 * 16);
        assert_eq!(specks.pixels.len(), 16);
        assert!(specks.pixels.iter().all(|&k| k % w == 7));
        assert!((specks.fraction() - 1.0 / 16.0).abs() < 1e-12);
    }

    #[test]
    fn only_pixels_whose_square_is_covered_count() {
        let (w, h) = (12, 12);
        let mut pixels = vec![[200u8, 200, 200, 255]; w * h];
        pixels[6 * w + 6] = [0, 0, 0, 255];
        // The dark pixel's square reaches an uncovered column: it is not counted.
        let covered: Vec<bool> = (0..w * h).map(|k| k % w != 8).collect();
        let specks = find_specks(&pixels, &covered, w, h);
        assert!(specks.pixels.is_empty());
        assert!(specks.counted > 0);
    }
}
