//! Distance from a point to one cell of a patch, the bilinear quad through its four nodes.
//!
//! Input: a point `p` and a quad `[p00, p10, p01, p11]`. Output: the distance from `p` to the
//! quad `B(s, t) = (1−t)((1−s)p00 + s p10) + t((1−s)p01 + s p11)` over `[0, 1]²`, the surface
//! the renderer draws for a cell.
//!
//! The start `(s, t)`: where `p` projects onto the quad's linearisation at its centre,
//! `L(s, t) = B(½, ½) + (s − ½)(e1 + τ/2) + (t − ½)(e2 + τ/2)` (one 2 × 2 solve), when that
//! point lies over the cell, which is the case for a point on or near the surface over its
//! own cell; `L` differs from the quad by `(s − ½)(t − ½)τ`, at most `|τ| / 4`. A flat cell
//! (a twist below 1e-6 of its sides: f32 rounding of a planar cell) stops there. Otherwise
//! the quad is split into the triangles `(p00, p10, p11)` and `(p00, p11, p01)`; the
//! nearest point on the nearer triangle (Voronoi regions of vertices, edges and face) gives a
//! start `(s, t)`. Either start is refined on the true bilinear surface by clamped Gauss–Newton steps that
//! are kept only while they bring the point closer. The two-triangle surface differs from the
//! quad by at most `|τ| / 4`, where `τ = p11 − p10 − p01 + p00` is the quad's twist (the
//! difference is `t(1−s)τ` or `s(1−t)τ`, largest at the centre). The returned distance is that
//! of a true point of the quad, so it is never below the exact distance, and it exceeds it by
//! at most `|τ| / 2` (from either start: the start's own surface is within `|τ| / 4` of
//! the quad, and so is its nearest point); the refinement usually closes that gap. For patches `τ` lies along the
//! frame's normal and is the second difference of four displacements times the step: for
//! converted models and scans it is a small fraction of a step. A planar parallelogram
//! (`τ = 0`) is its two triangles, and the distance is exact.
//!
//! Cost: one 2 × 2 solve for a point over the cell (and at most four Gauss–Newton steps on a
//! twisted cell); otherwise two point–triangle tests and at most four steps. (Before the
//! projection start, every distance took the two triangle tests: about a fifth of the
//! error measurement of a 1 M-triangle plane.)
//!
//! Based on: C. Ericson, *Real-Time Collision Detection* (2005), §5.1.5 (closest point on a
//! triangle).

use glam::Vec3;

/// A cell: corners `[p00, p10, p01, p11]`.
pub type Quad = [Vec3; 4];

/// Gauss–Newton refinement steps at most.
const REFINE_STEPS: usize = 4;

/// A cell whose squared twist is at most this share of its squared sides is flat: its
/// twist is f32 rounding of a planar cell, and the projection onto its linearisation is
/// within `|τ| / 2` of the exact distance (the bound below) without refinement.
const FLAT_TWIST: f32 = 1e-12;

/// Cells whose `det / (|u|² |v|²)` (the squared sine of the angle between the sides of the
/// linearisation) is at most this are slivers, measured through the triangles.
const SLIVER: f32 = 1e-6;

/// Nearest point of triangle `(a, b, c)` to `p`, as barycentric weights (Ericson §5.1.5).
fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return Vec3::X;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return Vec3::Y;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return Vec3::new(1.0 - v, v, 0.0);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return Vec3::Z;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return Vec3::new(1.0 - w, 0.0, w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Vec3::new(0.0, 1.0 - w, w);
    }
    let denom = va + vb + vc;
    if denom == 0.0 || !denom.is_finite() {
        // Degenerate triangle: the nearest corner.
        let (da, db, dc) = (
            ap.length_squared(),
            bp.length_squared(),
            cp.length_squared(),
        );
        return if da <= db && da <= dc {
            Vec3::X
        } else if db <= dc {
            Vec3::Y
        } else {
            Vec3::Z
        };
    }
    let inv = 1.0 / denom;
    let (v, w) = (vb * inv, vc * inv);
    Vec3::new(1.0 - v - w, v, w)
}

/// The bilinear point `B(s, t)` of quad `q`.
#[inline]
pub fn bilinear(q: &Quad, s: f32, t: f32) -> Vec3 {
    let bottom = q[0].lerp(q[1], s);
    let top = q[2].lerp(q[3], s);
    bottom.lerp(top, t)
}

