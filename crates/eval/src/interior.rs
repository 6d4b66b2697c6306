//! The interior of a covered-pixel mask: the pixels whose whole
//! `(2·radius + 1)²` square lies in the mask (an erosion by a square).
//!
//! ../shared/MEASURES.md counts holes and specks only there ("reference mask eroded by
//! 2 px"): a pixel on or next to an outline is not a hole when the patches miss it, since
//! where exactly an outline falls between two pixel centres is the renderer's choice (its
//! pixel-centre coverage against the source's), not a gap in the surface.
//!
//! Method: a separable erosion. Per row, the length of the covered run ending at each
//! pixel (then the square's row span is inside when that run reaches `2·radius + 1` at the
//! span's right end); then the same down each column over that result. Pixels within
//! `radius` of the image's border are never interior.
//!
//! Cost: O(pixels), two passes and, besides the result, one `width × height` mask of the
//! rows' pass.

use spatch_render::RenderedImage;

/// The radius ../shared/MEASURES.md erodes by: 2 px on each side, a 5 × 5 square.
pub const MEASURES_RADIUS: usize = 2;

/// Which pixels of the `width × height` mask `covered` (row-major) are interior: their whole
/// `(2·radius + 1)²` square is covered and lies in the image.
///
/// ```
/// // A 9 × 9 covered square in a 13 × 13 image keeps its 5 × 5 middle at radius 2.
/// let (w, h) = (13, 13);
/// let inside = |k: usize| (2..11).contains(&(k % w)) && (2..11).contains(&(k / w));
/// let covered: Vec<bool> = (0..w * h).map(inside).collect();
/// let interior = spatch_eval::interior_mask(&covered, w, h, 2);
/// assert_eq!(interior.iter().filter(|&&i| i).count(), 25);
/// ```
pub fn interior_mask(covered: &[bool], width: usize, height: usize, radius: usize) -> Vec<bool> {
    assert_eq!(covered.len(), width * height, "mask of {width} × {height}");
    if width == 0 {
        return Vec::new();
    }
    let side = 2 * radius + 1;
    // Rows: `across[k]` is true when the row span `x - radius ..= x + radius` is covered.
    let mut across = vec![false; covered.len()];
    for (row_in, row_out) in covered
        .chunks_exact(width)
        .zip(across.chunks_exact_mut(width))
    {
        mark_full_spans(row_in.iter().copied(), side, radius, |x| row_out[x] = true);
    }
    // Columns over the rows' result.
    let mut interior = vec![false; covered.len()];
    for x in 0..width {
        let column = (0..height).map(|y| across[y * width + x]);
        mark_full_spans(column, side, radius, |y| interior[y * width + x] = true);
    }
    interior
}

/// The interior of a rendered image's coverage (pixels with a finite depth) at
/// [`MEASURES_RADIUS`]: where ../shared/MEASURES.md counts holes and specks.
pub(crate) fn interior_of(image: &RenderedImage) -> Vec<bool> {
    let covered: Vec<bool> = image.depth().iter().map(|d| d.is_finite()).collect();
    let (width, height) = (image.width() as usize, image.height() as usize);
    interior_mask(&covered, width, height, MEASURES_RADIUS)
}

/// Calls `mark(i)` for every index `i` whose span `i - radius ..= i + radius` (of length
/// `side`) lies within `values` and holds only `true`.
fn mark_full_spans(
    values: impl Iterator<Item = bool>,
    side: usize,
    radius: usize,
    mut mark: impl FnMut(usize),
) {
    let mut run = 0;
    for (end, value) in values.enumerate() {
        run = if value { run + 1 } else { 0 };
        if run >= side {
            mark(end - radius);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain definition: every pixel of the square inside the image and covered.
    fn brute(covered: &[bool], width: usize, height: usize, radius: usize) -> Vec<bool> {
        let r = radius as isize;
        (0..width * height)
            .map(|k| {
                let (x, y) = ((k % width) as isize, (k / width) as isize);
                (-r..=r).all(|dy| {
                    (-r..=r).all(|dx| {
                        let (xx, yy) = (x + dx, y + dy);
                        xx >= 0
                            && yy >= 0
                            && (xx as usize) < width
                            && (yy as usize) < height
                            && covered[yy as usize * width + xx as usize]
                    })
                })
            })
            .collect()
    }

    #[test]
    fn matches_the_definition_on_random_masks() {
        let mut rng = spatch_fixtures::XorShift(0x1234_5678);
        let sizes = [
            (17, 11, 2),
            (5, 5, 2),
            (4, 9, 2),
            (30, 20, 1),
            (12, 12, 0),
            (0, 0, 2),
        ];
        for (width, height, radius) in sizes {
            for density in [60, 85, 97] {
                let covered: Vec<bool> = (0..width * height)
                    .map(|_| rng.next_u64() % 100 < density)
                    .collect();
                assert_eq!(
                    interior_mask(&covered, width, height, radius),
                    brute(&covered, width, height, radius),
                    "{width} × {height}, radius {radius}, {density} % covered"
                );
            }
        }
    }

    #[test]
    fn an_uncovered_pixel_takes_its_square_out_of_a_full_mask() {
        let (w, h) = (20, 20);
        let mut covered = vec![true; w * h];
        covered[10 * w + 10] = false;
        let interior = interior_mask(&covered, w, h, MEASURES_RADIUS);
        // 16 × 16 interior pixels away from the border, less the 5 × 5 square around the gap.
        assert_eq!(interior.iter().filter(|&&i| i).count(), 16 * 16 - 25);
        assert!(!interior[10 * w + 10] && !interior[12 * w + 12] && interior[13 * w + 10]);
    }
}
