//! `spatch render`: a scene to a PNG on the CPU, with depth, statistics
//! and a frame-time benchmark.

use std::mem::ManuallyDrop;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use glam::DVec3;
use spatch_eval::{Counts, Stages};
use spatch_format::{ContainerInfo, Scene};
use spatch_render::{
    measure_shortcuts, Camera, PreparedScene, RenderError, RenderOptions, RenderOutput, Renderer,
};

use super::frame_bench::{bench, BenchReport};
use super::render_output::{
    depth_format, image_files, print_result, render_report, stats_file_bytes, CameraJson,
    DepthFormatArg, RenderDetails, StatsFile,
};
use super::render_values::{
    parse_colour, parse_vec3, CellsArg, CullArg, ModeArg, ProjectionArg, ShadingArg,
};
use super::ThreadsArg;
use crate::failure::render_failure;
use crate::output::{print_json, read_spatch, write_output};
use crate::progress::Progress;
use crate::report::scene_diagonal;

/// Arguments of `spatch render`.
#[derive(Debug, clap::Args)]
pub(crate) struct RenderArgs {
    /// Input .spatch file, or a tiled scene's index.json (`spatch from-cloud --plan`), of
    /// which only the tiles in view are read.
    #[arg(value_name = "FILE")]
    input: PathBuf,
    /// With a tiled scene's index: draw its coarse level (one file holding every tile with
    /// one node in 4 kept along each axis) instead of reading the tiles. Without it, the
    /// level is drawn only when its cells are under a pixel from the eye everywhere.
    #[arg(long)]
    coarse: bool,
    /// Output PNG (RGBA, transparent background unless --background); may be
    /// left out with --bench or --stats.
    #[arg(short, long, value_name = "FILE", required_unless_present_any = ["bench", "stats"])]
    output: Option<PathBuf>,
    /// Eye position x,y,z (default: a three-quarter view framing the scene).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    eye: Option<DVec3>,
    /// Point looked at x,y,z (default: the centre of the scene).
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    target: Option<DVec3>,
    /// Up vector x,y,z.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true, default_value = "0,1,0")]
    up: DVec3,
    /// Vertical field of view in degrees, in (0, 180).
    #[arg(long, value_name = "DEG", default_value_t = Camera::DEFAULT_FOV_Y_DEGREES)]
    fov: f64,
    /// Near plane distance (default: from the scene bounds).
    #[arg(long, value_name = "DIST")]
    near: Option<f64>,
    /// Far plane distance (default: from the scene bounds).
    #[arg(long, value_name = "DIST")]
    far: Option<f64>,
    /// Image width in pixels.
    #[arg(long, value_name = "PX", default_value_t = Camera::DEFAULT_WIDTH)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, value_name = "PX", default_value_t = Camera::DEFAULT_HEIGHT)]
    height: u32,
    /// Patches, or each cell as two triangles through the scan-line rasterizer.
    #[arg(long, value_enum, default_value_t = ModeArg::Patches)]
    mode: ModeArg,
    /// Node projection: trilinear (fast, approximate) or exact.
    #[arg(long, value_enum, default_value_t = ProjectionArg::Trilinear)]
    projection: ProjectionArg,
    /// Cell filling of magnified patches.
    #[arg(long, value_enum, default_value_t = CellsArg::Bilinear)]
    cells: CellsArg,
    /// Shading model.
    #[arg(long, value_enum, default_value_t = ShadingArg::Phong)]
    shading: ShadingArg,
    /// Back-face culling by normal cones. auto culls where the converter
    /// found it safe and draws the patches an opening lets the eye see from
    /// behind from both sides, lit two-sided.
    #[arg(long, value_enum, default_value_t = CullArg::Auto)]
    cull: CullArg,
    #[command(flatten)]
    threads: ThreadsArg,
    /// Supersampling factor per axis, 1..=4.
    #[arg(long, value_name = "K", default_value_t = 1)]
    ssaa: u32,
    /// Do not minify far patches through their mip pyramid.
    #[arg(long)]
    no_mip: bool,
    /// Keep the portable instructions instead of the AVX2 copy of the
    /// frame's kernels chosen at run time (same image, for comparisons).
    #[arg(long)]
    no_simd: bool,
    /// Draw the cells of every coloured patch by sub-quads that write the
    /// pixel centres they cover, as a triangle rasterizer does, instead of
    /// letting them reach about half a pixel past the outline: sharper
    /// coloured silhouettes (fuze, unlit: 27.9 -> 30.7 dB against its
    /// source) for several times the frame's cost on coloured scenes.
    /// Patches with a colour grid are drawn by pixel-centre coverage by
    /// default, more cheaply (see --no-exact-grid-outlines).
    #[arg(long)]
    exact_outlines: bool,
    /// Let the cells of patches with a colour grid reach about half a pixel
    /// past the outline (sub-nodes) instead of the default pixel-centre
    /// coverage: fuze, unlit, 30.3 -> 27.9 dB against its source. Scenes
    /// without colour grids draw the same either way.
    #[arg(long)]
    no_exact_grid_outlines: bool,
    /// Leave out pieces already hidden behind the pixels drawn before them
    /// in their band (8 x 8 tiles' farthest depths against a piece's
    /// nearest): the same image bit for bit; bunny 500²: 1 % fewer
    /// instructions per frame, 1000²: 3 %; the sphere and the mannequin,
    /// which hide little: about 1 % more.
    #[arg(long)]
    occlusion_skip: bool,
    /// Cut magnified cells into sub-nodes up to 1.5 px apart and close the
    /// gaps between them by one pass per band, instead of a sub-node in
    /// every pixel a cell covers: bunny 1000²: 12 % fewer instructions per
    /// frame at about the same PSNR against its source, but a pixel on an
    /// outline its surface covers by a fraction of a pixel can stay open
    #[arg(long)]
    gap_fill: bool,
    /// Take the coarsest mip level whose projected cells stay below PX
    /// pixels, 0.1..=16. The default (3) draws cells of up to about three
    /// pixels, subdivided (bunny 500²: 37 % fewer instructions per frame
    /// than 0.9, the same PSNR against the source); 0.9, the default before,
    /// takes a coarser level only where its cells stay under a pixel;
    /// larger values trade more detail for speed.
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_MIP_LIMIT)]
    mip_limit: f32,
    /// Let an uncoloured patch with a full grid take a coarser mip level
    /// than --mip-limit allows (cells up to 4 × the limit) while that level
    /// moves its surface by at most PX pixels on screen, 0..=2; 0 turns it
    /// off. Default 0.25: smooth full grids (the perfect sphere at 500²: 25 %
    /// fewer instructions per frame) draw fewer, larger cells; scans, whose
    /// patches have empty nodes, and coloured patches are unchanged.
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_MIP_TOLERANCE)]
    mip_tolerance: f32,
    /// Let level 1 draw cells of up to PX pixels (0.1..=16; 0, the
    /// default, turns it off) where --mip-limit keeps a patch at level 0,
    /// while it moves the surface by at most 0.25 px (root mean square) and
    /// 98 % of the nodes by at most 0.5 px; level 1's cells along the
    /// outline are then drawn by the level-0 cells they hold, so the
    /// outline stays level 0's; it carries level 0's normals at the nodes
    /// both levels share (patches with node colours lift only under Phong,
    /// shaded from level 0 throughout). Large views of scans draw faster (the bunny at
    /// 1000² with 6: 0.75–0.91 of the frame, PSNR against the source 27.45
    /// → 27.59 dB; the mannequin at 500²: 0.86, 0.17 dB less), but the
    /// lowered surface lets dark specks through along creases and
    /// silhouettes, and CAD models lose detail (fandisk: 0.4 dB)
    #[arg(long, value_name = "PX", default_value_t = 0.0)]
    level_one_limit: f32,
    /// Splat the nodes of pixel-sized cells as rectangles of half-width up
    /// to PX pixels (0.5..=3) instead of subdividing the cells, and take
    /// mip levels whose nodes land within that reach: fewer samples, each
    /// pixel shaded from its nearest node (bunny 500²: 22 % fewer
    /// instructions per frame, 1.6 dB lower PSNR). 0 (default): off.
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_SPLAT_LIMIT)]
    splat_limit: f32,
    /// Phong, bilinear cells: draw a whole patch's positions from the mip
    /// level above its shading level when that level's cells stay below
    /// PX pixels (1..=16), still shading each pixel from the shading
    /// level's normals: 4× fewer nodes, a surface bilinear between every
    /// other node (bunny 500² at 3.6: 37 % fewer instructions per frame,
    /// 1.7 dB lower PSNR, specks on thin rims). 0 (default): off.
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_GEOMETRY_LIMIT)]
    geometry_limit: f32,
    /// Draw bilinear cells up to PX pixels (0.5..=4) by pixel-centre
    /// coverage (two triangles per cell, the resolve interpolating the
    /// cell's corners at each pixel centre) instead of sub-nodes, and take
    /// mip levels whose cells stay below PX: no sub-nodes for pixel-sized
    /// cells, exact outlines. 0: off (sub-nodes).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_CENTRE_LIMIT)]
    centre_limit: f32,
    /// With --geometry-limit, coarsen only patches whose shading-level
    /// nodes all lie within T of their own node spacing of the coarser
    /// level's bilinear surface (measured once per scene): rough parts of
    /// a scan keep their own surface. 0 (default): every whole patch.
    #[arg(long, value_name = "T", default_value_t = RenderOptions::DEFAULT_GEOMETRY_TOLERANCE)]
    geometry_tolerance: f32,
    /// Trim, once per scene, the level-0 cells that an earlier patch
    /// already draws (same surface within 5 % of a cell, normals within
    /// 1°): each frame then draws fewer cells where patches overlap, for a
    /// one-off cost (the perfect sphere: 13 % fewer instructions per 500²
    /// frame for about 40 ms more with 2 threads). Worth it with --bench or
    /// many frames.
    #[arg(long)]
    trim_overlaps: bool,
    /// Rows per framebuffer band, 4..=256, or 0 (default): automatic, two
    /// bands per thread within 64..=128 rows (128 with 2 threads at 500²).
    /// The unit of work a thread takes: taller bands walk fewer cells
    /// twice; shorter ones keep a band's buffer in a smaller cache and
    /// share the work more evenly.
    #[arg(long, value_name = "ROWS", default_value_t = RenderOptions::DEFAULT_TILE_ROWS)]
    tile_rows: u32,
    /// Guard band beyond each viewport side, as a fraction of its size, 0..=1.
    #[arg(long, value_name = "FRACTION", default_value_t = RenderOptions::DEFAULT_GUARD_BAND)]
    guard_band: f32,
    /// Background colour r,g,b or r,g,b,a (0..=255); default transparent.
    #[arg(long, value_name = "R,G,B[,A]", value_parser = parse_colour)]
    background: Option<[u8; 4]>,
    /// Also write the depth: as 16-bit greyscale PNG (0 = no surface, else
    /// linear between near and far), or with --depth-format tiff|exr as a
    /// 32-bit float TIFF, or OpenEXR with one float channel `Z`, of eye
    /// depth in model units (NaN = no surface) with the camera in FILE's
    /// name with extension `camera.json`.
    #[arg(long, value_name = "FILE")]
    depth: Option<PathBuf>,
    /// Depth file format [default: tiff for a .tif/.tiff name, exr for a
    /// .exr name, else png].
    #[arg(long, value_enum, requires = "depth")]
    depth_format: Option<DepthFormatArg>,
    /// Also write statistics as JSON, with the cost of the shortcuts
    /// (trilinear vs exact, bilinear vs smooth, trimmed vs kept overlaps:
    /// time and PSNR), each band's work and time, and how much of the
    /// drawing ends up hidden (occlusion). Only with --stats or --json does
    /// a Phong frame count its normal-buffer lookups (`normals_needed`,
    /// `normals_computed_*`; 0 otherwise).
    #[arg(long, value_name = "FILE")]
    stats: Option<PathBuf>,
    /// Render N frames after a warm-up and print median and min ms per
    /// frame and per stage.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    bench: Option<u32>,
    /// Time the planning's stages in every frame (cull, split, traverse,
    /// normals, triangle set-up: the *_cpu planning rows of --bench and
    /// those times in --json). On with --stats, off otherwise: three clock
    /// reads per drawn patch cost about 1.5 % of a 500² bunny frame. The
    /// frame's walls and the bands' cells, triangles and resolve times are
    /// measured either way.
    #[arg(long)]
    stage_times: bool,
    /// Print a report (docs/report-schema.md: the scene's counts, stages, the frame's
    /// statistics, camera and --bench timings in `details`) as one JSON object on
    /// standard output instead of the summary; refused with `-o -`.
    #[arg(long)]
    json: bool,
}

