//! The frame driver: resolves the camera, runs the planning stage over
//! chunks of patches (or triangles), bins the work into bands, rasterizes
//! the bands on the thread pool, and assembles the image and statistics.
//!
//! A [`Renderer`] owns its thread pool and every scratch buffer, so
//! rendering frame after frame allocates almost nothing.

use std::sync::Mutex;
use std::time::Instant;

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use spatch_format::Scene;

use crate::camera::{Camera, View};
use crate::error::RenderError;
use crate::frame::band_tasks::{band_job, band_tasks, run_band_task};
use crate::frame::image::RenderedImage;
use crate::frame::occlusion::{self, Frame, OcclusionStats};
use crate::frame::occlusion_skip::SkipTiles;
use crate::frame::schedule::{run_in_order, BandOrder};
use crate::frame::stats::{BandStats, RenderStats};
use crate::frame::tiles::Bins;
use crate::isa::Isa;
use crate::lighting::{Material, ShadeFrame, WorldLight};
use crate::options::RenderOptions;
use crate::plan::chunk::plan_chunk;
use crate::plan::counters::Counters;
use crate::plan::cull::Frustum;
use crate::plan::mesh::{plan_mesh_chunk, TriangleMesh};
use crate::plan::sides::PortalsInView;
use crate::plan::work::{ChunkWork, FrameSetup, PATCH_CHUNK};
use crate::prepare::patch::PreparedPatch;
use crate::prepare::scene::PreparedScene;
use crate::raster::band::{Band, Sample};
use crate::raster::gap_fill::GAP_FILL_REACH;
use crate::shade::phong_items::PhongItems;

/// Triangles per unit of parallel set-up work for meshes.
const TRIANGLE_CHUNK: usize = 4096;

/// The portals of a frame without openings (meshes).
static NO_PORTALS: PortalsInView = PortalsInView::NONE;

/// An image and what it took to render it.
#[derive(Debug, Clone)]
pub struct RenderOutput {
    /// The image.
    pub image: RenderedImage,
    /// Counts and timings.
    pub stats: RenderStats,
}

/// A renderer with its thread pool and scratch buffers.
pub struct Renderer {
    options: RenderOptions,
    /// The instruction set of the hot kernels ([`Isa::detect`]).
    isa: Isa,
    pool: rayon::ThreadPool,
    chunks: Vec<ChunkWork>,
    frames: Vec<ShadeFrame>,
    order: BandOrder,
    bins: Bins,
    bands: Vec<Band>,
    /// One sample buffer per pool thread, lent to each band the thread
    /// draws ([`Band::swap_samples`]). Why per thread, not per band: a
    /// first frame writes every buffer's pages for the first time: four
    /// bands' buffers at 500² (4 MB) against two threads' (2 MB) were 421
    /// more page faults of a one-image bunny render (`perf stat`); later
    /// frames draw as fast either way (ratio 1.007,
    /// `bench/compare_binaries.py`).
    thread_samples: Vec<Mutex<Vec<Sample>>>,
    /// Each band's occlusion-skip tiles.
    skips: Vec<SkipTiles>,
    /// Colour and depth buffers handed back by [`Self::recycle`].
    spare: Option<(Vec<[u8; 4]>, Vec<f32>)>,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Renderer")
            .field("options", &self.options)
            .field("threads", &self.pool.current_num_threads())
            .finish()
    }
}

impl Renderer {
    /// A renderer with `options` (checked) and its own thread pool.
    pub fn new(options: RenderOptions) -> Result<Self, RenderError> {
        options.validate()?;
        let threads = if options.threads == 0 {
            std::thread::available_parallelism().map_or(1, |n| n.get())
        } else {
            options.threads
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|source| RenderError::ThreadPool { threads, source })?;
        Ok(Self {
            options,
            isa: Isa::detect(options.simd),
            pool,
            chunks: Vec::new(),
            frames: Vec::new(),
            order: BandOrder::default(),
            bins: Bins::default(),
            bands: Vec::new(),
            thread_samples: (0..threads).map(|_| Mutex::default()).collect(),
            skips: Vec::new(),
            spare: None,
        })
    }

