//! The Pareto front of points that minimize two costs (time and error).
//!
//! A point *dominates* another when it is no worse in both costs and better in at least one.
//! The front is the set of points no other point dominates: the trade-offs worth choosing.
//! Equal points do not dominate each other, so duplicates are on the front together. A point
//! with a NaN cost is never on the front and dominates nothing.
//!
//! Cost: O(n log n) — sort by the first cost (then the second), sweep keeping the best second
//! cost seen so far.

/// True when `a` dominates `b` (both costs minimized).
pub fn dominates(a: (f64, f64), b: (f64, f64)) -> bool {
    a.0 <= b.0 && a.1 <= b.1 && (a.0 < b.0 || a.1 < b.1)
}

/// For each point, whether it is on the Pareto front (both costs minimized).
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&k| !points[k].0.is_nan() && !points[k].1.is_nan())
        .collect();
    order.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut front = vec![false; points.len()];
    // The best second cost among points with a strictly smaller first cost, and among the
    // points of the current run of equal first costs.
    let mut best_before: Option<f64> = None;
    let mut i = 0;
    while i < order.len() {
        let x = points[order[i]].0;
        let mut j = i;
        while j < order.len() && points[order[j]].0 == x {
            j += 1;
        }
        // Within the run (sorted by second cost), only those with the run's least second
        // cost are undominated by their own run.
        let run_best = points[order[i]].1;
        for &k in &order[i..j] {
            let y = points[k].1;
            front[k] = y == run_best && best_before.is_none_or(|b| y < b);
        }
        best_before = Some(best_before.map_or(run_best, |b| b.min(run_best)));
        i = j;
    }
    front
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition, checked pairwise.
    fn brute(points: &[(f64, f64)]) -> Vec<bool> {
        points
            .iter()
            .map(|&p| !p.0.is_nan() && !p.1.is_nan() && !points.iter().any(|&q| dominates(q, p)))
            .collect()
    }

    #[test]
    fn a_known_front() {
        let points = [
            (1.0, 5.0), // front: fastest
            (2.0, 3.0), // front
            (3.0, 3.0), // dominated by (2, 3)
            (4.0, 1.0), // front: most accurate
            (5.0, 2.0), // dominated by (4, 1)
            (2.0, 3.0), // duplicate of a front point: also on the front
            (1.0, 6.0), // same time as (1, 5), worse error
            (f64::NAN, 0.0),
        ];
        let front = pareto_front(&points);
        assert_eq!(front, [true, true, false, true, false, true, false, false]);
        assert_eq!(front, brute(&points));
    }

    #[test]
    fn matches_the_definition_on_many_point_sets() {
        // A small deterministic generator with many ties (coordinates in 0..6).
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) % 6) as f64
        };
        for n in 0..40 {
            let points: Vec<(f64, f64)> = (0..n).map(|_| (next(), next())).collect();
            assert_eq!(pareto_front(&points), brute(&points), "{points:?}");
        }
    }

    #[test]
    fn infinities_are_ordinary_costs() {
        let points = [(1.0, f64::INFINITY), (f64::INFINITY, 0.0), (2.0, 1.0)];
        assert_eq!(pareto_front(&points), [true, true, true]);
        assert_eq!(pareto_front(&[]), Vec::<bool>::new());
    }
}
