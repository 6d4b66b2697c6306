//! Pixel-sized bilinear cells drawn by pixel-centre coverage, cheaply:
//! each drawn cell is two triangles `(c00, c10, c11)` and `(c00, c11, c01)`
//! on the piece's 16-fractional-bit node positions, and writes exactly the
//! pixel centres they hold (integer edge functions, top-left rule), with
//! its place in the cell for the resolve.
//!
//! Why: the sub-node path ([`crate::raster::cell_bilinear`]) must keep its
//! lattice under a pixel in each axis, so cells of 0.6–2 px are cut 2–3
//! per side and a pixel takes about ten samples (bunny 500²: 746k nodes
//! and sub-nodes for 69k covered pixels). Here a cell costs one box test
//! and, when its box holds a pixel centre (about one in two at level 0,
//! always above 1 px), the set-up of two triangles; a pixel costs its
//! edge functions. The planner pairs this path with a coarser mip level
//! ([`crate::RenderOptions::centre_limit`]), so cells of 1–2 px draw
//! without sub-nodes.
//!
//! Coverage: two cells of a piece share their corner nodes bit for bit, so
//! a shared side is the same integer line in both, walked in opposite
//! directions; the top-left rule (a centre exactly on a side belongs to
//! the side whose direction points down, or left when level) gives it to
//! exactly one. Triangles turning the other way on screen (mirrored
//! patches, folds) are turned round first. So the cells of a piece write
//! every pixel centre inside them once (tested on jittered lattices).
//!
//! Interpolation: a pixel records the point of its cell it shows, `(u, v)`
//! from the triangle's barycentric weights (which the edge functions give
//! up to one reciprocal of the area per triangle), rounded to
//! [`CENTRE_STEPS`] steps per side; the draw item says its cut is
//! `CENTRE_STEPS × CENTRE_STEPS`, so the resolve pass interpolates the
//! cell's corners bilinearly there as it does at a sub-node, unchanged.
//! Depth is interpolated at the pixel centre from the triangle's corners.

use std::hint::black_box;

use crate::fixed::{Node, XY_FRAC_BITS};
use crate::raster::band::{keep_nearer, patch_word, BandTarget};

/// Steps per cell side of the recorded place `(u, v)` of a pixel centre
/// (the `nu × nv` the resolve's weight table reads): at most half a step
/// (1/32 of a cell, 0.05 px in a 1.5 px cell) from the exact place.
pub(crate) const CENTRE_STEPS: u32 = 16;

/// How far (position units) the sides of a pixel-sized cell on the
/// piece's outline (toward an undrawn cell or past the piece) are pushed
/// out: half a pixel. Why: two patches' borders do not quite meet
/// everywhere, which the sub-nodes' half-pixel reach closed; with no
/// margin the bunny's eval counted 0.22 % holes. Cells of patches with a
/// colour grid take less ([`crate::raster::centre_piece::CentreStyle`]).
pub(crate) const CELL_MARGIN: i32 = 1 << (XY_FRAC_BITS - 1);

/// Outline sides of a cell (bits of [`Cell::new`]'s `outline`).
pub(super) const BOTTOM: u8 = 1;
pub(super) const RIGHT: u8 = 2;
pub(super) const TOP: u8 = 4;
pub(super) const LEFT: u8 = 8;

/// Half a pixel in position units (a pixel centre's fraction).
const HALF: i32 = 1 << (XY_FRAC_BITS - 1);

/// The first and last pixel (inclusive) whose centre lies in `[lo, hi]`
/// (position units), clamped to `[min, max]`.
#[inline(always)]
fn centre_span(lo: i32, hi: i32, min: i32, max: i32) -> (i32, i32) {
    let first = (lo - HALF + (1 << XY_FRAC_BITS) - 1) >> XY_FRAC_BITS;
    let last = (hi - HALF) >> XY_FRAC_BITS;
    (first.max(min), last.min(max))
}

