//! `spatch from-cloud`: point clouds and scan sets (PLY, XYZ, PTS, Stanford `.conf`) to
//! patches through range images.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use serde_json::{json, Value};
use spatch_cloud::{
    cloud_to_scene_owned, cloud_to_scene_with_progress, measure_cloud_error_in_order,
    CloudConversion, CloudError, CloudErrorReport, CloudOptions, CloudReport, ProgressFn,
    SmoothOptions, StageTime,
};
use spatch_eval::{cloud_error_entries, Report};
use spatch_format::WriteOptions;
use spatch_mesh::load::xyz::XyzLayout;
use spatch_mesh::PointCloud;
use spatch_scan::{load_scans, parse_columns, LoadedScans, ScanOptions, ScanWarning};

use super::cloud_progress::CloudSteps;
use super::cloud_scanners::scanners_of;
use super::ThreadsArg;
use crate::failure::InternalFailure;
use crate::output::{print_json, print_summary, write_json_report, write_output};
use crate::progress::Progress;
use crate::report::{details_from, new_report, set_detail, stages_from};

/// Whether `spatch from-cloud` uses where structured scans' scanners were.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum RangeGridUse {
    /// Normals turned toward each point's scanner; views draw and cover the points facing them.
    On,
    /// Normals used up to sign.
    Off,
}

/// An on/off choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Switch {
    /// On.
    On,
    /// Off.
    Off,
}

/// Which points `spatch from-cloud` measures its error against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum ErrorAgainst {
    /// The points as read from the inputs.
    Given,
    /// The points with each scan moved by its alignment shift.
    Aligned,
}

impl ErrorAgainst {
    /// The report's name.
    fn name(self) -> &'static str {
        match self {
            ErrorAgainst::Given => "given",
            ErrorAgainst::Aligned => "aligned",
        }
    }
}