    /// The options.
    pub fn options(&self) -> &RenderOptions {
        &self.options
    }

    /// Hands back the buffers of an image this renderer made, so the next
    /// frame reuses them. Why: a fresh 500² frame's two megabytes of colour
    /// and depth cost ~460 page faults per frame (`/usr/bin/time` over
    /// `--bench 10` and `--bench 50`).
    pub fn recycle(&mut self, image: RenderedImage) {
        self.spare = Some(image.into_buffers());
    }

    /// Worker threads in the pool.
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }

    /// Prepares `scene` on this renderer's threads and with its instruction
    /// set ([`PreparedScene::new`]).
    pub fn prepare(&self, scene: &Scene) -> PreparedScene {
        self.pool
            .install(|| PreparedScene::prepare(scene, false, self.isa))
    }

    /// Prepares `scene` with its overlaps trimmed, on this renderer's
    /// threads ([`PreparedScene::trimming_overlaps`]).
    pub fn prepare_trimming_overlaps(&self, scene: &Scene) -> PreparedScene {
        self.pool
            .install(|| PreparedScene::prepare(scene, true, self.isa))
    }

    /// [`Self::prepare`] (or, with `trim_overlaps`,
    /// [`Self::prepare_trimming_overlaps`]) taking the scene's nodes
    /// instead of copying them: for a caller done with the scene, it saves
    /// a copy of every node (1.5 MB for the bunny) and the memory it takes.
    pub fn prepare_owned(&self, scene: Scene, trim_overlaps: bool) -> PreparedScene {
        self.pool
            .install(|| PreparedScene::prepare_owned(scene, trim_overlaps, self.isa))
    }

    fn setup<'a>(&self, view: &'a View, options: &'a RenderOptions) -> FrameSetup<'a> {
        let (z_scale, z_offset) = view.depth_scale();
        let [r, g, b] = options.lighting.base_colour;
        FrameSetup {
            view,
            frustum: Frustum {
                width: view.width as f32,
                height: view.height as f32,
                near: view.near as f32,
                far: view.far as f32,
                guard: options.guard_band,
            },
            light: WorldLight::new(&options.lighting, view.basis),
            material: Material::new(&options.lighting),
            options,
            z_scale,
            z_offset,
            base_colour: Vec3::new(r as f32, g as f32, b as f32),
            portals: &NO_PORTALS,
            two_sided_through_openings: false,
        }
    }

    /// Renders a prepared scene.
    pub fn render(
        &mut self,
        scene: &PreparedScene,
        camera: &Camera,
    ) -> Result<RenderOutput, RenderError> {
        let start = Instant::now();
        let options = self.options;
        let view = View::new(camera, options.ssaa, scene.bounds)?;
        let outside = |(lo, hi): (DVec3, DVec3)| !(view.eye.cmpge(lo) & view.eye.cmple(hi)).all();
        let portals = PortalsInView::new(&scene.portals, view.eye);
        let setup = FrameSetup {
            portals: &portals,
            two_sided_through_openings: scene.inside_box.is_some_and(outside),
            ..self.setup(&view, &options)
        };
        let count = scene.patches.len();
        let chunk_count = count.div_ceil(PATCH_CHUNK);
        self.chunks.resize_with(chunk_count, ChunkWork::default);
        self.frames
            .resize(count.max(1), ShadeFrame::one_sided(Vec3::Z, Vec3::Z));
        let chunks = &mut self.chunks;
        let frames = &mut self.frames;
        let isa = self.isa;
        self.pool.install(|| {
            chunks
                .par_iter_mut()
                .zip(frames.par_chunks_mut(PATCH_CHUNK))
                .zip(scene.patches.par_chunks(PATCH_CHUNK))
                .enumerate()
                .for_each(|(c, ((work, frames), patches))| {
                    let first = (c * PATCH_CHUNK) as u32;
                    isa.run(
                        #[inline(always)]
                        || plan_chunk(work, patches, first, frames, &setup),
                    );
                });
        });
        let plan_wall = start.elapsed();
        let clock = FrameClock { start, plan_wall };
        self.finish(clock, &view, &setup, camera, &scene.patches)
    }

    /// Rasterizes a triangle mesh with the same camera, shading and
    /// framebuffer as patches.
    pub fn rasterize(
        &mut self,
        mesh: &TriangleMesh<'_>,
        camera: &Camera,
    ) -> Result<RenderOutput, RenderError> {
        let start = Instant::now();
        // Triangles are drawn exactly: no gaps to fill.
        let options = RenderOptions {
            gap_fill: false,
            ..self.options
        };
        let view = View::new(camera, options.ssaa, mesh.bounds())?;
        let setup = self.setup(&view, &options);
        let normals = mesh.vertex_normals();
        let world = setup.light.frame_in(&glam::DMat3::IDENTITY, None);
        self.frames.clear();
        self.frames.push(world);
        let count = mesh.triangle_count();
        self.chunks
            .resize_with(count.div_ceil(TRIANGLE_CHUNK), ChunkWork::default);
        let chunks = &mut self.chunks;
        self.pool.install(|| {
            chunks.par_iter_mut().enumerate().for_each(|(c, work)| {
                let lo = c * TRIANGLE_CHUNK;
                let range = lo..(lo + TRIANGLE_CHUNK).min(count);
                plan_mesh_chunk(work, mesh, &normals, range, &world, &setup);
            });
        });
        let plan_wall = start.elapsed();
        let clock = FrameClock { start, plan_wall };
        self.finish(clock, &view, &setup, camera, &[])
    }

    /// Bins the planned work into bands, rasterizes and resolves the bands
    /// on the pool and gathers the image and its statistics.
    fn finish(
        &mut self,
        clock: FrameClock,
        view: &View,
        setup: &FrameSetup<'_>,
        camera: &Camera,
        patches: &[PreparedPatch],
    ) -> Result<RenderOutput, RenderError> {
        let options = setup.options;
        let bin_start = Instant::now();
        let layout = self.bin_work(view, options);
        let bin_wall = bin_start.elapsed();

        let raster_start = Instant::now();
        let (rgba, eye_depth) = self.raster_bands(layout, view, setup, patches);
        let raster_wall = raster_start.elapsed();

        let gather_start = Instant::now();
        let image = RenderedImage::from_internal(
            rgba,
            eye_depth,
            camera.width(),
            camera.height(),
            options.ssaa,
            view.near,
            view.far,
        );
        let gather_wall = gather_start.elapsed();

        let walls = FrameWalls {
            plan: clock.plan_wall,
            bin: bin_wall,
            raster: raster_wall,
            gather: gather_wall,
            total: clock.start.elapsed(),
        };
        let band_count = layout.band_count;
        let stats = self.frame_stats(&image, walls, band_count, (view, camera), options);
        Ok(RenderOutput { image, stats })
    }

    /// Sorts the planned items and triangles into bands of rows and orders
    /// the bands for the pool; returns how the image was cut.
    fn bin_work(&mut self, view: &View, options: &RenderOptions) -> BandLayout {
        let tile_rows = options.band_rows(view.height, self.pool.current_num_threads());
        let band_count = view.height.div_ceil(tile_rows) as usize;
        let apron = if options.fills_gaps() {
            GAP_FILL_REACH
        } else {
            0
        };
        self.bins.fill(&self.chunks, tile_rows, band_count, apron);
        let size = (view.width, view.height);
        (self.order).plan(&self.chunks, size, tile_rows, band_count);
        BandLayout {
            tile_rows,
            band_count,
            apron,
        }
    }

    /// Draws and resolves every band of `layout` on the pool, each into its
    /// rows of the image's colour and eye-depth buffers, which it returns.
    fn raster_bands(
        &mut self,
        layout: BandLayout,
        view: &View,
        setup: &FrameSetup<'_>,
        patches: &[PreparedPatch],
    ) -> (Vec<[u8; 4]>, Vec<f32>) {
        let BandLayout {
            tile_rows,
            band_count,
            apron,
        } = layout;
        let phong = PhongItems::new(
            setup.options.shading,
            &self.bins.all_items,
            &self.chunks,
            patches,
            &self.frames,
        );
        let width = view.width as i32;
        let pixels = (view.width * view.height) as usize;
        let (mut rgba, mut eye_depth) = self.image_buffers(pixels);
        let job = band_job(
            setup,
            view,
            (&self.chunks, &self.bins),
            (&phong, patches),
            self.isa,
        );
        self.skips.resize_with(band_count, SkipTiles::default);
        let tasks = band_tasks(
            (&mut self.bands, &mut self.skips),
            band_count,
            tile_rows,
            (view.width, view.height),
            &mut rgba,
            &mut eye_depth,
        );
        let thread_samples = &self.thread_samples;
        let draw = |task| run_band_task(task, &job, thread_samples, (width, apron));
        run_in_order(&self.pool, tasks, &self.order.order, draw);
        (rgba, eye_depth)
    }

    /// The image's colour and eye-depth buffers for `pixels` pixels: the
    /// last frame's handed back ([`Renderer::recycle`]) when they fit, else
    /// fresh ones.
    fn image_buffers(&mut self, pixels: usize) -> (Vec<[u8; 4]>, Vec<f32>) {
        // Every pixel is written by its band, so recycled buffers need no
        // clearing; fresh ones are zero-filled on the pool. Why not
        // `vec![0; n]`: from the allocator's padded heap
        // (`spatch::heap`) a zeroed allocation is cleared by one thread,
        // first touch of every page included (1.3 ms of a one-image bunny
        // render on the main thread).
        match self.spare.take() {
            Some((rgba, depth)) if rgba.len() == pixels && depth.len() == pixels => (rgba, depth),
            _ => self.pool.install(|| {
                let (mut rgba, mut depth) = (Vec::new(), Vec::new());
                rgba.par_extend(rayon::iter::repeat_n([0u8; 4], pixels));
                depth.par_extend(rayon::iter::repeat_n(0f32, pixels));
                (rgba, depth)
            }),
        }
    }

    /// The statistics of the frame just drawn into `image` in `band_count`
    /// bands: the chunks' counters, the bands' times and coverage, and the
    /// stages' walls.
    fn frame_stats(
        &self,
        image: &RenderedImage,
        walls: FrameWalls,
        band_count: usize,
        (view, camera): (&View, &Camera),
        options: &RenderOptions,
    ) -> RenderStats {
        let mut counters = Counters::default();
        for chunk in &self.chunks {
            counters += &chunk.counters;
        }
        let mut stats = RenderStats::default();
        stats.set_counters(&counters);
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let sum = |f: fn(&Band) -> u64| self.bands.iter().map(f).sum::<u64>() as f64 / 1e6;
        stats.times_ms.cells = sum(|b| b.times.cells);
        stats.times_ms.triangles = sum(|b| b.times.triangles);
        stats.times_ms.resolve = sum(|b| b.times.resolve);
        stats.times_ms.plan_wall = ms(walls.plan);
        stats.times_ms.bin_wall = ms(walls.bin);
        stats.times_ms.raster_wall = ms(walls.raster);
        stats.times_ms.gather_wall = ms(walls.gather);
        stats.times_ms.total_wall = ms(walls.total);
        stats.image = [camera.width(), camera.height()];
        stats.internal = [view.width, view.height];
        stats.near_far = [view.near, view.far];
        stats.threads = self.pool.current_num_threads();
        stats.kernels = self.isa.name();
        stats.tiles = band_count;
        stats.bands = self.band_stats();
        // With supersampling the image's pixels are not the bands'.
        stats.covered_pixels = if options.ssaa == 1 {
            self.bands.iter().map(|b| b.covered).sum()
        } else {
            image.covered_count() as u64
        };
        stats.pieces_skipped_hidden = self.skips.iter().map(|s| s.skipped).sum();
        stats.options = Some(*options);
        stats
    }

    /// How much of the last frame's drawing ends up hidden
    /// ([`OcclusionStats`]): its pieces drawn again one at a time, each
    /// merged with the depth test. Zero counts before the first frame.
    pub fn occlusion(&self) -> OcclusionStats {
        let Some(band) = self.bands.first() else {
            return OcclusionStats::default();
        };
        let height: i32 = self.bands.iter().map(|b| b.rows).sum();
        let threads = self.pool.current_num_threads();
        let frame = Frame {
            chunks: &self.chunks,
            bins: &self.bins,
            cells: self.options.cells,
            width: band.width,
            height,
            tile_rows: self.options.band_rows(height as u32, threads) as i32,
            skip: self.options.occlusion_skip,
            apron: band.apron,
        };
        occlusion::measure(&frame)
    }

    /// Rows, work and time of each band of the last frame.
    fn band_stats(&self) -> Vec<BandStats> {
        let ms = |ns: u64| ns as f64 / 1e6;
        (0..self.bands.len())
            .map(|b| {
                let band = &self.bands[b];
                let (items, triangles) = self.bins.counts(b);
                let t = band.times;
                BandStats {
                    y0: band.y0 as u32,
                    rows: band.rows as u32,
                    items,
                    triangles,
                    work: self.order.work[b],
                    ms: ms(t.cells + t.triangles + t.resolve),
                    thread: band.thread,
                }
            })
            .collect()
    }
}

