//! Gap filling: one screen-space pass over a drawn band that closes the
//! small gaps a sparser sub-node lattice leaves, so that cells need not
//! place a sample in every pixel they cover.
//!
//! With the gap fill on, the plain sub-node drawer cuts cells so that each
//! sub-cell's extent `max(|u_x| + |v_x|, |u_y| + |v_y|)` stays below
//! [`crate::plan::subdivision::GAP_FILL_LIMIT`] (1.5 px) instead of 0.95:
//! about half the samples on magnified cells. Every pixel centre inside
//! such a cell lies within 0.75 px (max norm) of a sub-node, so a pixel the
//! lattice missed has a drawn pixel among its eight neighbours, and mostly
//! drawn pixels on two opposite sides within two steps.
//!
//! The pass takes every pixel `p` and its eight directions (every 45°). On
//! each, the *side* of `p` is the nearer of the pixels one and two steps
//! away. Two opposite sides *span* `p` when both are drawn, their depths
//! differ by at most the tolerance `tol`, and `p` is empty or behind both
//! by more than `tol / 4`; of the spanning pairs, `p` takes the one whose
//! farther side is nearest, and gets the sample of its closer side's pixel
//! (one step before two) at the two sides' mean depth, and where both sides
//! are sub-nodes of one cell, the sub-node between them, so it shades where
//! it lies. Where no pair spans `p`, its sides within the looser `loose` of
//! the nearest may still *surround* it, leaving no closed half-plane
//! through it empty (no three consecutive directions without one); then,
//! if it is empty or behind all of those sides by more than `tol / 4`, it
//! takes its nearest drawn neighbour's sample. So a gap inside a surface
//! closes, a slanted one too, and so does a pixel where a gap let a farther
//! surface through; an outline does not grow, since a pixel past a straight
//! outline has five consecutive directions without a side. Every test reads
//! the depths as drawn, before the pass. Not a bound: a pixel on an outline
//! that its surface covers by a hair can stay open (docs/algorithms/render.md,
//! "Gap fill"), one reason the gap fill is opt-in.
//!
//! A band is drawn with two extra rows above and below
//! ([`GAP_FILL_REACH`]) so that its first and last rows see both sides;
//! pieces within [`GAP_FILL_REACH`] pixels of the image's left or right
//! side keep the dense cut, since past that side nothing is drawn.
//!
//! Cost: O(pixels of the band's box): the spanning and surround tests in
//! lanes over whole rows, the fill itself only at the pixels it flags.
//!
//! Based on: the screen-space hole filling of point-based renderers, which
//! complete a sparse set of splats by an image pass.

use std::ops::Range;

use crate::fixed::Z_FAR;
use crate::raster::band::{Band, GapScratch, Sample, PATCH_SAMPLE};
use crate::raster::band_box::PixelBox;

/// Pixels the pass reads on each side of a pixel along a direction: the
/// rows a band draws above and below its own with the gap fill on (its
/// apron), and the columns a piece keeps from the image's left and right
/// sides to take the sparser cut.
pub(crate) const GAP_FILL_REACH: i32 = 2;

/// Largest depth difference (fixed-point units, of [`Z_FAR`] over the
/// frame's depth range) between the two sides of a gap: 1/64 of the range.
pub(crate) const GAP_DEPTH_TOLERANCE: i32 = Z_FAR >> 6;

/// Largest depth difference between the sides that surround a pixel and
/// the nearest of them: 1/8 of the range. Looser than
/// [`GAP_DEPTH_TOLERANCE`]: a slanted surface's sides four pixels apart
/// differ by more than 1/64 of the range, and a surrounded pixel is
/// replaced only where it is empty or behind all of them.
pub(crate) const GAP_SURROUND_TOLERANCE: i32 = Z_FAR >> 3;

