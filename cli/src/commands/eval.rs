//! `spatch eval`: a scene against its source (error and time), or a sweep of settings with
//! an error-versus-time plot.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use serde_json::{json, Value};
use spatch_eval::sweep::{Width, SWEEP_CSV_COLUMNS};
use spatch_eval::{
    evaluate, load_source, per_patch_csv, run_sweep, sweep_csv, sweep_svg, views_for_count, Counts,
    EvalError, EvalOptions, Evaluation, ImageOptions, LoadedSource, PatchError, Report, Source,
    SweepOptions, SweepResult, MAX_VIEWS,
};
use spatch_render::RenderOptions;

use super::render_values::{CellsArg, CullArg, ModeArg, ProjectionArg, ShadingArg};
use super::ThreadsArg;
use crate::failure::InternalFailure;
use crate::output::{print_json, print_summary, read_spatch, write_json_report, write_output};
use crate::progress::Progress;
use crate::report::{new_report, set_detail, tool};

/// Default number of views of `spatch eval` (the 6 axes and 8 diagonals).
const EVAL_VIEWS: usize = 14;
/// Default number of views of the sweep's render rows (the 6 axes).
const SWEEP_VIEWS: usize = 6;
/// Patches listed as the worst in the report and the summary.
const WORST_LISTED: usize = 5;

