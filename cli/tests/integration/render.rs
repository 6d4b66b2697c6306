//! `spatch render`: PNG, depth and statistics outputs, camera flags, the
//! benchmark report, and bad input (one error line, exit code 2, no file).

use crate::test_command::TestCommand;

fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[1..4], b"PNG");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn renders_png_depth_and_stats() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let run = t
        .run(&[
            "render",
            &name,
            "-o",
            "s.png",
            "--width",
            "120",
            "--height",
            "90",
            "--depth",
            "d.png",
            "--stats",
            "stats.json",
        ])
        .success();
    assert!(run.stdout.contains("s.png"));
    let png = std::fs::read(t.path("s.png")).unwrap();
    assert_eq!(png_size(&png), (120, 90));
    let depth = std::fs::read(t.path("d.png")).unwrap();
    assert_eq!(png_size(&depth), (120, 90));
    assert_eq!(depth[24], 16, "16-bit depth");
    assert_eq!(depth[25], 0, "greyscale");
    let stats: serde_json::Value = t.json("stats.json");
    for key in [
        "patch_nodes",
        "interpolated_nodes",
        "normals_computed_with_buffer_percent",
        "normals_computed_with_ordering_percent",
        "patches_culled_backface",
        "patches_split",
        "patches_optimized",
        "mip_levels",
        "times_ms",
    ] {
        assert!(stats.get(key).is_some(), "missing {key}");
    }
    assert_eq!(stats["patches"], 200);
    // --stats turns on the normal-buffer counts.
    assert!(stats["normals_needed"].as_u64().unwrap() > 0);
    assert!(stats["covered_pixels"].as_u64().unwrap() > 1000);
    let shortcuts = &stats["shortcuts"];
    assert!(
        shortcuts["trilinear_vs_exact"]["shortcut_ms"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(shortcuts["bilinear_vs_smooth"].get("psnr_db").is_some());
    assert!(shortcuts["mip_limit_vs_default"].is_null());
    // Trimming is not the default; its cost is measured all the same.
    assert_eq!(stats["overlap_cells_trimmed"], 0);
    let trim = &shortcuts["trimmed_vs_kept_overlaps"];
    assert!(trim["shortcut_ms"].as_f64().unwrap() > 0.0, "{trim}");
    // The bands cover the image's rows once; the occlusion counts leave
    // the covered pixels visible.
    let bands = stats["bands"].as_array().unwrap();
    assert_eq!(bands.len(), stats["tiles"].as_u64().unwrap() as usize);
    let rows: u64 = bands.iter().map(|b| b["rows"].as_u64().unwrap()).sum();
    assert_eq!(rows, 90);
    let o = &stats["occlusion"];
    let visible = o["fragments"].as_u64().unwrap() - o["hidden_fragments"].as_u64().unwrap();
    assert_eq!(visible, stats["covered_pixels"].as_u64().unwrap(), "{o}");
}

#[test]
fn trim_overlaps_trims_the_default_sphere() {
    // The small sphere's patches bend too much for the 1° normal test, so
    // this takes the default one (1362 patches of 17 × 17).
    let t = TestCommand::new();
    t.run(&["sphere", "-o", "big.spatch"]).success();
    // Below a pixel, the sphere's cells stay at level 0, which trimming cuts.
    let args = ["render", "big.spatch", "-o", "s.png", "--width", "200"];
    let args = [
        &args[..],
        &["--height", "200", "--trim-overlaps", "--mip-limit", "0.9"],
    ]
    .concat();
    t.run(&[&args[..], &["--stats", "stats.json"]].concat())
        .success();
    let stats: serde_json::Value = t.json("stats.json");
    let trimmed = stats["overlap_cells_trimmed"].as_u64().unwrap();
    assert!(trimmed > 348_672 / 4, "{trimmed}");
    assert_eq!(stats["overlap_cells_trimmable"], trimmed);
    let trim = &stats["shortcuts"]["trimmed_vs_kept_overlaps"];
    assert!(trim["psnr_db"].as_f64().unwrap() > 35.0, "{trim}");
}

#[test]
fn a_mip_limit_reports_its_cost_against_the_default() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    t.run(&[
        "render",
        &name,
        "-o",
        "s.png",
        "--mip-limit",
        "8",
        "--stats",
        "stats.json",
    ])
    .success();
    let stats: serde_json::Value = t.json("stats.json");
    let mip = &stats["shortcuts"]["mip_limit_vs_default"];
    assert!(mip["shortcut_ms"].as_f64().unwrap() > 0.0, "{mip}");
    assert!(mip["reference_ms"].as_f64().unwrap() > 0.0, "{mip}");
    assert!(mip.get("psnr_db").is_some());
}

