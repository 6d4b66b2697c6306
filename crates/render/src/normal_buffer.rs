//! Node normals reconstructed in patch space, and the normal buffer that
//! reuses them.
//!
//! In patch space a node's normal depends only on the displacement
//! differences around it and on the ratios `rx = |az| / |ax|`,
//! `ry = |az| / |ay|`: with `gi = d[i+1] - d[i-1]` and `gj = d[j+1] -
//! d[j-1]` (one-sided differences doubled at borders and next to empty
//! nodes, 0 when both neighbours are missing), the normal is
//! `(-gi · rx / 2, -gj · ry / 2, 1)`, normalized. The differences are small
//! integers, so a table indexed by `(gi, gj)` for the current ratios — the
//! *normal buffer* of the original work — computes each distinct normal once.
//!
//! The buffer keeps one table per mip level (levels have different ratios)
//! and is invalidated when the ratios change; patches are drawn sorted by
//! their ratios so that it rarely is. Two counts are kept: normals computed
//! when the buffer is cleared for every patch ("with buffer") and when it
//! persists across patches ("with patch ordering").
//!
//! Cost: one table probe per node; a miss costs one normalization. Memory:
//! 65 × 65 entries (20 bytes) per level.

use glam::Vec3;

use crate::fixed::attr_to_bits;

/// Differences in `-RADIUS..=RADIUS` are cached; others are computed.
const RADIUS: i32 = 32;
const SIDE: usize = (2 * RADIUS + 1) as usize;

/// The table slot of a node whose differences lie outside the table.
pub(crate) const OUTSIDE_TABLE: u16 = u16::MAX;

