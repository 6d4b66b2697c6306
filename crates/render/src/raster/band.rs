//! The band store: the pixels of one band of rows during rasterization,
//! and the depth-tested writes every drawing path makes into them.
//!
//! Per pixel: depth (`i32`, fixed point, initialised to the far plane) and
//! three `u32` payload words ([`Sample`]), words 0 and 2 kept as the low
//! and high halves of one `u64` ([`Sample::words`]).
//!
//! - A **patch sample** (a node or sub-node) is a visibility-buffer entry:
//!   word 2 is the draw item's index with [`PATCH_SAMPLE`] set, word 0 the
//!   cell and the sub-node's position in it (`ci << 24 | cj << 16 | a << 8 | b`);
//!   the drawers carry both as one [`patch_word`].
//!   Placing a sample therefore interpolates only position and depth; the
//!   attributes (normal, albedo or colour) are interpolated bilinearly from
//!   the cell's corner nodes once per visible pixel, in the resolve pass
//!   ([`crate::shade::resolve`]).
//! - A **triangle sample** stores its shading inputs directly — Flat and
//!   Gouraud: the shaded colour in word 0; Phong: the packed normal, the
//!   packed albedo and the shade frame's index in words 0, 1, 2
//!   ([`Payload`]).
//!
//! Depth test: strictly less, so of two equal depths the first drawn wins;
//! the drawing order within a band is fixed, hence the image does not
//! depend on the thread count.
//!
//! Cost: O(pixels) to clear; 16 bytes per internal pixel.

use spatch_format::ColourGrid;

use crate::fixed::{ATTR_FRAC_BITS, ATTR_ONE, Z_FAR};
use crate::lighting::pack_fixed_normal;
use crate::raster::band_box::PixelBox;

/// A band's buffers, borrowed for drawing.
pub(crate) struct BandTarget<'a> {
    pub(crate) width: i32,
    pub(crate) y0: i32,
    pub(crate) rows: i32,
    /// One record per pixel of the band, row-major.
    pub(crate) px: &'a mut [Sample],
}

impl<'a> BandTarget<'a> {
    /// A target over `px`: `rows` rows of `width` pixels, the first of them image row `y0`.
    pub(crate) fn new(px: &'a mut [Sample], width: i32, y0: i32, rows: i32) -> Self {
        debug_assert!(px.len() >= (width.max(0) * rows.max(0)) as usize);
        BandTarget {
            width,
            y0,
            rows,
            px,
        }
    }
}

/// What a pixel holds during rasterization: its depth and three payload
/// words (see the module header). Why one record rather than four arrays:
/// the depth test and the payload stores touch one cache line and one
/// bounds check (callgrind, `profile_sphere 500 1`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Sample {
    pub(crate) depth: i32,
    pub(crate) w1: u32,
    /// Word 0 in the low half, word 2 in the high half. Why one `u64`: a
    /// patch sample's depth test selects and stores one word instead of
    /// two; 152.78 → 147.01 M instructions per bunny 1000² frame (callgrind).
    pub(crate) words: u64,
}

impl Sample {
    /// An empty pixel (depth at the far plane).
    pub(crate) const EMPTY: Sample = Sample {
        depth: Z_FAR,
        w1: 0,
        words: 0,
    };

    /// Payload word 0.
    #[inline(always)]
    pub(crate) fn w0(&self) -> u32 {
        self.words as u32
    }

    /// Payload word 2.
    #[inline(always)]
    pub(crate) fn w2(&self) -> u32 {
        (self.words >> 32) as u32
    }

    /// Sets payload word 0.
    #[inline(always)]
    pub(crate) fn set_w0(&mut self, w0: u32) {
        self.words = patch_word(w0, self.w2());
    }

    /// Sets payload words 0 and 2.
    #[inline(always)]
    pub(crate) fn set_words(&mut self, w0: u32, w2: u32) {
        self.words = patch_word(w0, w2);
    }
}