/// The outline sides of a cell (bits [`BOTTOM`], [`RIGHT`], [`TOP`],
/// [`LEFT`]) and how far (position units) they are pushed out.
#[derive(Debug, Clone, Copy)]
pub(super) struct Sides {
    /// The sides on the piece's outline.
    pub(super) outline: u8,
    /// How far they are pushed out (position units).
    pub(super) margin: i32,
}

/// Draws one cell with corners `c` (`(0,0)`, `(1,0)`, `(0,1)`, `(1,1)`)
/// whose sub-word of `(0, 0)` is `sub0`, its outline `sides` pushed out:
/// the pixel centres of its box, each tested against its two triangles.
/// Why set up only when the box holds a pixel centre: most cells of a
/// coarse-enough level hold one or two, finer ones often none. Cells that
/// do not fold (most of them) take [`Lazy`]: only the edges a centre
/// needs, and interior ones no margins.
#[inline(always)]
pub(super) fn draw_cell(t: &mut BandTarget<'_>, c: [&Node; 4], sides: Sides, sub0: u32, item: u32) {
    let Some(span) = cell_box(t, c, sides) else {
        return;
    };
    let Sides { outline, margin } = sides;
    let o = (c[0][0], c[0][1]);
    // Why a box of one centre apart: it is the most common at the levels
    // this path draws, and a lazy set-up tested once costs the least;
    // bigger boxes step precomputed edges along their centres instead.
    if span.px0 == span.px1 && span.py0 == span.py1 {
        let (px, py) = (span.px0, span.py0);
        if outline == 0 {
            if let Some(cell) = Lazy::<false>::new(c, 0, margin) {
                return draw_centre(t, &cell, px, py, o, sub0, item);
            }
        } else if let Some(cell) = Lazy::<true>::new(c, outline, margin) {
            return draw_centre(t, &cell, px, py, o, sub0, item);
        }
        return draw_centre(t, &Cell::new(c, outline, margin), px, py, o, sub0, item);
    }
    if outline == 0 {
        if let Some(cell) = Lazy::<false>::new(c, 0, margin) {
            return draw_centres(t, c, span, sub0, item, &cell);
        }
    } else if (span.px1 - span.px0 + 1) * (span.py1 - span.py0 + 1) <= LAZY_OUTLINE_CENTRES {
        if let Some(cell) = Lazy::<true>::new(c, outline, margin) {
            return draw_centres_unstepped(t, c, span, sub0, item, &cell);
        }
    }
    draw_centres(t, c, span, sub0, item, &Cell::new(c, outline, margin));
}

/// Most centres in the box of an outline cell that is tested lazily and
/// unstepped ([`draw_centres_unstepped`]): below that, the six edges'
/// set-up (about 275 instructions) costs more than the lazy tests (about
/// 35 each against 12 stepped).
const LAZY_OUTLINE_CENTRES: i32 = 6;

/// The pixel centres of the band that the box of a cell with corners `c`
/// holds, grown at the ends of its `outline` sides; `None` when empty.
/// Why two copies: an interior cell's box needs no growth, and most
/// drawn cells are interior.
#[inline(always)]
fn cell_box(t: &BandTarget<'_>, c: [&Node; 4], sides: Sides) -> Option<CentreBox> {
    if sides.outline == 0 {
        grown_box(t, c, [0; 4])
    } else {
        grown_box(t, c, corner_growth(sides))
    }
}

