//! Sorting `(key, point)` pairs by a counting sort on the key's high bits, then a
//! comparison sort of each bucket's short run.
//!
//! Input: the pairs and `shift`, the bucket of a pair being `key >> shift`. Output: the
//! pairs in increasing order, exactly as `sort_unstable` orders them (pairs are compared
//! whole, so equal keys end up in point order), whatever the thread count.
//!
//! Method: when the buckets span at most four per pair, one histogram pass and one scatter
//! pass put every pair in its bucket (in input order), then the buckets are sorted on
//! their own, in parallel; otherwise the whole list goes to `sort_unstable`. The pipeline
//! uses it on Morton codes (buckets: the top 18 of 48 bits, cells of 1/64 of the bounding
//! box), on voxel keys (buckets: the `(x, y)` columns) and on the spacing's cell keys. (Moving
//! the pairs into their buckets in place, by cycles of swaps, saved the second list and 37 M
//! sequential instructions on the evenly spread 1 M scan set, but each swap waits for the
//! cache miss of the one before: the 4 M terrain's normals took 2.9 s instead of 1.0 s.)
//!
//! Cost: O(n + buckets) plus the sorts of the runs (short on a surface); memory one extra
//! list of pairs and one `usize` per bucket.
//!
//! Based on: H. H. Seward, "Information sorting in the application of electronic digital
//! computers to business operations", MIT report R-232, 1954 (counting sort).

use glam::Vec3;
use rayon::prelude::*;

/// `pairs` in increasing order, buckets `key >> shift` first (see the module documentation).
pub(crate) fn sort_pairs(mut pairs: Vec<(u64, u32)>, shift: u32) -> Vec<(u64, u32)> {
    let bucket = |key: u64| key.checked_shr(shift).unwrap_or(0);
    let buckets = pairs.iter().map(|p| bucket(p.0)).max().map_or(0, |m| m + 1);
    if buckets > 4 * pairs.len().max(1024) as u64 {
        pairs.sort_unstable();
        return pairs;
    }
    let buckets = buckets as usize;
    let mut start = vec![0usize; buckets + 1];
    for p in &pairs {
        start[bucket(p.0) as usize + 1] += 1;
    }
    for b in 0..buckets {
        start[b + 1] += start[b];
    }
    let mut next = start.clone();
    // Zeroed in parallel: `vec!` zeroed it on this thread (calloc's memset, 56 M sequential
    // instructions of the four sorts on the covering 1 M scan set, callgrind).
    let mut sorted = Vec::with_capacity(pairs.len());
    sorted.par_extend(rayon::iter::repeat_n((0u64, 0u32), pairs.len()));
    for &p in &pairs {
        let slot = &mut next[bucket(p.0) as usize];
        sorted[*slot] = p;
        *slot += 1;
    }
    sort_buckets(&mut sorted, &start, 0, shift);
    sorted
}

/// Every point's cell key `x·2^(y_bits+z_bits) + y·2^z_bits + z` (`cell_of` gives the cell
/// coordinates `[x, y, z]`, `y < 2^y_bits`, `z < 2^z_bits`) paired with its index, sorted:
/// by `(x, y)` column first, then `z`, then point. The keys are made in parallel. (The
/// spacing's neighbour grid and the normals' voxels both index their cells this way.)
pub(crate) fn column_sorted_keys(
    positions: &[Vec3],
    cell_of: impl Fn(Vec3) -> [u64; 3] + Sync,
    (y_bits, z_bits): (u32, u32),
) -> Vec<(u64, u32)> {
    let pairs: Vec<(u64, u32)> = positions
        .par_iter()
        .enumerate()
        .map(|(i, &p)| {
            let [x, y, z] = cell_of(p);
            ((x << (y_bits + z_bits)) | (y << z_bits) | z, i as u32)
        })
        .collect();
    // By column first: a column's cells are a short run.
    sort_pairs(pairs, z_bits)
}

/// Buckets handed to one parallel task by [`sort_buckets`].
const BUCKETS_PER_TASK: usize = 2048;

