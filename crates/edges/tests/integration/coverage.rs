//! Edge patches go only where the surface patches leave a gap; soft creases the surface
//! patches reach over get none.

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

/// Edge and corner patches of `fitted` with soft creases under `soft_deg`.
fn with_soft(fitted: &crate::surface::Fitted, soft_deg: f32) -> spatch_edges::EdgeStats {
    let mut options = EdgeOptions::default();
    options.soft_crease_deg = soft_deg;
    fitted.edges(&options).1
}

#[test]
fn soft_creases_the_surface_reaches_over_get_no_edge_patch() {
    // A frustum whose top rim is a 48° fold (soft) and bottom rim a 132° one (sharp). A cell
    // straddling the 48° fold cuts its corner by up to tan(48°) / 4 = 0.28 cells: over the
    // usual tolerance (0.2), within the soft one (0.35).
    let fitted = fit_with_spacing(frustum(48.0, 96), Some(0.045));
    let strict = with_soft(&fitted, 0.0);
    let soft = with_soft(&fitted, 50.0);
    assert_eq!(
        soft,
        with_soft(&fitted, EdgeOptions::default().soft_crease_deg)
    );
    eprintln!(
        "48°/132° frustum: {} + {} patches, {} covered of {} without soft creases; {} + {}, {} \
         covered with",
        strict.edge_patches,
        strict.corner_patches,
        strict.covered_creases,
        strict.creases,
        soft.edge_patches,
        soft.corner_patches,
        soft.covered_creases
    );
    // The soft rim's creases the surface patches reach over but cut by more than 0.2 cells
    // are covered with soft creases and gaps without.
    assert!(soft.covered_creases > strict.covered_creases, "{soft:?}");
    assert!(soft.edge_patches < strict.edge_patches);
    // The sharp rim keeps its edge patches: a gap of a cell at 140°, covered by neither.
    assert!(soft.covered_creases <= 96 + 10, "{soft:?}");
    assert!(soft.edge_patches > 0);
}

#[test]
fn sharp_folds_are_not_soft() {
    // Both rims 90°: nothing under 50°, so soft creases change nothing.
    let fitted = fit_with_spacing(frustum(90.0, 96), Some(0.045));
    assert_eq!(with_soft(&fitted, 0.0), with_soft(&fitted, 50.0));
    // Raised past 90°, the same rims become soft and some are covered.
    let all_soft = with_soft(&fitted, 120.0);
    assert!(all_soft.covered_creases >= with_soft(&fitted, 0.0).covered_creases);
}