/// The pixel centres of the band that the box of the corners `c`, each
/// grown by `g` (position units), holds; `None` when empty.
#[inline(always)]
fn grown_box(t: &BandTarget<'_>, c: [&Node; 4], g: [i32; 4]) -> Option<CentreBox> {
    let x_lo = (c[0][0] - g[0])
        .min(c[1][0] - g[1])
        .min(c[2][0] - g[2])
        .min(c[3][0] - g[3]);
    let x_hi = (c[0][0] + g[0])
        .max(c[1][0] + g[1])
        .max(c[2][0] + g[2])
        .max(c[3][0] + g[3]);
    let (px0, px1) = centre_span(x_lo, x_hi, 0, t.width - 1);
    if px0 > px1 {
        return None;
    }
    let y_lo = (c[0][1] - g[0])
        .min(c[1][1] - g[1])
        .min(c[2][1] - g[2])
        .min(c[3][1] - g[3]);
    let y_hi = (c[0][1] + g[0])
        .max(c[1][1] + g[1])
        .max(c[2][1] + g[2])
        .max(c[3][1] + g[3]);
    let (py0, py1) = centre_span(y_lo, y_hi, t.y0, t.y0 + t.rows - 1);
    (py0 <= py1).then_some(CentreBox { px0, px1, py0, py1 })
}

/// How far (position units) the box of a cell with outline `sides` grows
/// around each corner (`c00`, `c10`, `c01`, `c11`): the margin at the
/// ends of an outline side, 0 elsewhere. Why not the whole box: an
/// outline side's pushed-out pixels lie within the margin of that side,
/// so a box grown on every side held about four centres per outline cell
/// where it needs about two (bunny 500² `--centre-limit 2`: 259k centre
/// tests in outline cells per frame before).
#[inline(always)]
fn corner_growth(sides: Sides) -> [i32; 4] {
    let at = |bits: u8| {
        if sides.outline & bits != 0 {
            sides.margin
        } else {
            0
        }
    };
    [
        at(BOTTOM | LEFT),
        at(BOTTOM | RIGHT),
        at(TOP | LEFT),
        at(TOP | RIGHT),
    ]
}

/// The pixel centres `px0..=px1 × py0..=py1` of a cell's box.
#[derive(Clone, Copy)]
struct CentreBox {
    px0: i32,
    px1: i32,
    py0: i32,
    py1: i32,
}

/// A cell set up for pixel-centre tests.
trait CentreTest {
    /// Depth and recorded place `(a, b)` at the pixel centre `(x, y)`
    /// (relative to `c00`) when the cell holds it.
    fn at(&self, x: i64, y: i64) -> Option<(i32, u32, u32)>;
}

/// Writes the centres of `span` that `cell` takes and the depth test
/// passes. Why a trait, not a closure: the closure was not inlined, a
/// call per centre (bunny 500² `--centre-limit 2`: 2.3 M per frame).
#[inline(always)]
fn draw_centres<C: CentreTest>(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    span: CentreBox,
    sub0: u32,
    item: u32,
    cell: &C,
) {
    let o = (c[0][0], c[0][1]);
    // Why exclusive ranges: an inclusive one costs a flag and a branch
    // per step (callgrind).
    for py in span.py0..span.py1 + 1 {
        for px in span.px0..span.px1 + 1 {
            draw_centre(t, cell, px, py, o, sub0, item);
        }
    }
}

/// Writes the centres of `span` that `cell` takes, as [`draw_centres`]
/// does, but tests each centre afresh. Why `black_box`: without it the
/// compiler steps every edge function along the box, and the set-up of
/// that stepping (hoisted out of the loops) costs more than the few
/// tests of a small box.
#[inline(always)]
fn draw_centres_unstepped<C: CentreTest>(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    span: CentreBox,
    sub0: u32,
    item: u32,
    cell: &C,
) {
    let o = (c[0][0], c[0][1]);
    for py in span.py0..span.py1 + 1 {
        for px in span.px0..span.px1 + 1 {
            let (px, py) = black_box((px, py));
            draw_centre(t, cell, px, py, o, sub0, item);
        }
    }
}