/// Sorts each bucket of `pairs` on its own, `bounds` holding the buckets' limits (indices
/// into the whole list, whose part `pairs` is starts at `first`), `shift` the bucket's place
/// in the key.
///
/// The buckets are disjoint, so halves of them sort in parallel, in place (no memory beyond
/// the two lists): these sorts were the larger half of the sequential instructions of the
/// two sorts (0.18 G of 0.38 G on the evenly spread 1 M scan set, callgrind). Rayon's
/// `par_chunk_by_mut` over the bucket test cost 63 M more instructions than this split.
fn sort_buckets(pairs: &mut [(u64, u32)], bounds: &[usize], first: usize, shift: u32) {
    if bounds.len() <= BUCKETS_PER_TASK {
        let mut packed = Vec::new();
        for run in bounds.windows(2) {
            if run[1] - run[0] > 1 {
                sort_run(
                    &mut pairs[run[0] - first..run[1] - first],
                    shift,
                    &mut packed,
                );
            }
        }
        return;
    }
    let mid = bounds.len() / 2;
    let (low, high) = pairs.split_at_mut(bounds[mid] - first);
    rayon::join(
        || sort_buckets(low, &bounds[..=mid], first, shift),
        || sort_buckets(high, &bounds[mid..], bounds[mid], shift),
    );
}

/// Sorts one bucket's run (keys equal above bit `shift`). When the key's bits below `shift`
/// and the point fit one `u64`, the run is sorted as such words (`packed`: scratch), the same
/// order as the pairs': one integer comparison instead of a pair's two, and the standard
/// sort's sorting networks for integers (about 45 M fewer worker instructions on the evenly
/// spread 1 M scan set, callgrind).
fn sort_run(run: &mut [(u64, u32)], shift: u32, packed: &mut Vec<u64>) {
    if shift > 32 {
        run.sort_unstable();
        return;
    }
    let low = (1u64 << shift) - 1;
    packed.clear();
    packed.extend(run.iter().map(|&(key, i)| (key & low) << 32 | u64::from(i)));
    packed.sort_unstable();
    let high = run[0].0 & !low;
    for (pair, &word) in run.iter_mut().zip(packed.iter()) {
        *pair = (high | word >> 32, word as u32);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equals_a_comparison_sort() {
        let mut rng = spatch_mesh::SplitMix64::new(5);
        // Dense buckets, sparse buckets (the fallback), every bit a bucket bit, and ties.
        for (buckets, shift) in [
            (300u64, 6u32),
            (1u64 << 40, 9),
            (5000, 0),
            (7, 60),
            (90, 32),
        ] {
            let pairs: Vec<(u64, u32)> = (0..20_000)
                .map(|i| {
                    let b = (rng.next_f64() * buckets as f64) as u64;
                    let low = (rng.next_f64() * 40.0) as u64;
                    let low = if shift == 0 {
                        0
                    } else {
                        low % (1 << shift.min(6))
                    };
                    ((b << shift) | low, i)
                })
                .collect();
            let mut expected = pairs.clone();
            expected.sort_unstable();
            assert_eq!(sort_pairs(pairs, shift), expected, "{buckets} buckets");
        }
        assert_eq!(sort_pairs(Vec::new(), 3), Vec::new());
    }

    #[test]
    fn column_sorted_keys_pack_the_cells_and_sort_them() {
        let mut rng = spatch_mesh::SplitMix64::new(9);
        let positions: Vec<Vec3> = (0..5_000)
            .map(|_| Vec3::new(rng.next_f64() as f32, rng.next_f64() as f32, 0.0) * 8.0)
            .collect();
        // Cells of side 1 in x and y, z from the point's index parity via its x fraction.
        let cell_of = |p: Vec3| [p.x as u64, p.y as u64, u64::from(p.x.fract() > 0.5)];
        let got = column_sorted_keys(&positions, cell_of, (3, 1));
        let mut expected: Vec<(u64, u32)> = positions
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let [x, y, z] = cell_of(p);
                (x * 16 + y * 2 + z, i as u32)
            })
            .collect();
        expected.sort_unstable();
        assert_eq!(got, expected);
    }
}