/// Distance from `p` to the bilinear quad `q` (see the module docs for its accuracy).
pub fn distance_to_quad(p: Vec3, q: &Quad) -> f32 {
    let [p00, p10, p01, p11] = *q;
    let (e1, e2, twist) = (p10 - p00, p01 - p00, p11 - p10 - p01 + p00);
    if let Some((s, t)) = inside_projection(p, q, e1, e2, twist) {
        let r = bilinear(q, s, t) - p;
        let (u, v) = (e1 + twist * 0.5, e2 + twist * 0.5);
        if twist.length_squared() <= FLAT_TWIST * (u.length_squared() + v.length_squared()) {
            // Flat: the projection is the nearest point (up to the bound for the twist).
            return r.length();
        }
        return refine(p, q, (e1, e2, twist), (s, t), r.length_squared());
    }
    // Triangle A = (p00, p10, p11): (s, t) = (w1 + w2, w2). B = (p00, p11, p01): (w1, w1 + w2).
    let wa = closest_on_triangle(p, p00, p10, p11);
    let wb = closest_on_triangle(p, p00, p11, p01);
    let da = (p00 * wa.x + p10 * wa.y + p11 * wa.z - p).length_squared();
    let db = (p00 * wb.x + p11 * wb.y + p01 * wb.z - p).length_squared();
    let (s, t) = if da <= db {
        (wa.y + wa.z, wa.z)
    } else {
        (wb.y, wb.y + wb.z)
    };
    let d2 = (bilinear(q, s, t) - p).length_squared();
    if twist == Vec3::ZERO {
        // A planar parallelogram: the triangles are the quad.
        return d2.min(da.min(db)).sqrt();
    }
    refine(p, q, (e1, e2, twist), (s, t), d2)
}

/// Relative margin of [`quad_beyond`] for f32 rounding: of the coordinates' magnitude (the
/// differences from the cell's centre lose up to an ulp of it) and of the limit.
const BEYOND_MARGIN: f32 = 1e-5;

/// Whether the quad `q` is certainly farther from `p` than `limit`, so that
/// [`distance_to_quad`] gives more than `limit` (`false` says nothing). Cheaper than the
/// distance (no triangle and no refinement step): the linearisation
/// `L(s, t) = B(½, ½) + (s − ½)u + (t − ½)v` (`u = e1 + τ/2`, `v = e2 + τ/2`) differs from
/// the quad by `(s − ½)(t − ½)τ`, at most `|τ| / 4` over the cell, so the exact distance is
/// at least the distance to the parallelogram `L([0, 1]²)` less `|τ| / 4`; and that distance
/// is at least the root of the squared height over its plane plus the squared distance, in
/// the plane, to the nearer strip `0 ≤ s ≤ 1` or `0 ≤ t ≤ 1` that the projection lies
/// outside of (`excess · area / |v|` for `s`). [`distance_to_quad`] gives the distance of
/// a true point of the quad, never below the exact one beyond rounding, which
/// [`BEYOND_MARGIN`] covers with room to spare. A sliver or non-finite cell is never ruled
/// out.
#[inline]
pub(crate) fn quad_beyond(p: Vec3, q: &Quad, limit: f32) -> bool {
    let [p00, p10, p01, p11] = *q;
    let twist = p11 - p10 - p01 + p00;
    let (u, v) = (p10 - p00 + twist * 0.5, p01 - p00 + twist * 0.5);
    let centre = (p00 + p10 + p01 + p11) * 0.25;
    let r = p - centre;
    let (a, b, c) = (u.dot(u), u.dot(v), v.dot(v));
    let det = a * c - b * b;
    let conditioned = det > SLIVER * a * c;
    if !conditioned || !det.is_finite() {
        return false;
    }
    let (gu, gv) = (u.dot(r), v.dot(r));
    // Offsets from the centre in (s, t), and how far they pass the cell's half-width.
    let ds = ((c * gu - b * gv) / det).abs() - 0.5;
    let dt = ((a * gv - b * gu) / det).abs() - 0.5;
    // det = |u × v|²: the strips' widths per unit of s and t are sqrt(det / c), sqrt(det / a).
    let side = (ds.max(0.0) * ds.max(0.0) * det / c).max(dt.max(0.0) * dt.max(0.0) * det / a);
    let height = r.dot(u.cross(v));
    let scale = p.abs().max_element() + centre.abs().max_element();
    let reach = (limit + twist.length() * 0.25) * (1.0 + BEYOND_MARGIN) + scale * BEYOND_MARGIN;
    height * height / det + side > reach * reach
}

