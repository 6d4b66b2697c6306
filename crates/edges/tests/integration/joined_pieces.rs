//! Pieces that meet at a crease vertex share one patch where it loses no probe
//! (`EdgeOptions::join_pieces`): fewer edge patches, and the holes stay where they were.

use spatch_edges::{EdgeOptions, EdgeStats};
use spatch_mesh::load_mesh;

use crate::surface::{fit, fit_with_spacing, frustum, Fitted};

/// Joins the pieces of `fitted` and checks the counts and holes against one patch per
/// piece; returns the stats with joining.
fn check(name: &str, fitted: &Fitted) -> EdgeStats {
    let mut separate = EdgeOptions::default();
    separate.join_pieces = false;
    let (found_separate, apart) = fitted.holes_with(&separate);
    let holes_separate = found_separate.hole_pixels;
    let (found_joined, joined) = fitted.holes_with(&EdgeOptions::default());
    let holes_joined = found_joined.hole_pixels;
    eprintln!(
        "{name}: {} + {} patches, {holes_separate} hole px separate; {} + {} ({} joined), \
         {holes_joined} hole px joined",
        apart.edge_patches,
        apart.corner_patches,
        joined.edge_patches,
        joined.corner_patches,
        joined.joined_pieces,
    );
    assert_eq!(apart.joined_pieces, 0);
    assert_eq!(apart.pieces, joined.pieces);
    assert!(
        joined.edge_patches + joined.covered_pieces + joined.joined_pieces <= joined.pieces,
        "{name}: {joined:?}"
    );
    assert!(
        joined.edge_patches + joined.corner_patches <= apart.edge_patches + apart.corner_patches,
        "{name}: more patches joined"
    );
    assert!(
        holes_joined <= holes_separate + holes_separate / 10 + 2,
        "{name}: {holes_joined} hole px joined against {holes_separate}"
    );
    joined
}

#[test]
fn shared_low_poly_models_join_pieces() {
    for relative in ["gltf/Duck.glb", "textured_obj/fuze/fuze.obj"] {
        let Some(path) = spatch_fixtures::shared_data(relative) else {
            continue;
        };
        let fitted = fit(load_mesh(&path).unwrap().mesh);
        let joined = check(relative, &fitted);
        assert!(joined.joined_pieces > 0, "{relative}: no piece joined");
        // Issue 22 item 8's bound on the share of edge and corner patches.
        let crease = joined.edge_patches + joined.corner_patches;
        let share = crease as f64 / (crease + fitted.surface.len()) as f64;
        assert!(
            share <= 0.30,
            "{relative}: {:.1} % edge + corner",
            share * 100.0
        );
    }
}

#[test]
fn a_frustum_rim_keeps_its_holes_when_joined() {
    check(
        "90° frustum",
        &fit_with_spacing(frustum(90.0, 96), Some(0.045)),
    );
}