/// The pieces per mip level (`--stats`) of a 64² render of `scene` with
/// `flags`.
fn mip_levels_at_64(t: &TestCommand, scene: &str, flags: &[&str]) -> Vec<u64> {
    let size = ["--width", "64", "--height", "64", "--stats", "stats.json"];
    let args = [&["render", scene, "-o", "s.png"][..], &size, flags].concat();
    t.run(&args).success();
    let stats: serde_json::Value = t.json("stats.json");
    let levels = stats["mip_levels"].as_array().expect("levels");
    levels.iter().map(|n| n.as_u64().unwrap()).collect()
}

#[test]
fn a_mip_tolerance_takes_full_grids_past_the_mip_limit() {
    // The small sphere's grids are full: at 64² the default tolerance takes
    // some of them to level 1, which the limit alone keeps at level 0.
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let coarse = |tolerance: &str| {
        let levels = mip_levels_at_64(&t, &name, &["--mip-tolerance", tolerance]);
        levels.iter().skip(1).sum::<u64>()
    };
    assert_eq!(coarse("0"), 0);
    assert!(coarse("0.25") > 0);
    let run = t.run(&["render", &name, "-o", "x.png", "--mip-tolerance", "3"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(!t.path("x.png").exists());
}

#[test]
fn a_level_one_limit_takes_level_one_past_the_mip_limit() {
    // At 64² the mip limit alone (no tolerance) keeps the small sphere's
    // near patches at level 0; a level-one limit of 16 px takes them to
    // level 1.
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let levels = |limit: &str| {
        let flags = ["--mip-tolerance", "0", "--level-one-limit", limit];
        mip_levels_at_64(&t, &name, &flags)
    };
    let (off, on) = (levels("0"), levels("16"));
    assert!(off[0] > 0 && on[0] < off[0], "off {off:?}, on {on:?}");
    assert_eq!(off.iter().sum::<u64>(), on.iter().sum::<u64>());
    let run = t.run(&["render", &name, "-o", "x.png", "--level-one-limit", "20"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(!t.path("x.png").exists());
}

#[test]
fn camera_flags_and_modes_are_honoured() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    for extra in [
        vec!["--mode", "triangles", "--shading", "gouraud"],
        vec![
            "--projection",
            "exact",
            "--cells",
            "smooth",
            "--shading",
            "flat",
            "--ssaa",
            "2",
        ],
        vec![
            "--eye", "0,0,-40", "--target", "0,0,0", "--up", "0,1,0", "--fov", "30", "--near", "1",
            "--far", "100",
        ],
        vec![
            "--eye",
            "0,0,0",
            "--target",
            "1,0,0",
            "--cull",
            "none",
            "--threads",
            "1",
            "--background",
            "10,20,30",
        ],
    ] {
        let mut args = vec![
            "render", &name, "-o", "v.png", "--width", "64", "--height", "48",
        ];
        args.extend(extra.iter().copied());
        t.run(&args).success();
        assert_eq!(png_size(&std::fs::read(t.path("v.png")).unwrap()), (64, 48));
    }
}

#[test]
fn bench_prints_median_and_min_per_stage() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let run = t
        .run(&[
            "render", &name, "--bench", "3", "--width", "64", "--height", "64",
        ])
        .success();
    assert!(
        run.stdout.contains("median") && run.stdout.contains("frame"),
        "{}",
        run.stdout
    );
    let run = t
        .run(&[
            "render", &name, "--bench", "3", "--json", "--width", "64", "--height", "64",
        ])
        .success();
    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let bench = &v["details"]["bench"];
    assert!(bench["ms"]["frame"]["median_ms"].as_f64().unwrap() > 0.0);
    assert_eq!(bench["frames"], 3);
    // --json turns on the normal-buffer counts.
    assert!(v["details"]["stats"]["normals_needed"].as_u64().unwrap() > 0);
    // The planning's stages are timed only when asked (--stage-times or
    // --stats); the bands' stages always.
    assert!(bench["ms"]["traverse_cpu"].is_null(), "{bench}");
    assert!(bench["ms"]["cells_cpu"]["median_ms"].as_f64().unwrap() > 0.0);
    let run = t
        .run(&[
            "render",
            &name,
            "--bench",
            "3",
            "--json",
            "--stage-times",
            "--width",
            "64",
            "--height",
            "64",
        ])
        .success();
    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    let ms = &v["details"]["bench"]["ms"];
    assert!(
        ms["traverse_cpu"]["median_ms"].as_f64().unwrap() > 0.0,
        "{ms}"
    );
    assert!(
        v["details"]["stats"]["times_ms"]["traverse"]
            .as_f64()
            .unwrap()
            > 0.0
    );
}

#[test]
fn band_height_does_not_change_the_image() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    for (rows, png) in [("64", "a.png"), ("5", "b.png"), ("256", "c.png")] {
        let args = ["render", &name, "-o", png, "--tile-rows", rows];
        t.run(&[&args[..], &["--width", "150", "--height", "130"]].concat())
            .success();
    }
    let read = |f: &str| std::fs::read(t.path(f)).unwrap();
    assert!(read("a.png") == read("b.png") && read("a.png") == read("c.png"));
}

#[test]
fn no_simd_keeps_the_portable_kernels_and_the_same_image() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    for (extra, png, json) in [
        (None, "a.png", "a.json"),
        (Some("--no-simd"), "b.png", "b.json"),
    ] {
        let args = ["render", &name, "-o", png, "--stats", json];
        t.run(&[&args[..], extra.as_slice()].concat()).success();
    }
    let read = |f: &str| std::fs::read(t.path(f)).unwrap();
    assert!(read("a.png") == read("b.png"));
    let kernels = |f: &str| t.json::<serde_json::Value>(f)["kernels"].clone();
    assert_eq!(kernels("b.json"), "base");
    let fast = kernels("a.json");
    assert!(fast == "base" || fast == "x86-64-v3", "{fast}");
}

