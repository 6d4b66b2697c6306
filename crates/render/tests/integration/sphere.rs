//! The perfect sphere from a known camera: silhouette within 1 px of the
//! analytic circle, no empty pixel inside it (minified and magnified), and
//! the depth at the centre pixel within 0.5 % of the analytic value.

use spatch_render::{RenderOptions, Renderer};

use crate::common::{known_camera, prepared_sphere, silhouette_radius_px, RADIUS};

/// Renders at `size`² from `distance` and checks the silhouette both ways.
fn check_silhouette(distance: f64, size: u32, options: RenderOptions) {
    let camera = known_camera(distance, size);
    let out = Renderer::new(options)
        .unwrap()
        .render(prepared_sphere(), &camera)
        .unwrap();
    let image = &out.image;
    let r = silhouette_radius_px(distance, size);
    // Splats reach up to their half-width past the nodes, where sub-nodes
    // reach half a pixel.
    let reach = 1.0 + (options.splat_limit as f64 - 0.5).max(0.0);
    let c = size as f64 / 2.0;
    let mut holes = 0;
    let mut outside = 0;
    for y in 0..size {
        for x in 0..size {
            let d = ((x as f64 + 0.5 - c).powi(2) + (y as f64 + 0.5 - c).powi(2)).sqrt();
            let covered = image.is_covered(x, y);
            if d < r - 1.0 && !covered {
                holes += 1;
            }
            if d > r + reach && covered {
                outside += 1;
            }
        }
    }
    assert_eq!(
        (holes, outside),
        (0, 0),
        "{size}² from {distance}: {holes} holes inside and {outside} pixels outside the circle of {r:.1} px; stats {:?}",
        out.stats
    );
}

#[test]
fn silhouette_and_no_holes_at_250() {
    // Minified: nodes far denser than pixels (mip levels in use).
    check_silhouette(700.0, 250, RenderOptions::default());
}

#[test]
fn silhouette_and_no_holes_at_500() {
    check_silhouette(600.0, 500, RenderOptions::default());
}

#[test]
fn a_larger_mip_limit_keeps_the_silhouette_and_fills_the_disc() {
    // Coarser levels magnified instead of level 0: same guarantees.
    for (distance, size) in [(600.0, 500), (500.0, 1000)] {
        let mut o = RenderOptions::default();
        o.mip_limit = 6.0;
        check_silhouette(distance, size, o);
    }
}

#[test]
fn coarse_geometry_keeps_the_silhouette_and_shades_as_the_shading_level() {
    // Positions from the level above the shading level: the same
    // guarantees at every size, and on the smooth sphere an image close to
    // the default one (the normals come from the same level; only
    // silhouette pixels and rounding move: 44 dB here).
    for (distance, size) in [(700.0, 250), (600.0, 500), (500.0, 1000), (400.0, 2000)] {
        let mut o = RenderOptions::default();
        o.geometry_limit = 3.6;
        check_silhouette(distance, size, o);
    }
    let camera = known_camera(1500.0, 200);
    let render = |geometry_limit: f32| {
        let mut o = RenderOptions::default();
        // Level 0 shades at this size below a pixel; the default limit
        // would already take the coarse levels for both.
        o.mip_limit = 0.9;
        o.geometry_limit = geometry_limit;
        Renderer::new(o)
            .unwrap()
            .render(prepared_sphere(), &camera)
            .unwrap()
    };
    let (fine, coarse) = (render(0.0), render(3.6));
    assert!(
        coarse.stats.patch_nodes * 3 < fine.stats.patch_nodes * 2,
        "{:?}",
        coarse.stats
    );
    let psnr = coarse.image.psnr(&fine.image).expect("the surfaces differ");
    assert!(psnr > 40.0, "PSNR {psnr:.1} dB against the default image");
}

#[test]
fn geometry_tolerance_chooses_between_the_default_and_every_patch_coarse() {
    // The tolerance only takes patches out of coarse geometry: one no
    // patch meets gives the default image bit for bit, one every patch
    // meets the image without a tolerance.
    let camera = known_camera(1500.0, 200);
    let render = |geometry_limit: f32, geometry_tolerance: f32| {
        let mut o = RenderOptions::default();
        o.geometry_limit = geometry_limit;
        o.geometry_tolerance = geometry_tolerance;
        Renderer::new(o)
            .unwrap()
            .render(prepared_sphere(), &camera)
            .unwrap()
    };
    let (fine, coarse) = (render(0.0, 0.0), render(3.6, 0.0));
    let strict = render(3.6, 0.001);
    assert_eq!(strict.image, fine.image);
    assert_eq!(strict.stats.patch_nodes, fine.stats.patch_nodes);
    let loose = render(3.6, 16.0);
    assert_eq!(loose.image, coarse.image);
    assert_eq!(loose.stats.patch_nodes, coarse.stats.patch_nodes);
}

