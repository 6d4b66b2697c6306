//! The normal buffer of the original work: a cache of node normals
//! reconstructed in patch space ([`crate::prepare::normals`]), one table
//! per mip level indexed by the displacement differences' slot.
//!
//! The buffer keeps one table per mip level (levels have different ratios)
//! and is invalidated when the ratios change; patches are drawn sorted by
//! their ratios so that it rarely is. Two counts are kept: normals computed
//! when the buffer is cleared for every patch ("with buffer") and when it
//! persists across patches ("with patch ordering").
//!
//! Which entries are valid for the current ratios, and which the current
//! patch used, are bitsets over the table: a mip level drawn whole counts
//! its lookups word by word from the set of its slots found at preparation
//! ([`SlotSet`]).
//!
//! Cost: one table probe per node (one bitset word per 64 slots for a level
//! drawn whole); a miss costs one normalization. Memory: 65 × 65 entries
//! (24 bytes) per level that computes a normal (a Phong frame's chunks only
//! count their lookups and allocate none).

use glam::Vec3;

use crate::fixed::attr_to_bits;
use crate::prepare::normals::{
    reconstruct_normal, slot_differences, table_slot, OUTSIDE_TABLE, SIDE,
};

/// Words of a bitset over the table's slots.
const WORDS: usize = (SIDE * SIDE).div_ceil(64);

/// The first bit of the spare word past a [`SlotSetBuilder`]'s table
/// words: [`SlotSetBuilder::add_used`] sets it for unused nodes (and the
/// next bit for nodes outside the table), so its loop has no branch.
const SPARE: u16 = (WORDS * 64) as u16;

#[derive(Debug, Clone, Copy, Default)]
struct Entry {
    normal: Vec3,
    /// `normal` as stored in projected nodes ([`attr_to_bits`]).
    bits: [i32; 3],
}

#[derive(Debug, Clone)]
struct Table {
    ratios: (f32, f32),
    /// Entries computed for `ratios` (one bit per slot).
    valid: [u64; WORDS],
    /// Entries counted as computed for `ratios` (a superset of `valid`):
    /// a Phong frame counts its lookups without computing the normals it
    /// reads from the prepared scene ([`NormalBuffer::touch_at`],
    /// [`NormalBuffer::touch_all`]). Why: the normalizations of those
    /// entries were ≈ 0.65 M instructions per 500² sphere frame for
    /// statistics alone (callgrind, `profile_sphere 500 1`).
    counted: [u64; WORDS],
    /// `counted` has no bit set (new ratios since the last count).
    counted_empty: bool,
    /// Entries used by patch `seen_patch`.
    seen: [u64; WORDS],
    seen_patch: u32,
    /// `seen` has no bit set.
    seen_empty: bool,
    /// The cached normals, allocated at the first one computed (a valid
    /// bit implies it is). Why not with the table: a Phong frame only
    /// counts its lookups, and the chunks' tables were 10 MB of a one-frame
    /// render's 24 MB heap peak, every page written (massif,
    /// `spatch render sphere.spatch`).
    entries: Vec<Entry>,
}

/// Counts of normal requests and computations.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct NormalCounts {
    pub(crate) needed: u64,
    pub(crate) computed_per_patch_buffer: u64,
    pub(crate) computed_ordered_buffer: u64,
}

/// The distinct table slots of a set of nodes (those of a mip level drawn
/// whole), for counting their lookups at once ([`NormalBuffer::touch_all`]).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct SlotSet {
    /// The non-zero words of the set's bitset, with their index.
    words: Vec<(u16, u64)>,
    /// Nodes in the set.
    nodes: u32,
    /// Nodes whose differences lie outside the table.
    outside: u32,
    /// Distinct slots (bits set in `words`).
    slots: u32,
}

impl SlotSet {
    /// The set of the nodes `slots` (each [`OUTSIDE_TABLE`] or a slot): the
    /// reference [`SlotSetBuilder::add_used`] is tested against.
    #[cfg(test)]
    pub(crate) fn new(slots: impl Iterator<Item = u16>) -> Self {
        let mut builder = SlotSetBuilder::default();
        slots.for_each(|slot| builder.add(slot));
        builder.finish()
    }
}

/// A [`SlotSet`] gathered a node at a time.
#[derive(Debug, Clone)]
pub(crate) struct SlotSetBuilder {
    /// The table's words, then one spare word ([`SPARE`]).
    bits: [u64; WORDS + 1],
    nodes: u32,
    outside: u32,
}

impl Default for SlotSetBuilder {
    fn default() -> Self {
        Self {
            bits: [0; WORDS + 1],
            nodes: 0,
            outside: 0,
        }
    }
}