/// Converts the arguments into the library's options (one place).
fn render_options(args: &RenderArgs) -> RenderOptions {
    let mut o = RenderOptions::default();
    o.mode = args.mode.into();
    o.projection = args.projection.into();
    o.cells = args.cells.into();
    args.shading.apply(&mut o);
    o.culling = args.cull.into();
    o.threads = args.threads.count();
    o.ssaa = args.ssaa;
    o.mip = !args.no_mip;
    o.simd = !args.no_simd;
    o.exact_outlines = args.exact_outlines;
    o.exact_grid_outlines = !args.no_exact_grid_outlines;
    o.occlusion_skip = args.occlusion_skip;
    o.gap_fill = args.gap_fill;
    o.mip_limit = args.mip_limit;
    o.mip_tolerance = args.mip_tolerance;
    o.level_one_limit = args.level_one_limit;
    o.splat_limit = args.splat_limit;
    o.geometry_limit = args.geometry_limit;
    o.geometry_tolerance = args.geometry_tolerance;
    o.centre_limit = args.centre_limit;
    o.guard_band = args.guard_band;
    o.tile_rows = args.tile_rows;
    // Only --stats and --json show the normal-buffer counts.
    o.normal_counts = args.stats.is_some() || args.json;
    o.stage_times = args.stage_times || args.stats.is_some();
    if let Some(bg) = args.background {
        o.background = bg;
    }
    o
}

