//! The subdivision of a piece: the fewest sub-cells `nu × nv` per cell
//! that keep every sub-cell below a limit on screen (a pixel, or 1.5 px
//! with the gap fill).
//!
//! Every point of a bilinear cell lies within half a pixel (max norm) of
//! one of its sub-nodes when each sub-cell's extent
//! `max(|u_x| + |v_x|, |u_y| + |v_y|)` (u, v its edges) is below one
//! pixel, so placing the sub-nodes covers every pixel centre inside the
//! cell ([`crate::raster::cell_bilinear`]). The cut is anisotropic: a
//! foreshortened piece is cut less across.
//!
//! Cost: at most [`MAX_SUBDIVISION`] trial cuts per piece.

use crate::raster::cell_bilinear::MAX_SUBDIVISION;

/// Largest sub-cell extent (pixels, max-norm sum of edges) allowed; below
/// 1 so that rounding never opens a hole.
pub(crate) const SUBPIXEL_LIMIT: f32 = 0.95;
/// Largest sub-cell extent with the gap fill ([`crate::raster::gap_fill`]):
/// every pixel centre then lies within 0.75 px (max norm) of a sub-node, so
/// a pixel the lattice misses has a drawn pixel among its eight neighbours
/// (the pass looks for two opposite ones within two steps, or drawn ones
/// around it, which this does not guarantee).
/// Why 1.5: at 1.9 the bunny lost 0.18 dB and its holes tripled, at 1.7
/// the mannequin's holes tripled, at 1.2 it placed more samples for the
/// same image (docs/algorithms/render.md).
pub(crate) const GAP_FILL_LIMIT: f32 = 1.5;
/// Extra subdivision for Catmull-Rom cells, which bulge past their corners:
/// their limit is [`SUBPIXEL_LIMIT`] divided by this.
pub(crate) const SMOOTH_MARGIN: f32 = 1.3;

/// The cheapest cut `nu × nv` of cells whose largest edges are
/// `[ux, uy, vx, vy]` pixels such that sub-cells satisfy
/// `ux/nu + vx/nv < limit` and `uy/nu + vy/nv < limit`; `None` when more
/// than [`MAX_SUBDIVISION`] per side would be needed.
#[inline(always)]
pub(crate) fn choose_subdivision(edges: [f32; 4], limit: f32) -> Option<(u32, u32)> {
    let [ux, uy, vx, vy] = edges;
    // No cut needs fewer than `nu_least` along u (its `rx`, `ry` never
    // exceed `limit`), nor fewer than `nv_least` along v: below
    // `nv_least - 1` a sub-cell's v edges alone reach the limit (`rx` or
    // `ry` ≤ 0 whatever the rounding; one cut of margin for it).
    let least = |a: f32, b: f32| ((a / limit).max(b / limit).floor() as u32).saturating_add(1);
    let (nu_least, nv_least) = (least(ux, uy), least(vx, vy));
    let mut best: Option<(u32, u32)> = None;
    for nv in nv_least.saturating_sub(1).max(1)..=MAX_SUBDIVISION {
        // Every later cut has at least `nu_least · nv` sub-cells: none can
        // beat the best once that reaches its count. Why: cells wider than
        // the limit walked every `nv` up to the best's count (≈ 390
        // instructions per bunny piece at 500², ≈ 100 since; callgrind).
        if best.is_some_and(|(bu, bv)| nu_least.saturating_mul(nv) >= bu * bv) {
            break;
        }
        let (rx, ry) = (limit - vx / nv as f32, limit - vy / nv as f32);
        if rx <= 0.0 || ry <= 0.0 {
            continue;
        }
        let nu = (ux / rx).max(uy / ry).floor() as u32 + 1;
        if nu > MAX_SUBDIVISION {
            continue;
        }
        if best.is_none_or(|(bu, bv)| nu * nv < bu * bv) {
            best = Some((nu, nv));
        }
        if nu == 1 {
            break;
        }
    }
    best
}

/// The search [`choose_subdivision`] must equal: every `nv` from 1,
/// stopping only once `nv` alone reaches the best count.
#[cfg(test)]
fn choose_subdivision_reference(edges: [f32; 4], limit: f32) -> Option<(u32, u32)> {
    let [ux, uy, vx, vy] = edges;
    let mut best: Option<(u32, u32)> = None;
    for nv in 1..=MAX_SUBDIVISION {
        if best.is_some_and(|(bu, bv)| nv >= bu * bv) {
            break;
        }
        let (rx, ry) = (limit - vx / nv as f32, limit - vy / nv as f32);
        if rx <= 0.0 || ry <= 0.0 {
            continue;
        }
        let nu = (ux / rx).max(uy / ry).floor() as u32 + 1;
        if nu > MAX_SUBDIVISION {
            continue;
        }
        if best.is_none_or(|(bu, bv)| nu * nv < bu * bv) {
            best = Some((nu, nv));
        }
        if nu == 1 {
            break;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subdivision_is_anisotropic_and_keeps_sub_cells_below_a_pixel() {
        assert_eq!(
            choose_subdivision([0.3, 0.2, 0.2, 0.4], SUBPIXEL_LIMIT),
            Some((1, 1))
        );
        // Foreshortened along v: cut along u only.
        let (nu, nv) = choose_subdivision([3.0, 0.0, 0.0, 0.4], SUBPIXEL_LIMIT).unwrap();
        assert_eq!(nv, 1);
        assert!(3.0 / (nu as f32) < SUBPIXEL_LIMIT && nu <= 4);
        let (nu, nv) = choose_subdivision([2.0, 2.0, 2.0, 2.0], SUBPIXEL_LIMIT).unwrap();
        assert!(2.0 / (nu as f32) + 2.0 / (nv as f32) < SUBPIXEL_LIMIT);
        assert_eq!(
            choose_subdivision([500.0, 0.0, 0.0, 1.0], SUBPIXEL_LIMIT),
            None
        );
    }

    /// The pruned search gives the cut of the full one on random edges
    /// (small, at the limit's multiples, and past the largest cut) for
    /// each limit in use.
    #[test]
    fn pruned_search_equals_the_reference() {
        let mut rng = crate::test_rng::XorShift(0x0dd_c0ff_ee15_600d);
        let limits = [
            SUBPIXEL_LIMIT,
            GAP_FILL_LIMIT,
            SUBPIXEL_LIMIT / SMOOTH_MARGIN,
        ];
        for case in 0..200_000 {
            let limit = limits[case % 3];
            let mut pick = || match rng.below(4) {
                0 => rng.unit() * 2.0,
                1 => rng.below(40) as f32 * limit,
                2 => rng.unit() * 20.0,
                _ => rng.unit() * 120.0,
            };
            let edges = [pick(), pick(), pick(), pick()];
            assert_eq!(
                choose_subdivision(edges, limit),
                choose_subdivision_reference(edges, limit),
                "case {case}: {edges:?}"
            );
        }
    }
}