/// Fills the gaps of `band`'s pixels in `b` (image rows and columns, the
/// rows within the band and its apron), reading the rows and columns around
/// them. Inlined so that it runs with the band's instruction set
/// ([`crate::isa`]).
#[inline(always)]
pub(crate) fn fill_band_gaps(band: &mut Band, b: PixelBox) {
    let (first, _) = band.buffer_rows();
    let cols = b.x0 as usize..b.x1 as usize;
    let rows = (b.y0 - first) as usize..(b.y1 - first) as usize;
    let width = band.width as usize;
    let (px, scratch) = band.buffer_and_scratch();
    let tolerances = (GAP_DEPTH_TOLERANCE, GAP_SURROUND_TOLERANCE);
    fill_gaps(px, width, (cols, rows), tolerances, scratch);
}

/// [`GAP_FILL_REACH`] as an index step.
const REACH: usize = GAP_FILL_REACH as usize;

/// The four directions of the opposite pairs, as (column, row) steps.
const DIRECTIONS: [(isize, isize); 4] = [(1, 0), (0, 1), (1, 1), (1, -1)];

/// Fills the gaps (see the module header) of the box of columns `cols` and
/// rows `rows` (counted from the buffer's first row) of `px` (`width`
/// wide), all but its two outer rows, which it reads as neighbours only;
/// past the box's sides nothing is drawn. Inlined so that
/// it runs with the band's instruction set ([`crate::isa`]).
#[inline(always)]
pub(crate) fn fill_gaps(
    px: &mut [Sample],
    width: usize,
    (cols, rows): (Range<usize>, Range<usize>),
    (tol, loose): (i32, i32),
    s: &mut GapScratch,
) {
    let edge = 2 * REACH + 1;
    // Why not `Range::len`: it cost 0.46 M instructions per bunny 1000²
    // frame in the lanes below (callgrind).
    if cols.end < cols.start + edge || rows.end < rows.start + edge {
        return;
    }
    let n = cols.end - cols.start;
    // A row's drawn depths with REACH empty entries more on each side
    // (past the box nothing is drawn, and those pixels are not cleared).
    let depths = |px: &[Sample], r: usize, out: &mut Vec<i32>| {
        let row = &px[r * width + cols.start..r * width + cols.end];
        out.clear();
        out.extend([Z_FAR; REACH]);
        out.extend(row.iter().map(|s| s.depth));
        out.extend([Z_FAR; REACH]);
    };
    for k in 0..edge - 1 {
        depths(px, rows.start + k, &mut s.rows[k + 1]);
    }
    s.flags.resize(n, 0);
    let place = Place {
        width,
        x0: cols.start as isize,
    };
    for r in rows.start + REACH..rows.end - REACH {
        s.rows.rotate_left(1);
        depths(px, r + REACH, &mut s.rows[edge - 1]);
        if !flag_row(&s.rows, (tol, loose), &mut s.flags) {
            continue;
        }
        for k in 0..n {
            if s.flags[k] == 0 {
                continue;
            }
            let at = Neighbourhood {
                rows: &s.rows,
                place,
                k,
                r,
            };
            if s.flags[k] == SURROUNDED {
                fill_from_nearest(px, at, loose);
            } else {
                let direction = DIRECTIONS[s.flags[k] as usize - 1];
                fill_pixel(px, at, direction, tol);
            }
        }
    }
}

/// Where the columns of a box lie in the band's buffer.
#[derive(Debug, Clone, Copy)]
struct Place {
    width: usize,
    x0: isize,
}

impl Place {
    /// The buffer index of column `k` of the box (counted from its first)
    /// in buffer row `r`.
    #[inline(always)]
    fn index(self, k: isize, r: usize) -> usize {
        r * self.width + (self.x0 + k) as usize
    }
}

/// One pixel of the pass: its column `k` of the box and buffer row `r`,
/// with the drawn depths around it (`rows`, see [`flag_row`]).
#[derive(Clone, Copy)]
struct Neighbourhood<'a> {
    rows: &'a [Vec<i32>; 5],
    place: Place,
    k: usize,
    r: usize,
}

