//! The image error of a scene against its source mesh (DESIGN §6), with frame times.
//!
//! For each view the source is drawn by the project's scan-line triangle rasterizer
//! (in colour when [`ImageOptions::colour_source`] is set and the source has colours or a
//! texture: see [`crate::source_colours`]; the result's `source_drawn_with` says how)
//! (`Renderer::rasterize`) and the scene by the patch renderer (`Renderer::render`), with the
//! same camera, the same lights and the same options (shading; projection, cells and
//! culling only matter to the patches: the source is culled only where it is closed, so an
//! open source shows its inside as ../shared/MEASURES.md's reference does). Per view and
//! pooled over all views:
//!
//! - **PSNR** of the RGB channels over the pixels either image covers (background pixels
//!   that both leave empty are left out, so the figure does not depend on the framing);
//!   `None` when those pixels are identical;
//! - **hole fraction**: pixels the source covers that the patches leave empty *at the
//!   source's depth* (empty, or farther than [`HOLE_DEPTH_TOLERANCE`] of the source's
//!   bounding radius behind it), over pixels the source covers (as `holes`); and the
//!   **interior** hole fraction of ../shared/MEASURES.md, the same over the source pixels
//!   whose 5 × 5 square the source covers whole (outline pixels left out);
//! - **specks** of ../shared/MEASURES.md ([`crate::specks`]) in the patches' render and, as
//!   the peer's figure, in the source's;
//! - **mean depth error**: mean |patch depth − source depth| (linear eye depth, model units)
//!   over pixels both cover, also divided by the source's bounding-box diagonal;
//! - **frame time**: the median over `runs` timed frames after one warm-up frame, for the
//!   patches and for the source alike, each frame reusing the buffers of the one before (as
//!   `spatch render --bench` times its frames), in milliseconds.
//!
//! Views: [`views_for_count`] — the 14 standard views (6 axes, 8 diagonals) or fewer of
//! them, or an even spiral of more; each frames the source's bounding sphere as
//! [`crate::hole_view_camera`] does.
//!
//! The source's views are rendered and timed once ([`SourceViews::render`]) and can be
//! compared with any number of scenes or render options ([`compare_views`]), which is what
//! the sweep does.
//!
//! Cost: per view `runs + 1` source frames and `runs + 1` patch frames, O(pixels) each to
//! compare.

use std::time::Instant;

use glam::DVec3;
use serde::Serialize;
use spatch_render::{
    Camera, Culling, MeshColours, PreparedScene, RenderError, RenderOptions, RenderedImage,
    Renderer, TriangleMesh as RasterMesh,
};

use crate::holes::{covers, standard_views, view_camera, HoleOptions, HOLE_DEPTH_TOLERANCE};
use crate::interior::interior_of;
use crate::source_colours::{colour_source, ColouredSource, SourceDrawing};
use crate::specks::{specks_within, Specks};

/// Most timed frames per view ([`ImageOptions::runs`] is taken into `1..=MAX_RUNS`).
const MAX_RUNS: usize = 1000;

/// Largest number of views [`views_for_count`] accepts.
pub const MAX_VIEWS: usize = 256;

/// `count` view directions: the first `count` of [`standard_views`] (6 axes, then 8
/// diagonals) when `count <= 14`, otherwise `count` directions on a Fibonacci spiral (even
/// spread over the sphere). `None` when `count` is 0 or above [`MAX_VIEWS`].
pub fn views_for_count(count: usize) -> Option<Vec<DVec3>> {
    let standard = standard_views();
    if count == 0 || count > MAX_VIEWS {
        return None;
    }
    if count <= standard.len() {
        return Some(standard[..count].to_vec());
    }
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    Some(
        (0..count)
            .map(|k| {
                let y = 1.0 - 2.0 * (k as f64 + 0.5) / count as f64;
                let r = (1.0 - y * y).max(0.0).sqrt();
                let a = golden * k as f64;
                DVec3::new(r * a.cos(), y, r * a.sin())
            })
            .collect(),
    )
}

