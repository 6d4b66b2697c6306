//! Modes against each other: triangle mode and patch mode cover the same
//! pixels; 1 and N threads give the same image; the AVX2 kernels give the
//! portable ones' image; an owned scene prepares as a borrowed one; every
//! projection, cell, shading, mip and
//! supersampling variant renders the sphere without holes.

use spatch_format::{ColourChannel, Patch, Scene};
use spatch_render::{
    CellScheme, PreparedScene, Projection, RenderMode, RenderOptions, Renderer, Shading,
};

use crate::common::{known_camera, prepared_sphere, sphere_scene};

fn render(options: RenderOptions, distance: f64, size: u32) -> spatch_render::RenderOutput {
    render_scene(prepared_sphere(), options, distance, size)
}

/// [`render`] for another scene.
fn render_scene(
    prepared: &PreparedScene,
    options: RenderOptions,
    distance: f64,
    size: u32,
) -> spatch_render::RenderOutput {
    Renderer::new(options)
        .unwrap()
        .render(prepared, &known_camera(distance, size))
        .unwrap()
}

/// The default options with mip tolerance `tolerance`.
fn with_tolerance(tolerance: f32) -> RenderOptions {
    let mut o = RenderOptions::default();
    o.mip_tolerance = tolerance;
    o
}

/// Pieces per mip level above level 0.
fn coarse_pieces(s: &spatch_render::RenderStats) -> u64 {
    s.mip_levels[1..].iter().sum()
}

#[test]
fn triangle_mode_and_patch_mode_agree_on_coverage() {
    for (distance, size) in [(600.0, 300), (350.0, 600)] {
        let patches = render(RenderOptions::default(), distance, size).image;
        let mut o = RenderOptions::default();
        o.mode = RenderMode::Triangles;
        let triangles = render(o, distance, size).image;
        let mut differ = 0;
        for y in 0..size {
            for x in 0..size {
                differ += (patches.is_covered(x, y) != triangles.is_covered(x, y)) as usize;
            }
        }
        // Only silhouette pixels may differ (nodes are placed by rounding,
        // triangles by pixel centres): well under the perimeter's length.
        let perimeter = std::f64::consts::TAU * crate::common::silhouette_radius_px(distance, size);
        assert!(
            (differ as f64) < perimeter,
            "{differ} pixels differ (perimeter {perimeter:.0})"
        );
        let psnr = patches.psnr(&triangles).unwrap_or(f64::INFINITY);
        assert!(psnr > 25.0, "psnr {psnr}");
    }
}

#[test]
fn one_and_many_threads_give_the_same_image() {
    for shading in [Shading::Phong, Shading::Gouraud, Shading::Flat] {
        for mode in [RenderMode::Patches, RenderMode::Triangles] {
            let mut o = RenderOptions::default();
            o.shading = shading;
            o.mode = mode;
            o.threads = 1;
            let one = render(o, 500.0, 400);
            o.threads = 3;
            o.tile_rows = 8;
            let three = render(o, 500.0, 400);
            assert!(one.image == three.image, "{shading:?} {mode:?}");
            assert_eq!(one.stats.patch_nodes, three.stats.patch_nodes);
            assert_eq!(one.stats.normals_needed, three.stats.normals_needed);
        }
    }
}

#[test]
fn automatic_bands_are_two_per_thread_within_64_to_128_rows() {
    let auto = RenderOptions::default();
    assert_eq!(auto.tile_rows, 0);
    for (height, threads, rows) in [
        (500, 2, 128),
        (1000, 2, 128),
        (250, 2, 64),
        (500, 8, 64),
        (300, 1, 128),
        (400, 3, 80),
    ] {
        assert_eq!(
            auto.band_rows(height, threads),
            rows,
            "{height} rows, {threads} threads"
        );
    }
    let mut fixed = RenderOptions::default();
    fixed.tile_rows = 32;
    assert_eq!(fixed.band_rows(500, 2), 32);
    // The stats count the bands the automatic height gives.
    fixed.tile_rows = 0;
    fixed.threads = 2;
    let out = render(fixed, 500.0, 400);
    assert_eq!(out.stats.tiles, 4, "{:?}", out.stats.bands);
}

