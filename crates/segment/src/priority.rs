//! Totally ordered heap keys for non-negative `f32` priorities (angles, distances).
//!
//! The stages keep their frontiers in `BinaryHeap<Reverse<(u32, …ids)>>`: the first element is
//! the priority as produced by [`priority_key`], the rest are face and region indices, so equal
//! priorities are broken by index and every pop order is deterministic.
//!
//! Invariant: for finite `a, b >= 0`, `a < b` ⇔ `priority_key(a) < priority_key(b)` (IEEE 754
//! non-negative floats order like their bit patterns). Negative zero and NaN map to 0 and
//! `u32::MAX` so no input breaks the order.
//!
//! Cost: O(1).
//!
//! Based on: the bit-pattern ordering of IEEE 754 floats (Herf, *Radix tricks*, 2001).

/// The heap key of a non-negative priority (see the module docs).
#[inline]
pub(crate) fn priority_key(value: f32) -> u32 {
    if value > 0.0 {
        value.to_bits()
    } else if value.is_nan() {
        u32::MAX
    } else {
        0
    }
}

/// The priority a key was made from (inverse of [`priority_key`] for positive finite values).
#[inline]
pub(crate) fn priority_value(key: u32) -> f32 {
    f32::from_bits(key)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_order_like_values() {
        let values = [0.0f32, 1e-30, 1e-6, 0.5, 1.0, 3.0, 1e30, f32::INFINITY];
        for w in values.windows(2) {
            assert!(priority_key(w[0]) < priority_key(w[1]));
        }
        assert_eq!(priority_key(-0.0), 0);
        assert_eq!(priority_key(f32::NAN), u32::MAX);
        assert_eq!(priority_value(priority_key(0.25)), 0.25);
    }
}