/// Writes the pixel `(px, py)` when `cell` (first corner at `o`) takes
/// its centre and the depth test passes.
#[inline(always)]
fn draw_centre<C: CentreTest>(
    t: &mut BandTarget<'_>,
    cell: &C,
    px: i32,
    py: i32,
    o: (i32, i32),
    sub0: u32,
    item: u32,
) {
    let x = ((px as i64) << XY_FRAC_BITS) + HALF as i64 - o.0 as i64;
    let y = ((py as i64) << XY_FRAC_BITS) + HALF as i64 - o.1 as i64;
    let Some((z, a, b)) = cell.at(x, y) else {
        return;
    };
    let s = &mut t.px[((py - t.y0) * t.width + px) as usize];
    keep_nearer(s, z, patch_word(sub0 + (a << 8) + b, item));
}

/// Draws one cell as [`draw_cell`] does but always through the general
/// set-up of six edge functions ([`Cell`]): the reference the lazy set-up
/// is tested against.
#[cfg(test)]
pub(super) fn draw_cell_general(
    t: &mut BandTarget<'_>,
    c: [&Node; 4],
    sides: Sides,
    sub0: u32,
    item: u32,
) {
    if let Some(span) = cell_box(t, c, sides) {
        let cell = Cell::new(c, sides.outline, sides.margin);
        draw_centres(t, c, span, sub0, item, &cell);
    }
}

/// Whether a centre exactly on a side of direction `d` (oriented by its
/// triangle) belongs to it: the top-left rule, the side pointing down, or
/// left when level.
#[inline(always)]
fn owns(d: [i64; 2]) -> bool {
    d[1] > 0 || (d[1] == 0 && d[0] < 0)
}

/// Whether the oriented edge value `v` of a side of direction `d` takes
/// its centre. Why test the tie apart: it is rare, so the top-left rule
/// costs nothing on most centres.
#[inline(always)]
fn holds(v: i64, d: [i64; 2]) -> bool {
    v > 0 || (v == 0 && owns(d))
}

/// A cell whose two triangles turn the same way, set up lazily: corners
/// relative to `c00` with the orientation folded in, so that each edge
/// value is one cross product computed only when a centre needs it (the
/// diagonal, then the two other sides of the triangle on its side). With
/// `GROW` its outline sides are pushed out by their margins and depths
/// are kept within the corners' (as [`Cell`] does); without, it is an
/// interior cell and needs neither. Gives the same pixels as [`Cell`]
/// (tested).
pub(super) struct Lazy<const GROW: bool> {
    /// `c10`, `c11`, `c01` relative to `c00`, times the orientation.
    p1: [i64; 2],
    p3: [i64; 2],
    p2: [i64; 2],
    /// Twice the lower and upper triangles' areas, positive.
    area: [i64; 2],
    /// The unoriented corners (edge values are taken at unoriented
    /// offsets and oriented directions).
    q1: [i64; 2],
    q3: [i64; 2],
    /// With `GROW`, the margins of the bottom, right, top and left sides
    /// (0 where the side is not on the outline).
    grow: [i64; 4],
    /// Depth of `c00`, and `c10`, `c01`, `c11` minus it.
    z0: i32,
    dz: [f32; 3],
    /// With `GROW`, the corners' nearest and farthest depths.
    z_range: [i32; 2],
}