/// Arguments of `spatch eval`.
#[derive(Debug, clap::Args)]
pub(crate) struct EvalArgs {
    /// The .spatch scene to measure (not with --sweep).
    #[arg(
        value_name = "SCENE",
        required_unless_present = "sweep",
        conflicts_with = "sweep"
    )]
    scene: Option<PathBuf>,
    /// The source the scene was made from: a mesh (.obj, .gltf, .glb, .ply, .off, .stl) or a point
    /// cloud (.xyz, .txt, .pts, or a .ply without faces). A source that does not overlap the
    /// scene (bounding boxes apart even when each is grown by 1 % of the larger diagonal) is
    /// refused before anything is measured.
    #[arg(
        long,
        value_name = "MESH|CLOUD",
        required_unless_present = "sweep",
        conflicts_with = "sweep"
    )]
    source: Option<PathBuf>,
    /// Views of the image error: 1-14 take the standard views in order (6 axes, then 8
    /// diagonals), more are spread evenly (up to 256) [default: 14; 6 with --sweep].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=MAX_VIEWS as i64))]
    views: Option<u16>,
    /// Side of the square images of the image error, in pixels (16-4096).
    #[arg(long, value_name = "PX", default_value_t = 500, value_parser = clap::value_parser!(u32).range(16..=4096))]
    size: u32,
    /// Timed frames per view (after one warm-up), of the patches and of the source mesh alike;
    /// the medians are reported (1-100).
    #[arg(long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    runs: u32,
    /// Patches, or every cell as two triangles through the scan-line rasterizer (the
    /// baseline the patch renders' specks and times compare with; not with --sweep).
    #[arg(long, value_enum, default_value_t = ModeArg::Patches, conflicts_with = "sweep")]
    mode: ModeArg,
    /// Back-face culling of the patch renders, as `spatch render --cull` (the source is
    /// culled only where it is closed, whatever this says; not with --sweep).
    #[arg(long, value_enum, default_value_t = CullArg::Auto, conflicts_with = "sweep")]
    cull: CullArg,
    /// Node projection of the patch renders (not with --sweep, which tries both).
    #[arg(long, value_enum, default_value_t = ProjectionArg::Trilinear, conflicts_with = "sweep")]
    projection: ProjectionArg,
    /// Cell filling of the patch renders (not with --sweep, which tries both).
    #[arg(long, value_enum, default_value_t = CellsArg::Bilinear, conflicts_with = "sweep")]
    cells: CellsArg,
    /// Shading of both the source and the patch renders (not with --sweep); `unlit` compares
    /// the albedo alone (colour and texture, no light), as `spatch render --shading unlit`.
    #[arg(long, value_enum, default_value_t = ShadingArg::Phong, conflicts_with = "sweep")]
    shading: ShadingArg,
    /// Draw coloured patches' cells by pixel-centre coverage, as `spatch
    /// render --exact-outlines`.
    #[arg(long, conflicts_with = "sweep")]
    exact_outlines: bool,
    /// Let the cells of patches with a colour grid reach about half a pixel
    /// past the outline (sub-nodes) instead of the default pixel-centre
    /// coverage: fuze, unlit, 30.3 -> 27.9 dB against its source. Scenes
    /// without colour grids draw the same either way.
    #[arg(long)]
    no_exact_grid_outlines: bool,
    /// Draw the patches with the gap fill, as `spatch render --gap-fill`.
    #[arg(long, conflicts_with = "sweep")]
    gap_fill: bool,
    /// Splat limit of the patch renders in pixels (see `spatch render
    /// --splat-limit`; 0 = off, the default; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_SPLAT_LIMIT, conflicts_with = "sweep")]
    splat_limit: f32,
    /// Geometry limit of the patch renders in pixels (see `spatch render
    /// --geometry-limit`; 0 = off, the default; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_GEOMETRY_LIMIT, conflicts_with = "sweep")]
    geometry_limit: f32,
    /// Geometry tolerance of the patch renders in node spacings (see
    /// `spatch render --geometry-tolerance`; 0 = none, the default).
    #[arg(long, value_name = "T", default_value_t = RenderOptions::DEFAULT_GEOMETRY_TOLERANCE, conflicts_with = "sweep")]
    geometry_tolerance: f32,
    /// Mip limit of the patch renders in pixels (see `spatch render
    /// --mip-limit`; 0.1..=16, default 3; not with --sweep): what a
    /// coarser level costs in PSNR and holes.
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_MIP_LIMIT, conflicts_with = "sweep")]
    mip_limit: f32,
    /// Mip tolerance of the patch renders in pixels (see `spatch render
    /// --mip-tolerance`; 0..=2, default 0.25, 0 = off; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_MIP_TOLERANCE, conflicts_with = "sweep")]
    mip_tolerance: f32,
    /// Level-one limit of the patch renders in pixels (see `spatch render
    /// --level-one-limit`; 0 = off, the default; not with --sweep).
    #[arg(
        long,
        value_name = "PX",
        default_value_t = 0.0,
        conflicts_with = "sweep"
    )]
    level_one_limit: f32,
    /// Centre limit of the patch renders in pixels (see `spatch render
    /// --centre-limit`; 0 = off; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_CENTRE_LIMIT, conflicts_with = "sweep")]
    centre_limit: f32,
    /// Skip the image error (geometric error only).
    #[arg(long, conflicts_with = "sweep")]
    no_images: bool,
    /// Write the error of every patch as CSV (to find the worst patch).
    #[arg(long, value_name = "FILE", conflicts_with = "sweep")]
    per_patch: Option<PathBuf>,
    /// Print the JSON report (docs/report-schema.md) instead of the summary.
    #[arg(long, conflicts_with = "sweep")]
    json: bool,
    /// Also write the JSON report to this file.
    #[arg(long, value_name = "FILE", conflicts_with = "sweep")]
    report: Option<PathBuf>,
    #[command(flatten)]
    threads: ThreadsArg,
    /// Sweep conversion and render settings on this mesh, writing sweep.csv, sweep.json and
    /// sweep.svg (error against time, Pareto front marked) into --out.
    #[arg(long, value_name = "MESH", requires = "out")]
    sweep: Option<PathBuf>,
    /// Folder for the sweep's files (created if missing).
    #[arg(long, value_name = "DIR", requires = "sweep")]
    out: Option<PathBuf>,
    /// Sweep: grid sizes (nodes per patch side, 2-257).
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "5,9,17,33", requires = "sweep", value_parser = clap::value_parser!(u32).range(2..=257))]
    grids: Vec<u32>,
    /// Sweep: cone angles in degrees (0-89].
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "15,30,45", requires = "sweep", value_parser = cone_angle)]
    cone_angles: Vec<f32>,
    /// Sweep: displacement widths, 8 and/or 16.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "8,16", requires = "sweep", value_parser = width)]
    widths: Vec<u8>,
    /// Sweep: grids whose scenes the render settings (trilinear/exact x bilinear/smooth) are
    /// measured on; each must be one of --grids.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "9,17,33", requires = "sweep", value_parser = clap::value_parser!(u32).range(2..=257))]
    render_grids: Vec<u32>,
    /// Sweep: leave out the render rows.
    #[arg(long, requires = "sweep")]
    no_render: bool,
    /// Sweep: conversions per setting; the median time is kept (1-100).
    #[arg(long, value_name = "N", default_value_t = 3, requires = "sweep", value_parser = clap::value_parser!(u32).range(1..=100))]
    repeats: u32,
}