#[test]
fn splatted_pixel_sized_cells_leave_no_hole_at_250_to_2000() {
    // The splatting path: no empty pixel inside the disc, silhouette within
    // the splats' reach, and splatted pieces at the sizes where cells are
    // about a pixel.
    for (distance, size) in [(700.0, 250), (600.0, 500), (500.0, 1000), (400.0, 2000)] {
        let mut o = RenderOptions::default();
        o.splat_limit = 1.5;
        check_silhouette(distance, size, o);
    }
    let mut o = RenderOptions::default();
    o.splat_limit = 1.5;
    let out = Renderer::new(o)
        .unwrap()
        .render(prepared_sphere(), &known_camera(600.0, 500))
        .unwrap();
    assert!(out.stats.patches_splatted > 0, "{:?}", out.stats);
}

#[test]
fn silhouette_and_no_holes_at_1000() {
    check_silhouette(500.0, 1000, RenderOptions::default());
}

#[test]
fn silhouette_and_no_holes_at_2000_magnified() {
    // Magnified: several pixels per cell, so cells are subdivided.
    check_silhouette(400.0, 2000, RenderOptions::default());
}

#[test]
fn minified_views_use_the_mip_pyramid_and_the_node_path() {
    // The default limit (cells up to 3 px) and one below a pixel, which
    // draws levels whose nodes alone cover the cells (the node path).
    let camera = known_camera(2500.0, 250);
    let mut below_a_pixel = RenderOptions::default();
    below_a_pixel.mip_limit = 0.9;
    for o in [RenderOptions::default(), below_a_pixel] {
        let out = Renderer::new(o)
            .unwrap()
            .render(prepared_sphere(), &camera)
            .unwrap();
        let s = &out.stats;
        assert!(
            s.mip_levels.len() > 1 && s.mip_levels[1..].iter().sum::<u64>() > 0,
            "{s:?}"
        );
        assert_eq!(s.patches_optimized > 0, o.mip_limit < 1.0, "{s:?}");
        check_silhouette(2500.0, 250, o);
    }
}

#[test]
fn depth_at_the_centre_pixel_is_within_half_a_percent() {
    for (distance, size) in [(600.0, 500), (400.0, 1000)] {
        let camera = known_camera(distance, size);
        let out = Renderer::new(RenderOptions::default())
            .unwrap()
            .render(prepared_sphere(), &camera)
            .unwrap();
        let image = &out.image;
        // The centre pixel's centre is at the image centre exactly: the ray
        // through it hits the sphere at distance - R.
        let k = (size / 2 * size + size / 2) as usize;
        let depth = image.depth()[k] as f64;
        let expected = distance - RADIUS;
        assert!(
            ((depth - expected) / expected).abs() < 0.005,
            "depth {depth} vs {expected}"
        );
    }
}

#[test]
fn back_faces_are_culled_and_the_table_rows_are_filled() {
    let camera = known_camera(600.0, 500);
    // Level 0 wherever the mip limit keeps it (the node count below).
    let mut options = RenderOptions::default();
    options.mip_tolerance = 0.0;
    let out = Renderer::new(options)
        .unwrap()
        .render(prepared_sphere(), &camera)
        .unwrap();
    let s = &out.stats;
    assert_eq!(s.patches, 1362);
    // Roughly half the sphere faces away.
    assert!(
        s.patches_culled_backface > 500 && s.patches_culled_backface < 800,
        "{s:?}"
    );
    assert!(s.patch_nodes > 100_000);
    assert!(s.normals_needed == s.patch_nodes);
    assert!(s.normals_computed_with_ordering_percent <= s.normals_computed_with_buffer_percent);
    assert!(s.normals_computed_with_buffer_percent < 100.0);
}

#[test]
fn the_gap_fill_keeps_the_silhouette_and_fills_the_disc_at_250_to_2000() {
    // Sparser sub-node lattices closed by the screen-space pass
    // (`--gap-fill`): the same guarantees as the dense lattice.
    for (distance, size) in [(700.0, 250), (600.0, 500), (500.0, 1000), (400.0, 2000)] {
        let mut o = RenderOptions::default();
        o.gap_fill = true;
        check_silhouette(distance, size, o);
    }
}