impl Neighbourhood<'_> {
    /// The drawn depth `(dx, dy)` steps away (`rows` hold REACH entries
    /// more on each side than the box).
    #[inline(always)]
    fn depth(self, dx: isize, dy: isize) -> i32 {
        let column = (self.k + REACH) as isize + dx;
        self.rows[(REACH as isize + dy) as usize][column as usize]
    }

    /// The buffer index of the pixel `(dx, dy)` steps away.
    #[inline(always)]
    fn index(self, (dx, dy): (isize, isize)) -> usize {
        let row = self.r.wrapping_add_signed(dy);
        self.place.index(self.k as isize + dx, row)
    }
}

/// Whether the sides `a` and `c` of a pixel at depth `here` span it: both
/// drawn, within `tol` of each other, and the pixel empty or behind both
/// by more than a quarter of `tol`.
#[inline(always)]
fn spans(a: i32, c: i32, here: i32, tol: i32) -> bool {
    let far = a.max(c);
    far < Z_FAR && (a - c).abs() <= tol && (here == Z_FAR || far + (tol >> 2) < here)
}

/// Code of [`flag_row`] for a pixel that no pair spans but whose sides
/// surround it ([`surround`]): filled from its nearest neighbour.
const SURROUNDED: u8 = DIRECTIONS.len() as u8 + 1;

/// Flags each pixel `k` of the middle row of `rows` (whose entries start
/// REACH columns before the pixels): where pairs of sides span it
/// ([`spans`]), with the direction of [`DIRECTIONS`] whose farther side is
/// nearest (`flags[k]`, 1-based, the first on a tie); else, where its
/// sides surround it ([`surround`]) and it is empty or behind all of them
/// by more than a quarter of `tol`, with [`SURROUNDED`]; 0 elsewhere.
/// Returns whether any pixel is flagged. A side is the nearer of the two
/// pixels one and two steps away. Hot kernel: one pass of lanes over the
/// row.
#[inline(always)]
fn flag_row(rows: &[Vec<i32>; 5], (tol, loose): (i32, i32), flags: &mut [u8]) -> bool {
    let m = rows[2].len() - 2 * REACH;
    // Column `k + dx` of row `dy` (both from -2), as a slice of length m:
    // equal lengths, so the loop runs without bounds checks, in lanes.
    let at = |dx: isize, dy: isize| {
        let from = (REACH as isize + dx) as usize;
        &rows[(REACH as isize + dy) as usize][from..from + m]
    };
    let here = at(0, 0);
    let (w1, w2, e1, e2) = (at(-1, 0), at(-2, 0), at(1, 0), at(2, 0));
    let (s1, s2, n1, n2) = (at(0, -1), at(0, -2), at(0, 1), at(0, 2));
    let (sw1, sw2, ne1, ne2) = (at(-1, -1), at(-2, -2), at(1, 1), at(2, 2));
    let (se1, se2, nw1, nw2) = (at(1, -1), at(2, -2), at(-1, 1), at(-2, 2));
    let out = &mut flags[..m];
    let mut any = 0u8;
    for k in 0..m {
        let h = here[k];
        // The sides counterclockwise from across (east).
        let sides = [
            e1[k].min(e2[k]),
            ne1[k].min(ne2[k]),
            n1[k].min(n2[k]),
            nw1[k].min(nw2[k]),
            w1[k].min(w2[k]),
            sw1[k].min(sw2[k]),
            s1[k].min(s2[k]),
            se1[k].min(se2[k]),
        ];
        let mut code = nearest_span(&sides, h, tol);
        let (surrounded, farthest) = surround(&sides, loose);
        let surrounded = surrounded && (h == Z_FAR || farthest + (tol >> 2) < h);
        code = if code == 0 && surrounded {
            SURROUNDED
        } else {
            code
        };
        out[k] = code;
        any |= code;
    }
    any != 0
}