fn cone_angle(s: &str) -> Result<f32, String> {
    let v: f32 = s.trim().parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && v > 0.0 && v <= 89.0 {
        Ok(v)
    } else {
        Err("must be in (0, 89] degrees".to_owned())
    }
}

fn width(s: &str) -> Result<u8, String> {
    match s.trim() {
        "8" => Ok(8),
        "16" => Ok(16),
        _ => Err("must be 8 or 16".to_owned()),
    }
}

impl EvalArgs {
    /// The render options of the image error.
    fn render_options(&self) -> RenderOptions {
        let mut render = RenderOptions::default();
        render.mode = self.mode.into();
        render.culling = self.cull.into();
        render.projection = self.projection.into();
        render.cells = self.cells.into();
        self.shading.apply(&mut render);
        render.exact_outlines = self.exact_outlines;
        render.exact_grid_outlines = !self.no_exact_grid_outlines;
        render.gap_fill = self.gap_fill;
        render.threads = self.threads.count();
        render.splat_limit = self.splat_limit;
        render.geometry_limit = self.geometry_limit;
        render.geometry_tolerance = self.geometry_tolerance;
        render.centre_limit = self.centre_limit;
        render.mip_limit = self.mip_limit;
        render.mip_tolerance = self.mip_tolerance;
        render.level_one_limit = self.level_one_limit;
        // The eval times whole frames only: no clock reads per patch.
        render.stage_times = false;
        render
    }

    fn image_options(&self, default_views: usize) -> anyhow::Result<ImageOptions> {
        let count = self.views.map_or(default_views, usize::from);
        let mut image = ImageOptions::default();
        image.views = views_for_count(count)
            .ok_or_else(|| anyhow::anyhow!("--views must be in 1..={MAX_VIEWS}"))?;
        image.size = [self.size, self.size];
        image.render = self.render_options();
        image.runs = self.runs as usize;
        Ok(image)
    }

    fn sweep_options(&self) -> anyhow::Result<SweepOptions> {
        let mut options = SweepOptions::default();
        options.grids = self.grids.clone();
        options.cone_angles = self.cone_angles.clone();
        options.widths = self
            .widths
            .iter()
            .map(|&w| {
                if w == 16 {
                    Width::Sixteen
                } else {
                    Width::Eight
                }
            })
            .collect();
        options.render_grids = if self.no_render {
            Vec::new()
        } else {
            self.render_grids.clone()
        };
        options.image = self.image_options(SWEEP_VIEWS)?;
        options.repeats = self.repeats as usize;
        Ok(options)
    }
}

/// Runs `spatch eval`.
pub(crate) fn run(args: &EvalArgs) -> anyhow::Result<()> {
    args.threads.init()?;
    // A render option out of range is the user's (exit 2), said before any measuring.
    args.render_options().validate()?;
    match (&args.sweep, &args.out, &args.scene, &args.source) {
        (Some(mesh), Some(out), _, _) => sweep(args, mesh, out),
        (None, _, Some(scene), Some(source)) => eval(args, scene, source),
        _ => Err(anyhow::anyhow!(
            "give a scene and --source, or --sweep MESH --out DIR"
        )),
    }
}

