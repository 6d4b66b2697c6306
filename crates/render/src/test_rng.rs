//! A small deterministic generator (xorshift64) for the unit tests' random
//! pieces, pixels and scenes (and random drawn cells on top of it):
//! reproducible, and no dependency for a test.

/// Xorshift64 state (never zero).
pub(crate) struct XorShift(pub(crate) u64);

impl XorShift {
    /// The next 64-bit state.
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// The high 32 bits of the next state.
    pub(crate) fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    /// A number in `0..n` from [`Self::next_u32`].
    pub(crate) fn below(&mut self, n: u32) -> u32 {
        self.next_u32() % n
    }

    /// A number in `0..n` from [`Self::next_u64`].
    pub(crate) fn below64(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    /// A number in `[0, 1)` with 24 random bits.
    pub(crate) fn unit(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Displacements of a grid of `nodes` nodes for tests: each empty with
    /// probability `holes` % ([`spatch_format::EMPTY`]), else
    /// `base + below(span)`.
    pub(crate) fn holed_grid(
        &mut self,
        nodes: usize,
        holes: u32,
        base: u32,
        span: u32,
    ) -> Vec<u16> {
        (0..nodes)
            .map(|_| match self.below(100) < holes {
                true => spatch_format::EMPTY,
                false => (base + self.below(span)) as u16,
            })
            .collect()
    }

    /// A square cell of side `s_min + s_span · u` with its first corner
    /// in `[4, 12)²` pixels, each corner moved by up to ±2 px: the corners
    /// in ring order (00, 10, 11, 01) and the side. For the cell drawers'
    /// coverage tests.
    pub(crate) fn jittered_square(&mut self, s_min: f32, s_span: f32) -> ([(f32, f32); 4], f32) {
        let j = |r: &mut XorShift| 4.0 * (r.unit() - 0.5);
        let (ox, oy, s) = (
            4.0 + 8.0 * self.unit(),
            4.0 + 8.0 * self.unit(),
            s_min + s_span * self.unit(),
        );
        let q = [
            (ox + j(self), oy + j(self)),
            (ox + s + j(self), oy + j(self)),
            (ox + s + j(self), oy + s + j(self)),
            (ox + j(self), oy + s + j(self)),
        ];
        (q, s)
    }
}

/// Random flags of a `ccols × crows` grid of cells for tests: every cell
/// drawn except about one in `one_in`, closing flags set
/// (`crate::grid::close_cells`).
pub(crate) fn random_drawn_cells(
    rng: &mut XorShift,
    ccols: usize,
    crows: usize,
    one_in: u32,
) -> Vec<u8> {
    use crate::grid::{close_cells, CELL_DRAW};
    let mut flags: Vec<u8> = (0..ccols * crows)
        .map(|_| if rng.below(one_in) == 0 { 0 } else { CELL_DRAW })
        .collect();
    close_cells(&mut flags, ccols, crows);
    flags
}