/// Where `p` projects onto the quad's linearisation at its centre,
/// `L(s, t) = B(½, ½) + (s − ½)(e1 + τ/2) + (t − ½)(e2 + τ/2)`, when that point lies in
/// `[0, 1]²` (it is then the nearest point of `L` over the square) and the cell is not a
/// sliver; `None` otherwise.
#[inline]
fn inside_projection(p: Vec3, q: &Quad, e1: Vec3, e2: Vec3, twist: Vec3) -> Option<(f32, f32)> {
    let (u, v) = (e1 + twist * 0.5, e2 + twist * 0.5);
    let r = p - (q[0] + q[1] + q[2] + q[3]) * 0.25;
    let (a, b, c) = (u.dot(u), u.dot(v), v.dot(v));
    let det = a * c - b * b;
    // A sliver (sine of the angle between its sides below 1e-3) goes to the triangles.
    let conditioned = det > SLIVER * a * c;
    if !conditioned || !det.is_finite() {
        return None;
    }
    let (gu, gv) = (u.dot(r), v.dot(r));
    let s = 0.5 + (c * gu - b * gv) / det;
    let t = 0.5 + (a * gv - b * gu) / det;
    ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t)).then_some((s, t))
}

/// Clamped Gauss–Newton steps on the bilinear quad from `(s, t)` (at squared distance
/// `d2`), each kept only while it brings the point closer; the distance reached.
fn refine(
    p: Vec3,
    q: &Quad,
    (e1, e2, twist): (Vec3, Vec3, Vec3),
    (mut s, mut t): (f32, f32),
    mut d2: f32,
) -> f32 {
    let mut r = bilinear(q, s, t) - p;
    for _ in 0..REFINE_STEPS {
        let bs = e1 + twist * t;
        let bt = e2 + twist * s;
        let (a, b, c) = (bs.dot(bs), bs.dot(bt), bt.dot(bt));
        let (gs, gt) = (bs.dot(r), bt.dot(r));
        let det = a * c - b * b;
        if det == 0.0 || !det.is_finite() {
            break;
        }
        let ns = (s - (c * gs - b * gt) / det).clamp(0.0, 1.0);
        let nt = (t - (a * gt - b * gs) / det).clamp(0.0, 1.0);
        let nr = bilinear(q, ns, nt) - p;
        let nd2 = nr.length_squared();
        if nd2.partial_cmp(&d2) != Some(std::cmp::Ordering::Less) {
            break;
        }
        (s, t, r, d2) = (ns, nt, nr, nd2);
    }
    d2.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense sampling of the quad: an upper bound on the exact distance.
    fn dense(p: Vec3, q: &Quad) -> f32 {
        let n = 400;
        let mut best = f32::INFINITY;
        for j in 0..=n {
            for i in 0..=n {
                let b = bilinear(q, i as f32 / n as f32, j as f32 / n as f32);
                best = best.min((b - p).length());
            }
        }
        best
    }

    #[test]
    fn twisted_quad_distance_matches_dense_sampling() {
        let q: Quad = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.3),
            Vec3::new(0.0, 1.0, 0.3),
            Vec3::new(1.0, 1.0, -0.2),
        ];
        let twist = (q[3] - q[1] - q[2] + q[0]).length();
        for p in [
            Vec3::new(0.5, 0.5, 0.4),
            Vec3::new(0.3, 0.8, -0.3),
            Vec3::new(1.5, 0.2, 0.0),
            Vec3::new(0.5, 0.5, 0.1),
        ] {
            let d = distance_to_quad(p, &q);
            let b = dense(p, &q);
            // Never (meaningfully) below the exact distance, within the documented bound above.
            assert!(d >= b - 2e-3, "{p}: {d} < {b}");
            assert!(d <= b + twist * 0.5 + 1e-4, "{p}: {d} vs {b}");
            assert!(
                (d - b).abs() < 5e-3,
                "refinement should close the gap: {d} vs {b}"
            );
        }
    }

    #[test]
    fn random_quads_stay_within_the_twist_bound() {
        // Points over the cell (the projection path) and beside it (the triangles), on flat,
        // slightly and strongly twisted cells: never below the exact distance, at most
        // |τ|/2 above it.
        let mut rng = spatch_mesh::SplitMix64::new(11);
        let mut r = move || rng.next_f64() as f32 - 0.5;
        for k in 0..60 {
            let twist = [0.0, 1e-4, 0.05, 0.4][k % 4];
            let e1 = Vec3::new(1.0, r() * 0.5, r() * 0.2);
            let e2 = Vec3::new(r() * 0.5, 1.0, r() * 0.2);
            let o = Vec3::new(r(), r(), r());
            let tau = Vec3::new(r(), r(), 1.0) * twist;
            let q: Quad = [o, o + e1, o + e2, o + e1 + e2 + tau];
            let bound = tau.length() * 0.5;
            for _ in 0..8 {
                let p = o + Vec3::new(r() * 2.4 + 0.5, r() * 2.4 + 0.5, r());
                let (d, b) = (distance_to_quad(p, &q), dense(p, &q));
                assert!(d >= b - 2e-3, "{p}: {d} < {b}");
                assert!(d <= b + bound + 1e-4, "{p}: {d} vs {b} (twist {twist})");
            }
        }
    }

    #[test]
    fn a_quad_ruled_out_is_farther_than_the_limit() {
        // Points over, beside and far from flat and twisted cells, limits around their
        // distance: whenever `quad_beyond` says so, the distance exceeds the limit; and it
        // rules out most cells well beyond the limit.
        let mut rng = spatch_mesh::SplitMix64::new(17);
        let mut r = move || rng.next_f64() as f32 - 0.5;
        let (mut ruled_out, mut clearly_beyond) = (0, 0);
        for k in 0..400 {
            let twist = [0.0, 1e-3, 0.05, 0.4][k % 4];
            let e1 = Vec3::new(1.0, r() * 0.5, r() * 0.2);
            let e2 = Vec3::new(r() * 0.5, 1.0, r() * 0.2);
            let o = Vec3::new(r(), r(), r()) * 100.0;
            let tau = Vec3::new(r(), r(), 1.0) * twist;
            let q: Quad = [o, o + e1, o + e2, o + e1 + e2 + tau];
            for _ in 0..20 {
                let p = o + Vec3::new(r() * 4.0 + 0.5, r() * 4.0 + 0.5, r() * 3.0);
                let d = distance_to_quad(p, &q);
                for limit in [d * 0.3, d * 0.9, d * 0.999, d] {
                    let beyond = quad_beyond(p, &q, limit);
                    assert!(!beyond || d > limit, "{p} {q:?}: {d} <= {limit}");
                    if d > 2.0 * limit + twist {
                        clearly_beyond += 1;
                        ruled_out += usize::from(beyond);
                    }
                }
            }
        }
        assert!(
            clearly_beyond > 1000 && ruled_out * 4 > clearly_beyond * 3,
            "{ruled_out} ruled out of {clearly_beyond}"
        );
        let square: Quad = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        assert!(quad_beyond(Vec3::new(0.5, 0.5, 1.0), &square, 0.99));
        assert!(!quad_beyond(Vec3::new(0.5, 0.5, 1.0), &square, 1.0));
        assert!(quad_beyond(Vec3::new(2.5, 0.5, 0.0), &square, 1.49));
        assert!(!quad_beyond(Vec3::new(2.5, 0.5, 0.0), &square, 1.5));
    }

    #[test]
    fn flat_square_is_exact() {
        let q: Quad = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        assert_eq!(distance_to_quad(Vec3::new(0.25, 0.75, 2.0), &q), 2.0);
        assert_eq!(distance_to_quad(Vec3::new(3.0, 0.5, 0.0), &q), 2.0);
        assert_eq!(distance_to_quad(Vec3::new(-3.0, -4.0, 0.0), &q), 5.0);
    }

    #[test]
    fn degenerate_quad_is_its_point() {
        let c = Vec3::new(1.0, 2.0, 3.0);
        let d = distance_to_quad(Vec3::new(1.0, 2.0, 5.0), &[c; 4]);
        assert_eq!(d, 2.0);
    }
}
