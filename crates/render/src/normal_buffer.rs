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

/// Differences in `-RADIUS..=RADIUS` are cached; others are computed.
const RADIUS: i32 = 32;
const SIDE: usize = (2 * RADIUS + 1) as usize;

/// The table slot of a node whose differences lie outside the table.
pub(crate) const OUTSIDE_TABLE: u16 = u16::MAX;

/// The table slot of differences `(gi, gj)` (the same for every ratio and
/// frame), or [`OUTSIDE_TABLE`]. Why slots: the differences depend on the
/// displacements only, so [`crate::mip`] finds them once per scene and a
/// frame starts from the slot (callgrind, `profile_sphere 500 1`: the
/// per-node border logic was ~4 M instructions per frame). One unsigned
/// compare per difference: it runs for every node of a scene.
#[inline(always)]
pub(crate) fn table_slot(gi: i32, gj: i32) -> u16 {
    let (x, y) = (
        gi.wrapping_add(RADIUS) as u32,
        gj.wrapping_add(RADIUS) as u32,
    );
    if x < SIDE as u32 && y < SIDE as u32 {
        (y as usize * SIDE + x as usize) as u16
    } else {
        OUTSIDE_TABLE
    }
}

/// Words of a bitset over the table's slots.
const WORDS: usize = (SIDE * SIDE).div_ceil(64);

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
#[derive(Debug, Clone, Default)]
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
    /// The set of the nodes `slots` (each [`OUTSIDE_TABLE`] or a slot).
    pub(crate) fn new(slots: impl Iterator<Item = u16>) -> Self {
        let mut bits = [0u64; WORDS];
        let (mut nodes, mut outside) = (0, 0);
        for slot in slots {
            nodes += 1;
            if slot == OUTSIDE_TABLE {
                outside += 1;
            } else {
                bits[slot as usize / 64] |= 1 << (slot % 64);
            }
        }
        let words: Vec<(u16, u64)> = (0..WORDS as u16)
            .zip(bits)
            .filter(|&(_, w)| w != 0)
            .collect();
        Self {
            slots: words.iter().map(|&(_, w)| w.count_ones()).sum(),
            words,
            nodes,
            outside,
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
            t.valid = [0; WORDS];
            t.counted = [0; WORDS];
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
                valid: [0; WORDS],
                counted: [0; WORDS],
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
        }
        if table.seen_patch != patch {
            table.seen_patch = patch;
            table.seen = [0; WORDS];
            table.seen_empty = true;
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
        self.count_probe(level, slot as usize);
    }

    /// Counts a lookup of a normal outside the table (always computed), as
    /// [`Self::normal_bits`] would.
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
        for &(w, bits) in &set.words {
            let w = w as usize;
            if !first {
                c.computed_per_patch_buffer += (bits & !table.seen[w]).count_ones() as u64;
            }
            table.seen[w] |= bits;
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

    /// The cached entry at `index` of the table of `level`, computed if the
    /// table was invalidated since it was written.
    #[inline(always)]
    fn probe(&mut self, level: usize, index: usize) -> (Vec3, [i32; 3]) {
        self.count_probe(level, index);
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
        }
    }
}