/// Arguments of `spatch from-cloud`.
#[derive(Debug, clap::Args)]
pub(crate) struct FromCloudArgs {
    /// Input point clouds, converted together in one frame: .ply (ASCII or binary, optional
    /// colours and normals), .xyz/.txt/.pts text (see --columns; Leica .pts may start with its
    /// point count), .las/.laz (LAS 1.0-1.4), .e57 (every scan, each with its pose), or a
    /// Stanford .conf scan set (each `bmesh FILE tx ty tz qx qy qz qw` line is a scan and its
    /// pose; files relative to the .conf). Colours are kept where present; a file with
    /// intensity but no colour shows its intensity as grey.
    #[arg(value_name = "CLOUD", required = true, num_args = 1..)]
    inputs: Vec<PathBuf>,
    /// What each column of .xyz/.txt/.pts inputs holds, comma separated: x y z, nx ny nz,
    /// r g b, a, intensity, skip (e.g. `x,y,z,nx,ny,nz,r,g,b`). Default: a header line
    /// (CloudCompare's `//X Y Z R G B`, or names alone) when there is one, else guessed from
    /// the number of columns.
    #[arg(long, value_name = "LAYOUT", value_parser = parse_layout)]
    columns: Option<XyzLayout>,
    /// Output .spatch file (`-`: standard output).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print the report (the --report JSON, docs/report-schema.md) as one object on
    /// standard output instead of the summary; refused with `-o -`.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    threads: ThreadsArg,
    /// Also write a JSON report (counts, stage times and the cloud error; the shape of
    /// docs/report-schema.md) to this file.
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Measure the error (cloud to patch, node to cloud) even without --report or --json.
    #[arg(long)]
    error: bool,
    /// Number of view directions, spread evenly over the sphere (1..=1000).
    #[arg(long, default_value_t = CloudOptions::DEFAULT_VIEWS)]
    views: usize,
    /// Pixel (node) spacing in multiples of the point spacing (0.25..=16): smaller keeps
    /// more detail and costs more nodes.
    #[arg(long, default_value_t = CloudOptions::DEFAULT_PIXEL_FACTOR)]
    pixel_factor: f32,
    /// Widest sampling gap filled by interpolation, in pixels (0..=8).
    #[arg(long, default_value_t = CloudOptions::DEFAULT_MAX_GAP)]
    max_gap: u32,
    /// Depth step between neighbouring pixels that counts as a discontinuity, in pixels.
    #[arg(long, default_value_t = CloudOptions::DEFAULT_JUMP_FACTOR)]
    jump: f32,
    /// Steepest surface (degrees from the view direction) taken in the first pass.
    #[arg(long, default_value_t = CloudOptions::DEFAULT_PREFERRED_SLOPE)]
    preferred_slope: f32,
    /// Steepest surface (degrees) taken in the second pass.
    #[arg(long, default_value_t = CloudOptions::DEFAULT_MAX_SLOPE)]
    max_slope: f32,
    /// Distance (in point spacings) within which a patch covers a point.
    #[arg(long, default_value_t = CloudOptions::DEFAULT_COVER_TOLERANCE)]
    cover_tolerance: f32,
    /// Smooth the range images with an edge-preserving (bilateral) filter: for noisy scans.
    #[arg(long)]
    smooth: bool,
    /// Smoothing radius in pixels (1..=8), with --smooth.
    #[arg(long, default_value_t = SmoothOptions::DEFAULT_RADIUS, requires = "smooth")]
    smooth_radius: u32,
    /// Smoothing passes (1..=8), with --smooth.
    #[arg(long, default_value_t = SmoothOptions::DEFAULT_ITERATIONS, requires = "smooth")]
    smooth_iterations: u32,
    /// Most nodes per patch side (2..=257): each region of a view's range image becomes one patch when it fits, else it is halved until the pieces do.
    #[arg(long, default_value_t = CloudOptions::DEFAULT_GRID)]
    grid: u32,
    /// Point spacing in model units (default: estimated from 12 nearest neighbours).
    #[arg(long)]
    spacing: Option<f32>,
    /// Voxel side for PCA normals when the file has none, in point spacings (0.5..=8).
    #[arg(long, default_value_t = CloudOptions::DEFAULT_NORMAL_VOXEL)]
    normal_voxel: f32,
    /// Do not move the points onto their local plane before drawing the
    /// range images. When the inputs hold several scans (a pose file, several
    /// files, an E57 of several scans), overlapping scans are first merged into
    /// one surface (each point onto the least-squares plane of its voxel block,
    /// except at creases and thin parts), which removes the specks and
    /// z-fighting of registered scan sets.
    #[arg(long)]
    no_consensus: bool,
    /// Merge overlapping points into one surface even when the inputs hold a
    /// single scan (see --no-consensus; it can flatten fine detail of a clean
    /// single cloud).
    #[arg(long, conflicts_with = "no_consensus")]
    consensus: bool,
    /// Structured scans (a PLY `range_grid` element, an E57 scan with row and column
    /// indices) say where their scanner was. `on`: when every input scan is structured and
    /// has no normals of its own, each point's estimated normal is turned toward the
    /// scanner that saw it and each view draws and covers only the points facing it, so the two sides
    /// of a thin part seen by different scans are not averaged together (fewer specks and
    /// holes on the bunny scans). `off`: normals are used up to sign, as for any cloud.
    #[arg(long, value_enum, value_name = "WHEN", default_value_t = RangeGridUse::On)]
    range_grid: RangeGridUse,
    /// With --range-grid on and the consensus on (several scans): `on` moves each scan by
    /// the translation that best puts its points on the planes of all scans before they are
    /// merged into one surface (the rigid part of their misregistration; fewer specks).
    /// `off` merges the scans as registered.
    #[arg(long, value_enum, value_name = "WHEN", default_value_t = Switch::On)]
    align_scans: Switch,
    /// Which points the error (--report, --error) is measured against when the scans were
    /// aligned: `given`, the points as read (their misregistration counts as error), or
    /// `aligned`, each scan moved by its translation (the report's `scan_shifts`), the
    /// surface the patches were made from.
    #[arg(long, value_enum, value_name = "POINTS", default_value_t = ErrorAgainst::Given)]
    error_against: ErrorAgainst,
    /// Compress node data (grid prediction + range coding).
    #[arg(long)]
    compress: bool,
    /// Side of the spatial tiles, in model units: each tile gets its own range images
    /// (with a 16-pixel buffer so no seam opens), so memory follows the points. Default:
    /// one tile when the whole cloud's images fit the pixel budget (16 M pixels), else
    /// tiles sized to that budget.
    #[arg(long, value_name = "SIZE")]
    tile_size: Option<f32>,
    /// When a tile's range images would exceed the pixel budget (a --tile-size too large
    /// for the spacing), enlarge its pixel with a warning. Without it the run fails (exit 2)
    /// rather than lose resolution silently.
    #[arg(long)]
    allow_coarsening: bool,
    /// Convert with a tile plan (`spatch plan`, docs/scale.md): with --tile K only tile K
    /// (its own points and its buffer's, read as a stream) to -o FILE; without, every tile
    /// on this machine to the folder -o DIR (tile_00000.spatch, ...) and DIR/index.json.
    /// A .conf or .e57 scan set is tiled in its common frame (each scan by its pose).
    #[arg(long, value_name = "PLAN", conflicts_with_all = ["json", "report", "error", "tile_size"])]
    plan: Option<PathBuf>,
    /// The tile of --plan to convert (its index in the plan).
    #[arg(long, value_name = "K", requires = "plan")]
    tile: Option<usize>,
    /// Plan tiles of SIZE model units (as `spatch plan --tile SIZE`, written as
    /// DIR/plan.json), then convert every tile on this machine to the folder -o DIR.
    #[arg(long, value_name = "SIZE", conflicts_with_all = ["plan", "json", "report", "error", "tile_size"])]
    plan_tile: Option<f64>,
}

