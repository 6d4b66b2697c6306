//! Edge patches go only where the surface patches leave a gap.

use spatch_edges::EdgeOptions;
use spatch_fixtures::shapes;

use crate::surface::{fit, fit_with_spacing, frustum, mesh_of};

#[test]
fn a_cubes_fitted_faces_cover_its_edges() {
    // The fitter's rectangles end exactly on a cube's straight edges: no gap to close.
    let fitted = fit(mesh_of(&shapes::cube(2.0)));
    let (patches, stats) = fitted.edges(&EdgeOptions::default());
    assert_eq!(stats.creases, 12);
    assert_eq!(stats.covered_creases, 12);
    assert_eq!((stats.edge_patches, stats.corner_patches), (0, 0));
    assert!(patches.is_empty());

    // Asked to cover every crease, it does.
    let mut all = EdgeOptions::default();
    all.only_gaps = false;
    let (patches, stats) = fitted.edges(&all);
    assert_eq!(stats.covered_creases, 0);
    assert_eq!(stats.edge_patches, 12);
    assert_eq!(stats.corner_patches, 8);
    assert_eq!(patches.len(), 20);
}

#[test]
fn curved_rims_are_gaps() {
    // A cylinder's rims: the cap's rectangle cannot end on a circle, so gaps remain.
    let fitted = fit_with_spacing(frustum(90.0, 96), Some(0.045));
    let (_, stats) = fitted.edges(&EdgeOptions::default());
    assert_eq!(stats.creases, 192);
    assert!(
        stats.covered_creases < 20,
        "{} of 192 rim creases read as covered",
        stats.covered_creases
    );
    assert!(stats.edge_patches > 0);
}