/// The camera from the flags; missing parts frame the scene.
fn camera(args: &RenderArgs, sphere: Option<(DVec3, f64)>) -> Result<Camera, RenderError> {
    let (centre, radius) = sphere.unwrap_or((DVec3::ZERO, 1.0));
    let target = args.target.unwrap_or(centre);
    let eye = match args.eye {
        Some(eye) => eye,
        None => Camera::framing(
            target,
            radius + (target - centre).length(),
            args.fov,
            args.width,
            args.height,
        )?
        .eye(),
    };
    Ok(
        Camera::look_at(eye, target, args.up, args.fov, args.width, args.height)?
            .with_clip_planes(args.near, args.far)?,
    )
}

/// A bounding sphere: centre and radius.
type Sphere = (DVec3, f64);

/// The scene to draw and its container: a `.spatch` file, or the tiles of an index in
/// the camera's view (with the index's bounding sphere, which frames the camera).
fn read_input(args: &RenderArgs) -> anyhow::Result<(Scene, ContainerInfo, Option<Sphere>)> {
    use super::tiled_scene::{index_sphere, is_index, read_visible_tiles};
    if !is_index(&args.input) {
        if args.coarse {
            anyhow::bail!("--coarse needs a tiled scene's index.json");
        }
        let (scene, info) = read_spatch(&args.input)?;
        return Ok((scene, info, None));
    }
    let index = spatch_tiling::SceneIndex::read(&args.input).map_err(anyhow::Error::msg)?;
    let sphere = index_sphere(&index);
    let view = camera(args, sphere).map_err(render_failure)?;
    let far_enough = match (&index.coarse, &index.bounds) {
        (Some(level), Some(bounds)) => level.fine_enough(
            bounds,
            view.eye(),
            view.fov_y_degrees(),
            view.height().saturating_mul(args.ssaa.max(1)),
        ),
        _ => false,
    };
    if args.coarse || far_enough {
        if far_enough && !crate::progress::is_quiet() {
            eprintln!("drew the coarse level (its cells are under a pixel from this eye)");
        }
        let path = index.coarse_path(&args.input).with_context(|| {
            format!(
                "{}: no coarse level (run `spatch index PLAN DIR` to write one)",
                args.input.display()
            )
        })?;
        let (scene, info) = read_spatch(&path)?;
        return Ok((scene, info, sphere));
    }
    let tiles = read_visible_tiles(&args.input, &index, &view, args.far)?;
    let info = tiles
        .info
        .with_context(|| format!("{}: no tile in view", args.input.display()))?;
    eprintln_tiles(tiles.loaded, tiles.total);
    Ok((tiles.scene, info, sphere))
}

