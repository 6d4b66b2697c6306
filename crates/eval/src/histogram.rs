//! A histogram of distances on fixed bins relative to the source's diagonal.
//!
//! The bins are the same for every model and run, so two histograms can be compared bin by
//! bin: upper edges 1, 2, 5 × 10^k of the diagonal from 10^-7 to 10^-1 ([`HISTOGRAM_EDGES`]),
//! then one open bin for everything larger (including infinite distances: points with no
//! patch at all). Bin `k` counts distances `d` with `edge[k-1] < d / diagonal <= edge[k]`
//! (the first bin starts at 0 inclusive).
//!
//! Cost: one pass, O(n log bins).

use serde::{Deserialize, Serialize};

/// Upper bin edges as fractions of the diagonal; the last bin (beyond the last edge) is
/// open.
pub const HISTOGRAM_EDGES: [f64; 19] = [
    1e-7, 2e-7, 5e-7, 1e-6, 2e-6, 5e-6, 1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2,
    2e-2, 5e-2, 1e-1,
];

/// How many distances fall in each bin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ErrorHistogram {
    /// Upper edges of the closed bins, as fractions of the diagonal ([`HISTOGRAM_EDGES`]).
    pub upper_edges_rel: Vec<f64>,
    /// One count per closed bin, then the count of the open bin beyond the last edge
    /// (`upper_edges_rel.len() + 1` counts).
    pub counts: Vec<usize>,
}

impl ErrorHistogram {
    /// Bins `distances` (model units) relative to `diagonal`. A non-positive diagonal puts
    /// every non-zero distance in the open bin.
    pub fn from_distances(distances: &[f32], diagonal: f64) -> Self {
        let mut counts = vec![0; HISTOGRAM_EDGES.len() + 1];
        for &d in distances {
            let rel = if diagonal > 0.0 {
                f64::from(d) / diagonal
            } else if d == 0.0 {
                0.0
            } else {
                f64::INFINITY
            };
            // NaN never compares below an edge, so it lands in the open bin too.
            let bin = HISTOGRAM_EDGES.partition_point(|&edge| edge < rel);
            counts[bin] += 1;
        }
        Self {
            upper_edges_rel: HISTOGRAM_EDGES.to_vec(),
            counts,
        }
    }

    /// Number of distances binned.
    pub fn total(&self) -> usize {
        self.counts.iter().sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_land_in_their_bins() {
        // Diagonal 10: relative distances 0, 1e-7 (on the first edge), 3e-4, 0.5, infinity.
        let h = ErrorHistogram::from_distances(&[0.0, 1e-6, 3e-3, 5.0, f32::INFINITY], 10.0);
        assert_eq!(h.total(), 5);
        assert_eq!(h.counts.len(), HISTOGRAM_EDGES.len() + 1);
        assert_eq!(
            h.counts[0], 2,
            "0 and exactly the first edge: {:?}",
            h.counts
        );
        // 3e-4 is above 2e-4 and at most 5e-4: the bin whose upper edge is 5e-4.
        let k = HISTOGRAM_EDGES.iter().position(|&e| e == 5e-4).unwrap();
        assert_eq!(h.counts[k], 1);
        assert_eq!(h.counts[HISTOGRAM_EDGES.len()], 2, "0.5 and infinity");
    }
}