impl FromCloudArgs {
    /// How to read the inputs.
    fn scan_options(&self) -> ScanOptions {
        let mut options = ScanOptions::default();
        options.columns = self.columns.clone();
        options.ignore_range_grids = self.range_grid == RangeGridUse::Off;
        options
    }

    /// The inputs for messages: the one file, or the first and how many more.
    fn input_label(&self) -> String {
        match self.inputs.as_slice() {
            [one] => one.display().to_string(),
            [first, rest @ ..] => format!("{} (+{} more)", first.display(), rest.len()),
            [] => String::new(),
        }
    }

    /// The library options these arguments ask for.
    fn options(&self) -> CloudOptions {
        let mut options = CloudOptions::default();
        options.views = self.views;
        options.pixel_factor = self.pixel_factor;
        options.max_gap = self.max_gap;
        options.jump_factor = self.jump;
        options.preferred_slope_degrees = self.preferred_slope.min(self.max_slope);
        options.max_slope_degrees = self.max_slope;
        options.cover_tolerance = self.cover_tolerance;
        options.smooth = self.smooth.then(|| {
            let mut smooth = SmoothOptions::default();
            smooth.radius = self.smooth_radius;
            smooth.iterations = self.smooth_iterations;
            smooth
        });
        options.grid = self.grid;
        options.spacing = self.spacing;
        options.normal_voxel = self.normal_voxel;
        options.write = WriteOptions::with_compression(super::compression(self.compress));
        options.tile_size = self.tile_size;
        options.allow_coarsening = self.allow_coarsening;
        options.align_scans = self.align_scans == Switch::On;
        options
    }
}

/// Stages the cloud pipeline reports at most (docs/report-schema.md: filter to encode).
const CLOUD_STAGES: usize = 9;

/// Converts the loaded `cloud`, reporting through `on_progress`: the
/// conversion, and the cloud itself when the error is to be measured
/// (`measure`; without it the cloud is not needed after its sorted copy).
fn convert_cloud(
    cloud: PointCloud,
    options: &CloudOptions,
    measure: bool,
    on_progress: ProgressFn<'_>,
    label: &str,
) -> anyhow::Result<(CloudConversion, Option<PointCloud>)> {
    let (converted, kept) = if measure {
        let converted = cloud_to_scene_with_progress(&cloud, options, on_progress);
        (converted, Some(cloud))
    } else {
        (cloud_to_scene_owned(cloud, options, on_progress), None)
    };
    let conversion = converted.map_err(|e| match e {
        CloudError::Bug(_) | CloudError::Internal { .. } => {
            anyhow::Error::new(InternalFailure(format!("{label}: {e}")))
        }
        e @ CloudError::PixelBudgetExceeded { .. } => {
            anyhow::anyhow!("{label}: {e} (--tile-size, --allow-coarsening)")
        }
        e => anyhow::Error::new(e).context(label.to_string()),
    })?;
    Ok((conversion, kept))
}