/// Notes on standard error how many tiles of an index were read (unless quiet).
fn eprintln_tiles(loaded: usize, total: usize) {
    if !crate::progress::is_quiet() {
        eprintln!("read {loaded} of {total} tiles (the others are out of view)");
    }
}

/// `scene` prepared on `renderer`'s threads, its overlaps trimmed when
/// `trim` says.
fn prepare(renderer: &Renderer, scene: &Scene, trim: bool) -> PreparedScene {
    if trim {
        renderer.prepare_trimming_overlaps(scene)
    } else {
        renderer.prepare(scene)
    }
}

/// A scene read, prepared and rendered once: what the later steps of
/// [`run`] (benchmark, files, report) work from.
struct Session {
    renderer: Renderer,
    prepared: PreparedScene,
    /// The scene as read, kept for `--stats`' second preparation and never
    /// freed (see [`prepare_scene`]).
    kept: Option<ManuallyDrop<Scene>>,
    camera: Camera,
    out: RenderOutput,
    /// The report's scene counts and diagonal (`--json` only).
    counts: Option<(Counts, Option<f64>)>,
}

/// Reads, prepares and renders the scene of `args`, timing each step
/// into `stages`.
fn render_once(
    args: &RenderArgs,
    progress: &Progress,
    stages: &mut Stages,
) -> anyhow::Result<Session> {
    let started = Instant::now();
    progress.step("read");
    let (scene, info, index_sphere) = read_input(args)?;
    stages.push("read", started.elapsed().as_secs_f64());
    // What the report says of the scene, found while it is whole.
    let counts = args
        .json
        .then(|| (Counts::of(&scene, info.file_len), scene_diagonal(&scene)));
    let mut renderer = Renderer::new(render_options(args)).map_err(render_failure)?;
    progress.step("prepare");
    let clock = Instant::now();
    let (prepared, kept) = prepare_scene(&renderer, scene, args);
    stages.push("prepare", clock.elapsed().as_secs_f64());
    let sphere = index_sphere.or_else(|| prepared.bounding_sphere());
    let camera = camera(args, sphere).map_err(render_failure)?;
    progress.step("render");
    let clock = Instant::now();
    let out = renderer
        .render(&prepared, &camera)
        .map_err(render_failure)?;
    stages.push("render", clock.elapsed().as_secs_f64());
    Ok(Session {
        renderer,
        prepared,
        kept,
        camera,
        out,
        counts,
    })
}

