//! Portal cells: which cells of a patch seen through an opening are drawn
//! from behind (`--cull auto`; docs/algorithms/render.md, "Open surfaces").
//!
//! A patch of an open surface shows its back only through an opening
//! ([`crate::plan::cull::portals_between`]): a line of sight from the eye
//! to a point on its back crosses a surface spanning one of the surface's
//! boundary loops, which lies inside that loop's sphere and slab. So the
//! point's pixel lies in the projection of the sphere's part inside the
//! slab. Per frame, each portal gets a screen box ([`portal_box`]: the
//! exact box of its sphere's projection met with that of the cylinder
//! holding the sphere inside the slab, widened by [`REGION_MARGIN_PX`] for
//! the rasterizer's reach and the trilinear projection's error); a portal
//! reaching in front of the near plane has none. Per patch "through
//! openings", the boxes of the portals it may be seen through are
//! collected ([`back_of_patch`]); the patch is then culled like a closed
//! one (whole when its normal cone faces away and the projection of its
//! box touches none of them, [`local_box_touches`]; else cell by cell)
//! except that a cell facing away whose screen box touches one of the
//! boxes is kept ([`keep_cells_in_regions`]). A patch seen through a
//! portal without a box is drawn whole, as before. Back faces kept are lit
//! two-sided as before.
//!
//! Conservative: a cell whose back may show through an opening is never
//! dropped. Cost: per frame, two quadratics and 32 projected corners per
//! portal; per patch through openings, the portal test per portal (as
//! before) and 8 projected corners when it faces away; per node of a piece
//! touching a region, an outcode per region.

use glam::{DVec3, Mat3, Vec3};

use spatch_format::Sides;

use crate::camera::View;
use crate::fixed::XY_ONE;
use crate::grid::CELL_DRAW;
use crate::options::Culling;
use crate::plan::cull::{back_culled, portals_between};
use crate::plan::split::NodeRange;
use crate::plan::work::FrameSetup;
use crate::prepare::mip::MipLevel;
use crate::prepare::patch::PreparedPatch;
use crate::prepare::scene::Portal;

/// A screen box in node position units (pixels with
/// [`crate::fixed::XY_FRAC_BITS`] fractional bits): `[x0, y0, x1, y1]`,
/// inclusive.
pub(crate) type ScreenBox = [i32; 4];

/// Pixels added on every side of a portal's projected sphere: the half
/// pixel a sub-node reaches past its cell, the trilinear projection's
/// error (at most 2 px, `piece.rs`), and rounding.
pub(crate) const REGION_MARGIN_PX: f64 = 3.0;

/// The pixel box `[x0, y0, x1, y1]` of the projection of the sphere
/// `(centre, radius)`, or `None` when it is not wholly in front of the
/// near plane. Exact: the box's side `x` is where the plane through the
/// eye of the points with `X = x W` touches the sphere, `|(r_x - x r_w)·c|
/// = R |r_x - x r_w|` with `c` the centre from the eye, a quadratic in `x`
/// whose two roots are the box's left and right sides (likewise `y`).
pub(crate) fn sphere_bounds(view: &View, centre: DVec3, radius: f64) -> Option<[f64; 4]> {
    let [rx, ry, rw] = view.clip_rows();
    let c = centre - view.eye;
    let w = rw.dot(c);
    let r2 = radius * radius;
    if w - radius * rw.length() < view.near {
        return None;
    }
    let lead = w * w - r2 * rw.length_squared();
    let range = |row: DVec3| {
        let a = row.dot(c);
        let half = a * w - r2 * row.dot(rw);
        let disc = half * half - lead * (a * a - r2 * row.length_squared());
        let root = disc.max(0.0).sqrt();
        ((half - root) / lead, (half + root) / lead)
    };
    let ((x0, x1), (y0, y1)) = (range(rx), range(ry));
    Some([x0, y0, x1, y1])
}

/// Sides of the polygon circumscribing each end disc of a portal's
/// cylinder ([`cylinder_bounds`]): 16 sides reach 2 % past the circle.
const DISC_SIDES: usize = 16;