/// Image size arguments for the 200² renders below.
const AT_200: [&str; 4] = ["--width", "200", "--height", "200"];

/// Renders `big.spatch` with `extra` arguments and reads the `--stats` it
/// wrote to `name`.
fn render_stats(t: &TestCommand, extra: &[&str], name: &str) -> serde_json::Value {
    let args = ["render", "big.spatch", "-o", "s.png", "--stats", name];
    t.run(&[&args[..], extra].concat()).success();
    t.json(name)
}

#[test]
fn splat_limit_splats_the_pieces_subdivision_would_cut() {
    // The default sphere at 500²: cells of 1.3-1.9 px are cut without
    // splats and splatted with them; the disc is as covered either way.
    let t = TestCommand::new();
    t.run(&["sphere", "-o", "big.spatch"]).success();
    let stats = |extra: &[&str], name: &str| render_stats(&t, extra, name);
    let off = stats(&[], "off.json");
    let on = stats(&["--splat-limit", "1.5"], "on.json");
    assert_eq!(off["patches_splatted"], 0);
    assert!(on["patches_splatted"].as_u64().unwrap() > 0, "{on}");
    assert!(on["interpolated_nodes"].as_u64() < off["interpolated_nodes"].as_u64());
    let covered = |s: &serde_json::Value| s["covered_pixels"].as_u64().unwrap();
    assert!(
        covered(&on) >= covered(&off),
        "{} < {}",
        covered(&on),
        covered(&off)
    );
}