/// The pipeline's report completed with what the command did around it:
/// the points the readers dropped, the load and write times. Gives the
/// warnings as sentences, the readers' first.
fn complete_report(
    report: &mut CloudReport,
    dropped_non_finite: u64,
    load_warnings: &[ScanWarning],
    [load_seconds, write_seconds]: [f64; 2],
) -> Vec<String> {
    report.input_points += dropped_non_finite as usize;
    report.dropped_non_finite += dropped_non_finite;
    let warnings = load_warnings
        .iter()
        .map(ToString::to_string)
        .chain(report.warnings.iter().map(ToString::to_string))
        .collect();
    let load = StageTime {
        name: "load",
        seconds: load_seconds,
    };
    report.stages.insert(0, load);
    report.stages.push(StageTime {
        name: "write",
        seconds: write_seconds,
    });
    report.seconds = report.stages.iter().map(|s| s.seconds).sum();
    warnings
}

/// Loads the cloud, converts it, writes the scene (and the report).
pub(crate) fn run(args: &FromCloudArgs) -> anyhow::Result<()> {
    args.threads.init()?;
    let mut options = args.options();
    if args.plan.is_some() || args.plan_tile.is_some() {
        return run_planned(args, options);
    }
    let measure = args.error || args.report.is_some() || args.json;
    // load, the pipeline's stages (CLOUD_STAGES, consensus included), write, the error.
    let progress = Progress::new(&args.input_label(), 2 + CLOUD_STAGES + usize::from(measure));
    let (loaded, load_seconds) = load_inputs(args, &progress, &mut options)?;
    let label = args.input_label();
    let steps = CloudSteps::new(&progress);
    let on_progress = |p| steps.report(p);
    let points = loaded.cloud.len();
    let LoadedScans {
        cloud,
        scans,
        dropped_non_finite,
        warnings: load_warnings,
        ..
    } = loaded;
    let (conversion, mut kept) = convert_cloud(cloud, &options, measure, &on_progress, &label)?;
    progress.step("write");
    let write_started = Instant::now();
    write_output(&args.output, &conversion.bytes)?;
    let write_seconds = write_started.elapsed().as_secs_f64();
    let mut report = conversion.report;
    let seconds = [load_seconds, write_seconds];
    let warnings = complete_report(&mut report, dropped_non_finite, &load_warnings, seconds);
    if let Some(cloud) = &mut kept {
        progress.step("measuring error");
        let order = conversion.point_order.as_ref();
        let error = measure_error(args, cloud, &scans, &conversion.scene, order, &report)
            .with_context(|| format!("{label}: measuring the error"))?;
        report.error = Some(error);
    }
    drop(progress);
    print_results(args, &report, warnings, (scans.len(), points))
}

/// Reads the inputs (the progress's `load` step) and sets the consensus and the scanners of
/// `options` from what they hold; with the seconds that took.
fn load_inputs(
    args: &FromCloudArgs,
    progress: &Progress,
    options: &mut CloudOptions,
) -> anyhow::Result<(LoadedScans, f64)> {
    let started = Instant::now();
    progress.step("load");
    let loaded = read_inputs(args)?;
    options.consensus = args.consensus || (!args.no_consensus && loaded.scans.len() > 1);
    options.scanners = loaded.sight_lines.then(|| scanners_of(&loaded.scans));
    Ok((loaded, started.elapsed().as_secs_f64()))
}

/// The error of the converted `scene` (the cloud's points sorted in `order`) against the
/// loaded `cloud`, first moved by the report's scan shifts when `--error-against aligned`
/// asks.
fn measure_error(
    args: &FromCloudArgs,
    cloud: &mut PointCloud,
    scans: &[spatch_scan::ScanSummary],
    scene: &spatch_format::Scene,
    order: Option<&spatch_cloud::PointOrder>,
    report: &CloudReport,
) -> Result<spatch_cloud::CloudErrorReport, CloudError> {
    if args.error_against == ErrorAgainst::Aligned {
        shift_loaded_scans(cloud, scans, &report.scan_shifts);
    }
    measure_cloud_error_in_order(cloud, scene, report.spacing, order)
}

