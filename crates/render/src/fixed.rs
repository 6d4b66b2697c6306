//! Fixed-point formats of the rasterizer.
//!
//! Screen positions, depths and interpolated attributes of projected nodes
//! are `i32` fixed-point numbers, so cell subdivision is integer forward
//! differencing with exactly reproducible results on every machine and
//! thread count.
//!
//! - **Positions**: pixels with [`XY_FRAC_BITS`] = 16 fractional bits. The
//!   pixel holding a point is `x >> 16` (floor), so a point lands in the
//!   pixel whose centre (at +0.5) is nearest in the max norm. The guard band
//!   keeps every coordinate within ±2 · [`crate::MAX_IMAGE_SIDE`] pixels,
//!   i.e. within ±2^30, with room for differences in `i64`.
//!   Rounding: conversion truncates (error < 2^-16 px); forward differencing
//!   over `n` steps adds at most `n` units (below 0.002 px for n ≤ 128).
//! - **Depth**: linear eye depth mapped to `[0, Z_FAR]` between the near and
//!   the far plane (`z = (w - near) / (far - near) · 2^28`). Resolution is
//!   `(far - near) / 2^28`. A depth buffer is initialised to [`Z_FAR`], so
//!   anything beyond the far plane fails the depth test for free.
//! - **Attributes** (shaded colour channels 0..=255, normal components in
//!   -1..=1, albedo): [`ATTR_FRAC_BITS`] = 16 fractional bits; flat and
//!   Gouraud frames keep them beside the projected nodes
//!   ([`NodeAttributes`]) as the `f32` bits of that rounded value
//!   ([`attr_to_bits`]); Phong reads the prepared levels' normals instead.
//!
//! Cost: one multiply and one truncating conversion per value.

/// Fractional bits of screen positions.
pub(crate) const XY_FRAC_BITS: u32 = 16;
/// One pixel in position units.
pub(crate) const XY_ONE: f32 = (1u32 << XY_FRAC_BITS) as f32;
/// Depth value of the far plane (and of an empty depth-buffer entry).
pub(crate) const Z_FAR: i32 = 1 << 28;
/// Fractional bits of attributes.
pub(crate) const ATTR_FRAC_BITS: u32 = 16;
/// One attribute unit.
pub(crate) const ATTR_ONE: f32 = (1u32 << ATTR_FRAC_BITS) as f32;
/// Marks an empty (or unused) node in a projected-node array.
pub(crate) const EMPTY_NODE: i32 = i32::MIN;

/// Values per projected node: x, y, depth (fixed point) and a zero word,
/// sixteen bytes. Why no attributes: Phong, the default, reads none (the
/// resolve pass interpolates the prepared normals), and the six words it
/// carried made the node array 2.25 times larger, written by the planning
/// and read by every band (bunny 500², 2 threads: 3.57 → 3.28 ms per frame,
/// medians of 10 alternated `--bench 40` runs; docs/algorithms/render-log.md,
/// "Where a frame waits on memory").
pub(crate) const NODE_WIDTH: usize = 4;
/// A projected node (fixed point; see the module header).
pub(crate) type Node = [i32; NODE_WIDTH];
/// Attributes per node of flat and Gouraud frames: the shaded colour (and
/// a zero word); the resolve pass reads no more (a node's other attributes
/// serve the triangle path, which keeps its own).
pub(crate) const NODE_ATTRIBUTES: usize = 4;
/// A projected node's attributes (float bits, see [`attr_to_bits`]), kept
/// beside the node array ([`crate::plan::work::ChunkWork::node_attributes`]).
pub(crate) type NodeAttributes = [i32; NODE_ATTRIBUTES];

/// A screen position in pixels to fixed point (saturating, truncating).
#[inline]
pub(crate) fn position_to_fixed(v: f32) -> i32 {
    (v * XY_ONE) as i32
}

/// An attribute to fixed point.
#[inline]
pub(crate) fn attr_to_fixed(v: f32) -> i32 {
    (v * ATTR_ONE) as i32
}

/// An attribute as stored in a projected node: the float bits of its value
/// rounded to the fixed-point grid ([`ATTR_FRAC_BITS`]). Why floats: the
/// resolve pass reads four corners × six attributes per pixel and skips the
/// int-to-float conversions (callgrind, `profile_sphere 500 1`); why
/// rounded: images stay identical to the fixed-point format.
#[inline]
pub(crate) fn attr_to_bits(v: f32) -> i32 {
    (attr_to_fixed(v) as f32 * (1.0 / ATTR_ONE)).to_bits() as i32
}

/// The value of an attribute stored by [`attr_to_bits`].
#[inline(always)]
pub(crate) fn attr_from_bits(b: i32) -> f32 {
    f32::from_bits(b as u32)
}

/// A fixed-point attribute back to a float.
#[cfg(test)]
#[inline]
pub(crate) fn attr_to_f32(v: i32) -> f32 {
    v as f32 * (1.0 / ATTR_ONE)
}

/// Converts a normalized depth in [0, 1] (near..far) to fixed point.
#[inline]
pub(crate) fn depth_to_fixed(unit_depth: f32) -> i32 {
    (unit_depth.clamp(0.0, 2.0) * Z_FAR as f32) as i32
}

/// A fixed-point position to its pixel index (floor).
#[cfg(test)]
#[inline]
pub(crate) fn pixel_of(v: i32) -> i32 {
    v >> XY_FRAC_BITS
}

/// A test node at pixel position `(x, y)` with depth 1000 and no
/// attributes (the cell drawers' unit tests).
#[cfg(test)]
pub(crate) fn test_node(x: f32, y: f32) -> Node {
    let mut n = [0; NODE_WIDTH];
    n[0] = (x * XY_ONE) as i32;
    n[1] = (y * XY_ONE) as i32;
    n[2] = 1000;
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_of_floors_negative_and_positive_positions() {
        assert_eq!(pixel_of(position_to_fixed(0.999)), 0);
        assert_eq!(pixel_of(position_to_fixed(1.0)), 1);
        assert_eq!(pixel_of(position_to_fixed(-0.25)), -1);
        assert_eq!(pixel_of(position_to_fixed(-1.5)), -2);
        assert_eq!(depth_to_fixed(1.0), Z_FAR);
        assert_eq!(attr_to_f32(attr_to_fixed(0.5)), 0.5);
        assert_eq!(
            attr_from_bits(attr_to_bits(0.3)),
            attr_to_f32(attr_to_fixed(0.3))
        );
    }
}