/// How the image error is measured.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct ImageOptions {
    /// View directions (target to eye). Default: the 14 standard views.
    pub views: Vec<DVec3>,
    /// Image width and height in pixels. Default 500 × 500.
    pub size: [u32; 2],
    /// Vertical field of view, degrees. Default 40°.
    pub fov_y_degrees: f64,
    /// Render options shared by the source and the patches (the defaults of
    /// `spatch render`). `threads` 0 means all cores.
    pub render: RenderOptions,
    /// Timed frames per view (after one warm-up), of the patches and of the source,
    /// 1..=1000; the medians are reported. Default 3.
    pub runs: usize,
    /// Draw the source with its colours and texture when it has them (so PSNR measures
    /// the patches' colour too); off, or without source colour, it is drawn grey like
    /// colourless patches. Default on; [`crate::evaluate()`] turns it off for a
    /// colourless scene.
    pub colour_source: bool,
}

impl Default for ImageOptions {
    fn default() -> Self {
        let holes = HoleOptions::default();
        Self {
            views: holes.views,
            size: holes.size,
            fov_y_degrees: holes.fov_y_degrees,
            render: RenderOptions::default(),
            runs: 3,
            colour_source: true,
        }
    }
}

impl ImageOptions {
    fn hole_options(&self) -> HoleOptions {
        HoleOptions {
            views: self.views.clone(),
            size: self.size,
            fov_y_degrees: self.fov_y_degrees,
            threads: self.render.threads,
        }
    }
}

/// The source drawn from every view, ready to be compared with scenes.
#[derive(Debug, Clone)]
pub struct SourceViews {
    cameras: Vec<Camera>,
    images: Vec<RenderedImage>,
    /// Per view, the source pixels whose 5 × 5 square the source covers
    /// ([`crate::interior_mask`]), for the holes and the source's specks alike.
    interiors: Vec<Vec<bool>>,
    /// Per view, the specks of the source's image.
    specks: Vec<Specks>,
    source_ms: Vec<f64>,
    directions: Vec<DVec3>,
    /// Hole depth tolerance in model units.
    tolerance: f32,
    diagonal: f64,
    drawing: SourceDrawing,
}

/// The source as the triangle rasterizer draws it: with its per-corner colours when
/// `coloured` gives them, else grey.
fn raster_mesh<'a>(
    source: &'a spatch_mesh::TriangleMesh,
    coloured: Option<&'a ColouredSource>,
) -> Result<RasterMesh<'a>, RenderError> {
    match coloured {
        Some(c) => RasterMesh::new(
            source.origin,
            &c.positions,
            &c.triangles,
            MeshColours::PerCorner(&c.corner_colours),
        ),
        None => RasterMesh::new(
            source.origin,
            &source.positions,
            &source.triangles,
            MeshColours::None,
        ),
    }
}

impl SourceViews {
    /// Renders `source` from every view of `options` with the triangle rasterizer.
    pub fn render(
        source: &spatch_mesh::TriangleMesh,
        options: &ImageOptions,
    ) -> Result<SourceViews, RenderError> {
        let coloured = options
            .colour_source
            .then(|| colour_source(source))
            .flatten();
        let mesh = raster_mesh(source, coloured.as_ref())?;
        let (centre, radius) = mesh
            .bounding_sphere()
            .ok_or(spatch_render::CameraProblem::NothingToFrame)?;
        // The source as ../shared/MEASURES.md's reference: culled only where it is closed
        // (no pixel changes), whatever culling the patches are drawn with.
        let mut source_render = options.render;
        source_render.culling = Culling::Auto;
        let mut renderer = Renderer::new(source_render)?;
        let hole_options = options.hole_options();
        let mut views = SourceViews {
            cameras: Vec::with_capacity(options.views.len()),
            images: Vec::with_capacity(options.views.len()),
            interiors: Vec::with_capacity(options.views.len()),
            specks: Vec::with_capacity(options.views.len()),
            source_ms: Vec::with_capacity(options.views.len()),
            directions: Vec::with_capacity(options.views.len()),
            tolerance: (HOLE_DEPTH_TOLERANCE * radius) as f32,
            diagonal: f64::from(source.diagonal()),
            drawing: coloured.as_ref().map_or(SourceDrawing::Grey, |c| c.drawing),
        };
        for &direction in &options.views {
            let camera = view_camera(centre, radius, direction, &hole_options)?;
            let (ms, image) = time_frames(&mut renderer, options.runs, |r| {
                Ok(r.rasterize(&mesh, &camera)?.image)
            })?;
            views.push(camera, direction, (ms, image));
        }
        Ok(views)
    }