/// Words 0 and 2 as one [`Sample::words`]: `w2 << 32 | w0`. For a patch
/// sample, `w0` is the sub-word and `w2` the draw item; adding `1 << 8` to
/// the result steps `a` as it does on the sub-word alone.
#[inline(always)]
pub(crate) const fn patch_word(w0: u32, w2: u32) -> u64 {
    (w2 as u64) << 32 | w0 as u64
}

/// What a drawn sample stores besides its depth.
pub(crate) trait Payload<const N: usize> {
    /// Stores the payload of a sample that passed the depth test in its
    /// pixel `s`.
    fn store(&self, s: &mut Sample, attrs: &[i32; N]);
}

/// Flag of word 2 marking a patch sample.
pub(crate) const PATCH_SAMPLE: u32 = 1 << 31;

/// Writes a patch sample (see the module header) if it is in the band and
/// passes the depth test.
#[inline(always)]
pub(crate) fn splat_sample(t: &mut BandTarget<'_>, px: i32, py: i32, z: i32, word: u64) {
    let row = py - t.y0;
    // Unsigned compares reject negatives too.
    if (px as u32) < t.width as u32 && (row as u32) < t.rows as u32 {
        let s = &mut t.px[row as usize * t.width as usize + px as usize];
        keep_nearer(s, z, word);
    }
}

/// The depth test of a patch sample at depth `z` with words `word`
/// ([`patch_word`] of its sub-word and draw item) against the pixel `s`: the nearer of the two is kept. Why selects
/// rather than a branch: whether a sample is nearer than what its pixel
/// holds follows no pattern (a pixel takes several samples of several
/// pieces), so the branch was mispredicted about one time in five
/// (callgrind's branch simulation, bunny 1000²), which cost more than
/// always storing the words (two-thread frames 0.912 of the branch's
/// for the bunny at 1000², 0.950 for the mannequin and 0.838 for the sphere
/// at 500², images identical; see docs/algorithms/render.md, "The depth
/// test without a branch").
#[inline(always)]
pub(crate) fn keep_nearer(s: &mut Sample, z: i32, word: u64) {
    let nearer = z < s.depth;
    s.depth = std::hint::select_unpredictable(nearer, z, s.depth);
    s.words = std::hint::select_unpredictable(nearer, word, s.words);
}

/// Writes a triangle sample with its payload into its pixel `s` if it
/// passes the depth test; its attributes are computed (`attrs`) only then.
/// Why lazily: a pixel's perspective-correct attributes and their
/// conversions cost more than its depth test, and a magnified cell's
/// triangles are drawn where other patches already lie.
#[inline(always)]
pub(crate) fn store_if_nearer<const N: usize, P: Payload<N>>(
    s: &mut Sample,
    z: i32,
    attrs: impl FnOnce() -> [i32; N],
    payload: &P,
) {
    if z < s.depth {
        s.depth = z;
        payload.store(s, &attrs());
    }
}

/// Flat shading: one colour for the whole cell or triangle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FlatPayload(pub(crate) u32);

impl Payload<0> for FlatPayload {
    #[inline(always)]
    fn store(&self, s: &mut Sample, _: &[i32; 0]) {
        s.set_words(self.0, 0);
    }
}

/// Gouraud: interpolated colour (attributes 0..3, 0..=255 in fixed point).
#[derive(Debug, Clone, Copy)]
pub(crate) struct GouraudPayload;

#[inline(always)]
fn channel(v: i32) -> u32 {
    (v >> ATTR_FRAC_BITS).clamp(0, 255) as u32
}

impl Payload<3> for GouraudPayload {
    #[inline(always)]
    fn store(&self, s: &mut Sample, a: &[i32; 3]) {
        let rgba = channel(a[0]) | channel(a[1]) << 8 | channel(a[2]) << 16 | 0xff00_0000;
        s.set_words(rgba, 0);
    }
}

/// Phong: interpolated normal and albedo, and the shade frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PhongPayload(pub(crate) u32);

impl Payload<6> for PhongPayload {
    #[inline(always)]
    fn store(&self, s: &mut Sample, a: &[i32; 6]) {
        s.set_words(pack_fixed_normal(a[0], a[1], a[2]), self.0);
        s.w1 = channel(a[3]) | channel(a[4]) << 8 | channel(a[5]) << 16;
    }
}