/// The table slot of differences `(gi, gj)` (the same for every ratio and
/// frame), or [`OUTSIDE_TABLE`]. Why slots: the differences depend on the
/// displacements only, so [`crate::mip`] finds them once per scene and a
/// frame starts from the slot (callgrind, `profile_sphere 500 1`: the
/// per-node border logic was ~4 M instructions per frame).
pub(crate) fn table_slot(gi: i32, gj: i32) -> u16 {
    if gi.abs() > RADIUS || gj.abs() > RADIUS {
        OUTSIDE_TABLE
    } else {
        ((gj + RADIUS) as usize * SIDE + (gi + RADIUS) as usize) as u16
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct Entry {
    normal: Vec3,
    /// `normal` as stored in projected nodes ([`attr_to_bits`]).
    bits: [i32; 3],
    /// Table generation that wrote the entry.
    generation: u32,
    /// Patch that last used the entry.
    patch: u32,
}

#[derive(Debug, Clone)]
struct Table {
    ratios: (f32, f32),
    generation: u32,
    entries: Vec<Entry>,
}

/// Counts of normal requests and computations.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct NormalCounts {
    pub(crate) needed: u64,
    pub(crate) computed_per_patch_buffer: u64,
    pub(crate) computed_ordered_buffer: u64,
}

/// The normal buffer (one per worker chunk).
#[derive(Debug, Clone, Default)]
pub(crate) struct NormalBuffer {
    tables: Vec<Table>,
    patch: u32,
    pub(crate) counts: NormalCounts,
}

/// The patch-space normal for differences `(gi, gj)` and ratios `(rx, ry)`
/// (not normalized: z is 1).
#[inline]
pub(crate) fn reconstruct_normal(gi: i32, gj: i32, rx: f32, ry: f32) -> Vec3 {
    Vec3::new(-(gi as f32) * rx * 0.5, -(gj as f32) * ry * 0.5, 1.0)
}

impl NormalBuffer {
    /// Forgets every cached normal (start of a chunk of patches).
    pub(crate) fn clear(&mut self) {
        for t in &mut self.tables {
            t.generation = t.generation.wrapping_add(1);
            t.ratios = (f32::NAN, f32::NAN);
        }
    }

    /// Starts a new patch (for the per-patch count).
    pub(crate) fn begin_patch(&mut self) {
        self.patch = self.patch.wrapping_add(1);
    }

    /// The unit patch-space normal at a node of mip `level`.
    #[inline]
    pub(crate) fn normal(&mut self, level: usize, ratios: (f32, f32), gi: i32, gj: i32) -> Vec3 {
        self.select(level, ratios);
        self.entry(level, gi, gj).0
    }

    /// Selects the table of mip `level` for `ratios` (invalidating it when
    /// the ratios changed) before a run of [`Self::normal_bits`] calls.
    pub(crate) fn select(&mut self, level: usize, ratios: (f32, f32)) {
        while self.tables.len() <= level {
            self.tables.push(Table {
                ratios: (f32::NAN, f32::NAN),
                generation: 1,
                entries: vec![Entry::default(); SIDE * SIDE],
            });
        }
        let table = &mut self.tables[level];
        if table.ratios != ratios {
            table.ratios = ratios;
            table.generation = table.generation.wrapping_add(1);
        }
    }

    /// The unit normal of [`Self::normal`] as stored in projected nodes, from
    /// the table chosen by [`Self::select`] (the conversion is cached with
    /// the normal). Why a separate selection: the table and ratio checks
    /// run once per piece instead of once per node (callgrind,
    /// `profile_sphere 500 1`).
    #[inline]
    pub(crate) fn normal_bits(&mut self, level: usize, gi: i32, gj: i32) -> [i32; 3] {
        self.entry(level, gi, gj).1
    }

    /// [`Self::normal_bits`] for a node whose differences have table slot
    /// `slot` (not [`OUTSIDE_TABLE`]; see [`table_slot`]).
    #[inline(always)]
    pub(crate) fn normal_bits_at(&mut self, level: usize, slot: u16) -> [i32; 3] {
        debug_assert!(slot != OUTSIDE_TABLE);
        self.counts.needed += 1;
        self.probe(level, slot as usize).1
    }

    /// Counts a lookup of the normal at `slot` (not [`OUTSIDE_TABLE`]) in
    /// the table chosen by [`Self::select`] exactly as
    /// [`Self::normal_bits_at`] would, for a frame that reads its normals
    /// from the prepared scene ([`crate::prepare::LevelShading`]).
    #[inline(always)]
    pub(crate) fn touch_at(&mut self, level: usize, slot: u16) {
        debug_assert!(slot != OUTSIDE_TABLE);
        self.counts.needed += 1;
        self.probe(level, slot as usize);
    }

    /// Counts a lookup of a normal outside the table (always computed), as
    /// [`Self::normal_bits`] would.
    pub(crate) fn touch_outside(&mut self) {
        self.counts.needed += 1;
        self.counts.computed_per_patch_buffer += 1;
        self.counts.computed_ordered_buffer += 1;
    }

    /// The normal and its node format from the selected table of `level`.
    /// Why always inlined: it runs once per node of every drawn piece and
    /// the call returned its 24-byte result through memory (callgrind,
    /// `profile_sphere 500 1`).
    #[inline(always)]
    fn entry(&mut self, level: usize, gi: i32, gj: i32) -> (Vec3, [i32; 3]) {
        self.counts.needed += 1;
        let slot = table_slot(gi, gj);
        if slot == OUTSIDE_TABLE {
            let ratios = self.tables[level].ratios;
            self.counts.computed_per_patch_buffer += 1;
            self.counts.computed_ordered_buffer += 1;
            let n = reconstruct_normal(gi, gj, ratios.0, ratios.1).normalize();
            return (n, n.to_array().map(attr_to_bits));
        }
        self.probe(level, slot as usize)
    }

    /// The cached entry at `index` of the table of `level`, computed if the
    /// table was invalidated since it was written.
    #[inline(always)]
    fn probe(&mut self, level: usize, index: usize) -> (Vec3, [i32; 3]) {
        let table = &mut self.tables[level];
        let ratios = table.ratios;
        let entry = &mut table.entries[index];
        if entry.patch != self.patch {
            self.counts.computed_per_patch_buffer += 1;
            entry.patch = self.patch;
        }
        if entry.generation != table.generation {
            self.counts.computed_ordered_buffer += 1;
            entry.generation = table.generation;
            let (gi, gj) = (
                (index % SIDE) as i32 - RADIUS,
                (index / SIDE) as i32 - RADIUS,
            );
            entry.normal = reconstruct_normal(gi, gj, ratios.0, ratios.1).normalize();
            entry.bits = entry.normal.to_array().map(attr_to_bits);
        }
        (entry.normal, entry.bits)
    }
}

/// Displacement differences `(gi, gj)` at node `(i, j)` of a grid (see the
/// module header for borders and empty neighbours).
#[inline]
pub(crate) fn node_differences(
    d: &[u16],
    cols: usize,
    rows: usize,
    i: usize,
    j: usize,
    empty: u16,
) -> (i32, i32) {
    let at = |i: usize, j: usize| d[j * cols + i];
    let centre = at(i, j) as i32;
    let diff = |prev: Option<u16>, next: Option<u16>| match (prev, next) {
        (Some(p), Some(n)) => n as i32 - p as i32,
        (Some(p), None) => 2 * (centre - p as i32),
        (None, Some(n)) => 2 * (n as i32 - centre),
        (None, None) => 0,
    };
    let get = |i: Option<usize>, j: Option<usize>| match (i, j) {
        (Some(i), Some(j)) if i < cols && j < rows && at(i, j) != empty => Some(at(i, j)),
        _ => None,
    };
    let gi = diff(get(i.checked_sub(1), Some(j)), get(Some(i + 1), Some(j)));
    let gj = diff(get(Some(i), j.checked_sub(1)), get(Some(i), Some(j + 1)));
    (gi, gj)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffer_counts_reuse_within_and_across_patches() {
        let mut b = NormalBuffer::default();
        b.begin_patch();
        let n1 = b.normal(0, (0.01, 0.01), 3, -2);
        let n2 = b.normal(0, (0.01, 0.01), 3, -2);
        assert_eq!(n1, n2);
        b.begin_patch();
        b.normal(0, (0.01, 0.01), 3, -2);
        assert_eq!(b.counts.needed, 3);
        assert_eq!(b.counts.computed_per_patch_buffer, 2);
        assert_eq!(b.counts.computed_ordered_buffer, 1);
        // New ratios invalidate the table.
        b.normal(0, (0.02, 0.01), 3, -2);
        assert_eq!(b.counts.computed_ordered_buffer, 2);
        let expected = reconstruct_normal(3, -2, 0.02, 0.01).normalize();
        assert!((b.normal(0, (0.02, 0.01), 3, -2) - expected).length() < 1e-7);
    }

    #[test]
    fn differences_are_one_sided_at_borders_and_holes() {
        const E: u16 = u16::MAX;
        // 3 x 2 grid, row-major.
        let d = [10, 12, 20, 11, E, 15];
        assert_eq!(node_differences(&d, 3, 2, 1, 0, E), (10, 0));
        assert_eq!(node_differences(&d, 3, 2, 0, 0, E), (4, 2));
        assert_eq!(node_differences(&d, 3, 2, 0, 1, E), (0, 2));
    }
}