    /// Adds the view from `direction` seen by `camera`: its image, drawn in `ms`, with the
    /// image's interior and specks.
    fn push(&mut self, camera: Camera, direction: DVec3, (ms, image): (f64, RenderedImage)) {
        self.source_ms.push(ms);
        let interior = interior_of(&image);
        let width = image.width() as usize;
        self.specks
            .push(specks_within(image.pixels(), &interior, width));
        self.interiors.push(interior);
        self.images.push(image);
        self.cameras.push(camera);
        self.directions.push(direction.normalize());
    }

    /// Number of views.
    pub fn len(&self) -> usize {
        self.cameras.len()
    }

    /// True when there are no views.
    pub fn is_empty(&self) -> bool {
        self.cameras.is_empty()
    }

    /// What the source was drawn with.
    pub fn drawing(&self) -> SourceDrawing {
        self.drawing
    }

    /// The source's image of each view, in view order (to look at what the error compares).
    pub fn images(&self) -> &[RenderedImage] {
        &self.images
    }

    /// The camera of each view, in view order.
    pub fn cameras(&self) -> &[Camera] {
        &self.cameras
    }
}

/// The image error seen from one view.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ViewError {
    /// Direction from the target to the eye (unit).
    pub direction: [f64; 3],
    /// Pixels the source covers.
    pub source_pixels: usize,
    /// Pixels the patches cover.
    pub patch_pixels: usize,
    /// Source pixels the patches leave empty at the source's depth.
    pub hole_pixels: usize,
    /// `hole_pixels / source_pixels`.
    pub hole_fraction: f64,
    /// Source pixels whose 5 × 5 square the source covers whole.
    pub interior_source_pixels: usize,
    /// Of those, pixels the patches leave empty at the source's depth.
    pub interior_hole_pixels: usize,
    /// Specks over counted pixels in the patches' image ([`crate::specks`]).
    pub speck_fraction: f64,
    /// The same in the source's image.
    pub source_speck_fraction: f64,
    /// PSNR (dB) over the pixels either image covers; `None` when they are identical.
    pub psnr_db: Option<f64>,
    /// Mean |depth difference| over pixels both cover (model units).
    pub mean_depth_error: f64,
    /// Median patch frame time (ms).
    pub patch_ms: f64,
    /// Source frame time with the triangle rasterizer (ms).
    pub source_ms: f64,
}

/// The image error over all views.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ImageError {
    /// One entry per view, in order.
    pub views: Vec<ViewError>,
    /// Image width and height.
    pub size: [u32; 2],
    /// PSNR (dB) pooled over all views (total squared error over all compared pixels);
    /// `None` when every compared pixel is identical.
    pub psnr_db: Option<f64>,
    /// PSNR (dB) pooled over the pixels both images cover: the colour error alone, without
    /// the silhouette pixels one image covers and the other does not (those count in
    /// `psnr_db`, against the background). `None` when those pixels are identical.
    pub psnr_covered_db: Option<f64>,
    /// Hole pixels over source pixels, summed over the views (the outlines' pixels
    /// included).
    pub hole_fraction: f64,
    /// ../shared/MEASURES.md's hole fraction: interior hole pixels over interior source
    /// pixels, summed over the views (a source pixel is interior when the source covers its
    /// whole 5 × 5 square).
    pub interior_hole_fraction: f64,
    /// Specks over counted pixels of the patches' images, summed over the views
    /// (../shared/MEASURES.md, [`crate::specks`]).
    pub speck_fraction: f64,
    /// The same for the source's images (the triangle rasterizer on the source mesh).
    pub source_speck_fraction: f64,
    /// Mean |depth difference| over pixels both cover in all views (model units).
    pub mean_depth_error: f64,
    /// `mean_depth_error` over the source's bounding-box diagonal.
    pub mean_depth_error_rel: f64,
    /// Median over the views of the patch frame time (ms).
    pub patch_ms: f64,
    /// Median over the views of the source frame time (ms).
    pub source_ms: f64,
    /// Timed frames per view, of the patches and of the source.
    pub runs: usize,
    /// Worker threads of the renderer.
    pub threads: usize,
    /// What the source was drawn with (`grey`, `colours` or `texture`).
    pub source_drawn_with: SourceDrawing,
}