/// Marks failures of spatch itself (rendering, plotting) as internal (exit code 1); the rest
/// is the input's (exit code 2).
fn classify(err: EvalError, context: &Path) -> anyhow::Error {
    match err {
        EvalError::Render(_) | EvalError::Plot(_) => {
            anyhow::Error::new(InternalFailure(format!("{}: {err}", context.display())))
        }
        // These already name their file.
        EvalError::Source(_)
        | EvalError::NoSurface { .. }
        | EvalError::Cloud { .. }
        | EvalError::NoOverlap { .. } => anyhow::Error::new(err),
        _ => anyhow::Error::new(err).context(format!("{}", context.display())),
    }
}

fn eval(args: &EvalArgs, scene_path: &Path, source_path: &Path) -> anyhow::Result<()> {
    let measured = measure(args, scene_path, source_path)?;
    let evaluation = &measured.evaluation;
    if let Some(path) = &args.per_patch {
        write_output(
            path,
            per_patch_csv(&evaluation.patches, evaluation.diagonal).as_bytes(),
        )?;
    }
    let report = eval_report(args, scene_path, source_path, &measured)?;
    if let Some(path) = &args.report {
        write_json_report(path, &report)?;
    }
    if args.json {
        return print_json(&report);
    }
    print_summary(
        &summary(args, scene_path, source_path, &report, evaluation),
        false,
    )
}

/// What `spatch eval` read and measured: the scene (of `bytes` bytes), the source, the
/// evaluation, and the seconds each read took.
struct Measured {
    scene: spatch_format::Scene,
    bytes: usize,
    loaded: LoadedSource,
    evaluation: Evaluation,
    load_seconds: f64,
    load_source_seconds: f64,
}

/// Reads the scene and the source and evaluates one against the other, each step shown on
/// the progress display.
fn measure(args: &EvalArgs, scene_path: &Path, source_path: &Path) -> anyhow::Result<Measured> {
    let progress = Progress::new("eval", 3);
    progress.step("reading the scene");
    let start = Instant::now();
    let (scene, _) = read_spatch(scene_path)?;
    let load_seconds = start.elapsed().as_secs_f64();
    let bytes = std::fs::metadata(scene_path)
        .with_context(|| format!("{}: cannot read", scene_path.display()))?
        .len() as usize;
    progress.step("reading the source");
    let start = Instant::now();
    let loaded = load_source(source_path).map_err(|e| classify(e, source_path))?;
    let load_source_seconds = start.elapsed().as_secs_f64();
    let mut options = EvalOptions::default();
    options.image = if args.no_images {
        None
    } else {
        Some(args.image_options(EVAL_VIEWS)?)
    };
    progress.step("measuring");
    let evaluation = evaluate(&scene, &loaded.source, source_path, &options)
        .map_err(|e| classify(e, scene_path))?;
    drop(progress);
    Ok(Measured {
        scene,
        bytes,
        loaded,
        evaluation,
        load_seconds,
        load_source_seconds,
    })
}

/// The JSON report of an evaluation of `scene_path` against `source_path`: counts, stage
/// times, error, warnings and details.
fn eval_report(
    args: &EvalArgs,
    scene_path: &Path,
    source_path: &Path,
    m: &Measured,
) -> anyhow::Result<Report<Value>> {
    let evaluation = &m.evaluation;
    let mut report = new_report("eval", &scene_path.display().to_string());
    report.output = args.per_patch.as_ref().map(|p| p.display().to_string());
    report.counts = Counts::of(&m.scene, m.bytes);
    report.stages.push("load", m.load_seconds);
    report
        .stages
        .push("prepare_render", evaluation.prepare_render_seconds);
    if let Some(image) = &evaluation.image {
        report.stages.push("render", image.patch_ms / 1e3);
    }
    report.seconds = report.stages.total();
    report
        .measure_stages
        .push("load_source", m.load_source_seconds);
    for (name, seconds) in &evaluation.stages {
        report.measure_stages.push(name, *seconds);
    }
    report.measure_seconds = report.measure_stages.total();
    report.threads = rayon::current_num_threads();
    report.diagonal = Some(evaluation.diagonal);
    report.error = evaluation.error.clone();
    report.warnings = m.loaded.warnings.clone();
    fill_details(&mut report, args, source_path, &m.loaded.source, evaluation)?;
    Ok(report)
}