impl<const GROW: bool> Lazy<GROW> {
    /// The cell of corners `c` with its `outline` sides pushed out by
    /// `margin` (only with `GROW`), or `None` when its triangles do not
    /// turn the same way (a fold) or both are flat.
    #[inline(always)]
    pub(super) fn new(c: [&Node; 4], outline: u8, margin: i32) -> Option<Self> {
        let rel = |n: &Node| [n[0] as i64 - c[0][0] as i64, n[1] as i64 - c[0][1] as i64];
        let (q1, q2, q3) = (rel(c[1]), rel(c[2]), rel(c[3]));
        let [al, au] = triangle_areas(c);
        let s = al.signum();
        if s == 0 || au.signum() != s {
            return None;
        }
        let or = |p: [i64; 2]| [p[0] * s, p[1] * s];
        let z0 = c[0][2];
        let (mut grow, mut z_range) = ([0; 4], [0; 2]);
        if GROW {
            // As [`Edge::new`]: `(|dx| + |dy|)` times the margin.
            let side = |d: [i64; 2], bit: u8| {
                (outline & bit != 0) as i64 * (d[0].abs() + d[1].abs()) * margin as i64
            };
            let sub = |a: [i64; 2], b: [i64; 2]| [a[0] - b[0], a[1] - b[1]];
            grow = [
                side(q1, BOTTOM),
                side(sub(q3, q1), RIGHT),
                side(sub(q2, q3), TOP),
                side(q2, LEFT),
            ];
            z_range = [
                z0.min(c[1][2]).min(c[2][2]).min(c[3][2]),
                z0.max(c[1][2]).max(c[2][2]).max(c[3][2]),
            ];
        }
        Some(Lazy {
            p1: or(q1),
            p3: or(q3),
            p2: or(q2),
            area: [al * s, au * s],
            q1,
            q3,
            grow,
            z0,
            dz: [c[1], c[2], c[3]].map(|n| (n[2] - z0) as f32),
            z_range,
        })
    }

    /// The depth `z0 + dz`; with `GROW` within the corners' depths (see
    /// [`Cell::depth`]), without the weights are within 0..=1.
    #[inline(always)]
    fn depth(&self, dz: f32) -> i32 {
        let z = self.z0.saturating_add(dz as i32);
        if GROW {
            z.clamp(self.z_range[0], self.z_range[1])
        } else {
            z
        }
    }

    /// The edge value `v` of side `k` (bottom, right, top, left) with its
    /// margin.
    #[inline(always)]
    fn grown(&self, v: i64, k: usize) -> i64 {
        if GROW {
            v + self.grow[k]
        } else {
            v
        }
    }
}

impl<const GROW: bool> CentreTest for Lazy<GROW> {
    /// The oriented edge values are cross products of a side's direction
    /// and `q` minus its start.
    #[inline(always)]
    fn at(&self, x: i64, y: i64) -> Option<(i32, u32, u32)> {
        let q = [x, y];
        let sub = |a: [i64; 2], b: [i64; 2]| [a[0] - b[0], a[1] - b[1]];
        let neg = |d: [i64; 2]| [-d[0], -d[1]];
        // The upper triangle's diagonal c00 -> c11; the lower one walks it
        // back, with the opposite value. The diagonal is never pushed out.
        let d = cross(self.p3, q);
        if holds(-d, neg(self.p3)) {
            // Lower: bottom c00 -> c10, right c10 -> c11.
            let e0 = cross(self.p1, q);
            let right = sub(self.p3, self.p1);
            let e1 = cross(right, sub(q, self.q1));
            if !holds(self.grown(e0, 0), self.p1) || !holds(self.grown(e1, 1), right) {
                return None;
            }
            // Weights of c10 and c11: the diagonal's and the bottom's.
            let inv = 1.0 / self.area[0] as f32;
            let (w1, w3) = (-d as f32 * inv, e0 as f32 * inv);
            let z = self.depth(w1 * self.dz[0] + w3 * self.dz[2]);
            return Some((z, place(w1 + w3), place(w3)));
        }
        // Else the upper triangle's diagonal holds the centre: of `d` and
        // `-d` one is positive, or both zero and the top-left rule gives
        // the centre to exactly one (the diagonal is not a point: area).
        // Upper: top c11 -> c01, left c01 -> c00.
        let top = sub(self.p2, self.p3);
        let e2 = -cross(self.p2, q);
        let e1 = cross(top, sub(q, self.q3));
        if !holds(self.grown(e2, 3), neg(self.p2)) || !holds(self.grown(e1, 2), top) {
            return None;
        }
        // Weights of c11 and c01: the left side's and the diagonal's.
        let inv = 1.0 / self.area[1] as f32;
        let (w3, w2) = (e2 as f32 * inv, d as f32 * inv);
        let z = self.depth(w2 * self.dz[1] + w3 * self.dz[2]);
        Some((z, place(w3), place(w3 + w2)))
    }
}