/// Sums over pixels of one view.
#[derive(Default)]
struct PixelSums {
    source: usize,
    patch: usize,
    holes: usize,
    interior: usize,
    interior_holes: usize,
    compared: usize,
    squared: u64,
    /// Squared error over the pixels both cover (`depth_pixels` of them).
    covered_squared: u64,
    depth_pixels: usize,
    depth_sum: f64,
}

fn compare_images(
    source: &RenderedImage,
    interior: &[bool],
    patch: &RenderedImage,
    tolerance: f32,
) -> PixelSums {
    let mut sums = PixelSums::default();
    let pixels = source.pixels().iter().zip(patch.pixels());
    let depths = source.depth().iter().zip(patch.depth());
    for (((sc, pc), (&sd, &pd)), &inner) in pixels.zip(depths).zip(interior) {
        let (s_in, p_in) = (sd.is_finite(), pd.is_finite());
        if s_in {
            let hole = !covers(sd, pd, tolerance);
            sums.source += 1;
            sums.holes += usize::from(hole);
            sums.interior += usize::from(inner);
            sums.interior_holes += usize::from(inner && hole);
        }
        if p_in {
            sums.patch += 1;
        }
        if s_in || p_in {
            sums.compared += 1;
            for c in 0..3 {
                let d = i64::from(sc[c]) - i64::from(pc[c]);
                sums.squared += (d * d) as u64;
            }
        }
        if s_in && p_in {
            for c in 0..3 {
                let d = i64::from(sc[c]) - i64::from(pc[c]);
                sums.covered_squared += (d * d) as u64;
            }
            sums.depth_pixels += 1;
            sums.depth_sum += f64::from((pd - sd).abs());
        }
    }
    sums
}

fn psnr(squared: u64, pixels: usize) -> Option<f64> {
    if squared == 0 || pixels == 0 {
        return None;
    }
    let mse = squared as f64 / (3 * pixels) as f64;
    Some(10.0 * (255.0 * 255.0 / mse).log10())
}

fn ratio(part: f64, whole: f64) -> f64 {
    if whole > 0.0 {
        part / whole
    } else {
        0.0
    }
}

/// The median of `values` (sorted in place); 0 when empty.
pub(crate) fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Renders `scene` from every view of `source` with `render` options and compares
/// (`runs` timed frames per view). The frames leave out the normal-lookup
/// statistics ([`RenderOptions::normal_counts`]), which nothing here reads: the
/// same image, timed as `spatch render --bench` times its frames.
pub fn compare_views(
    source: &SourceViews,
    scene: &PreparedScene,
    mut render: RenderOptions,
    runs: usize,
) -> Result<ImageError, RenderError> {
    let runs = runs.clamp(1, MAX_RUNS);
    render.normal_counts = false;
    let mut renderer = Renderer::new(render)?;
    let mut views = Vec::with_capacity(source.len());
    let mut pooled = PooledSums::default();
    let mut size = [0, 0];
    for (k, camera) in source.cameras.iter().enumerate() {
        let (patch_ms, image) =
            time_frames(&mut renderer, runs, |r| Ok(r.render(scene, camera)?.image))?;
        size = [image.width(), image.height()];
        views.push(measure_view(source, k, &image, patch_ms, &mut pooled));
    }
    let drawn = DrawnViews {
        size,
        runs,
        threads: renderer.threads(),
    };
    Ok(pooled_error(source, views, &pooled, drawn))
}

/// Sums over all views: the pixel sums, then the specks and counted pixels of the
/// patches' images and of the source's.
#[derive(Default)]
struct PooledSums {
    /// Pixel sums over all views (`patch` is left at 0: nothing pooled reads it).
    total: PixelSums,
    /// Specks and counted pixels of the patches' images, then of the source's.
    speck_sums: [usize; 4],
}

