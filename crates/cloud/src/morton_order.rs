//! The points of a cloud in Morton (Z-order) order of their position in a box: consecutive
//! points are near each other.
//!
//! Input: positions and the box they lie in. Output: `(code, point)` pairs in increasing
//! order, the code interleaving 16 bits of each coordinate (x in the lowest bit), the point
//! its index in the input. The conversion reorders the cloud by it (every pass over the
//! points, one per view, then touches the images in a cache-friendly order) and hands the
//! order on to the error measurement, whose point hierarchy (`point_hierarchy.rs`) is cut
//! along the codes.
//!
//! Invariants: deterministic (ties in code go in point order); points outside the box are
//! clamped to it, a NaN coordinate counts as the box's low side.
//!
//! Cost: O(n) for the codes and a bucket sort on their top 18 bits (`bucket_sort.rs`), then
//! short sorts of the runs; 16 bytes per point.
//!
//! Based on: G. M. Morton, "A computer oriented geodetic data base and a new technique in
//! file sequencing", IBM, 1966.

use glam::Vec3;
use rayon::prelude::*;
use spatch_mesh::Aabb;

use crate::bucket_sort::sort_pairs;

/// A conversion's spatial order of its cloud's points: the index in the cloud of each point,
/// in increasing Morton code (a permutation of the cloud's indices, made only by the
/// pipeline).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PointOrder(Vec<u32>);

impl PointOrder {
    /// The order of sorted `(code, point)` pairs.
    pub(crate) fn of_pairs(pairs: &[(u64, u32)]) -> PointOrder {
        PointOrder(pairs.par_iter().map(|&(_, i)| i).collect())
    }

    /// The cloud index of each point, in order.
    pub fn indices(&self) -> &[u32] {
        &self.0
    }
}

/// Bits of each axis in a code.
pub(crate) const MORTON_AXIS_BITS: u32 = 16;

/// The frame of the codes: a box's low corner and the scale to 16-bit cells.
#[derive(Clone, Copy, Debug)]
pub(crate) struct MortonFrame {
    min: Vec3,
    scale: Vec3,
}

impl MortonFrame {
    /// The frame of `bounds`.
    pub(crate) fn new(bounds: &Aabb) -> MortonFrame {
        let top = Vec3::splat(f32::from(u16::MAX));
        MortonFrame {
            min: bounds.min,
            scale: top / bounds.size().max(Vec3::splat(f32::MIN_POSITIVE)),
        }
    }

    /// The Morton code of `p` (see the module documentation).
    #[inline]
    pub(crate) fn code(&self, p: Vec3) -> u64 {
        let top = Vec3::splat(f32::from(u16::MAX));
        let q = ((p - self.min) * self.scale).clamp(Vec3::ZERO, top);
        // Through `i32` (`q` is clamped to 0..=65535): Rust's saturating `f32 as u64` is
        // several instructions more a coordinate (the codes: 96 → 74 M worker instructions
        // on the covering 1 M scan set, callgrind).
        let axis = |v: f32| spread(v as i32 as u64);
        axis(q.x) | (axis(q.y) << 1) | (axis(q.z) << 2)
    }
}

/// The low 16 bits of `v`, two zero bits inserted after each.
#[inline]
fn spread(v: u64) -> u64 {
    let mut x = v & 0xFFFF;
    x = (x | (x << 16)) & 0x0000_FF00_00FF;
    x = (x | (x << 8)) & 0x00F0_0F00_F00F;
    x = (x | (x << 4)) & 0x0C30_C30C_30C3;
    (x | (x << 2)) & 0x2492_4924_9249
}

/// `(code, point)` of every position, in increasing order (see the module documentation).
pub(crate) fn morton_order(positions: &[Vec3], bounds: &Aabb) -> Vec<(u64, u32)> {
    let frame = MortonFrame::new(bounds);
    let order: Vec<(u64, u32)> = positions
        .par_iter()
        .enumerate()
        .map(|(i, &p)| (frame.code(p), i as u32))
        .collect();
    // Buckets of the top 18 code bits (cells of 1/64 of the box), then short runs: cheaper
    // than one sort of the whole list (rayon's parallel sort and a radix sort were slower
    // than `sort_unstable` on the shared machine).
    sort_pairs(order, 3 * MORTON_AXIS_BITS - 18)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_interleave_the_axes() {
        let bounds = Aabb {
            min: Vec3::ZERO,
            max: Vec3::splat(f32::from(u16::MAX)),
        };
        let frame = MortonFrame::new(&bounds);
        assert_eq!(spread(0b1011), 0b001_000_001_001);
        assert_eq!(frame.code(Vec3::new(1.0, 0.0, 0.0)), 0b001);
        assert_eq!(frame.code(Vec3::new(0.0, 1.0, 0.0)), 0b010);
        assert_eq!(frame.code(Vec3::new(0.0, 0.0, 1.0)), 0b100);
        assert_eq!(frame.code(Vec3::new(3.0, 0.0, 0.0)), 0b001_001);
        assert_eq!(frame.code(Vec3::splat(-3.0)), 0);
        assert_eq!(frame.code(Vec3::splat(1e9)), (1 << 48) - 1);
    }

    #[test]
    fn order_sorts_by_code_then_point() {
        let positions: Vec<Vec3> = (0..5000)
            .map(|k| {
                let t = k as f32;
                Vec3::new((t * 0.37).sin(), (t * 0.11).cos(), (k % 7) as f32 * 0.1)
            })
            .collect();
        let bounds = Aabb::from_points(positions.iter().copied());
        let order = morton_order(&positions, &bounds);
        let frame = MortonFrame::new(&bounds);
        let mut expected: Vec<(u64, u32)> = positions
            .iter()
            .enumerate()
            .map(|(i, &p)| (frame.code(p), i as u32))
            .collect();
        expected.sort_unstable();
        assert_eq!(order, expected);
    }
}