/// The albedo of a triangle sample of a patch with a colour grid: the grid
/// read at the patch position in attributes 3 and 4 (level-0 grid units,
/// see [`crate::plan::cell_triangles`]).
#[inline]
fn grid_albedo(grid: &ColourGrid, a: &[i32; 6]) -> [f32; 3] {
    grid.albedo_at(a[3] as f32 / ATTR_ONE, a[4] as f32 / ATTR_ONE)
}

/// Gouraud on a cell triangle of a patch with a colour grid: the light's
/// factor (attributes 0..3) times the grid's albedo.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridGouraudPayload<'a>(pub(crate) &'a ColourGrid);

impl Payload<6> for GridGouraudPayload<'_> {
    #[inline]
    fn store(&self, s: &mut Sample, a: &[i32; 6]) {
        let albedo = grid_albedo(self.0, a);
        let c = |k: usize| {
            let v = a[k] as f32 / ATTR_ONE * albedo[k];
            v.clamp(0.0, 255.0) as u32
        };
        s.set_words(c(0) | c(1) << 8 | c(2) << 16 | 0xff00_0000, 0);
    }
}

/// Phong on a cell triangle of a patch with a colour grid: the
/// interpolated normal, the grid's albedo and the shade frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridPhongPayload<'a> {
    pub(crate) frame: u32,
    pub(crate) grid: &'a ColourGrid,
}

impl Payload<6> for GridPhongPayload<'_> {
    #[inline]
    fn store(&self, s: &mut Sample, a: &[i32; 6]) {
        let [r, g, b] = grid_albedo(self.grid, a).map(|v| v.clamp(0.0, 255.0) as u32);
        s.set_words(pack_fixed_normal(a[0], a[1], a[2]), self.frame);
        s.w1 = r | g << 8 | b << 16;
    }
}

/// Scratch rows of the gap fill ([`crate::raster::gap_fill`]): the drawn
/// depths of five rows and the flags of the middle one. Kept by the band
/// so that frames allocate nothing for it.
#[derive(Debug, Default)]
pub(crate) struct GapScratch {
    pub(crate) rows: [Vec<i32>; 5],
    pub(crate) flags: Vec<u8>,
}

/// Time spent in one band, nanoseconds.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BandTimes {
    pub(crate) cells: u64,
    pub(crate) triangles: u64,
    pub(crate) resolve: u64,
}

/// The buffers of one band of rows.
#[derive(Debug, Default)]
pub(crate) struct Band {
    pub(crate) y0: i32,
    pub(crate) rows: i32,
    pub(crate) width: i32,
    /// Rows drawn above and below the band's own (0, or
    /// [`crate::raster::gap_fill::GAP_FILL_REACH`] with the gap fill); the
    /// buffer holds `rows + 2 * apron` rows from image row `y0 - apron`
    /// ([`Self::buffer_rows`]).
    pub(crate) apron: i32,
    px: Vec<Sample>,
    /// Scratch rows of the gap fill.
    gaps: GapScratch,
    pub(crate) times: BandTimes,
    /// Pixels of the band's rows that show a surface after its resolve.
    pub(crate) covered: u64,
    /// The pool thread that drew the band last (statistics only).
    pub(crate) thread: usize,
}

impl Band {
    /// Sizes and clears the buffers for rows `y0..y0 + rows` of `width`,
    /// with `apron` rows more on each side.
    /// Why a clear pass right before drawing rather than clearing in the
    /// resolve pass: the pass brings the band into the cache for the
    /// cells; clearing in the resolve pass saved ~0.45 M instructions per
    /// 500² sphere frame but cost ~1.5 ms of `cells_cpu` in cache misses
    /// (`--bench 50 --threads 1`, alternated runs). Why `fill`: stores of
    /// whole samples, a third of `resize`'s instructions (callgrind,
    /// `profile_sphere 500 1`).
    pub(crate) fn reset(&mut self, y0: i32, rows: i32, width: i32, apron: i32) {
        self.size_for(y0, rows, width, apron);
        self.px.fill(Sample::EMPTY);
    }