/// The cross product `a × b` (twice the signed area of `(0, a, b)`).
#[inline(always)]
fn cross(a: [i64; 2], b: [i64; 2]) -> i64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Twice the signed areas of the lower `(c00, c10, c11)` and upper
/// `(c00, c11, c01)` triangles of a cell with corners `c` (what [`Lazy::new`]
/// and [`Cell::new`] orient by): the cell folds when their signs differ.
#[inline(always)]
pub(super) fn triangle_areas(c: [&Node; 4]) -> [i64; 2] {
    let rel = |n: &Node| [n[0] as i64 - c[0][0] as i64, n[1] as i64 - c[0][1] as i64];
    let (q1, q2, q3) = (rel(c[1]), rel(c[2]), rel(c[3]));
    [cross(q1, q3), cross(q3, q2)]
}

/// One side of a triangle as an oriented edge function `a x + b y + c`
/// (positions relative to the cell's first corner): a pixel centre is on
/// the triangle's side of it when the value is `>= 0`. `c` includes the
/// outline margin and the top-left rule's bias; `k` is what they added,
/// so `value - k` is the plain edge function (the barycentric weight
/// times the area).
#[derive(Clone, Copy)]
struct Edge {
    a: i64,
    b: i64,
    c: i64,
    k: i64,
}

impl Edge {
    /// The side from `p` in direction `d` of a triangle of orientation
    /// `sign` (±1; 0 for a flat triangle, which covers nothing), pushed
    /// out by `margin` (position units; 0: not pushed).
    #[inline(always)]
    fn new(p: [i64; 2], d: [i64; 2], sign: i64, margin: i32) -> Edge {
        if sign == 0 {
            return Edge {
                a: 0,
                b: 0,
                c: -1,
                k: 0,
            };
        }
        let (dx, dy) = (d[0] * sign, d[1] * sign);
        // Top-left: a centre exactly on the side belongs to the direction
        // pointing down (or left when level), so to exactly one of the two
        // triangles that share it.
        let bias = !(dy > 0 || (dy == 0 && dx < 0)) as i64;
        // Outline sides take every pixel whose square reaches within the
        // margin of the side: `(|dx| + |dy|)` times it, no square root.
        let k = (dx.abs() + dy.abs()) * margin as i64 - bias;
        Edge {
            a: -dy,
            b: dx,
            c: dy * p[0] - dx * p[1] + k,
            k,
        }
    }

    #[inline(always)]
    fn at(&self, x: i64, y: i64) -> i64 {
        self.a * x + self.b * y + self.c
    }
}

/// A cell set up for pixel-centre tests, positions relative to its first
/// corner `c00`: the lower triangle `(c00, c10, c11)` and the upper one
/// `(c00, c11, c01)`, sharing the diagonal.
struct Cell {
    /// Lower: `c00 → c10`, `c10 → c11`, `c11 → c00`; upper: `c00 → c11`,
    /// `c11 → c01`, `c01 → c00` (each oriented by its triangle).
    lower: [Edge; 3],
    upper: [Edge; 3],
    /// `1 / |area|` of the lower and upper triangles (twice their areas).
    inv: [f32; 2],
    /// The triangles turn the same way (then the diagonal alone decides
    /// which one a centre may be in).
    same: bool,
    /// Depth of `c00`, and `c10`, `c01`, `c11` minus it.
    z0: i32,
    dz: [f32; 3],
    /// The corners' nearest and farthest depths.
    z_range: [i32; 2],
}