/// The pixel box of the projection of the cylinder that holds the part of
/// the portal's sphere inside its slab (radius the sphere's, half-height
/// the slab's), or `None` when it is not wholly in front of the near
/// plane. Why: a loop seen at a slant projects to a thin ellipse, much
/// smaller than its sphere's disc. The cylinder is the convex hull of its
/// end discs, each held by a circumscribed polygon of [`DISC_SIDES`]
/// sides, so the box of the polygons' projected corners holds it.
fn cylinder_bounds(view: &View, portal: &Portal) -> Option<[f64; 4]> {
    let rows = view.clip_rows();
    let n = portal.normal.normalize();
    let (u, v) = n.any_orthonormal_pair();
    let reach = portal.radius / (std::f64::consts::PI / DISC_SIDES as f64).cos();
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for side in [-1.0, 1.0] {
        let centre = portal.centre + n * (side * portal.half_thickness) - view.eye;
        for k in 0..DISC_SIDES {
            let a = std::f64::consts::TAU * k as f64 / DISC_SIDES as f64;
            let p = centre + (u * a.cos() + v * a.sin()) * reach;
            let [x, y, w] = rows.map(|r| r.dot(p));
            if w.is_nan() || w < view.near {
                return None;
            }
            let (x, y) = (x / w, y / w);
            b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
        }
    }
    Some(b)
}

/// The pixel box `b` widened by `margin` pixels in node position units,
/// or `None` when a side is not finite.
fn to_fixed(b: [f64; 4], margin: f64) -> Option<ScreenBox> {
    let one = XY_ONE as f64;
    let lo = |v: f64| ((v - margin) * one).floor();
    let hi = |v: f64| ((v + margin) * one).ceil();
    let b = [lo(b[0]), lo(b[1]), hi(b[2]), hi(b[3])];
    // Saturating casts: a box past the fixed-point range still holds every
    // position that range can hold.
    b.iter().all(|v| v.is_finite()).then(|| b.map(|v| v as i32))
}

/// The screen box of `portal` seen by `view`, widened by `margin` pixels:
/// the boxes of its sphere and of its cylinder ([`cylinder_bounds`]) met,
/// both holding every surface spanning its loop inside the loop's convex
/// hull; `None` when neither lies wholly in front of the near plane.
pub(crate) fn portal_box(view: &View, portal: &Portal, margin: f64) -> Option<ScreenBox> {
    let b = match (
        sphere_bounds(view, portal.centre, portal.radius),
        cylinder_bounds(view, portal),
    ) {
        (Some(s), Some(c)) => [
            s[0].max(c[0]),
            s[1].max(c[1]),
            s[2].min(c[2]),
            s[3].min(c[3]),
        ],
        (Some(b), None) | (None, Some(b)) => b,
        (None, None) => return None,
    };
    to_fixed(b, margin)
}

/// Fills `boxes` with the screen box of each of `portals` ([`portal_box`]:
/// `None` for a portal without one), once per frame.
pub(crate) fn portal_boxes(view: &View, portals: &[Portal], boxes: &mut Vec<Option<ScreenBox>>) {
    boxes.clear();
    boxes.extend(
        portals
            .iter()
            .map(|p| portal_box(view, p, REGION_MARGIN_PX)),
    );
}

/// Whether the back of a patch is culled this frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Back {
    /// Culled (cone test, then the per-cell test).
    Culled,
    /// Culled except within the screen boxes collected: it may be seen
    /// from behind through those portals only.
    InRegions,
    /// Drawn whole from both sides.
    Drawn,
}

/// Whether the back of `patch` is culled this frame under `setup`'s
/// options, and with [`Back::InRegions`] the screen boxes of the portals
/// it may be seen through, in `regions` (cleared first). As
/// [`back_culled`](crate::plan::cull::back_culled), except that a patch
/// "through openings" seen through portals that all have a screen box
/// ([`portal_boxes`]) is culled outside them (unless
/// [`crate::RenderOptions::portal_cells`] is off).
#[inline(always)]
pub(crate) fn back_of_patch(
    setup: &FrameSetup<'_>,
    patch: &PreparedPatch,
    regions: &mut Vec<ScreenBox>,
) -> Back {
    regions.clear();
    let (options, eye) = (setup.options, setup.view.eye);
    let (sides, centre, radius) = (patch.sides, patch.centre, patch.radius);
    let refine = options.portal_cells
        && options.culling == Culling::Auto
        && sides == Sides::ThroughOpenings
        && setup.portal_boxes.len() == setup.portals.len();
    if !refine {
        let mode = (options.culling, sides);
        return match back_culled(mode, setup.portals, eye, centre, radius) {
            true => Back::Culled,
            false => Back::Drawn,
        };
    }
    let Some(mut between) = portals_between(setup.portals, eye, centre, radius) else {
        return Back::Drawn;
    };
    let all_boxed = between.all(|k| match setup.portal_boxes[k] {
        Some(b) => {
            regions.push(b);
            true
        }
        None => false,
    });
    match (all_boxed, regions.is_empty()) {
        (false, _) => Back::Drawn,
        (true, true) => Back::Culled,
        (true, false) => Back::InRegions,
    }
}

