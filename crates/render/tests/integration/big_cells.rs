//! Cells large on screen (issue 22: a textured box's faces are 40-90 px
//! cells in the eval's views).
//!
//! - A cell drawn by the triangle path (too large to subdivide, or
//!   `--mode triangles`) reads its patch's colour grid per pixel, as the
//!   cell path does: a grid with a red left half and a blue right half
//!   shows both halves, not the grey of the node colours.
//! - Magnified cells of a flat square seen at a slant lie at their exact
//!   depth with the default (trilinear) projection: a piece whose
//!   trilinear positions may be off by more than half a pixel is projected
//!   exactly (before, 6 % of a box's pixels were drawn behind the source).

use glam::{DVec3, Vec3};
use spatch_format::{ColourChannel, ColourGrid, Frame, GridSize, Patch, Scene};
use spatch_render::{
    Camera, Culling, PreparedScene, RenderMode, RenderOptions, RenderedImage, Renderer, Shading,
};

/// A flat square of side 1 in the z = 0 plane with `n × n` nodes; with
/// `grid`, node colours grey and a colour grid of factor 8 per cell, red
/// where x < 0.5 and blue beyond.
fn square(n: u32, grid: bool) -> Scene {
    let s = 1.0 / (n - 1) as f32;
    let frame = Frame::new(Vec3::ZERO, Vec3::X * s, Vec3::Y * s, Vec3::Z * 0.01).expect("frame");
    let size = GridSize::new(n, n).expect("grid");
    let nodes = (n * n) as usize;
    let colours = grid.then(|| vec![[128, 128, 128, 255]; nodes]);
    let mut patch = Patch::new(frame, size, vec![0; nodes], colours).expect("patch");
    let channel = if grid {
        let f = 8u8;
        let (cols, rows) = ColourGrid::sample_size(size, f);
        let samples = (0..cols * rows)
            .map(|k| {
                let x = (k % cols) as f32 / (cols - 1) as f32;
                if x < 0.5 {
                    [240, 20, 20, 255]
                } else {
                    [20, 20, 240, 255]
                }
            })
            .collect();
        let g = ColourGrid::new(size, f, samples).expect("colour grid");
        patch = patch.with_colour_grid(g).expect("patch with grid");
        ColourChannel::Rgb8
    } else {
        ColourChannel::None
    };
    Scene::new(DVec3::ZERO, channel, vec![patch]).expect("scene")
}

fn draw(scene: &Scene, options: RenderOptions, eye: DVec3) -> RenderedImage {
    let camera =
        Camera::look_at(eye, DVec3::new(0.5, 0.5, 0.0), DVec3::Y, 40.0, 200, 200).expect("camera");
    Renderer::new(options)
        .expect("renderer")
        .render(&PreparedScene::new(scene), &camera)
        .expect("frame")
        .image
}

fn unlit() -> RenderOptions {
    let mut o = RenderOptions::default();
    o.shading = Shading::Gouraud;
    o.lighting.ambient = 1.0;
    o.lighting.diffuse = 0.0;
    o.lighting.specular = 0.0;
    o.culling = Culling::None;
    o.threads = 1;
    o
}

/// Red and blue pixels among the covered ones of the left and right
/// thirds of the image.
fn halves(image: &RenderedImage) -> (usize, usize, usize) {
    let w = image.width() as usize;
    let (mut red_left, mut blue_right, mut covered) = (0, 0, 0);
    for (k, p) in image.pixels().iter().enumerate() {
        if p[3] == 0 {
            continue;
        }
        covered += 1;
        let x = k % w;
        red_left += (x < w / 3 && p[0] > 200 && p[2] < 60) as usize;
        blue_right += (x > 2 * w / 3 && p[2] > 200 && p[0] < 60) as usize;
    }
    (red_left, blue_right, covered)
}

#[test]
fn cells_drawn_as_triangles_read_the_colour_grid() {
    let scene = square(2, true);
    // One cell of about 150 px: past the subdivision limit, so the patch
    // mode draws it as two triangles too.
    let eye = DVec3::new(0.5, 0.5, 1.8);
    for shading in [Shading::Gouraud, Shading::Phong] {
        for mode in [RenderMode::Patches, RenderMode::Triangles] {
            let mut o = unlit();
            o.shading = shading;
            o.mode = mode;
            let (red, blue, covered) = halves(&draw(&scene, o, eye));
            assert!(covered > 10_000, "{shading:?} {mode:?}: {covered} pixels");
            assert!(
                red > covered / 5 && blue > covered / 5,
                "{shading:?} {mode:?}: {red} red, {blue} blue of {covered}"
            );
        }
    }
}