/// `scene` prepared for `args`, and the scene itself when `--stats` needs
/// it again. `--stats` prepares the scene a second time (the other
/// overlap setting), so it keeps the scene; otherwise the preparation
/// takes the scene's nodes instead of copying them. What is kept is left
/// to the OS at exit, not freed patch by patch (0.5 M of a one-frame bunny
/// render's 182 M instructions; callgrind).
fn prepare_scene(
    renderer: &Renderer,
    scene: Scene,
    args: &RenderArgs,
) -> (PreparedScene, Option<ManuallyDrop<Scene>>) {
    if args.stats.is_some() {
        let prepared = prepare(renderer, &scene, args.trim_overlaps);
        (prepared, Some(ManuallyDrop::new(scene)))
    } else {
        (renderer.prepare_owned(scene, args.trim_overlaps), None)
    }
}

/// `--bench`: `frames` frames of the session's view, timed.
fn bench_frames(
    session: &mut Session,
    frames: usize,
    progress: &Progress,
    stages: &mut Stages,
) -> anyhow::Result<BenchReport> {
    progress.step("bench");
    let clock = Instant::now();
    let Session {
        renderer,
        prepared,
        camera,
        ..
    } = session;
    let report = bench(renderer, prepared, camera, frames, &|k| {
        progress.count(k, frames)
    })?;
    stages.push("bench", clock.elapsed().as_secs_f64());
    Ok(report)
}