#[test]
fn phong_frames_without_normal_counts_draw_the_same_image() {
    // A scene whose first frames do not count (no slot set built), then
    // count: the image never changes, and the counts are those of a scene
    // that counted from its first frame. A near view (split pieces, whose
    // nodes are counted one by one) and a far one (levels drawn whole).
    let scene = spatch_render::PreparedScene::new(sphere_scene());
    for (distance, size) in [(350.0, 600), (900.0, 300)] {
        let camera = known_camera(distance, size);
        let draw = |prepared: &spatch_render::PreparedScene, counts: bool| {
            let mut o = RenderOptions::default();
            o.normal_counts = counts;
            Renderer::new(o).unwrap().render(prepared, &camera).unwrap()
        };
        let quiet = draw(&scene, false);
        assert_eq!(quiet.stats.normals_needed, 0);
        assert_eq!(quiet.stats.normals_computed_with_buffer_percent, 0.0);
        let late = draw(&scene, true);
        let counted = render(RenderOptions::default(), distance, size);
        assert!(quiet.image == counted.image, "{distance}");
        assert!(late.image == counted.image, "{distance}");
        assert!(counted.stats.normals_needed > 0);
        assert_eq!(late.stats.normals_needed, counted.stats.normals_needed);
        assert_eq!(
            late.stats.normals_computed_with_buffer_percent,
            counted.stats.normals_computed_with_buffer_percent
        );
        assert_eq!(
            late.stats.normals_computed_with_ordering_percent,
            counted.stats.normals_computed_with_ordering_percent
        );
    }
}

#[test]
fn the_avx2_kernels_draw_what_the_portable_ones_draw() {
    // Bit for bit, every shading, both modes, the splat and coarse-geometry
    // paths, a view close enough to magnify cells and one far enough to
    // minify them.
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::arch::is_x86_feature_detected!("avx2")
        && std::arch::is_x86_feature_detected!("fma")
        && std::arch::is_x86_feature_detected!("bmi2")
        && std::arch::is_x86_feature_detected!("lzcnt");
    #[cfg(not(target_arch = "x86_64"))]
    let avx2 = false;
    let mut variants = Vec::new();
    for shading in [Shading::Phong, Shading::Gouraud, Shading::Flat] {
        for mode in [RenderMode::Patches, RenderMode::Triangles] {
            let mut o = RenderOptions::default();
            (o.shading, o.mode) = (shading, mode);
            variants.push(o);
        }
    }
    let mut splats = RenderOptions::default();
    splats.splat_limit = 1.5;
    let mut coarse = RenderOptions::default();
    coarse.geometry_limit = 3.6;
    variants.extend([splats, coarse]);
    for (k, base) in variants.into_iter().enumerate() {
        for (distance, size) in [(300.0, 300), (2500.0, 200)] {
            let mut o = base;
            o.threads = 2;
            let fast = render(o, distance, size);
            o.simd = false;
            let portable = render(o, distance, size);
            assert_eq!(portable.stats.kernels, "base");
            let expected = if avx2 { "x86-64-v3" } else { "base" };
            assert_eq!(fast.stats.kernels, expected);
            assert!(fast.image.covered_count() > 1000);
            assert!(fast.image == portable.image, "variant {k} at {distance}");
            assert_eq!(fast.stats.patch_nodes, portable.stats.patch_nodes);
        }
    }
}

#[test]
fn preparation_does_not_depend_on_the_thread_count() {
    // Patches are prepared (and overlaps searched) in parallel on the
    // renderer's threads; the scene must come out the same.
    let camera = known_camera(420.0, 300);
    let mut images = Vec::new();
    for threads in [1, 2, 3] {
        let mut o = RenderOptions::default();
        o.threads = threads;
        let mut renderer = Renderer::new(o).unwrap();
        for trim in [false, true] {
            let prepared = if trim {
                renderer.prepare_trimming_overlaps(sphere_scene())
            } else {
                renderer.prepare(sphere_scene())
            };
            let out = renderer.render(&prepared, &camera).unwrap();
            images.push((threads, trim, prepared.trimmed_cells(), out.image));
        }
    }
    for (threads, trim, cells, image) in &images[2..] {
        let (_, _, first_cells, first) = &images[*trim as usize];
        assert_eq!(cells, first_cells, "{threads} threads, trim {trim}");
        assert!(image == first, "{threads} threads, trim {trim}");
    }
    assert!(images[1].2 > 80_000, "{}", images[1].2);
    // The shared sphere, prepared on the global pool, gives the same image.
    assert!(images[0].3 == render(RenderOptions::default(), 420.0, 300).image);
}

