//! Frustums whose top rim angle runs from 30° to 150° (the bottom rim from 150° to 30°): the
//! edge patches keep the rims closed at every angle.
//!
//! The frustums are fitted at a spacing of 0.045 (about 70 nodes across the 3.2-wide model,
//! cells about 5 pixels wide in the 500 × 500 views). The spacing derived from their long
//! sliver triangles would be 0.134, cells 13 pixels wide: then the curved rims' silhouettes
//! alias by up to a pixel (a piece's row along the crease follows its chord, and a cell 13
//! pixels wide cuts a visible corner where the rim bends away from it), 0.01-0.26 % of the
//! pixels (docs/algorithms/edges.md).

use spatch_edges::EdgeOptions;
use spatch_eval::{hole_fraction, HoleOptions};

use crate::surface::{fit_with_spacing, frustum};

/// Largest hole fraction allowed with edge patches: the target, 0.05 %.
const MAX_HOLES: f64 = 0.0005;

/// Node spacing of the surface patches (see the module docs).
const SPACING: f32 = 0.045;

#[test]
fn rims_stay_closed_from_30_to_150_degrees() {
    let mut options = HoleOptions::default();
    // Debug builds check fewer, smaller views; release builds all 14 at 500 × 500.
    if cfg!(debug_assertions) {
        options.views.truncate(6);
        options.size = [300, 300];
    }
    let mut total_without = 0.0;
    for angle in [30.0, 50.0, 70.0, 90.0, 110.0, 130.0, 150.0] {
        let fitted = fit_with_spacing(frustum(angle, 96), Some(SPACING));
        let (edges, stats) = fitted.edges(&EdgeOptions::default());
        assert_eq!(stats.chains, 2, "{angle}°: two rim loops");
        assert_eq!(stats.closed_chains, 2, "{angle}°");
        assert!(stats.edge_patches > 0);
        let with = hole_fraction(&fitted.scene(&edges), &fitted.mesh, &options).unwrap();
        let without = hole_fraction(&fitted.scene(&[]), &fitted.mesh, &options).unwrap();
        eprintln!(
            "rim {angle:>5}°: holes {:.4} % with edge patches, {:.4} % without ({} edge patches)",
            with.fraction * 100.0,
            without.fraction * 100.0,
            edges.len()
        );
        assert!(
            with.fraction <= MAX_HOLES,
            "{angle}°: hole fraction {} with edge patches",
            with.fraction
        );
        // The rims are where the gaps were: edge patches remove nearly all of them.
        assert!(
            with.fraction * 20.0 <= without.fraction,
            "{angle}°: {} with, {} without",
            with.fraction,
            without.fraction
        );
        total_without += without.fraction;
    }
    // The sweep must exercise real gaps, or it proves nothing.
    assert!(total_without > 0.0, "no holes even without edge patches");
}