#[test]
fn geometry_limit_projects_fewer_nodes_and_covers_the_same_disc() {
    // The default sphere seen small (shading at level 0, cells of about a
    // pixel, no full grid lifted past the limit): with --geometry-limit its
    // patches draw the level above their shading level, a quarter of the
    // nodes, and cover about the pixels the default covers.
    let t = TestCommand::new();
    t.run(&["sphere", "-o", "big.spatch"]).success();
    let at_200 = [&AT_200[..], &["--mip-limit", "0.9", "--mip-tolerance", "0"]].concat();
    let stats = |extra: &[&str], name: &str| render_stats(&t, &[&at_200[..], extra].concat(), name);
    let off = stats(&[], "off.json");
    let on = stats(&["--geometry-limit", "3.6"], "on.json");
    let count = |s: &serde_json::Value, k: &str| s[k].as_u64().unwrap();
    assert!(
        count(&on, "patch_nodes") * 3 < count(&off, "patch_nodes") * 2,
        "{on}"
    );
    let (a, b) = (count(&off, "covered_pixels"), count(&on, "covered_pixels"));
    assert!(a.abs_diff(b) * 200 < a, "{a} against {b}");
    // A tolerance no patch meets keeps every patch at its shading level.
    let strict = ["--geometry-limit", "3.6", "--geometry-tolerance", "0.001"];
    let strict = stats(&strict, "strict.json");
    assert_eq!(count(&strict, "patch_nodes"), count(&off, "patch_nodes"));
}

#[test]
fn centre_limit_draws_pixel_sized_cells_by_pixel_centres() {
    // The default sphere at 200² with level 0 kept below a pixel (and no
    // full grid lifted past the limit): cells of about a pixel are cut
    // into sub-nodes and drawn by pixel-centre coverage with --centre-limit
    // 2 (some at the next mip level), which places next to no sub-nodes and
    // covers the same disc within its outline margin.
    let t = TestCommand::new();
    t.run(&["sphere", "-o", "big.spatch"]).success();
    let at_200 = [&AT_200[..], &["--mip-limit", "0.9", "--mip-tolerance", "0"]].concat();
    let stats = |extra: &[&str], name: &str| render_stats(&t, &[&at_200[..], extra].concat(), name);
    let off = stats(&[], "off.json");
    let on = stats(&["--centre-limit", "2"], "on.json");
    let count = |s: &serde_json::Value, k: &str| s[k].as_u64().unwrap();
    assert!(count(&off, "interpolated_nodes") > 100_000, "{off}");
    assert!(
        count(&on, "interpolated_nodes") * 10 < count(&off, "interpolated_nodes"),
        "{on}"
    );
    assert!(
        count(&on, "patch_nodes") < count(&off, "patch_nodes"),
        "{on}"
    );
    let (a, b) = (count(&off, "covered_pixels"), count(&on, "covered_pixels"));
    assert!(a.abs_diff(b) * 200 < a, "{a} against {b}");
    let run = t.run(&[
        "render",
        "big.spatch",
        "-o",
        "bad.png",
        "--centre-limit",
        "9",
    ]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.starts_with("spatch: error:") && run.stderr.contains("centre_limit"));
    assert!(!t.path("bad.png").exists());
}

