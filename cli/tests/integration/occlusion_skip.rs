//! The occlusion skip (`--occlusion-skip`): the bunny, the
//! mannequin and the sphere render to the same PNG bytes with and without
//! it, the bunny's statistics count skipped pieces, and every fragment of a
//! skipped piece is hidden.

use crate::test_command::TestCommand;

/// The shared data file, or `None` when ../shared/data is missing.
fn shared(relative: &str) -> Option<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/data");
    let path = root.join(relative);
    path.is_file().then(|| path.display().to_string())
}

/// Renders `scene` at 300² with and without the skip (Phong, then the
/// given extra options) and returns the stats of the run with it.
fn same_image_either_way(t: &TestCommand, scene: &str, extra: &[&str]) -> serde_json::Value {
    let mut pngs = Vec::new();
    for (k, on) in [true, false].into_iter().enumerate() {
        let png = format!("{scene}.{k}.png");
        let mut args = vec![
            "render", scene, "-o", &png, "--width", "300", "--height", "300",
        ];
        args.extend_from_slice(extra);
        if on {
            args.extend_from_slice(&["--occlusion-skip", "--stats", "stats.json"]);
        }
        t.run(&args).success();
        pngs.push(std::fs::read(t.path(&png)).unwrap());
    }
    assert!(
        pngs[0] == pngs[1],
        "{scene} {extra:?}: the skip changed the image"
    );
    let stats: serde_json::Value = t.json("stats.json");
    let occlusion = &stats["occlusion"];
    assert_eq!(occlusion["skipped_fragments_shown"], 0, "{scene} {extra:?}");
    assert_eq!(
        stats["pieces_skipped_hidden"], occlusion["skipped_pieces"],
        "{scene} {extra:?}: the frame and the counts disagree"
    );
    stats
}

#[test]
fn the_skip_keeps_the_sphere_bit_for_bit() {
    let t = TestCommand::new();
    let sphere = t.small_sphere("s.spatch");
    for extra in [&[][..], &["--cull", "none"], &["--splat-limit", "1"]] {
        same_image_either_way(&t, &sphere, extra);
    }
}

#[test]
fn the_skip_leaves_out_hidden_pieces_of_real_scans_without_changing_them() {
    let t = TestCommand::new();
    let mut found = 0;
    for (mesh, min_skipped) in [
        ("bunny/reconstruction/bun_zipper_res2.ply", 20),
        ("head/mannequin.ply", 1),
    ] {
        let Some(path) = shared(mesh) else {
            continue;
        };
        found += 1;
        t.run(&["convert", &path, "-o", "m.spatch", "--no-error", "-q"])
            .success();
        for extra in [
            &[][..],
            &["--shading", "gouraud"],
            &["--centre-limit", "2"],
            &["--splat-limit", "1"],
        ] {
            let stats = same_image_either_way(&t, "m.spatch", extra);
            let skipped = stats["occlusion"]["skipped_pieces"].as_u64().unwrap();
            assert!(
                skipped >= min_skipped,
                "{mesh} {extra:?}: {skipped} skipped"
            );
        }
    }
    if found == 0 {
        eprintln!("skipped: ../shared/data is missing");
    }
}