/// True when the boxes `a` and `b` share a point.
#[inline(always)]
pub(crate) fn boxes_touch(a: &ScreenBox, b: &ScreenBox) -> bool {
    a[0] <= b[2] && b[0] <= a[2] && a[1] <= b[3] && b[1] <= a[3]
}

/// True when the box `outer` holds the whole box `inner`.
#[inline(always)]
pub(crate) fn box_holds(outer: &ScreenBox, inner: &ScreenBox) -> bool {
    outer[0] <= inner[0] && outer[1] <= inner[1] && inner[2] <= outer[2] && inner[3] <= outer[3]
}

/// True when the projection of the patch-space box `[lo, hi]` (level-0
/// coordinates) seen through the local map `(map, t0)` (to window clip
/// `(X, Y, W)`) may touch one of `regions` (always when a corner is not in
/// front of the near plane): a patch facing away whose box touches none
/// is culled whole. The box of the 8 projected corners holds the
/// projection of the box, widened by a pixel for the `f32` map.
pub(crate) fn local_box_touches(
    view: &View,
    (map, t0): (&Mat3, Vec3),
    (lo, hi): (Vec3, Vec3),
    regions: &[ScreenBox],
) -> bool {
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for k in 0..8 {
        let p = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let c = (*map * p + t0).as_dvec3();
        if c.z.is_nan() || c.z < view.near {
            return true;
        }
        let (x, y) = (c.x / c.z, c.y / c.z);
        b = [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)];
    }
    to_fixed(b, 1.0).is_none_or(|b| regions.iter().any(|r| boxes_touch(r, &b)))
}

/// Draws again the cells of a measured piece (`range` of `level`) that
/// the back-face test left out but whose screen box (of its four corners)
/// touches one of `regions`; returns how many. `xs`, `ys` are the
/// positions of the piece's nodes and `out` its flags (one row per row of
/// cells); a cell with four used corners ([`CELL_DRAW`] in the level's
/// flags) not drawn in `out` faced away. `codes` is scratch.
///
/// Per region, each node gets an outcode (left of, right of, above, below
/// the box); a cell's box misses the region exactly when its four corners
/// share a bit. Why outcodes: the per-cell boxes cost ≈ 2 M instructions
/// per bunny frame at 500² (callgrind), most of the cells tested lying
/// outside every region.
pub(crate) fn keep_cells_in_regions(
    (level, range): (&MipLevel, NodeRange),
    (xs, ys): (&[i32], &[i32]),
    out: &mut [u8],
    regions: &[ScreenBox],
    codes: &mut Vec<u8>,
) -> u64 {
    let cols = range.i1 - range.i0 + 1;
    let mut kept = 0;
    for r in regions {
        codes.clear();
        codes.extend(xs.iter().zip(ys).map(|(&x, &y)| {
            (x < r[0]) as u8
                | ((x > r[2]) as u8) << 1
                | ((y < r[1]) as u8) << 2
                | ((y > r[3]) as u8) << 3
        }));
        for (cj, row) in out.chunks_exact_mut(cols - 1).enumerate() {
            let j = range.j0 + cj;
            let mask = &level.cell_flags[j * (level.cols - 1) + range.i0..][..cols - 1];
            let (lo, hi) = (
                &codes[cj * cols..][..cols],
                &codes[(cj + 1) * cols..][..cols],
            );
            for (ci, (f, &m)) in row.iter_mut().zip(mask).enumerate() {
                let outside = lo[ci] & lo[ci + 1] & hi[ci] & hi[ci + 1];
                let keep = m & CELL_DRAW & !*f & (outside == 0) as u8;
                *f |= keep;
                kept += keep as u64;
            }
        }
    }
    kept
}