#[test]
fn bad_input_gives_one_line_exit_2_and_no_output() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    std::fs::write(t.path("junk.spatch"), b"not a scene").unwrap();
    let cases: [&[&str]; 10] = [
        &["render", "missing.spatch", "-o", "out.png"],
        &["render", "junk.spatch", "-o", "out.png"],
        &[
            "render", &name, "-o", "out.png", "--eye", "1,2,3", "--target", "1,2,3",
        ],
        &["render", &name, "-o", "out.png", "--width", "0"],
        &[
            "render", &name, "-o", "out.png", "--near", "5", "--far", "2",
        ],
        &["render", &name, "-o", "out.png", "--mip-limit", "40"],
        &["render", &name, "-o", "out.png", "--tile-rows", "2"],
        &["render", &name, "-o", "out.png", "--splat-limit", "0.2"],
        &["render", &name, "-o", "out.png", "--geometry-limit", "0.5"],
        &[
            "render",
            &name,
            "-o",
            "out.png",
            "--geometry-limit",
            "3.6",
            "--geometry-tolerance",
            "-1",
        ],
    ];
    for args in cases {
        let run = t.run(args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        assert_eq!(
            run.stderr.trim().lines().count(),
            1,
            "{args:?}: {}",
            run.stderr
        );
        assert!(!t.path("out.png").exists(), "{args:?} left an output file");
    }
    // A malformed flag is a usage error (clap prints usage too).
    let run = t.run(&["render", &name, "-o", "out.png", "--eye", "1,2"]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("three numbers") && !t.path("out.png").exists());
    let run = t.run(&[
        "render", &name, "-o", "out.png", "--eye", "1,2,3", "--target", "1,2,3",
    ]);
    assert!(
        run.stderr.starts_with("spatch: error:") && run.stderr.contains("eye and target"),
        "{}",
        run.stderr
    );
}

/// Issue 22, item 6: float depth as TIFF, with the camera beside it.
#[test]
fn issue_22_depth_as_float_tiff_with_its_camera() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    t.run(&[
        "render", &name, "-o", "s.png", "--width", "64", "--height", "48", "--depth", "d.tiff",
    ])
    .success();
    let bytes = std::fs::read(t.path("d.tiff")).unwrap();
    let mut decoder = tiff::decoder::Decoder::new(std::io::Cursor::new(bytes)).unwrap();
    assert_eq!(decoder.dimensions().unwrap(), (64, 48));
    let tiff::decoder::DecodingResult::F32(depth) = decoder.read_image().unwrap() else {
        panic!("not a float TIFF");
    };
    let camera: serde_json::Value = t.json("d.camera.json");
    let eye =
        glam::DVec3::from_array(serde_json::from_value::<[f64; 3]>(camera["eye"].clone()).unwrap());
    assert_eq!(camera["width"], 64);
    // The centre pixel sees the sphere (radius 10 at the origin) head on.
    let centre = depth[24 * 64 + 32];
    assert!(
        (f64::from(centre) - (eye.length() - 10.0)).abs() < 0.05,
        "{centre}"
    );
    assert!(depth[0].is_nan(), "a corner sees nothing");
    // --depth-format png writes a PNG: into a file named .png, never one named .tiff.
    let depth_png = |depth: &str| {
        let args = [
            "render",
            &name,
            "-o",
            "s.png",
            "--depth",
            depth,
            "--depth-format",
            "png",
        ];
        t.run(&args)
    };
    depth_png("e.tiff").assert_one_clear_line("e.tiff: this output is written as a PNG image");
    assert!(!t.path("e.tiff").exists());
    depth_png("e.png").success();
    assert_eq!(&std::fs::read(t.path("e.png")).unwrap()[1..4], b"PNG");
}

/// The `Z` channel of an EXR file: width, height and values.
fn read_exr_depth(bytes: Vec<u8>) -> (usize, usize, Vec<f32>) {
    use exr::prelude::{read, FlatSamples, ReadChannels, ReadLayers};
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .expect("a readable EXR file");
    let layer = image.layer_data;
    let channels = &layer.channel_data.list;
    assert_eq!(channels.len(), 1, "one channel");
    assert_eq!(channels[0].name.to_string(), "Z");
    let FlatSamples::F32(values) = &channels[0].sample_data else {
        panic!("not a 32-bit float channel");
    };
    (layer.size.0, layer.size.1, values.clone())
}