/// The worst `WORST_LISTED` patches by `key` (largest first, then by index).
fn worst(patches: &[PatchError], key: impl Fn(&PatchError) -> f64) -> Vec<PatchError> {
    let mut rows = patches.to_vec();
    rows.sort_by(|a, b| key(b).total_cmp(&key(a)).then(a.patch.cmp(&b.patch)));
    rows.truncate(WORST_LISTED);
    rows
}

fn fill_details(
    report: &mut Report<Value>,
    args: &EvalArgs,
    source_path: &Path,
    source: &Source,
    e: &Evaluation,
) -> anyhow::Result<()> {
    set_detail(report, "source", &source_path.display().to_string())?;
    set_detail(report, "source_kind", &source.kind())?;
    set_detail(report, "source_samples", &e.source_samples)?;
    set_detail(report, "histograms", &e.histograms)?;
    set_detail(report, "quantization_bound", &e.bound)?;
    set_detail(
        report,
        "worst_patches",
        &json!({
            "by_node_max": worst(&e.patches, |p| p.node_max),
            "by_source_max": worst(&e.patches, |p| p.source_max),
        }),
    )?;
    let render = args.render_options();
    set_detail(
        report,
        "render",
        &json!({
            "mode": render.mode,
            "projection": render.projection,
            "cells": render.cells,
            "shading": render.shading,
            "lighting": render.lighting,
            "culling": render.culling,
            "prepare_seconds": e.prepare_render_seconds,
        }),
    )?;
    set_detail(report, "image", &e.image)?;
    set_detail(report, "image_note", &e.image_note)?;
    set_detail(report, "cloud", &e.cloud)?;
    Ok(())
}

fn pct(v: f64) -> String {
    format!("{:.4} %", v * 100.0)
}

/// The summary printed after an evaluation of `scene_path` against
/// `source_path`: counts, geometric error, worst patches, image error,
/// times and the files written.
fn summary(
    args: &EvalArgs,
    scene_path: &Path,
    source_path: &Path,
    report: &Report<Value>,
    e: &Evaluation,
) -> String {
    let c = &report.counts;
    let mut text = format!(
        "{} against {} ({}): {} patches, {} nodes ({} filled), {} bytes\n",
        scene_path.display(),
        source_path.display(),
        report.details["source_kind"].as_str().unwrap_or("source"),
        c.patches,
        c.nodes,
        c.filled_nodes,
        c.bytes
    );
    text.push_str(&error_lines(e));
    text.push_str(&worst_patch_lines(e));
    if let Some(image) = &e.image {
        text.push_str(&image_lines(args, image));
    }
    if let Some(note) = e.image_note {
        text.push_str(&format!("  note: {note}\n"));
    }
    if let Some(cloud) = &e.cloud {
        text.push_str(&format!(
            "  cloud spacing {:.4e}; {:.3} % of the points farther than 2 spacings from every patch\n",
            cloud.spacing,
            cloud.share_beyond_2x_spacing * 100.0
        ));
    }
    text.push_str(&time_and_file_lines(args, report));
    text
}

/// `v` (model units) as a share of the evaluation's diagonal (0 for an
/// empty one).
fn of_diagonal(e: &Evaluation, v: f64) -> f64 {
    if e.diagonal > 0.0 {
        v / e.diagonal
    } else {
        0.0
    }
}