#[test]
fn magnified_cells_seen_at_a_slant_lie_at_their_depth() {
    // 10 × 10 cells of 15-25 px, the square seen 55° off its normal.
    let scene = square(11, false);
    let eye = DVec3::new(0.5, -0.8, 0.95);
    let mut exact = unlit();
    exact.projection = spatch_render::Projection::Exact;
    let (a, b) = (draw(&scene, unlit(), eye), draw(&scene, exact, eye));
    let (mut worst, mut both) = (0f32, 0);
    for (da, db) in a.depth().iter().zip(b.depth()) {
        if da.is_finite() && db.is_finite() {
            worst = worst.max((da - db).abs());
            both += 1;
        }
    }
    assert!(both > 10_000, "{both} pixels covered by both");
    // Half a pixel along the slant is about 0.004 units of depth here.
    assert!(worst < 0.01, "trilinear and exact depths differ by {worst}");
}

/// Pixels one image covers and the other does not.
fn coverage_difference(a: &RenderedImage, b: &RenderedImage) -> usize {
    let covered = |d: &f32| d.is_finite();
    a.depth()
        .iter()
        .zip(b.depth())
        .filter(|(x, y)| covered(x) != covered(y))
        .count()
}

/// A roof over the unit square: 48 × 48 cells rising along y to a ridge
/// 0.3 high at y = 0.625 (off the middle row, where a patch crossing the
/// frustum is split), then falling; grey node colours with `colour`.
fn roof(colour: bool) -> Scene {
    let n = 49u32;
    let s = 1.0 / (n - 1) as f32;
    let frame = Frame::new(Vec3::ZERO, Vec3::X * s, Vec3::Y * s, Vec3::Z * 0.001).expect("frame");
    let heights = (0..n * n)
        .map(|k| {
            let j = (k / n) as f32;
            let h = if j <= 40.0 {
                j / 40.0
            } else {
                1.0 - (j - 40.0) / 24.0
            };
            (300.0 * h).round() as u16
        })
        .collect();
    let colours = colour.then(|| vec![[128, 128, 128, 255]; (n * n) as usize]);
    let patch =
        Patch::new(frame, GridSize::new(n, n).expect("grid"), heights, colours).expect("patch");
    let channel = if colour {
        ColourChannel::Rgb8
    } else {
        ColourChannel::None
    };
    Scene::new(DVec3::ZERO, channel, vec![patch]).expect("scene")
}

#[test]
fn coloured_patches_draw_their_outlines_at_pixel_centres() {
    // The roof from afar (cells of 2-5 px, below the open sides' cut): its
    // ridge and borders are outlines. With `exact_outlines`, a coloured
    // patch's cells write the pixel centres they hold (`raster::cell_exact`),
    // as the triangle path does, up to the margin; a colourless one keeps the
    // sub-nodes' reach, and so does a coloured one by default.
    let camera = Camera::look_at(
        DVec3::new(0.5, -2.2, 0.5),
        DVec3::new(0.5, 0.6, 0.3),
        DVec3::new(0.3, 0.0, 1.0),
        40.0,
        200,
        200,
    )
    .expect("camera");
    let mut o = unlit();
    o.culling = Culling::Back;
    o.projection = spatch_render::Projection::Exact;
    o.exact_outlines = true;
    // The same levels with and without colour (coloured patches never go
    // past the mip limit; the colourless roof, a full grid, would).
    o.mip_tolerance = 0.0;
    let mut tri = o;
    tri.mode = RenderMode::Triangles;
    let off = |colour: bool, o: RenderOptions| {
        let prepared = PreparedScene::new(&roof(colour));
        let draw = |o: RenderOptions| {
            Renderer::new(o)
                .expect("renderer")
                .render(&prepared, &camera)
                .expect("frame")
                .image
        };
        let (cells, exact) = (draw(o), draw(tri));
        let covered = exact.depth().iter().filter(|d| d.is_finite()).count();
        (coverage_difference(&cells, &exact), covered)
    };
    let ((coloured, covered), (grey, _)) = (off(true, o), off(false, o));
    assert!((3_000..20_000).contains(&covered), "{covered} pixels");
    // 47 against 121 (the margin's pixels remain).
    assert!(
        coloured * 2 < grey,
        "{coloured} against {grey} pixels differ"
    );
    let mut default = o;
    default.exact_outlines = false;
    let (by_default, _) = off(true, default);
    assert_eq!(
        by_default, grey,
        "by default coloured cells keep the sub-nodes"
    );
}