impl PooledSums {
    /// Adds one view's pixel sums and the specks of its two images.
    fn add(&mut self, sums: &PixelSums, specks: &Specks, source_specks: &Specks) {
        let total = &mut self.total;
        total.source += sums.source;
        total.holes += sums.holes;
        total.interior += sums.interior;
        total.interior_holes += sums.interior_holes;
        self.speck_sums[0] += specks.pixels.len();
        self.speck_sums[1] += specks.counted;
        self.speck_sums[2] += source_specks.pixels.len();
        self.speck_sums[3] += source_specks.counted;
        total.compared += sums.compared;
        total.squared += sums.squared;
        total.covered_squared += sums.covered_squared;
        total.depth_pixels += sums.depth_pixels;
        total.depth_sum += sums.depth_sum;
    }
}

/// How the patches' frames were drawn: the image size, the timed frames per view and
/// the renderer's threads.
struct DrawnViews {
    size: [u32; 2],
    runs: usize,
    threads: usize,
}

/// Compares the patches' `image` of view `k` with the source's, adds its sums to
/// `pooled` and returns the view's error (`patch_ms`: the patches' frame time).
fn measure_view(
    source: &SourceViews,
    k: usize,
    image: &RenderedImage,
    patch_ms: f64,
    pooled: &mut PooledSums,
) -> ViewError {
    let interior = &source.interiors[k];
    let sums = compare_images(&source.images[k], interior, image, source.tolerance);
    let width = image.width() as usize;
    let specks = specks_within(image.pixels(), &interior_of(image), width);
    let source_specks = &source.specks[k];
    let view = ViewError {
        direction: source.directions[k].to_array(),
        source_pixels: sums.source,
        patch_pixels: sums.patch,
        hole_pixels: sums.holes,
        hole_fraction: ratio(sums.holes as f64, sums.source as f64),
        interior_source_pixels: sums.interior,
        interior_hole_pixels: sums.interior_holes,
        speck_fraction: specks.fraction(),
        source_speck_fraction: source_specks.fraction(),
        psnr_db: psnr(sums.squared, sums.compared),
        mean_depth_error: ratio(sums.depth_sum, sums.depth_pixels as f64),
        patch_ms,
        source_ms: source.source_ms[k],
    };
    pooled.add(&sums, &specks, source_specks);
    view
}

/// The image error over all `views` from the sums `pooled` over them.
fn pooled_error(
    source: &SourceViews,
    views: Vec<ViewError>,
    pooled: &PooledSums,
    drawn: DrawnViews,
) -> ImageError {
    let (total, speck_sums) = (&pooled.total, &pooled.speck_sums);
    let mean_depth_error = ratio(total.depth_sum, total.depth_pixels as f64);
    let mut patch_ms: Vec<f64> = views.iter().map(|v| v.patch_ms).collect();
    let mut source_ms = source.source_ms.clone();
    ImageError {
        size: drawn.size,
        psnr_db: psnr(total.squared, total.compared),
        psnr_covered_db: psnr(total.covered_squared, total.depth_pixels),
        hole_fraction: ratio(total.holes as f64, total.source as f64),
        interior_hole_fraction: ratio(total.interior_holes as f64, total.interior as f64),
        speck_fraction: ratio(speck_sums[0] as f64, speck_sums[1] as f64),
        source_speck_fraction: ratio(speck_sums[2] as f64, speck_sums[3] as f64),
        mean_depth_error,
        mean_depth_error_rel: ratio(mean_depth_error, source.diagonal),
        patch_ms: median(&mut patch_ms),
        source_ms: median(&mut source_ms),
        runs: drawn.runs,
        threads: drawn.threads,
        source_drawn_with: source.drawing,
        views,
    }
}