/// The summary's geometric error: each measure's max, rms and p95, and
/// the quantization-only bound.
fn error_lines(e: &Evaluation) -> String {
    let mut text = format!("  error (% of the diagonal {:.6}):\n", e.diagonal);
    for (name, s) in &e.error {
        text.push_str(&format!(
            "    {name:<17} max {}  rms {}  p95 {}  ({} measured)\n",
            pct(s.max_rel),
            pct(s.rms_rel),
            pct(of_diagonal(e, s.p95)),
            s.samples
        ));
    }
    let b = &e.bound;
    let beyond = b.patches_beyond.map_or_else(
        || "not comparable to node-to-point distances".to_owned(),
        |n| format!("{n} patches beyond their own bound"),
    );
    text.push_str(&format!(
        "  quantization-only bound |az|/2: max {}, mean {}; {beyond}\n",
        pct(b.max_rel),
        pct(b.mean_rel),
    ));
    text
}

/// The summary's worst patches, by node error and by source-to-patch
/// error.
fn worst_patch_lines(e: &Evaluation) -> String {
    let mut text = String::new();
    if let Some(p) = worst(&e.patches, |p| p.node_max).first() {
        text.push_str(&format!(
            "  worst patch by node error: #{} ({} x {}, {}-bit), max {} (its |az|/2 {})\n",
            p.patch,
            p.cols,
            p.rows,
            p.bits,
            pct(of_diagonal(e, p.node_max)),
            pct(of_diagonal(e, p.quantization_bound))
        ));
    }
    if let Some(p) = worst(&e.patches, |p| p.source_max).first() {
        text.push_str(&format!(
            "  worst patch by source-to-patch error: #{}, max {} over {} samples\n",
            p.patch,
            pct(of_diagonal(e, p.source_max)),
            p.source_samples
        ));
    }
    text
}

/// The summary's image error: PSNR, holes, depth error, specks and the
/// frame times against the source's.
fn image_lines(args: &EvalArgs, image: &spatch_eval::ImageError) -> String {
    let psnr = image
        .psnr_db
        .map_or("identical".to_owned(), |p| format!("{p:.2} dB"));
    let covered = image
        .psnr_covered_db
        .map_or("identical".to_owned(), |p| format!("{p:.2} dB"));
    let options = args.render_options();
    let mut text = format!(
        "  image over {} views ({}x{}, {:?} mode, {:?} projection, {:?} cells, {:?} shading): PSNR {psnr} ({covered} where both cover), holes {} ({} inside the outlines), mean depth error {}\n",
        image.views.len(),
        image.size[0],
        image.size[1],
        options.mode,
        options.projection,
        options.cells,
        args.shading,
        pct(image.hole_fraction),
        pct(image.interior_hole_fraction),
        pct(image.mean_depth_error_rel),
    );
    text.push_str(&format!(
        "  specks: {} of the patches' pixels, {} of the source's (isolated dark pixels)\n",
        pct(image.speck_fraction),
        pct(image.source_speck_fraction),
    ));
    let drawn = match image.source_drawn_with {
        spatch_eval::SourceDrawing::Grey => "grey (no colour)",
        spatch_eval::SourceDrawing::Colours => "its vertex and material colours",
        spatch_eval::SourceDrawing::Texture => "its texture (sampled at ~2 texels per edge)",
        _ => "its colours",
    };
    text.push_str(&format!(
        "  render: {:.2} ms per frame (median), source triangles {:.2} ms, source drawn with {drawn}\n",
        image.patch_ms, image.source_ms
    ));
    text
}

