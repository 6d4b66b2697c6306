//! The part of a band its work can touch: the union of the screen boxes
//! of the draw items and triangles binned to it, grown by [`MARGIN`] and
//! cut to the band and the image.
//!
//! Why: outside that box a band's pixels stay empty, so it neither clears
//! their samples before drawing nor reads them back in the resolve, which
//! writes the background there. An empty 1000² frame cost about 2.8 ms
//! (clearing and resolving 16-byte samples: the memory traffic of the
//! pixels, not their instructions), and a scan's view leaves most of the
//! image empty (the bunny covers 27 % of its 1000² view).
//!
//! Exactness: an item's box holds the pixels of its used nodes (its
//! footprints included: splats and smooth cells) and a triangle's the
//! pixel centres between its corners (a span's ends may round a pixel
//! past them); every sample lies within 2^-12 px of a convex
//! combination of its item's nodes, and an exact cell's sub-quads reach at most
//! `EXACT_MARGIN_PX` (0.15 px, `raster/cell_exact.rs`) further, both well
//! inside [`MARGIN`]. So no sample falls outside the box, and the image is
//! the same as with whole bands.
//!
//! Cost: O(items + triangles) of the band, once per band and frame.

/// Pixels added on each side of the union of the boxes.
pub(crate) const MARGIN: i32 = 2;

/// A box of pixels: columns `x0..x1` and rows `y0..y1` (half-open).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct PixelBox {
    pub(crate) x0: i32,
    pub(crate) x1: i32,
    pub(crate) y0: i32,
    pub(crate) y1: i32,
}

impl PixelBox {
    /// The whole band `y0..y0 + rows` of an image `width` wide.
    pub(crate) fn whole(y0: i32, rows: i32, width: i32) -> Self {
        PixelBox {
            x0: 0,
            x1: width,
            y0,
            y1: y0 + rows,
        }
    }
}

/// The box of `band` that work with the inclusive pixel boxes `boxes`
/// (`[x0, x1, y0, y1]`) can touch: their union grown by [`MARGIN`], cut
/// to `band` (whose columns are the image's). Empty when there is no box.
pub(crate) fn band_box(boxes: impl IntoIterator<Item = [i32; 4]>, band: PixelBox) -> PixelBox {
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (i32::MAX, i32::MIN, i32::MAX, i32::MIN);
    for [x0, x1, y0, y1] in boxes {
        (x_lo, x_hi) = (x_lo.min(x0), x_hi.max(x1));
        (y_lo, y_hi) = (y_lo.min(y0), y_hi.max(y1));
    }
    if x_lo > x_hi || y_lo > y_hi {
        return PixelBox {
            y1: band.y0,
            ..band
        };
    }
    let grow = |v: i32, by: i32| v.saturating_add(by);
    PixelBox {
        x0: grow(x_lo, -MARGIN).clamp(band.x0, band.x1),
        x1: grow(x_hi, MARGIN + 1).clamp(band.x0, band.x1),
        y0: grow(y_lo, -MARGIN).clamp(band.y0, band.y1),
        y1: grow(y_hi, MARGIN + 1).clamp(band.y0, band.y1),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_is_the_grown_union_cut_to_the_band() {
        let band = PixelBox::whole(64, 64, 100);
        let b = band_box([[10, 20, 70, 80], [30, 40, 100, 200]], band);
        assert_eq!(
            b,
            PixelBox {
                x0: 10 - MARGIN,
                x1: 40 + MARGIN + 1,
                y0: 70 - MARGIN,
                y1: 128
            }
        );
        // Far off screen: cut to the image.
        let wide = band_box([[i32::MIN, i32::MAX, i32::MIN, i32::MAX]], band);
        assert_eq!(wide, band);
        let none = band_box([], band);
        assert_eq!(none.y0, none.y1, "no rows");
    }
}