/// Prints the summary (led by the scan count when the `scans` of the inputs are several, and
/// the `points` read), and writes or prints the JSON report when asked.
fn print_results(
    args: &FromCloudArgs,
    report: &CloudReport,
    warnings: Vec<String>,
    (scans, points): (usize, usize),
) -> anyhow::Result<()> {
    let mut text = String::new();
    if scans > 1 {
        text.push_str(&format!(
            "read {} scans from {} inputs ({} points)\n",
            scans,
            args.inputs.len(),
            points
        ));
    }
    text.push_str(&cloud_summary(args, report, &warnings));
    if args.report.is_some() || args.json {
        let shared = shared_report(args, report, warnings)?;
        if let Some(path) = &args.report {
            write_json_report(path, &shared)?;
        }
        if args.json {
            print_json(&shared)?;
        }
    }
    print_summary(&text, args.json)
}

/// The summary of a conversion: counts, spacing, drops, tiles, warnings,
/// times and the error when measured.
fn cloud_summary(args: &FromCloudArgs, report: &CloudReport, warnings: &[String]) -> String {
    let mut text = format!(
        "{}: {} patches, {} nodes ({} filled) from {} points, {} bytes\n",
        args.output.display(),
        report.counts.patches,
        report.counts.nodes,
        report.counts.filled_nodes,
        report.points,
        report.counts.bytes,
    );
    text.push_str(&format!(
        "  spacing {:.4e} ({} normals), pixel {:.4e}, {} views, {} points uncovered\n",
        report.spacing, report.normals, report.pixel, report.views, report.uncovered_points,
    ));
    if report.dropped_non_finite > 0 {
        text.push_str(&format!(
            "  dropped {} non-finite points\n",
            report.dropped_non_finite
        ));
    }
    if report.tiles > 1 {
        text.push_str(&format!(
            "  {} tiles of {:.4e}, {} outlier points dropped\n",
            report.tiles,
            report.tile_size.unwrap_or(0.0),
            report.outlier_points,
        ));
    }
    for warning in warnings {
        text.push_str(&format!("  warning: {warning}\n"));
    }
    let stages: Vec<String> = report
        .stages
        .iter()
        .map(|s| format!("{} {:.0} ms", s.name, s.seconds * 1e3))
        .collect();
    text.push_str(&format!(
        "  time {:.2} s ({} threads): {}\n",
        report.seconds,
        report.threads,
        stages.join(", ")
    ));
    if let Some(error) = &report.error {
        text.push_str(&error_lines(error, args.error_against.name()));
    }
    text
}

/// The summary's two lines of the measured error (cloud to patches, nodes to the cloud, the
/// latter `against` the input or the kept points).
fn error_lines(error: &CloudErrorReport, against: &str) -> String {
    let c = &error.cloud_to_patch;
    let n = &error.node_to_cloud;
    let cloud = format!(
        "  cloud_to_patch: rms {:.3e} ({:.2} spacings), max {:.3e}, p95 {:.3e}, {:.2} % beyond 2 spacings\n",
        c.distance.rms,
        c.distance.rms / error.spacing,
        c.distance.max,
        c.distance.p95,
        c.share_beyond_2x_spacing * 100.0,
    );
    let nodes = format!(
        "  node_to_cloud: rms {:.3e}, max {:.3e}, p95 {:.3e} (measured in {:.2} s, against the {} points)\n",
        n.rms, n.max, n.p95, error.seconds, against
    );
    cloud + &nodes
}