/// The differences `(gi, gj)` of table slot `index` (the inverse of
/// [`table_slot`]).
fn slot_differences(index: usize) -> (i32, i32) {
    (
        (index % SIDE) as i32 - RADIUS,
        (index / SIDE) as i32 - RADIUS,
    )
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

/// The table slot ([`table_slot`]) of every node of a `cols × rows` grid,
/// row-major: [`node_differences`] at each node. Why a pass of its own: a
/// row walk with neighbours read as empty beyond the grid takes a few
/// compares per node, where the general form's optional lookups made this
/// a third of a scene's preparation (callgrind, `profile_sphere 500 1 1`).
pub(crate) fn grid_slots(d: &[u16], cols: usize, rows: usize, empty: u16) -> Vec<u16> {
    // A neighbour outside the grid reads as empty.
    let diff = |prev: u16, centre: u16, next: u16| -> i32 {
        match (prev != empty, next != empty) {
            (true, true) => next as i32 - prev as i32,
            (true, false) => 2 * (centre as i32 - prev as i32),
            (false, true) => 2 * (next as i32 - centre as i32),
            (false, false) => 0,
        }
    };
    let mut slots = Vec::with_capacity(cols * rows);
    let filled: Vec<bool> = d.chunks_exact(cols).map(|r| !r.contains(&empty)).collect();
    for j in 0..rows {
        let row = &d[j * cols..(j + 1) * cols];
        let below = (j > 0).then(|| &d[(j - 1) * cols..j * cols]);
        let above = (j + 1 < rows).then(|| &d[(j + 1) * cols..(j + 2) * cols]);
        // Why a path for rows whose nodes and neighbours are all filled: no
        // per-node empty tests, and most rows are (callgrind, `spatch render
        // sphere.spatch`: 78 instructions per node before).
        let whole = filled[j]
            && (j == 0 || filled[j - 1])
            && (j + 1 == rows || filled[j + 1])
            && cols >= 2
            && rows >= 2;
        if whole {
            filled_row_slots(row, below, above, &mut slots);
            continue;
        }
        for (i, &centre) in row.iter().enumerate() {
            let left = if i > 0 { row[i - 1] } else { empty };
            let right = row.get(i + 1).copied().unwrap_or(empty);
            let down = below.map_or(empty, |r| r[i]);
            let up = above.map_or(empty, |r| r[i]);
            slots.push(table_slot(
                diff(left, centre, right),
                diff(down, centre, up),
            ));
        }
    }
    slots
}

/// The slots of a row of filled nodes whose rows below and above (when
/// they exist, at least one does) are filled, appended to `slots`: the
/// differences of [`node_differences`] without its empty cases.
fn filled_row_slots(
    row: &[u16],
    below: Option<&[u16]>,
    above: Option<&[u16]>,
    slots: &mut Vec<u16>,
) {
    let n = row.len();
    // Across the rows: central between the rows below and above, else
    // one-sided (doubled) against the row itself.
    let (lo, hi, scale) = match (below, above) {
        (Some(b), Some(a)) => (b, a, 1),
        (None, Some(a)) => (row, a, 2),
        (Some(b), None) => (b, row, 2),
        (None, None) => unreachable!("a grid has at least two rows"),
    };
    let (lo, hi) = (&lo[..n], &hi[..n]);
    let gj = |i: usize| scale * (hi[i] as i32 - lo[i] as i32);
    let d = |a: u16, b: u16| b as i32 - a as i32;
    // Along the row: one-sided (doubled) at the ends, central inside.
    slots.push(table_slot(2 * d(row[0], row[1]), gj(0)));
    let inside = row.iter().zip(&row[2..]).zip(lo[1..].iter().zip(&hi[1..]));
    slots.extend(inside.map(|((&l, &r), (&b, &a))| table_slot(d(l, r), scale * d(b, a))));
    slots.push(table_slot(2 * d(row[n - 2], row[n - 1]), gj(n - 1)));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slot_exists_exactly_within_the_radius() {
        for gi in -RADIUS - 3..=RADIUS + 3 {
            for gj in [-RADIUS - 1, -RADIUS, -1, 0, 7, RADIUS, RADIUS + 1] {
                let slot = table_slot(gi, gj);
                if gi.abs() > RADIUS || gj.abs() > RADIUS {
                    assert_eq!(slot, OUTSIDE_TABLE, "{gi}, {gj}");
                } else {
                    assert_eq!(slot_differences(slot as usize), (gi, gj));
                }
            }
        }
        assert_eq!(table_slot(i32::MAX, 0), OUTSIDE_TABLE);
        assert_eq!(table_slot(0, i32::MIN), OUTSIDE_TABLE);
    }

    #[test]
    fn grid_slots_are_the_slots_of_each_nodes_differences() {
        // Random codes with empty nodes and large steps (some outside the
        // table), on grids from 2 × 2 up.
        let mut rng = crate::test_rng::XorShift(0x5107_5eed);
        for case in 0..400 {
            let (cols, rows) = (2 + rng.below(7) as usize, 2 + rng.below(7) as usize);
            // Every other grid has few empty nodes, so whole rows take the
            // filled-row path.
            let empties = if case % 2 == 0 { 8 } else { 60 };
            let d: Vec<u16> = (0..cols * rows)
                .map(|_| match rng.below(empties) {
                    0 => 9,
                    1 => rng.below(200) as u16,
                    _ => 100 + rng.below(12) as u16,
                })
                .collect();
            let slots = grid_slots(&d, cols, rows, 9);
            for j in 0..rows {
                for i in 0..cols {
                    let (gi, gj) = node_differences(&d, cols, rows, i, j, 9);
                    assert_eq!(slots[j * cols + i], table_slot(gi, gj), "{i}, {j}");
                }
            }
        }
    }

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