/// Renders `scene` once (prepares it, builds a thread pool). For repeated
/// frames, keep a [`PreparedScene`] and a [`Renderer`].
pub fn render(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
) -> Result<RenderOutput, RenderError> {
    let prepared = PreparedScene::new(scene);
    Renderer::new(*options)?.render(&prepared, camera)
}

/// Rasterizes a triangle mesh once with the scan-line rasterizer.
pub fn rasterize_triangles(
    mesh: &TriangleMesh<'_>,
    camera: &Camera,
    options: &RenderOptions,
) -> Result<RenderOutput, RenderError> {
    Renderer::new(*options)?.rasterize(mesh, camera)
}

/// When a frame started and how long its planning took.
#[derive(Debug, Clone, Copy)]
struct FrameClock {
    start: Instant,
    plan_wall: std::time::Duration,
}

/// How a frame's image is cut into bands of rows.
#[derive(Debug, Clone, Copy)]
struct BandLayout {
    /// Rows per band (the last may have fewer).
    tile_rows: u32,
    /// Bands in the image.
    band_count: usize,
    /// Rows each band draws above and below its own (the gap fill's reach).
    apron: i32,
}

/// The wall times of a frame's stages.
#[derive(Debug, Clone, Copy)]
struct FrameWalls {
    plan: std::time::Duration,
    bin: std::time::Duration,
    raster: std::time::Duration,
    gather: std::time::Duration,
    total: std::time::Duration,
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A `size`² view of the default sphere (radius 128) from `eye` (in
    /// sphere radii), looking at its centre.
    fn sphere_view(eye: DVec3, size: u32) -> Camera {
        Camera::look_at(eye * 128.0, DVec3::ZERO, DVec3::Y, 30.0, size, size).expect("camera")
    }

    /// Bands, buffers and tables are reused from frame to frame (bands are
    /// cleared by `fill` when their size is unchanged): a renderer reused
    /// across views, shadings and sizes must give the images of fresh
    /// renderers.
    #[test]
    fn a_reused_renderer_draws_every_frame_as_a_fresh_one() {
        let prepared = PreparedScene::default_sphere();
        let views = [
            sphere_view(DVec3::new(0.3, 0.5, 0.8) * 4.0, 90),
            sphere_view(DVec3::new(-0.7, 0.1, 0.4) * 2.5, 90),
            sphere_view(DVec3::new(0.0, 0.2, 1.0) * 9.0, 90),
            sphere_view(DVec3::new(0.5, -0.5, 0.5) * 3.0, 70),
            sphere_view(DVec3::new(0.3, 0.5, 0.8) * 4.0, 90),
        ];
        for shading in [crate::Shading::Phong, crate::Shading::Gouraud] {
            let options = RenderOptions {
                shading,
                threads: 2,
                ..Default::default()
            };
            let mut reused = Renderer::new(options).expect("renderer");
            for (k, camera) in views.iter().enumerate() {
                let again = reused.render(&prepared, camera).expect("frame");
                let fresh = Renderer::new(options)
                    .expect("renderer")
                    .render(&prepared, camera)
                    .expect("frame");
                assert!(fresh.image.covered_count() > 500, "view {k}");
                assert!(again.image == fresh.image, "view {k}, {shading:?}");
                // The bands' counts, summed, are the image's.
                let covered = again.image.covered_count() as u64;
                assert_eq!(again.stats.covered_pixels, covered, "view {k}");
                reused.recycle(again.image);
            }
        }
    }

    /// Without stage times a frame reads no planning clock: the same image,
    /// the planning's five stage times 0, the walls and bands still timed.
    #[test]
    fn stage_times_off_leave_the_image_and_zero_the_planning_times() {
        let prepared = PreparedScene::default_sphere();
        let camera = sphere_view(DVec3::new(0.3, 0.5, 0.8) * 4.0, 96);
        let frame = |stage_times: bool| {
            let options = RenderOptions {
                stage_times,
                threads: 2,
                ..Default::default()
            };
            let mut renderer = Renderer::new(options).expect("renderer");
            renderer.render(&prepared, &camera).expect("frame")
        };
        let (on, off) = (frame(true), frame(false));
        assert!(on.image == off.image);
        assert!(on.stats.times_ms.traverse > 0.0);
        let t = off.stats.times_ms;
        assert_eq!(
            [t.cull, t.split, t.traverse, t.normals, t.triangle_setup],
            [0.0; 5]
        );
        assert!(t.total_wall > 0.0 && t.cells > 0.0 && t.resolve > 0.0);
    }

    /// Gouraud frames keep an attribute entry for every node of every
    /// draw item (the resolve pass reads a drawn cell's corners by node
    /// index); Phong and flat frames keep none (their resolve reads the
    /// prepared levels).
    #[test]
    fn node_attributes_follow_the_node_array_only_when_shading_needs_them() {
        let prepared = PreparedScene::default_sphere();
        let camera = sphere_view(DVec3::new(1.2, 2.0, 3.2), 80);
        for shading in [
            crate::Shading::Flat,
            crate::Shading::Gouraud,
            crate::Shading::Phong,
        ] {
            let mut renderer = Renderer::new(RenderOptions {
                shading,
                ..Default::default()
            })
            .expect("renderer");
            let out = renderer.render(&prepared, &camera).expect("frame");
            assert!(out.image.covered_count() > 500, "{shading:?}");
            let nodes: usize = renderer.chunks.iter().map(|c| c.nodes.len()).sum();
            assert!(nodes > 0);
            for chunk in &renderer.chunks {
                let attributes = chunk.node_attributes.len();
                if shading != crate::Shading::Gouraud {
                    assert_eq!(attributes, 0, "{shading:?}");
                    continue;
                }
                for item in &chunk.items {
                    let end = item.first as usize + item.cols as usize * item.rows as usize;
                    assert!(
                        end <= attributes,
                        "{shading:?}: item to {end}, {attributes}"
                    );
                }
            }
        }
    }
}