/// Issue 22, item 6: float depth as OpenEXR holds the TIFF's values bit for
/// bit, with the same camera beside it; a wrong name is refused in one line.
#[test]
fn issue_22_depth_as_exr_matches_the_tiff_bit_for_bit() {
    let t = TestCommand::new();
    let name = t.small_sphere("s.spatch");
    let size = ["--width", "64", "--height", "48", "--eye", "30,12,9"];
    let render = |depth: &str, format: Option<&str>| {
        let mut args = vec!["render", &name, "-o", "s.png", "--depth", depth];
        args.extend(size);
        if let Some(format) = format {
            args.extend(["--depth-format", format]);
        }
        t.run(&args)
    };
    render("d.tiff", None).success();
    // A .exr name selects EXR; so does --depth-format exr with another name.
    render("d.exr", None).success();
    render("plain", Some("exr")).success();
    let tiff_bytes = std::fs::read(t.path("d.tiff")).unwrap();
    let mut decoder = tiff::decoder::Decoder::new(std::io::Cursor::new(tiff_bytes)).unwrap();
    let tiff::decoder::DecodingResult::F32(from_tiff) = decoder.read_image().unwrap() else {
        panic!("not a float TIFF");
    };
    let (width, height, from_exr) = read_exr_depth(std::fs::read(t.path("d.exr")).unwrap());
    assert_eq!((width, height), (64, 48));
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<u32>>();
    assert_eq!(bits(&from_exr), bits(&from_tiff));
    let (_, _, from_plain) = read_exr_depth(std::fs::read(t.path("plain")).unwrap());
    assert_eq!(bits(&from_plain), bits(&from_tiff));
    // Both surface and no-surface pixels are there to compare.
    assert!(from_exr.iter().any(|d| d.is_nan()) && from_exr.iter().any(|d| d.is_finite()));
    assert_eq!(
        std::fs::read(t.path("d.camera.json")).unwrap(),
        std::fs::read(t.path("plain.camera.json")).unwrap()
    );
    // An EXR is never written into a file named for another format, nor a
    // TIFF into a .exr.
    render("e.tiff", Some("exr"))
        .assert_one_clear_line("e.tiff: this output is written as an OpenEXR image");
    render("e.exr", Some("tiff"))
        .assert_one_clear_line("e.exr: this output is written as a TIFF image");
    assert!(!t.path("e.tiff").exists() && !t.path("e.exr").exists());
    assert!(!t.path("e.camera.json").exists());
}

#[test]
fn gap_fill_places_fewer_sub_nodes_and_covers_the_same_disc() {
    // The default sphere at 500² (magnified cells): with --gap-fill the
    // sub-nodes land up to 1.5 px apart, fewer than half as many, and the
    // pass closes the gaps: the disc covers the same pixels within a
    // thousandth, and --stats names the option.
    let t = TestCommand::new();
    t.run(&["sphere", "-o", "big.spatch"]).success();
    let at_500 = ["--width", "500", "--height", "500"];
    let stats = |extra: &[&str], name: &str| render_stats(&t, &[&at_500[..], extra].concat(), name);
    let off = stats(&[], "off.json");
    let on = stats(&["--gap-fill"], "on.json");
    let count = |s: &serde_json::Value, k: &str| s[k].as_u64().unwrap();
    assert!(
        count(&on, "interpolated_nodes") * 2 < count(&off, "interpolated_nodes"),
        "{on}"
    );
    let (a, b) = (count(&off, "covered_pixels"), count(&on, "covered_pixels"));
    assert!(a.abs_diff(b) * 1000 < a, "{a} against {b}");
    assert_eq!(on["options"]["gap_fill"], true);
    assert_eq!(off["options"]["gap_fill"], false);
}