#[test]
fn where_magnified_cells_fold_away_their_outline_is_the_triangle_paths() {
    // The roof seen from below its ridge, the camera rolled: the far slope faces away (culled),
    // so the ridge is the only outline in the image (the patch's borders
    // lie outside it), drawn by cells of 5-11 px. The patch covers the
    // pixels the triangle path covers up to a few along the ridge; before,
    // its sub-nodes wrote every pixel the ridge touched (about half of its
    // length more).
    let scene = roof(false);
    let mut o = unlit();
    o.culling = Culling::Back;
    o.projection = spatch_render::Projection::Exact;
    let mut tri = o;
    tri.mode = RenderMode::Triangles;
    let camera = Camera::look_at(
        DVec3::new(0.5, -0.6, 0.2),
        DVec3::new(0.5, 0.6, 0.45),
        DVec3::new(0.3, 0.0, 1.0),
        40.0,
        200,
        200,
    )
    .expect("camera");
    let prepared = PreparedScene::new(&scene);
    let draw = |o: RenderOptions| {
        Renderer::new(o)
            .expect("renderer")
            .render(&prepared, &camera)
            .expect("frame")
            .image
    };
    let (cells, exact) = (draw(o), draw(tri));
    let covered = exact.depth().iter().filter(|d| d.is_finite()).count();
    assert!((10_000..35_000).contains(&covered), "{covered} pixels");
    // Every column is covered at its bottom: no border of the patch shows.
    let w = exact.width() as usize;
    let last = &exact.depth()[w * (w - 1)..];
    assert!(last.iter().all(|d| d.is_finite()));
    let off = coverage_difference(&cells, &exact);
    // 17 here; 125 when the sub-nodes were not clipped.
    assert!(off < 30, "{off} pixels differ along a ridge of about 220");
}

/// A 4 × 1-cell strip folded into a ridge: displacements 0, 0, 255, 0, 0
/// along x (the ridge 2.55 high, cells 0.25 wide), so that from an eye
/// past one end some cells face away and the others face it.
fn folded_strip() -> Scene {
    let frame = Frame::new(Vec3::ZERO, Vec3::X * 0.25, Vec3::Y, Vec3::Z * 0.01).expect("frame");
    let heights = [0, 0, 255, 0, 0].repeat(2);
    let patch =
        Patch::new(frame, GridSize::new(5, 2).expect("grid"), heights, None).expect("patch");
    Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch]).expect("scene")
}

#[test]
fn cells_too_large_to_subdivide_facing_away_are_culled() {
    // Seen from above and past the strip's end, the ridge's far slope faces
    // away. Its cells are far too large to subdivide (the triangle path),
    // and with back-face culling the triangle path leaves out those facing
    // away as the sub-node path does: two triangles per cell facing the
    // eye, none for the others, and the near slope still drawn.
    let camera = Camera::look_at(
        DVec3::new(-2.5, 0.5, 4.0),
        DVec3::new(0.5, 0.5, 1.0),
        DVec3::Z,
        40.0,
        300,
        300,
    )
    .expect("camera");
    let prepared = PreparedScene::new(&folded_strip());
    let draw = |culling: Culling| {
        let mut o = unlit();
        o.culling = culling;
        Renderer::new(o)
            .expect("renderer")
            .render(&prepared, &camera)
            .expect("frame")
    };
    let (culled, all) = (draw(Culling::Back), draw(Culling::None));
    assert_eq!(culled.stats.oversized_pieces, 1, "{:?}", culled.stats);
    assert_eq!(all.stats.triangles, 8, "{:?}", all.stats);
    let away = culled.stats.cells_culled_backface;
    assert!(away > 0, "{:?}", culled.stats);
    assert_eq!(culled.stats.triangles, 8 - 2 * away);
    assert!(culled.image.covered_count() > 0);
}