/// The summary's times, warnings and the files written.
fn time_and_file_lines(args: &EvalArgs, report: &Report<Value>) -> String {
    let stages = |s: &spatch_eval::Stages| {
        s.0.iter()
            .map(|(n, v)| format!("{n} {:.0} ms", v * 1e3))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut text = format!(
        "  time ({} threads): {}; measuring {:.2} s ({})\n",
        report.threads,
        stages(&report.stages),
        report.measure_seconds,
        stages(&report.measure_stages)
    );
    for w in &report.warnings {
        text.push_str(&format!("  warning: {w}\n"));
    }
    if let Some(path) = &args.per_patch {
        text.push_str(&format!("  per-patch errors: {}\n", path.display()));
    }
    if let Some(path) = &args.report {
        text.push_str(&format!("  report: {}\n", path.display()));
    }
    text
}

fn sweep(args: &EvalArgs, mesh: &Path, out: &Path) -> anyhow::Result<()> {
    let options = args.sweep_options()?;
    std::fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create the output folder", out.display()))?;
    let progress = Progress::new("sweep", 1);
    let result =
        run_sweep(mesh, &options, &|step| progress.step(step)).map_err(|e| classify(e, mesh))?;
    drop(progress);
    let name = mesh.file_name().map_or_else(
        || mesh.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let svg = sweep_svg(&result, &format!("spatch eval --sweep {name}"))
        .map_err(|e| classify(e, mesh))?;
    let json = sweep_json(mesh, out, &result)?;
    write_output(&out.join("sweep.csv"), sweep_csv(&result).as_bytes())?;
    write_json_report(&out.join("sweep.json"), &json)?;
    write_output(&out.join("sweep.svg"), svg.as_bytes())?;
    print_summary(&sweep_summary(out, &result), false)
}

/// sweep.json: the shared header keys that apply to a sweep, then the sweep itself.
fn sweep_json(mesh: &Path, out: &Path, result: &SweepResult) -> anyhow::Result<Value> {
    let mut value = serde_json::to_value(result)
        .map_err(|e| InternalFailure(format!("cannot format the sweep: {e}")))?;
    if let Value::Object(map) = &mut value {
        map.insert("schema".to_owned(), json!(spatch_eval::REPORT_SCHEMA));
        map.insert("tool".to_owned(), json!(tool()));
        map.insert("command".to_owned(), json!("eval --sweep"));
        map.insert("input".to_owned(), json!(mesh.display().to_string()));
        map.insert("output".to_owned(), json!(out.display().to_string()));
        map.insert("columns".to_owned(), json!(SWEEP_CSV_COLUMNS));
    }
    Ok(value)
}

fn sweep_summary(out: &Path, result: &SweepResult) -> String {
    let conversions = result.rows.iter().filter(|r| r.render_ms.is_none()).count();
    let mut text = format!(
        "sweep: {} conversion rows, {} render rows in {:.1} s ({} threads); {} samples per error\n",
        conversions,
        result.rows.len() - conversions,
        result.seconds,
        result.threads,
        result.samples
    );
    text.push_str("  Pareto front, conversion (seconds, surface_to_patch rms % of diagonal):\n");
    for r in result
        .rows
        .iter()
        .filter(|r| r.on_front && r.render_ms.is_none())
    {
        text.push_str(&format!(
            "    {:<30} {:>7.3} s  {:.5} %  {} patches, {} bytes\n",
            r.label(),
            r.convert_seconds,
            r.surface_to_patch.rms_rel * 100.0,
            r.counts.patches,
            r.counts.bytes
        ));
    }
    if conversions < result.rows.len() {
        text.push_str("  Pareto front, rendering (ms per frame, PSNR):\n");
        for r in result
            .rows
            .iter()
            .filter(|r| r.on_front && r.render_ms.is_some())
        {
            let psnr = r
                .image
                .and_then(|i| i.psnr_db)
                .map_or("identical".to_owned(), |p| format!("{p:.2} dB"));
            text.push_str(&format!(
                "    {:<50} {:>8.2} ms  {psnr}\n",
                r.label(),
                r.render_ms.unwrap_or(0.0)
            ));
        }
    }
    text.push_str(&format!(
        "  wrote {0}/sweep.csv, {0}/sweep.json, {0}/sweep.svg\n",
        out.display()
    ));
    text
}

impl EvalArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .input(self.scene.as_deref())
            .input(self.source.as_deref())
            .input(self.sweep.as_deref())
            .output_as(self.per_patch.as_deref(), Written::Csv)
            .output_as(self.report.as_deref(), Written::Json)
            .json_on_stdout(self.json)
    }
}