impl SlotSetBuilder {
    /// Adds a node whose slot is `slot` ([`OUTSIDE_TABLE`] or a slot).
    #[cfg(test)]
    pub(crate) fn add(&mut self, slot: u16) {
        self.nodes += 1;
        if slot == OUTSIDE_TABLE {
            self.outside += 1;
        } else {
            self.bits[slot as usize / 64] |= 1 << (slot % 64);
        }
    }

    /// `add` (the tests' one-node reference) for each node whose `used`
    /// flag is set, its slot the [`table_slot`] of its differences in `gi`
    /// and `gj`. Why by blocks of
    /// 64 nodes, their slots found first in one branch-free pass (vector
    /// lanes) and then set a bit per node (unused nodes' and outside
    /// nodes' in the spare word): a slot, a test and a branch per node were
    /// 4 M instructions of a one-frame bunny render (callgrind, `spatch
    /// render bunny.spatch -o out.png --threads 1`).
    #[inline(always)]
    pub(crate) fn add_used(&mut self, used: &[bool], gi: &[i32], gj: &[i32]) {
        const BLOCK: usize = 64;
        let mut slots = [0u16; BLOCK];
        let blocks = used
            .chunks(BLOCK)
            .zip(gi.chunks(BLOCK))
            .zip(gj.chunks(BLOCK));
        for ((used, gi), gj) in blocks {
            let (mut nodes, mut outside) = (0u32, 0u32);
            for (((s, &u), &gi), &gj) in slots.iter_mut().zip(used).zip(gi).zip(gj) {
                let slot = table_slot(gi, gj);
                let out = slot == OUTSIDE_TABLE;
                nodes += u32::from(u);
                outside += u32::from(u & out);
                *s = match (u, out) {
                    (false, _) => SPARE,
                    (true, true) => SPARE + 1,
                    (true, false) => slot,
                };
            }
            for &s in &slots[..used.len()] {
                self.bits[usize::from(s / 64)] |= 1 << (s % 64);
            }
            self.nodes += nodes;
            self.outside += outside;
        }
    }

    /// The set of the nodes added. Why always inlined: a mip level's
    /// shading inputs build one with the AVX2 copy ([`crate::isa`]), whose
    /// `popcnt` counts a word in one instruction (a dozen without).
    #[inline(always)]
    pub(crate) fn finish(self) -> SlotSet {
        // Counted first, so the list is allocated once (growing it by
        // pushes reallocated it for most levels).
        let bits = &self.bits[..WORDS];
        let filled = bits.iter().filter(|&&w| w != 0).count();
        let mut words: Vec<(u16, u64)> = Vec::with_capacity(filled);
        words.extend(
            (0..WORDS as u16)
                .zip(bits.iter().copied())
                .filter(|&(_, w)| w != 0),
        );
        SlotSet {
            slots: words.iter().map(|&(_, w)| w.count_ones()).sum(),
            words,
            nodes: self.nodes,
            outside: self.outside,
        }
    }
}

/// The normal buffer (one per worker chunk).
#[derive(Debug, Clone, Default)]
pub(crate) struct NormalBuffer {
    tables: Vec<Table>,
    patch: u32,
    pub(crate) counts: NormalCounts,
}

