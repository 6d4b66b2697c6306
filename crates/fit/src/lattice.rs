//! The node lattice of one region: where node `(i, j)` lies, and mesh points in lattice
//! coordinates.
//!
//! The lattice is the region's rectangle (from `frame_fit`) divided into whole cells,
//! widened by the overlap rings. Node `(i, j)` projects to `(u0 + i·sx, v0 + j·sy)` in the
//! plane of the basis; a point `p` maps to `((p·x̂ − u0)/sx, (p·ŷ − v0)/sy, p·ẑ)`: two grid
//! coordinates and a height.

use glam::{DVec2, Vec3};

use crate::frame_fit::{Basis, PlaneRect};

/// One region's node lattice.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lattice {
    pub(crate) basis: Basis,
    /// Plane coordinates of node (0, 0).
    pub(crate) origin: DVec2,
    /// Node spacing along x̂ and ŷ.
    pub(crate) spacing: [f32; 2],
    pub(crate) cols: usize,
    pub(crate) rows: usize,
}

/// Cells needed to span `extent` at a target spacing `s`, and the spacing that makes them span
/// it exactly (never coarser than `s`; `s` itself for a rectangle narrower than half a cell).
fn cells_for(extent: f64, s: f64) -> (usize, f64) {
    // The small tolerance keeps an extent that is a whole multiple of `s` from gaining a cell
    // through rounding.
    let cells = ((extent / s) - 1e-3).ceil().max(1.0);
    let exact = extent / cells;
    if exact >= 0.5 * s {
        (cells as usize, exact)
    } else {
        (cells as usize, s)
    }
}

impl Lattice {
    /// The lattice over `rect` at target spacing `spacing`, widened by `rings` nodes on every
    /// side. Returns the lattice and the number of nodes it has (which may be too many: the
    /// caller checks before allocating).
    pub(crate) fn over_rect(rect: &PlaneRect, spacing: f32, rings: u32) -> (Lattice, u64) {
        let s = f64::from(spacing);
        let size = rect.max - rect.min;
        let (nx, sx) = cells_for(size.x, s);
        let (ny, sy) = cells_for(size.y, s);
        let r = rings as usize;
        let origin = rect.min - DVec2::new(sx, sy) * r as f64;
        // Saturating: an absurd extent (a model spanning 1e20) must give a count the caller
        // refuses, not one that wraps around to a small number.
        let cols = nx.saturating_add(1).saturating_add(r.saturating_mul(2));
        let rows = ny.saturating_add(1).saturating_add(r.saturating_mul(2));
        let lattice = Lattice {
            basis: rect.basis,
            origin,
            spacing: [sx as f32, sy as f32],
            cols,
            rows,
        };
        (lattice, (cols as u64).saturating_mul(rows as u64))
    }

    /// `p` (mesh coordinates) as `(grid x, grid y, height)`.
    #[inline]
    pub(crate) fn grid_point(&self, p: Vec3) -> Vec3 {
        let b = &self.basis;
        let u = (f64::from(p.dot(b.x)) - self.origin.x) as f32 / self.spacing[0];
        let v = (f64::from(p.dot(b.y)) - self.origin.y) as f32 / self.spacing[1];
        Vec3::new(u, v, p.dot(b.z))
    }

    /// Row-major index of node `(i, j)`.
    #[inline]
    pub(crate) fn index(&self, i: usize, j: usize) -> usize {
        j * self.cols + i
    }

    /// Mesh-space position of node `(i, j)` at height `h`.
    pub(crate) fn position(&self, i: usize, j: usize, h: f64) -> Vec3 {
        let u = self.origin.x + i as f64 * f64::from(self.spacing[0]);
        let v = self.origin.y + j as f64 * f64::from(self.spacing[1]);
        let b = &self.basis;
        (b.x.as_dvec3() * u + b.y.as_dvec3() * v + b.z.as_dvec3() * h).as_vec3()
    }

    /// The inclusive node range `[lo, hi]` along one axis covered by grid coordinates
    /// `[min, max]`, clipped to `0..len`, or `None` when empty.
    #[inline]
    pub(crate) fn node_range(min: f32, max: f32, len: usize) -> Option<(usize, usize)> {
        let lo = min.ceil().max(0.0);
        let hi = max.floor().min(len as f32 - 1.0);
        (lo <= hi).then_some((lo as usize, hi as usize))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_cells_span_the_extent() {
        assert_eq!(cells_for(1.0, 0.25), (4, 0.25));
        let (n, s) = cells_for(1.1, 0.25);
        assert_eq!(n, 5);
        assert!((s * 5.0 - 1.1).abs() < 1e-12);
        assert_eq!(cells_for(0.0, 0.25), (1, 0.25));
        assert_eq!(cells_for(0.2, 0.25), (1, 0.2));
    }

    #[test]
    fn an_absurd_extent_gives_a_count_that_does_not_wrap() {
        // Issue 20: 1e20 on each side used to wrap cols × rows to a small count.
        let rect = PlaneRect {
            basis: crate::frame_fit::basis_from_axis(Vec3::Z),
            min: DVec2::ZERO,
            max: DVec2::splat(1e20),
        };
        let (_, count) = Lattice::over_rect(&rect, 1.0, 3);
        assert_eq!(count, u64::MAX);
    }
}