impl Cell {
    /// The cell of corners `c` with its `outline` sides pushed out by
    /// `margin`; a cell whose triangles turn opposite ways (a fold) pushes
    /// out every side.
    #[inline(always)]
    fn new(c: [&Node; 4], outline: u8, margin: i32) -> Cell {
        let rel = |n: &Node| [n[0] as i64 - c[0][0] as i64, n[1] as i64 - c[0][1] as i64];
        let (p1, p2, p3) = (rel(c[1]), rel(c[2]), rel(c[3]));
        let area = triangle_areas(c);
        let [sl, su] = area.map(i64::signum);
        let same = sl == su;
        let outline = if same {
            outline
        } else {
            BOTTOM | RIGHT | TOP | LEFT
        };
        let o = [0, 0];
        let neg = |d: [i64; 2]| [-d[0], -d[1]];
        let sub = |a: [i64; 2], b: [i64; 2]| [a[0] - b[0], a[1] - b[1]];
        let z0 = c[0][2];
        let inv = |a: i64| if a != 0 { 1.0 / a.abs() as f32 } else { 0.0 };
        let grow = |side: u8| if outline & side != 0 { margin } else { 0 };
        Cell {
            lower: [
                Edge::new(o, p1, sl, grow(BOTTOM)),
                Edge::new(p1, sub(p3, p1), sl, grow(RIGHT)),
                Edge::new(p3, neg(p3), sl, 0),
            ],
            upper: [
                Edge::new(o, p3, su, 0),
                Edge::new(p3, sub(p2, p3), su, grow(TOP)),
                Edge::new(p2, neg(p2), su, grow(LEFT)),
            ],
            inv: [inv(area[0]), inv(area[1])],
            same,
            z0,
            dz: [c[1], c[2], c[3]].map(|n| (n[2] - z0) as f32),
            z_range: [
                z0.min(c[1][2]).min(c[2][2]).min(c[3][2]),
                z0.max(c[1][2]).max(c[2][2]).max(c[3][2]),
            ],
        }
    }

    /// The depth `z0 + dz`, within the corners' depths. Why: a sliver
    /// triangle's weights may be far off 0..=1 at a centre its margin
    /// takes (an area of a few units), and the sum overflowed.
    #[inline(always)]
    fn depth(&self, dz: f32) -> i32 {
        let [lo, hi] = self.z_range;
        self.z0.saturating_add(dz as i32).clamp(lo, hi)
    }
}

impl CentreTest for Cell {
    #[inline(always)]
    fn at(&self, x: i64, y: i64) -> Option<(i32, u32, u32)> {
        let [l0, l1, l2] = &self.lower;
        let [u0, u1, u2] = &self.upper;
        let d = l2.at(x, y);
        // Of two triangles turning the same way, the diagonal's side
        // decides which one may hold the centre (the top-left rule gives a
        // centre on it to one of them).
        if d >= 0 || !self.same {
            let (e0, e1) = (l0.at(x, y), l1.at(x, y));
            if d >= 0 && e0 >= 0 && e1 >= 0 {
                // Weights of c10 and c11: the diagonal's and the bottom's.
                let w1 = (d - l2.k) as f32 * self.inv[0];
                let w3 = (e0 - l0.k) as f32 * self.inv[0];
                let z = self.depth(w1 * self.dz[0] + w3 * self.dz[2]);
                return Some((z, place(w1 + w3), place(w3)));
            }
            if self.same {
                return None;
            }
        }
        let (d, e1, e2) = (u0.at(x, y), u1.at(x, y), u2.at(x, y));
        if d >= 0 && e1 >= 0 && e2 >= 0 {
            // Weights of c11 and c01: the left side's and the diagonal's.
            let w3 = (e2 - u2.k) as f32 * self.inv[1];
            let w2 = (d - u0.k) as f32 * self.inv[1];
            let z = self.depth(w2 * self.dz[1] + w3 * self.dz[2]);
            return Some((z, place(w3), place(w3 + w2)));
        }
        None
    }
}

/// A place in the cell (0..=1) in [`CENTRE_STEPS`], rounded.
#[inline(always)]
fn place(s: f32) -> u32 {
    ((s * CENTRE_STEPS as f32 + 0.5) as u32).min(CENTRE_STEPS)
}
