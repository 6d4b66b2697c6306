//! The window's framebuffer: a frame's colours as `0RGB` words, the
//! overlay text drawn over them, and the framebuffer as a PNG screenshot.

use spatch_render::RenderedImage;

use crate::error::ViewError;
use crate::font::{glyph, GLYPH_HEIGHT, GLYPH_WIDTH};

/// Colour of overlay text.
const TEXT: u32 = 0x00ff_ffff;
/// Margin around the overlay text, pixels (at scale 1).
const MARGIN: usize = 4;

/// A framebuffer of `0RGB` words, row 0 at the top.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Framebuffer {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width × height` words, `0x00RRGGBB`.
    pub words: Vec<u32>,
}

impl Framebuffer {
    /// The colours of `image` (alpha dropped: the viewer's background is
    /// opaque).
    pub fn of_image(image: &RenderedImage) -> Framebuffer {
        let words = image
            .pixels()
            .iter()
            .map(|[r, g, b, _]| (u32::from(*r) << 16) | (u32::from(*g) << 8) | u32::from(*b))
            .collect();
        Framebuffer {
            width: image.width() as usize,
            height: image.height() as usize,
            words,
        }
    }

    /// This buffer enlarged `scale` times per side (each pixel a square),
    /// cut to `width × height`.
    pub fn enlarged(self, scale: u32, width: u32, height: u32) -> Framebuffer {
        let k = scale.max(1) as usize;
        if k == 1 || self.words.is_empty() {
            return self;
        }
        let (width, height) = (width as usize, height as usize);
        let mut words = Vec::with_capacity(width * height);
        for y in 0..height {
            let row = &self.words[(y / k).min(self.height - 1) * self.width..][..self.width];
            words.extend((0..width).map(|x| row[(x / k).min(self.width - 1)]));
        }
        Framebuffer {
            width,
            height,
            words,
        }
    }

    /// Draws `text` at the bottom-left, wrapped at the width, on a darkened
    /// strip; `scale` enlarges each font pixel.
    pub fn draw_overlay(&mut self, text: &str, scale: usize) {
        let scale = scale.max(1);
        let advance = (GLYPH_WIDTH + 1) * scale;
        let per_line = (self.width.saturating_sub(2 * MARGIN) / advance).max(1);
        let chars: Vec<char> = text.chars().collect();
        let lines: Vec<&[char]> = chars.chunks(per_line).collect();
        let line_height = (GLYPH_HEIGHT + 2) * scale;
        let strip = lines.len() * line_height + 2 * MARGIN;
        let top = self.height.saturating_sub(strip);
        self.darken_rows(top);
        for (k, line) in lines.iter().enumerate() {
            let y = top + MARGIN + k * line_height;
            for (i, c) in line.iter().enumerate() {
                self.draw_glyph(*c, MARGIN + i * advance, y, scale);
            }
        }
    }

    /// Halves the brightness of the rows from `top` down.
    fn darken_rows(&mut self, top: usize) {
        for w in &mut self.words[top * self.width..] {
            *w = (*w >> 1) & 0x007f_7f7f;
        }
    }

    /// One glyph with its top-left corner at `(x, y)`, clipped.
    fn draw_glyph(&mut self, c: char, x: usize, y: usize, scale: usize) {
        for (row, bits) in glyph(c).iter().enumerate() {
            for col in 0..GLYPH_WIDTH {
                if bits & (1 << (GLYPH_WIDTH - 1 - col)) != 0 {
                    self.fill(x + col * scale, y + row * scale, scale);
                }
            }
        }
    }

    /// A `size × size` square of text colour, clipped to the buffer.
    fn fill(&mut self, x: usize, y: usize, size: usize) {
        for py in y..(y + size).min(self.height) {
            for px in x..(x + size).min(self.width) {
                self.words[py * self.width + px] = TEXT;
            }
        }
    }

    /// The framebuffer as RGBA PNG bytes (alpha 255), encoded as
    /// `spatch render` encodes its images.
    pub fn encode_png(&self) -> Result<Vec<u8>, ViewError> {
        let bytes: Vec<u8> = self
            .words
            .iter()
            .flat_map(|w| [(w >> 16) as u8, (w >> 8) as u8, *w as u8, 255])
            .collect();
        spatch_render::encode_rgba_png(self.width as u32, self.height as u32, &bytes)
            .map_err(|e| ViewError::Encode(e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(width: usize, height: usize) -> Framebuffer {
        Framebuffer {
            width,
            height,
            words: vec![0x0080_8080; width * height],
        }
    }

    #[test]
    fn the_overlay_writes_only_the_bottom_strip_and_wraps() {
        let mut fb = grey(100, 60);
        fb.draw_overlay("1", 1);
        let strip = GLYPH_HEIGHT + 2 + 2 * MARGIN;
        let top = 60 - strip;
        assert!(fb.words[..top * 100].iter().all(|w| *w == 0x0080_8080));
        assert!(fb.words[top * 100..].contains(&TEXT));
        // 16 characters fit a line of 100 px; 20 need two lines.
        let mut two = grey(100, 60);
        two.draw_overlay(&"8".repeat(20), 1);
        let first_changed = two.words.iter().position(|w| *w != 0x0080_8080).unwrap();
        assert_eq!(
            first_changed / 100,
            60 - (2 * (GLYPH_HEIGHT + 2) + 2 * MARGIN)
        );
    }

    #[test]
    fn a_scaled_image_repeats_each_pixel_and_is_cut_to_the_view() {
        let small = Framebuffer {
            width: 2,
            height: 2,
            words: vec![1, 2, 3, 4],
        };
        let big = small.clone().enlarged(2, 3, 4);
        assert_eq!((big.width, big.height), (3, 4));
        assert_eq!(big.words, [1, 1, 2, 1, 1, 2, 3, 3, 4, 3, 3, 4]);
        assert_eq!(small.clone().enlarged(1, 9, 9), small);
    }

    #[test]
    fn a_glyph_lands_where_its_bits_say() {
        let mut fb = grey(40, 20);
        fb.draw_glyph('-', 0, 0, 1);
        let row3: Vec<bool> = fb.words[3 * 40..3 * 40 + 6]
            .iter()
            .map(|w| *w == TEXT)
            .collect();
        assert_eq!(row3, [true, true, true, true, true, false]);
        assert!(fb.words[..3 * 40].iter().all(|w| *w != TEXT));
    }
}