#[test]
fn an_owned_scene_prepares_as_a_borrowed_one() {
    // `Renderer::prepare_owned` takes the patches' nodes instead of
    // copying them: the same prepared scene, so the same image, with and
    // without trimming, and with per-node colours.
    let camera = known_camera(420.0, 300);
    let mut renderer = Renderer::new(RenderOptions::default()).unwrap();
    let mut coloured = sphere_scene().clone().into_patches();
    for (k, patch) in coloured.iter_mut().enumerate() {
        let n = patch.displacements().len();
        let tint = [(k * 37 % 256) as u8, (k * 91 % 256) as u8, 200, 255];
        *patch = Patch::new(
            *patch.frame(),
            patch.grid(),
            patch.displacements().to_vec(),
            Some(vec![tint; n]),
        )
        .unwrap();
    }
    let coloured = Scene::new(sphere_scene().offset(), ColourChannel::Rgb8, coloured).unwrap();
    for scene in [sphere_scene(), &coloured] {
        for trim in [false, true] {
            let borrowed = if trim {
                renderer.prepare_trimming_overlaps(scene)
            } else {
                renderer.prepare(scene)
            };
            let owned = renderer.prepare_owned(scene.clone(), trim);
            assert_eq!(owned.patch_count(), borrowed.patch_count());
            assert_eq!(owned.trimmed_cells(), borrowed.trimmed_cells());
            assert_eq!(owned.bounding_sphere(), borrowed.bounding_sphere());
            let image = renderer.render(&owned, &camera).unwrap().image;
            assert!(image.covered_count() > 10_000);
            let expected = renderer.render(&borrowed, &camera).unwrap().image;
            assert!(image == expected, "trim {trim}");
        }
    }
}

#[test]
fn every_variant_renders_the_sphere_without_holes() {
    let reference = render(RenderOptions::default(), 450.0, 400).image;
    for projection in [Projection::Trilinear, Projection::Exact] {
        for cells in [CellScheme::Bilinear, CellScheme::Smooth] {
            for shading in [Shading::Flat, Shading::Gouraud, Shading::Phong] {
                let mut o = RenderOptions::default();
                o.projection = projection;
                o.cells = cells;
                o.shading = shading;
                let image = render(o, 450.0, 400).image;
                let differ = (0..400 * 400)
                    .filter(|&k| {
                        image.is_covered(k % 400, k / 400) != reference.is_covered(k % 400, k / 400)
                    })
                    .count();
                assert!(
                    differ < 2000,
                    "{projection:?} {cells:?} {shading:?}: {differ}"
                );
            }
        }
    }
}

#[test]
fn supersampling_smooths_the_edge_and_keeps_the_interior() {
    let mut o = RenderOptions::default();
    o.ssaa = 3;
    let aa = render(o, 600.0, 200);
    let plain = render(RenderOptions::default(), 600.0, 200);
    assert_eq!(aa.stats.internal, [600, 600]);
    // Edge pixels get partial alpha with supersampling; none without.
    let partial = |img: &spatch_render::RenderedImage| {
        img.pixels()
            .iter()
            .filter(|p| p[3] > 0 && p[3] < 255)
            .count()
    };
    assert_eq!(partial(&plain.image), 0);
    assert!(partial(&aa.image) > 100);
    assert!(aa.image.pixels()[100 * 200 + 100][3] == 255);
}

#[test]
fn without_mip_far_views_place_more_nodes() {
    let with = render(RenderOptions::default(), 3000.0, 200);
    let mut o = RenderOptions::default();
    o.mip = false;
    let without = render(o, 3000.0, 200);
    assert!(with.stats.patch_nodes * 3 < without.stats.patch_nodes);
    let differ = (0..200 * 200)
        .filter(|&k| {
            with.image.is_covered(k % 200, k / 200) != without.image.is_covered(k % 200, k / 200)
        })
        .count();
    assert!(differ < 150, "{differ}");
}

#[test]
fn a_larger_mip_limit_takes_coarser_levels_at_a_small_image_cost() {
    let mut o = RenderOptions::default();
    o.mip_limit = 0.9;
    o.mip_tolerance = 0.0;
    let fine = render(o, 600.0, 500);
    let mut o = RenderOptions::default();
    o.mip_limit = 6.0;
    let coarse = render(o, 600.0, 500);
    // A limit under a pixel keeps these cells (about a pixel) at level 0; a
    // limit of 6 px moves most patches to a coarser level and places fewer
    // nodes.
    assert_eq!(coarse_pieces(&fine.stats), 0, "{:?}", fine.stats.mip_levels);
    assert!(coarse_pieces(&coarse.stats) * 2 > coarse.stats.mip_levels.iter().sum::<u64>());
    assert!(coarse.stats.patch_nodes * 2 < fine.stats.patch_nodes);
    // The sphere is smooth: the image hardly changes.
    let psnr = fine.image.psnr(&coarse.image).expect("same size");
    assert!(psnr > 35.0, "PSNR {psnr:.1} dB");
    let (a, b) = (fine.image.covered_count(), coarse.image.covered_count());
    assert!(a.abs_diff(b) * 1000 < a, "{a} against {b} covered pixels");
}