/// The median wall time (ms) of `runs` frames (taken into `1..=MAX_RUNS`) `frame` draws
/// with `renderer` after one warm-up frame, and the last frame's image. Each frame's buffers go back to the renderer
/// for the next ([`Renderer::recycle`]), as `spatch render --bench` times its frames. Why:
/// a frame with fresh buffers pays their page faults (about 460 for a 500² frame), and the
/// source's frames were timed once each, cold, while the patches' were warmed: the two
/// timings the own-rasterizer ratio divides were taken two ways.
fn time_frames(
    renderer: &mut Renderer,
    runs: usize,
    mut frame: impl FnMut(&mut Renderer) -> Result<RenderedImage, RenderError>,
) -> Result<(f64, RenderedImage), RenderError> {
    let runs = runs.clamp(1, MAX_RUNS);
    let mut image = frame(renderer)?;
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs {
        renderer.recycle(image);
        let start = Instant::now();
        image = frame(renderer)?;
        times.push(start.elapsed().as_secs_f64() * 1e3);
    }
    Ok((median(&mut times), image))
}

/// [`SourceViews::render`] then [`compare_views`] with `options`.
pub fn image_error(
    scene: &PreparedScene,
    source: &spatch_mesh::TriangleMesh,
    options: &ImageOptions,
) -> Result<ImageError, RenderError> {
    let views = SourceViews::render(source, options)?;
    compare_views(&views, scene, options.render, options.runs)
}

/// The camera of view `direction` around `source` with `options` (as [`image_error`] uses).
pub fn image_view_camera(
    source: &spatch_mesh::TriangleMesh,
    direction: DVec3,
    options: &ImageOptions,
) -> Result<Camera, RenderError> {
    crate::holes::hole_view_camera(source, direction, &options.hole_options())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_counts() {
        assert_eq!(views_for_count(14).unwrap(), standard_views());
        assert_eq!(views_for_count(6).unwrap(), standard_views()[..6].to_vec());
        assert!(views_for_count(0).is_none());
        assert!(views_for_count(MAX_VIEWS + 1).is_none());
        let many = views_for_count(40).unwrap();
        assert_eq!(many.len(), 40);
        for v in &many {
            assert!((v.length() - 1.0).abs() < 1e-9);
        }
        // Spread: the mean direction of an even spiral is near the centre.
        let mean = many.iter().copied().sum::<DVec3>() / 40.0;
        assert!(mean.length() < 0.05, "{mean}");
    }

    #[test]
    fn psnr_of_known_errors() {
        // One pixel off by 255 in one channel out of 1 pixel: MSE 255²/3.
        let p = psnr(255 * 255, 1).unwrap();
        assert!((p - 10.0 * 3f64.log10()).abs() < 1e-12);
        assert_eq!(psnr(0, 10), None);
    }

    #[test]
    fn timed_frames_reuse_one_set_of_buffers_and_give_the_last_image() {
        // A triangle seen from the front: `runs` timed frames after a warm-up, each drawn
        // into the buffers of the one before (the same colour buffer throughout: without
        // the hand-back, two frames alive at once would hold two), the image unchanged.
        let positions = [
            glam::Vec3::new(-1.0, -1.0, 0.0),
            glam::Vec3::new(1.0, -1.0, 0.0),
            glam::Vec3::new(0.0, 1.0, 0.0),
        ];
        let triangles = [[0, 1, 2]];
        let mesh = RasterMesh::new(DVec3::ZERO, &positions, &triangles, MeshColours::None).unwrap();
        let camera = Camera::look_at(DVec3::Z * 5.0, DVec3::ZERO, DVec3::Y, 40.0, 64, 48).unwrap();
        let mut options = RenderOptions::default();
        options.threads = 1;
        let fresh = Renderer::new(options)
            .unwrap()
            .rasterize(&mesh, &camera)
            .unwrap()
            .image;
        let mut renderer = Renderer::new(options).unwrap();
        let mut buffers = Vec::new();
        let (ms, image) = time_frames(&mut renderer, 4, |r| {
            let image = r.rasterize(&mesh, &camera)?.image;
            buffers.push(image.pixels().as_ptr());
            Ok(image)
        })
        .unwrap();
        assert_eq!(buffers.len(), 5, "a warm-up and four timed frames");
        assert!(buffers.iter().all(|&b| b == buffers[0]), "{buffers:?}");
        assert!(ms >= 0.0 && ms.is_finite());
        assert_eq!(image, fresh);
        assert!(image.covered_count() > 100);
    }

    #[test]
    fn median_picks_the_middle() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut []), 0.0);
    }
}