impl NormalBuffer {
    /// Forgets every cached normal (start of a chunk of patches).
    pub(crate) fn clear(&mut self) {
        for t in &mut self.tables {
            t.valid = [0; WORDS];
            t.counted = [0; WORDS];
            t.counted_empty = true;
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
    /// the ratios changed) before a run of lookups or counts.
    pub(crate) fn select(&mut self, level: usize, ratios: (f32, f32)) {
        while self.tables.len() <= level {
            self.tables.push(Table {
                ratios: (f32::NAN, f32::NAN),
                valid: [0; WORDS],
                counted: [0; WORDS],
                counted_empty: true,
                seen: [0; WORDS],
                seen_patch: self.patch.wrapping_sub(1),
                seen_empty: true,
                entries: Vec::new(),
            });
        }
        let patch = self.patch;
        let table = &mut self.tables[level];
        if table.ratios != ratios {
            table.ratios = ratios;
            table.valid = [0; WORDS];
            table.counted = [0; WORDS];
            table.counted_empty = true;
        }
        if table.seen_patch != patch {
            table.seen_patch = patch;
            table.seen = [0; WORDS];
            table.seen_empty = true;
        }
    }

    /// The unit normal of [`Self::normal`] as stored in projected nodes
    /// ([`attr_to_bits`]) for a node whose differences have table slot
    /// `slot` (not [`OUTSIDE_TABLE`]; see [`table_slot`]), counted: the
    /// reference the counting of [`Self::touch_at`] is tested against.
    #[cfg(test)]
    pub(crate) fn normal_bits_at(&mut self, level: usize, slot: u16) -> [i32; 3] {
        debug_assert!(slot != OUTSIDE_TABLE);
        self.counts.needed += 1;
        self.probe(level, slot as usize).1
    }

    /// Counts a lookup of the normal at `slot` (not [`OUTSIDE_TABLE`]) in
    /// the table chosen by [`Self::select`] exactly as
    /// `normal_bits_at` (its tests' reference) would, for a frame that reads its normals
    /// from the prepared scene ([`crate::prepare::level_shading::LevelShading`]).
    #[inline(always)]
    pub(crate) fn touch_at(&mut self, level: usize, slot: u16) {
        debug_assert!(slot != OUTSIDE_TABLE);
        self.counts.needed += 1;
        self.count_probe(level, slot as usize);
    }

    /// Counts a lookup of a normal outside the table (always computed), as
    /// a lookup would.
    pub(crate) fn touch_outside(&mut self) {
        self.counts.needed += 1;
        self.counts.computed_per_patch_buffer += 1;
        self.counts.computed_ordered_buffer += 1;
    }

    /// [`Self::touch_at`] (or [`Self::touch_outside`]) for every node of
    /// `set`, in the table chosen by [`Self::select`], word by word. Why:
    /// one lookup per node cost ~30 instructions, 4.8 M per 500² sphere
    /// frame (callgrind, `profile_sphere 500 1`).
    pub(crate) fn touch_all(&mut self, level: usize, set: &SlotSet) {
        let c = &mut self.counts;
        c.needed += set.nodes as u64;
        c.computed_per_patch_buffer += set.outside as u64;
        c.computed_ordered_buffer += set.outside as u64;
        let table = &mut self.tables[level];
        // Why the special cases: `count_ones` is a dozen instructions
        // without `popcnt` (baseline x86-64); the patch's first lookups
        // find `seen` empty, and most words hold no slot new to the table
        // (callgrind, `profile_sphere 500 1`).
        let first = table.seen_empty;
        if first {
            c.computed_per_patch_buffer += set.slots as u64;
        }
        table.seen_empty = false;
        // Fresh ratios (nearly every patch of a scan): every slot of the set
        // is new to `counted`, so its words are copied, not counted. Why:
        // the two `count_ones` per word were most of a Phong frame's
        // counting (callgrind, `spatch render bunny.spatch --bench 5`).
        let fresh = table.counted_empty;
        if fresh {
            c.computed_ordered_buffer += set.slots as u64;
            table.counted_empty = set.words.is_empty();
        }
        for &(w, bits) in &set.words {
            let w = w as usize;
            if !first {
                c.computed_per_patch_buffer += (bits & !table.seen[w]).count_ones() as u64;
            }
            table.seen[w] |= bits;
            if fresh {
                table.counted[w] = bits;
                continue;
            }
            let new = bits & !table.counted[w];
            if new != 0 {
                c.computed_ordered_buffer += new.count_ones() as u64;
                table.counted[w] |= new;
            }
        }
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

    /// The cached entry at `index` of the table of `level` (computed if
    /// the table was invalidated since it was written), its lookup counted.
    #[inline(always)]
    fn probe(&mut self, level: usize, index: usize) -> (Vec3, [i32; 3]) {
        self.count_probe(level, index);
        self.lookup(level, index)
    }

    /// The entry at `index` of the table of `level`, computed if the table
    /// was invalidated since it was written.
    #[inline(always)]
    fn lookup(&mut self, level: usize, index: usize) -> (Vec3, [i32; 3]) {
        let table = &mut self.tables[level];
        let (w, bit) = (index / 64, 1u64 << (index % 64));
        if table.valid[w] & bit == 0 {
            if table.entries.is_empty() {
                table.entries = vec![Entry::default(); SIDE * SIDE];
            }
            table.valid[w] |= bit;
            table.entries[index] = compute_entry(index, table.ratios);
        }
        let entry = &table.entries[index];
        (entry.normal, entry.bits)
    }
}

impl NormalBuffer {
    /// The counts of a lookup of slot `index` of `level`'s table (see
    /// [`Table::counted`]), without computing its entry.
    #[inline(always)]
    fn count_probe(&mut self, level: usize, index: usize) {
        let table = &mut self.tables[level];
        let (w, bit) = (index / 64, 1u64 << (index % 64));
        if table.seen[w] & bit == 0 {
            self.counts.computed_per_patch_buffer += 1;
            table.seen[w] |= bit;
            table.seen_empty = false;
        }
        if table.counted[w] & bit == 0 {
            self.counts.computed_ordered_buffer += 1;
            table.counted[w] |= bit;
            table.counted_empty = false;
        }
    }
}

/// The entry of table slot `index` for `ratios`.
#[inline(never)]
fn compute_entry(index: usize, ratios: (f32, f32)) -> Entry {
    let (gi, gj) = slot_differences(index);
    let normal = reconstruct_normal(gi, gj, ratios.0, ratios.1).normalize();
    Entry {
        normal,
        bits: normal.to_array().map(attr_to_bits),
    }
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
    fn adding_used_nodes_equals_adding_them_one_by_one() {
        // Lengths across the 64-node blocks, unused nodes, differences in
        // and beyond the table (its edges included).
        let mut rng = crate::test_rng::XorShift(0x5107_5e75);
        for case in 0..200 {
            let n = [0, 1, 63, 64, 65, 200, 289][case % 7];
            let spread = [3, 33, 40, 300][case % 4];
            let diff = |rng: &mut crate::test_rng::XorShift| {
                rng.below(2 * spread + 1) as i32 - spread as i32
            };
            let used: Vec<bool> = (0..n).map(|_| rng.below(4) != 0).collect();
            let gi: Vec<i32> = (0..n).map(|_| diff(&mut rng)).collect();
            let gj: Vec<i32> = (0..n).map(|_| diff(&mut rng)).collect();
            let mut all = SlotSetBuilder::default();
            all.add_used(&used, &gi, &gj);
            let one = (0..n)
                .filter(|&k| used[k])
                .map(|k| table_slot(gi[k], gj[k]));
            assert_eq!(all.finish(), SlotSet::new(one), "case {case}");
        }
    }

    #[test]
    fn counting_a_slot_set_equals_counting_node_by_node() {
        let mut seed = 0x853c_49e6_748f_ea9bu64;
        let mut next = move |n: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % n
        };
        let (mut one, mut all) = (NormalBuffer::default(), NormalBuffer::default());
        for patch in 0..12 {
            // Neighbouring patches share most slots; some change ratios.
            let ratios = (0.01 * (1 + patch / 4) as f32, 0.02);
            let slots: Vec<u16> = (0..300)
                .map(|_| match next(40) {
                    0 => OUTSIDE_TABLE,
                    _ => table_slot(next(9) as i32 - 4, next(7) as i32 - 3 + patch),
                })
                .collect();
            for b in [&mut one, &mut all] {
                b.begin_patch();
                b.select(1, ratios);
            }
            for &slot in &slots {
                if slot == OUTSIDE_TABLE {
                    one.touch_outside();
                } else {
                    one.touch_at(1, slot);
                }
            }
            all.touch_all(1, &SlotSet::new(slots.iter().copied()));
            assert_eq!(one.counts, all.counts, "patch {patch}");
            // A second piece of the same patch (its slots partly seen).
            let more: Vec<u16> = (0..40)
                .map(|_| table_slot(next(11) as i32 - 5, next(9) as i32 - 4 + patch))
                .collect();
            for &slot in &more {
                one.touch_at(1, slot);
            }
            all.touch_all(1, &SlotSet::new(more.iter().copied()));
            assert_eq!(one.counts, all.counts, "patch {patch}, second piece");
            // The entries counted as computed are the normals.
            assert_eq!(one.normal(1, ratios, 2, 3), all.normal(1, ratios, 2, 3));
            assert_eq!(one.counts, all.counts);
        }
        assert!(one.counts.computed_ordered_buffer < one.counts.computed_per_patch_buffer);
    }

    /// A lookup only counted (Phong) computes its normal when a later
    /// lookup reads it, and counts exactly as computing it at once did.
    #[test]
    fn counted_lookups_compute_their_normal_when_read() {
        let ratios = (0.03, 0.05);
        let (mut a, mut b) = (NormalBuffer::default(), NormalBuffer::default());
        for buf in [&mut a, &mut b] {
            buf.begin_patch();
            buf.select(0, ratios);
        }
        let slot = table_slot(5, -7);
        a.touch_at(0, slot);
        b.normal_bits_at(0, slot);
        a.touch_all(0, &SlotSet::new([table_slot(1, 2)].into_iter()));
        b.normal_bits_at(0, table_slot(1, 2));
        assert_eq!(a.counts, b.counts);
        for (gi, gj) in [(5, -7), (1, 2)] {
            let (na, nb) = (a.normal(0, ratios, gi, gj), b.normal(0, ratios, gi, gj));
            assert_eq!(na, nb);
            assert_eq!(
                na,
                reconstruct_normal(gi, gj, ratios.0, ratios.1).normalize()
            );
            assert_eq!(a.counts, b.counts);
        }
    }
}