/// The direction of [`DIRECTIONS`] (1-based, the first on a tie; 0 for
/// none) whose pair of `sides` (counterclockwise from east) spans a pixel
/// of depth `h` ([`spans`], `tol`) with the nearest farther side: a pixel
/// between two surfaces takes the near one.
#[inline(always)]
fn nearest_span(sides: &[i32; 8], h: i32, tol: i32) -> u8 {
    // Each direction's farther side where its pair spans (else MAX).
    let far = |a: i32, c: i32| {
        if spans(a, c, h, tol) {
            a.max(c)
        } else {
            i32::MAX
        }
    };
    let fars = [
        far(sides[4], sides[0]),
        far(sides[6], sides[2]),
        far(sides[5], sides[1]),
        far(sides[7], sides[3]),
    ];
    let (mut code, mut best) = ((fars[0] != i32::MAX) as u8, fars[0]);
    for (d, &f) in fars.iter().enumerate().skip(1) {
        let nearer = f < best;
        code = if nearer { d as u8 + 1 } else { code };
        best = if nearer { f } else { best };
    }
    code
}

/// Whether the `sides` (counterclockwise, one per 45°) within `loose` of
/// the nearest surround the pixel, leaving no closed half-plane through it
/// empty (no three consecutive directions without one: a straight outline
/// leaves five), and the farthest of those sides.
#[inline(always)]
fn surround(sides: &[i32; 8], loose: i32) -> (bool, i32) {
    let near = sides.iter().fold(Z_FAR, |m, &d| m.min(d));
    let limit = near.saturating_add(loose).min(Z_FAR - 1);
    let (mut missing, mut farthest) = (0u32, near);
    for (d, &side) in sides.iter().enumerate() {
        let outside = side > limit;
        missing |= (outside as u32) << d;
        farthest = if outside {
            farthest
        } else {
            farthest.max(side)
        };
    }
    let twice = missing | missing << 8;
    let runs = twice & twice >> 1 & twice >> 2;
    (runs & 0xff == 0, farthest)
}

/// Fills the pixel `at` of `px` from the pair of sides along `(dx, dy)`,
/// which spans it, at the pair's mean depth: the sample of its closer side
/// (the nearer on a tie), or where both sides are sub-nodes of one cell,
/// the sub-node between them.
#[inline(always)]
fn fill_pixel(px: &mut [Sample], at: Neighbourhood<'_>, (dx, dy): (isize, isize), tol: i32) {
    // A side: its depth, its pixel's step and how many steps away that is
    // (the first pixel if it is drawn and not behind the second by more
    // than `tol`).
    let side = |dx: isize, dy: isize| {
        let (one, two) = (at.depth(dx, dy), at.depth(2 * dx, 2 * dy));
        if one < Z_FAR && one <= two.saturating_add(tol) {
            (one, (dx, dy), 1)
        } else {
            (two, (2 * dx, 2 * dy), 2)
        }
    };
    let ((a, at_a, da), (c, at_c, dc)) = (side(dx, dy), side(-dx, -dy));
    let ((near, dn), (other, d_other)) = if (da, a) <= (dc, c) {
        ((at_a, da), (at_c, dc))
    } else {
        ((at_c, dc), (at_a, da))
    };
    let (mut sample, beyond) = (px[at.index(near)], px[at.index(other)]);
    sample.depth = a / 2 + c / 2;
    let (w0, w2) = (sample.w0(), sample.w2());
    if w2 & PATCH_SAMPLE != 0 && w2 == beyond.w2() && w0 >> 16 == beyond.w0() >> 16 {
        sample.set_w0(between(w0, beyond.w0(), dn as u32, d_other as u32));
    }
    px[at.index((0, 0))] = sample;
}

