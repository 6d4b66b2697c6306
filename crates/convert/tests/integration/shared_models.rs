//! The shared real models: colour where the source has it, none elsewhere, no panic.

use spatch_convert::{convert, ConvertInput, ConvertOptions};
use spatch_fixtures::require_shared;

fn run(rel: &str) -> spatch_convert::Conversion {
    let path = spatch_fixtures::shared_data(rel).expect("checked by require_shared");
    convert(ConvertInput::Path(&path), &ConvertOptions::default())
        .unwrap_or_else(|e| panic!("{rel}: {e}"))
}

#[test]
fn textured_models_convert_with_colour() {
    for rel in [
        "textured_obj/fuze/fuze.obj",
        "textured_obj/spot/spot_triangulated.obj",
        "gltf/Duck.glb",
    ] {
        let _ = require_shared!(rel);
        let c = run(rel);
        assert_ne!(c.report.colour, "none", "{rel} lost its colour");
        assert!(c.report.counts.patches > 0);
    }
}

#[test]
fn colourless_models_get_no_colour_channel() {
    for rel in [
        "bunny/reconstruction/bun_zipper_res2.ply",
        "cad/fandisk.obj",
        "cad/cube-meshed.off",
    ] {
        let _ = require_shared!(rel);
        let c = run(rel);
        assert_eq!(c.report.colour, "none", "{rel}");
        assert!(c.report.counts.patches > 0);
    }
}

#[test]
fn vertex_coloured_scan_keeps_its_colour() {
    let rel = "head/mannequin.ply";
    let _ = require_shared!(rel);
    let c = run(rel);
    assert_eq!(c.report.colour, "rgb8");
}

/// fuze has sharp-edge patches and colour grids: what its edge patches add must be measured
/// with the grids as stored (it read 0 when the edge-less scene kept its full grids).
#[test]
fn edge_bytes_of_a_textured_model_are_part_of_its_file() {
    let rel = "textured_obj/fuze/fuze.obj";
    let _ = require_shared!(rel);
    let c = run(rel);
    let edges = c.report.edges.as_ref().expect("fuze has sharp edges");
    assert!(edges.edge_patches > 0, "fuze has crease patches");
    assert!(c.report.colour_grids.is_some(), "fuze has colour grids");
    let (edge, all) = (c.report.edge_bytes, c.report.counts.bytes);
    assert!(edge > 0 && edge < all / 2, "edge bytes {edge} of {all}");
}