#[test]
fn full_grids_go_past_the_mip_limit_within_the_tolerance() {
    // The sphere's grids are full and halve evenly: at 500² its cells
    // (about 4 px) keep level 0 under the 3 px limit alone, and the
    // tolerance takes most of them to levels 1-2 (cells under 12 px, no
    // piece large enough for the triangle path), with fewer nodes and the
    // same image but for rounding (the sphere is smooth).
    let limit_only = render(with_tolerance(0.0), 600.0, 500);
    let tolerant = render(RenderOptions::default(), 600.0, 500);
    let (few, many) = (
        coarse_pieces(&limit_only.stats),
        coarse_pieces(&tolerant.stats),
    );
    let all = tolerant.stats.mip_levels.iter().sum::<u64>();
    assert!(few * 10 < all, "{:?}", limit_only.stats.mip_levels);
    assert!(many * 2 > all, "{:?}", tolerant.stats.mip_levels);
    assert!(tolerant.stats.patch_nodes * 2 < limit_only.stats.patch_nodes);
    assert_eq!(tolerant.stats.oversized_pieces, 0);
    let psnr = limit_only.image.psnr(&tolerant.image).expect("same size");
    assert!(psnr > 35.0, "PSNR {psnr:.1} dB");
    let (a, b) = (
        limit_only.image.covered_count(),
        tolerant.image.covered_count(),
    );
    assert!(a.abs_diff(b) * 1000 < a, "{a} against {b} covered pixels");
    // Near, the box's estimate falls short of the largest cells: pieces
    // lifted past the triangle path's cut are planned at the limit's level
    // instead, so no piece goes to triangles that did not before.
    let near_limit = render(with_tolerance(0.0), 350.0, 600);
    let near = render(RenderOptions::default(), 350.0, 600);
    assert_eq!(
        near.stats.oversized_pieces,
        near_limit.stats.oversized_pieces
    );
    assert_eq!(near.stats.triangles, near_limit.stats.triangles);
    // A tolerance too small for the sphere's curvature keeps the limit's
    // levels.
    let strict = render(with_tolerance(1e-4), 600.0, 500);
    assert_eq!(coarse_pieces(&strict.stats), few);
}

#[test]
fn grids_with_an_empty_node_keep_the_mip_limits_level() {
    // The same sphere with one corner node of every patch emptied: coarse
    // levels would fill or drop cells along the outline, so the tolerance
    // leaves every patch where the limit puts it, image for image.
    let patches = sphere_scene()
        .patches()
        .iter()
        .map(|p| {
            let mut d = p.displacements().to_vec();
            d[0] = spatch_format::EMPTY;
            spatch_format::Patch::new(*p.frame(), p.grid(), d, None)
                .unwrap()
                .with_sides(p.sides())
        })
        .collect();
    let base = sphere_scene();
    let holed = spatch_format::Scene::new(base.offset(), base.channel(), patches).unwrap();
    let prepared = PreparedScene::new(&holed);
    let draw = |tolerance: f32| render_scene(&prepared, with_tolerance(tolerance), 600.0, 500);
    let (off, on) = (draw(0.0), draw(RenderOptions::DEFAULT_MIP_TOLERANCE));
    assert_eq!(on.stats.mip_levels, off.stats.mip_levels);
    assert!(on.image.pixels() == off.image.pixels(), "images differ");
}

#[test]
fn a_mip_tolerance_out_of_range_is_refused() {
    for bad in [-0.1, 2.5, f32::NAN, f32::INFINITY] {
        assert!(Renderer::new(with_tolerance(bad)).is_err(), "{bad}");
    }
}

#[test]
fn a_mip_limit_out_of_range_is_refused() {
    for bad in [0.0, 20.0, f32::NAN] {
        let mut o = RenderOptions::default();
        o.mip_limit = bad;
        assert!(Renderer::new(o).is_err(), "{bad}");
    }
}