/// `--plan` / `--plan-tile` runs (`tiled.rs`): one input; as the untiled run, the consensus
/// when it holds several scans and sight lines (and the scans aligned once for every tile)
/// when every scan's scanner is known.
fn run_planned(args: &FromCloudArgs, mut options: CloudOptions) -> anyhow::Result<()> {
    use super::tiled::{run_all, run_one, single_input, PlanScans, PlanSource};
    let input = single_input(&args.inputs)?;
    let scans = PlanScans::of(input, &args.scan_options())?;
    options.consensus = args.consensus || (!args.no_consensus && scans.count > 1);
    match (&args.plan, args.tile, args.plan_tile) {
        (Some(plan), Some(tile), _) => run_one(input, plan, tile, &args.output, &options, &scans),
        (Some(plan), None, _) => run_all(
            input,
            PlanSource::File(plan),
            &args.output,
            &options,
            &scans,
        ),
        (None, _, Some(size)) => {
            let plan = spatch_tiling::PlanOptions {
                tile: size,
                buffer: None,
                spacing: args.spacing,
                pixel_factor: args.pixel_factor,
            };
            run_all(
                input,
                PlanSource::Make(plan),
                &args.output,
                &options,
                &scans,
            )
        }
        (None, _, None) => anyhow::bail!("--plan or --plan-tile is needed"),
    }
}

/// Moves the points of each scan of the loaded `cloud` (`scans`, in its order) by its
/// alignment shift (`shifts`: one per scan, or none when the scans were not moved).
fn shift_loaded_scans(
    cloud: &mut PointCloud,
    scans: &[spatch_scan::ScanSummary],
    shifts: &[[f64; 3]],
) {
    if shifts.len() != scans.len() {
        return;
    }
    for (scan, shift) in scans.iter().zip(shifts) {
        let t = glam::DVec3::from_array(*shift);
        for p in &mut cloud.positions[scan.points.clone()] {
            *p = (p.as_dvec3() + t).as_vec3();
        }
    }
}

/// `--columns` as a layout (clap prints the message).
fn parse_layout(spec: &str) -> Result<XyzLayout, String> {
    parse_columns(spec).map_err(|e| e.to_string())
}

/// Reads and merges every input; a scan library's bug exits 1, anything else is the input's.
/// The message is the error's own one line (it names the file and carries its cause, so the
/// cause is not chained a second time).
fn read_inputs(args: &FromCloudArgs) -> anyhow::Result<LoadedScans> {
    load_scans(&args.inputs, &args.scan_options()).map_err(|e| match e {
        spatch_scan::ScanError::Bug(_) => anyhow::Error::new(InternalFailure(e.to_string())),
        e => anyhow::Error::msg(e.to_string()),
    })
}

/// The shared JSON report (docs/report-schema.md) of a cloud conversion: the cloud's own
/// figures under `details`, the error's spacing and share of far points under
/// `details.cloud_error`.
fn shared_report(
    args: &FromCloudArgs,
    r: &CloudReport,
    warnings: Vec<String>,
) -> anyhow::Result<Report<Value>> {
    let mut report = new_report("from-cloud", &args.input_label());
    report.output = Some(args.output.display().to_string());
    report.counts = r.counts;
    report.stages = stages_from(r.stages.iter().map(|s| (s.name, s.seconds)));
    report.seconds = r.seconds;
    report.threads = r.threads;
    report.diagonal = Some(r.diagonal);
    report.warnings = warnings;
    report.details = Value::Object(details_from(r)?);
    if let Some(e) = &r.error {
        report.measure_stages.push("error", e.seconds);
        report.measure_seconds = e.seconds;
        report.error.extend(cloud_error_entries(e));
        set_detail(
            &mut report,
            "cloud_error",
            &json!({
                "spacing": e.spacing,
                "share_beyond_2x_spacing": e.cloud_to_patch.share_beyond_2x_spacing,
                "against": args.error_against.name(),
            }),
        )?;
    }
    Ok(report)
}

impl FromCloudArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        // A planned run over every tile writes a folder, named by -o.
        let folder = self.plan_tile.is_some() || (self.plan.is_some() && self.tile.is_none());
        let mut files = crate::overwrite_guard::Files::default()
            .output_as((!folder).then_some(self.output.as_path()), Written::Spatch)
            .input(self.plan.as_deref())
            .output_as(self.report.as_deref(), Written::Json)
            .json_on_stdout(self.json);
        files
            .inputs
            .extend(self.inputs.iter().map(PathBuf::as_path));
        files
    }
}