    /// Sizes the buffers for rows `y0..y0 + rows` of `width`, with `apron`
    /// rows more on each side, without clearing what they hold: the caller
    /// clears the part it draws in ([`Self::clear_box`]) and reads nothing
    /// else.
    pub(crate) fn size_for(&mut self, y0: i32, rows: i32, width: i32, apron: i32) {
        let n = ((rows + 2 * apron) * width) as usize;
        (self.y0, self.rows, self.width, self.apron) = (y0, rows, width, apron);
        self.px.resize(n, Sample::EMPTY);
        self.times = BandTimes::default();
    }

    /// Clears the samples of the pixels of `b` (image rows and columns,
    /// inside the band and its apron). Why `fill` per row: see
    /// [`Self::reset`].
    pub(crate) fn clear_box(&mut self, b: PixelBox) {
        let w = self.width as usize;
        let (first, _) = self.buffer_rows();
        if b.x0 == 0 && b.x1 == self.width {
            let rows = (b.y0 - first) as usize..(b.y1 - first) as usize;
            return self.clear_rows(rows);
        }
        for y in b.y0..b.y1 {
            let row = (y - first) as usize * w;
            self.px[row + b.x0 as usize..row + b.x1 as usize].fill(Sample::EMPTY);
        }
    }

    /// Clears rows `rows` of the buffer (counted from its first row, the
    /// apron's).
    pub(crate) fn clear_rows(&mut self, rows: std::ops::Range<usize>) {
        let w = self.width as usize;
        self.px[rows.start * w..rows.end * w].fill(Sample::EMPTY);
    }

    /// Exchanges the band's sample buffer with `buffer`: a pool thread
    /// lends its buffer to each band it draws and takes it back after.
    pub(crate) fn swap_samples(&mut self, buffer: &mut Vec<Sample>) {
        std::mem::swap(&mut self.px, buffer);
    }

    /// The image row of the buffer's first row and the buffer's rows: the
    /// band's own and its apron above and below.
    pub(crate) fn buffer_rows(&self) -> (i32, i32) {
        (self.y0 - self.apron, self.rows + 2 * self.apron)
    }

    /// The buffers for drawing: the band's rows and its apron.
    pub(crate) fn target(&mut self) -> BandTarget<'_> {
        let (y0, rows) = self.buffer_rows();
        BandTarget::new(&mut self.px, self.width, y0, rows)
    }

    /// The samples of the band's buffer, its apron included, and the gap
    /// fill's scratch rows, for the gap fill.
    pub(crate) fn buffer_and_scratch(&mut self) -> (&mut [Sample], &mut GapScratch) {
        (&mut self.px, &mut self.gaps)
    }

    /// The samples of the band's buffer, its apron included, row-major.
    pub(crate) fn all_samples(&self) -> &[Sample] {
        &self.px
    }

    /// The samples of the band's own rows, row-major (for the resolve
    /// pass).
    pub(crate) fn samples(&self) -> &[Sample] {
        let w = self.width as usize;
        let a = self.apron as usize * w;
        &self.px[a..a + self.rows as usize * w]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nearer sample wins, a tie keeps the one already there, and the
    /// triangle word is never touched.
    #[test]
    fn keep_nearer_keeps_the_nearer_and_the_first_of_a_tie() {
        let mut s = Sample {
            w1: 7,
            ..Sample::EMPTY
        };
        keep_nearer(&mut s, 100, patch_word(1, 10));
        assert_eq!((s.depth, s.w0(), s.w1, s.w2()), (100, 1, 7, 10));
        keep_nearer(&mut s, 150, patch_word(2, 20));
        assert_eq!((s.depth, s.w0(), s.w2()), (100, 1, 10), "farther");
        keep_nearer(&mut s, 100, patch_word(3, 30));
        assert_eq!((s.depth, s.w0(), s.w2()), (100, 1, 10), "tie");
        keep_nearer(&mut s, 99, patch_word(4, 40));
        assert_eq!((s.depth, s.w0(), s.w1, s.w2()), (99, 4, 7, 40), "nearer");
    }
}