/// The `--stats` file of `session`: the frame's statistics and what its
/// shortcuts cost, measured against the other overlap setting.
fn stats_bytes(args: &RenderArgs, session: &Session) -> anyhow::Result<Vec<u8>> {
    let Session {
        renderer, prepared, ..
    } = session;
    let scene = session.kept.as_ref().expect("kept for --stats");
    let other = prepare(renderer, scene, !args.trim_overlaps);
    let overlaps = if args.trim_overlaps {
        (prepared, &other)
    } else {
        (&other, prepared)
    };
    let options = renderer.options();
    let shortcuts = measure_shortcuts(prepared, Some(overlaps), &session.camera, options, 3)
        .map_err(render_failure)?;
    stats_file_bytes(StatsFile {
        stats: &session.out.stats,
        input: args.input.display().to_string(),
        overlap_cells_trimmed: prepared.trimmed_cells(),
        overlap_cells_trimmable: overlaps.0.trimmed_cells(),
        camera: CameraJson::of(&session.camera),
        shortcuts,
        occlusion: renderer.occlusion(),
    })
}

/// Every file `args` asks for, encoded from `session`: the PNG, the depth
/// file (and its camera) and the `--stats` file.
fn encoded_files(
    args: &RenderArgs,
    session: &Session,
    progress: &Progress,
    stages: &mut Stages,
) -> anyhow::Result<Vec<(PathBuf, Vec<u8>)>> {
    progress.step("encode");
    let clock = Instant::now();
    let depth = args.depth.as_deref();
    let depth = depth.map(|path| (path, depth_format(args.depth_format, path)));
    let output = args.output.as_deref();
    let mut files = image_files(output, depth, &session.camera, &session.out.image)?;
    stages.push("encode", clock.elapsed().as_secs_f64());
    if let Some(path) = &args.stats {
        progress.step("shortcuts");
        let clock = Instant::now();
        files.push((path.clone(), stats_bytes(args, session)?));
        stages.push("shortcuts", clock.elapsed().as_secs_f64());
    }
    Ok(files)
}

/// Renders (and benchmarks) the scene and writes the requested files.
pub(crate) fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let steps = 5 + usize::from(args.bench.is_some()) + usize::from(args.stats.is_some());
    let progress = Progress::new("render", steps);
    let mut stages = Stages::default();
    let mut session = render_once(args, &progress, &mut stages)?;
    let bench = match args.bench {
        Some(frames) => Some(bench_frames(
            &mut session,
            frames as usize,
            &progress,
            &mut stages,
        )?),
        None => None,
    };
    // Encode everything first, so a failure leaves no output behind.
    let files = encoded_files(args, &session, &progress, &mut stages)?;
    progress.step("write");
    let clock = Instant::now();
    for (path, bytes) in &files {
        write_output(path, bytes)?;
    }
    stages.push("write", clock.elapsed().as_secs_f64());
    drop(progress);
    let threads = session.renderer.threads();
    let Session {
        renderer,
        prepared,
        camera,
        out,
        counts,
        ..
    } = session;
    // The process ends after this command: the prepared scene and the
    // renderer are left to the OS instead of freed piece by piece (so is
    // the scene read, see `prepare_scene`). Why: freeing every patch's
    // levels cost 7 M of the 265 M instructions of a one-frame bunny
    // render (callgrind, `spatch render bunny.spatch -o out.png --threads
    // 1`).
    std::mem::forget(prepared);
    std::mem::forget(renderer);
    let output = args.output.as_deref();
    if args.json {
        let details = RenderDetails {
            stats: &out.stats,
            camera: CameraJson::of(&camera),
            bench,
        };
        let paths = (args.input.as_path(), output);
        return print_json(&render_report(paths, details, counts, stages, threads));
    }
    print_result(output, &out.stats, bench.as_ref())
}

impl RenderArgs {
    /// The format `--depth` is written in.
    fn depth_written(&self) -> crate::overwrite_guard::Written {
        use crate::overwrite_guard::Written;
        let path = self.depth.as_deref().unwrap_or(std::path::Path::new(""));
        match depth_format(self.depth_format, path) {
            DepthFormatArg::Tiff => Written::Tiff,
            DepthFormatArg::Exr => Written::Exr,
            DepthFormatArg::Png => Written::Png,
        }
    }

    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .input(Some(&self.input))
            .output_as(self.output.as_deref(), Written::Png)
            .output_as(self.depth.as_deref(), self.depth_written())
            .output_as(self.stats.as_deref(), Written::Json)
            .json_on_stdout(self.json)
    }
}
