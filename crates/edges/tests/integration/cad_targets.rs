//! The targets on the shared CAD parts (and the soft creases of the low-poly textured
//! models, Duck and fuze): hole fraction with and without edge patches,
//! surface-to-patch error, and the file size the edge patches add.
//!
//! Debug builds check 6 views at 300 × 300; the figures in docs/algorithms/edges.md come from
//! the release run over the 14 views at 500 × 500:
//! `cargo test --release -p spatch-edges --test integration cad_ -- --nocapture`.

use spatch_edges::EdgeOptions;
use spatch_eval::{geometric_error, hole_fraction, HoleOptions};
use spatch_format::{encode_scene, WriteOptions};
use spatch_mesh::load_mesh;

use crate::surface::fit;

/// Checks the targets on `relative`; `max_share` bounds the edge and corner patches' share
/// of the patches, when given (issue 22 item 8 asks 30 %; fandisk is at 28.1 % since the
/// wider turn where faces are seen squarely).
fn check(relative: &str, max_share: Option<f64>) {
    let Some(path) = spatch_fixtures::shared_data(relative) else {
        return;
    };
    let fitted = fit(load_mesh(&path).unwrap().mesh);
    let (edges, stats) = fitted.edges(&EdgeOptions::default());
    let with = fitted.scene(&edges);
    let without = fitted.scene(&[]);
    let mut options = HoleOptions::default();
    if cfg!(debug_assertions) {
        options.views.truncate(6);
        options.size = [300, 300];
    }
    let holes_with = hole_fraction(&with, &fitted.mesh, &options).unwrap();
    let holes_without = hole_fraction(&without, &fitted.mesh, &options).unwrap();
    let bytes_with = encode_scene(&with, &WriteOptions::default()).unwrap().len();
    let bytes_without = encode_scene(&without, &WriteOptions::default())
        .unwrap()
        .len();
    let increase = bytes_with as f64 / bytes_without as f64 - 1.0;
    let geometric = geometric_error(&with, &fitted.mesh, 7);
    let error = geometric.surface_to_patch;
    eprintln!(
        "{relative}: {} views {}x{}; holes {:.4} % with, {:.4} % without; {} creases, {} chains, \
         {} corners; {} edge + {} corner patches, {} bytes of {} (+{:.1} %); surface_to_patch max \
         {:.4} %, node_to_surface max {:.4} % of the diagonal",
        options.views.len(),
        options.size[0],
        options.size[1],
        holes_with.fraction * 100.0,
        holes_without.fraction * 100.0,
        stats.creases,
        stats.chains,
        stats.corners,
        stats.edge_patches,
        stats.corner_patches,
        bytes_with - bytes_without,
        bytes_with,
        increase * 100.0,
        error.max_rel * 100.0,
        geometric.node_to_surface.max_rel * 100.0,
    );
    for v in &holes_with.views {
        eprintln!(
            "  view {:?}: {} / {}",
            v.direction, v.hole_pixels, v.source_pixels
        );
    }
    // cylinder.ply is an open partial tube: its rims are boundaries, not creases.
    if !relative.contains("cylinder") {
        assert!(stats.creases > 0);
    }
    assert!(
        holes_with.fraction <= 0.0005,
        "hole fraction {}",
        holes_with.fraction
    );
    assert!(holes_with.hole_pixels <= holes_without.hole_pixels);
    assert!(
        error.max_rel <= 0.0025,
        "surface_to_patch {}",
        error.max_rel
    );
    // The budget.
    assert!(
        increase <= 0.25,
        "edge patches add {:.1} %",
        increase * 100.0
    );
    // Issue 22 item 8: edge and corner patches at most 20 % of the bytes and (where the
    // caller asks) a bounded share of the patches.
    let byte_share = (bytes_with - bytes_without) as f64 / bytes_with as f64;
    assert!(byte_share <= 0.20, "edge bytes {:.1} %", byte_share * 100.0);
    let added = (stats.edge_patches + stats.corner_patches) as f64;
    let share = added / (added + fitted.surface.len() as f64);
    eprintln!(
        "  edge + corner patches {:.1} % of the patches",
        share * 100.0
    );
    if let Some(max) = max_share {
        assert!(share <= max, "edge + corner patches {:.1} %", share * 100.0);
    }
}

#[test]
fn cad_cylinder() {
    check("cad/cylinder.ply", None);
}

#[test]
fn cad_cube_meshed() {
    check("cad/cube-meshed.ply", None);
}

#[test]
fn cad_fandisk() {
    check("cad/fandisk.obj", Some(0.30));
}

/// Issue 22 item 8 on the low-poly textured models: the soft creases the surface patches
/// reach over get no edge patch (Duck's share under 30 % of the patches), and the real gaps
/// keep theirs (holes bounded as on the CAD parts).
fn check_soft(relative: &str, max_share: Option<f64>) {
    let Some(path) = spatch_fixtures::shared_data(relative) else {
        return;
    };
    let fitted = fit(load_mesh(&path).unwrap().mesh);
    let mut strict = EdgeOptions::default();
    strict.soft_crease_deg = 0.0;
    let (_, before) = fitted.edges(&strict);
    let (edges, after) = fitted.edges(&EdgeOptions::default());
    let surface = fitted.surface.len() as f64;
    let share = |s: &spatch_edges::EdgeStats| {
        let added = (s.edge_patches + s.corner_patches) as f64;
        added / (added + surface)
    };
    let mut options = HoleOptions::default();
    if cfg!(debug_assertions) {
        options.views.truncate(6);
        options.size = [300, 300];
    }
    let holes = hole_fraction(&fitted.scene(&edges), &fitted.mesh, &options).unwrap();
    eprintln!(
        "{relative}: edge + corner patches {} + {} ({:.1} %) without soft creases, {} + {} \
         ({:.1} %) with; holes {:.4} %, {:.4} % inside the outlines",
        before.edge_patches,
        before.corner_patches,
        share(&before) * 100.0,
        after.edge_patches,
        after.corner_patches,
        share(&after) * 100.0,
        holes.fraction * 100.0,
        holes.interior_fraction * 100.0
    );
    assert!(after.covered_creases > before.covered_creases);
    assert!(
        after.edge_patches + after.corner_patches < before.edge_patches + before.corner_patches
    );
    // Holes as ../shared/MEASURES.md counts them, inside the outlines: the gaps the edge
    // patches are there to close. Counting every source pixel, fuze's textured patches lose
    // about 0.09 % along their outlines in release builds (14 views at 500²), where their
    // pixel-centre outlines fall a little inside the source's (docs/algorithms/render.md,
    // "Where fuze's holes come from"): bounded at three times the interior bound.
    let inside = holes.interior_fraction;
    assert!(inside <= 0.0005, "holes inside the outlines {inside}");
    assert!(holes.fraction <= 0.0015, "hole fraction {}", holes.fraction);
    if let Some(max) = max_share {
        assert!(share(&after) <= max, "{:.1} %", share(&after) * 100.0);
    }
}

#[test]
fn shared_duck_soft_creases() {
    check_soft("gltf/Duck.glb", Some(0.30));
}

#[test]
fn shared_fuze_soft_creases() {
    check_soft("textured_obj/fuze/fuze.obj", None);
}