/// Fills the pixel `at` of `px`, which its sides surround ([`surround`]),
/// with the sample of its nearest drawn neighbour one step away (within
/// `loose` of the nearest two steps away), else two steps away, at that
/// neighbour's depth.
#[inline(always)]
fn fill_from_nearest(px: &mut [Sample], at: Neighbourhood<'_>, loose: i32) {
    let nearest = |step: isize| {
        let ring = DIRECTIONS
            .iter()
            .flat_map(|&(dx, dy)| [(dx, dy), (-dx, -dy)]);
        let steps = ring.map(|(dx, dy)| (step * dx, step * dy));
        steps
            .min_by_key(|&(dx, dy)| at.depth(dx, dy))
            .unwrap_or((0, 0))
    };
    let (one, two) = (nearest(1), nearest(2));
    let near_one = at.depth(one.0, one.1);
    let from = if near_one < Z_FAR && near_one <= at.depth(two.0, two.1).saturating_add(loose) {
        one
    } else {
        two
    };
    px[at.index((0, 0))] = px[at.index(from)];
}

/// The sub-node word of the cell both `near` and `far` lie in, at the
/// place `d_near / (d_near + d_far)` of the way from `near` to `far`
/// (rounded).
#[inline(always)]
fn between(near: u32, far: u32, d_near: u32, d_far: u32) -> u32 {
    let part = |w: u32, shift: u32| (w >> shift) & 0xff;
    let mix = |shift: u32| {
        let (p, q) = (part(near, shift), part(far, shift));
        (p * d_far + q * d_near + (d_near + d_far) / 2) / (d_near + d_far)
    };
    near & 0xffff_0000 | mix(8) << 8 | mix(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::raster::cell_bilinear::sub_word;

    fn band(width: usize, rows: usize) -> Vec<Sample> {
        vec![Sample::EMPTY; width * rows]
    }

    fn drawn(depth: i32, tag: u32) -> Sample {
        Sample {
            depth,
            w1: 0,
            words: tag as u64,
        }
    }

    fn fill(px: &mut [Sample], width: usize) {
        let whole = (0..width, 0..px.len() / width);
        let tolerances = (GAP_DEPTH_TOLERANCE, GAP_SURROUND_TOLERANCE);
        fill_gaps(px, width, whole, tolerances, &mut GapScratch::default());
    }

    /// Which pixels of `px` are drawn, row by row.
    fn coverage(px: &[Sample], width: usize) -> Vec<Vec<bool>> {
        px.chunks(width)
            .map(|row| row.iter().map(|s| s.depth < Z_FAR).collect())
            .collect()
    }

    #[test]
    fn a_lattice_with_gaps_closes_within_its_outline_and_only_there() {
        // Sub-nodes of one cell every second pixel over the square 4..=12,
        // then columns three pixels apart (two-pixel gaps) over 4..=13.
        let (w, h) = (18, 18);
        let square = |v: usize| (4..=12).contains(&v);
        let mut px = band(w, h);
        for r in (4..=12).step_by(2) {
            for x in (4..=12).step_by(2) {
                let sub = sub_word(1, 2, x as u32 / 2, r as u32 / 2);
                px[r * w + x] = drawn(1000 + x as i32, sub);
                px[r * w + x].set_words(sub, PATCH_SAMPLE | 5);
            }
        }
        fill(&mut px, w);
        let want: Vec<Vec<bool>> = (0..h)
            .map(|r| (0..w).map(|x| square(r) && square(x)).collect())
            .collect();
        assert_eq!(coverage(&px, w), want);
        // Between two sub-nodes of the cell: the sub-node between them, at
        // the mean depth of the two.
        let filled = px[4 * w + 5];
        assert_eq!((filled.depth, filled.w0()), (1005, sub_word(1, 2, 3, 2)));

        let mut columns = band(w, h);
        for r in 4..=12 {
            for x in [4, 7, 10, 13] {
                columns[r * w + x] = drawn(1000, 1);
            }
        }
        fill(&mut columns, w);
        let want: Vec<Vec<bool>> = (0..h)
            .map(|r| (0..w).map(|x| square(r) && (4..=13).contains(&x)).collect())
            .collect();
        assert_eq!(coverage(&columns, w), want);
    }

    #[test]
    fn a_surface_seen_through_a_gap_gives_way_to_the_near_one_and_depth_steps_stay() {
        let (w, h) = (7, 5);
        let at = |x: usize, r: usize| r * w + x;
        let row = |px: &mut [Sample], depth: i32, tag: u32| {
            for x in 0..w {
                px[at(x, 2)] = drawn(depth, tag);
            }
        };
        // A pixel showing a surface far behind its row: replaced.
        let mut through = band(w, h);
        row(&mut through, 100, 1);
        through[at(3, 2)] = drawn(Z_FAR / 2, 2);
        fill(&mut through, w);
        assert_eq!(through[at(3, 2)], drawn(100, 1));
        // A pixel just behind its row (a crease, within a quarter of the
        // tolerance): kept.
        let mut crease = band(w, h);
        row(&mut crease, 100, 1);
        let dent = drawn(100 + GAP_DEPTH_TOLERANCE / 8, 3);
        crease[at(3, 2)] = dent;
        fill(&mut crease, w);
        assert_eq!(crease[at(3, 2)], dent);
        // A gap between two surfaces far apart in depth: kept.
        let mut step = band(w, h);
        step[at(2, 2)] = drawn(100, 1);
        step[at(4, 2)] = drawn(100 + 2 * GAP_SURROUND_TOLERANCE, 1);
        fill(&mut step, w);
        assert_eq!(step[at(3, 2)], Sample::EMPTY);
        // An empty pixel between a far surface across and a near one up and
        // down takes the near one, though across comes first.
        let mut two = band(w, h);
        row(&mut two, Z_FAR / 2, 2);
        two[at(3, 2)] = Sample::EMPTY;
        two[at(3, 1)] = drawn(100, 1);
        two[at(3, 3)] = drawn(100, 1);
        fill(&mut two, w);
        assert_eq!(two[at(3, 2)], drawn(100, 1));
    }

    #[test]
    fn a_pixel_no_pair_spans_closes_where_its_sides_surround_it() {
        // A rotated sparse lattice as the sphere's magnified cells leave it
        // (traced at 1000²): the centre pixel's pairs all miss, since its
        // right, upper and lower neighbours are gaps too. The surface is
        // slanted: a step across differs by half the pairs' tolerance.
        let pattern = [
            "#..######.###",
            "##..###.#####",
            "#.##.#.####..",
            ".####..######",
            "..####...##.#",
            "##.##.#######",
            "###..#####.##",
            "####..#######",
            "###.##.#.####",
        ];
        let (w, h) = (pattern[0].len(), pattern.len());
        let mut px = band(w, h);
        for (r, line) in pattern.iter().enumerate() {
            for (x, c) in line.bytes().enumerate() {
                if c == b'#' {
                    let depth = 1000 + x as i32 * GAP_DEPTH_TOLERANCE / 2;
                    px[r * w + x] = drawn(depth, r as u32);
                }
            }
        }
        fill(&mut px, w);
        for r in 2..h - 2 {
            for x in 2..w - 2 {
                assert!(px[r * w + x].depth < Z_FAR, "({x}, {r})");
            }
        }
        // Past a straight outline nothing grows: a drawn half-plane with
        // every other pixel of its first row missing.
        let (w, h) = (9, 9);
        let mut half = band(w, h);
        for r in 4..h {
            for x in 0..w {
                if r > 4 || x % 2 == 0 {
                    half[r * w + x] = drawn(1000, 1);
                }
            }
        }
        fill(&mut half, w);
        let drawn_rows: Vec<bool> = (0..h).map(|r| half[r * w + 4].depth < Z_FAR).collect();
        assert_eq!(
            drawn_rows,
            [false, false, false, false, true, true, true, true, true]
        );
    }
}
