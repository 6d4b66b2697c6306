//! `spatch sphere`: the perfect sphere.

use std::path::PathBuf;
use std::time::Instant;

use serde::Serialize;
use spatch_eval::{Counts, Report};
use spatch_format::{Scene, WriteOptions};

use spatch_sphere::{build_sphere, Sphere, SphereOptions};

use super::ThreadsArg;
use crate::output::{encode_and_write, print_json, print_summary, SceneWritten};
use crate::progress::Progress;
use crate::report::{scene_diagonal, tool};

/// Arguments of `spatch sphere`.
#[derive(Debug, clap::Args)]
pub(crate) struct SphereArgs {
    /// Output .spatch file (`-`: standard output).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print a report (docs/report-schema.md: counts, stages, the radial error in
    /// `details`) as one JSON object on standard output instead of the summary; refused
    /// with `-o -`.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    threads: ThreadsArg,
    /// Sphere radius in model units.
    #[arg(long, default_value_t = SphereOptions::DEFAULT_RADIUS)]
    radius: f64,
    /// Number of patches (centres spread almost evenly over the sphere).
    #[arg(long, default_value_t = SphereOptions::DEFAULT_PATCHES)]
    patches: usize,
    /// Nodes per patch side (2..=257).
    #[arg(long, default_value_t = SphereOptions::DEFAULT_GRID)]
    grid: u32,
    /// Node spacing |ax| = |ay| in model units.
    #[arg(long, default_value_t = SphereOptions::DEFAULT_SPACING)]
    spacing: f64,
    /// Displacement step |az|: the radial error is at most half of it.
    #[arg(long, default_value_t = SphereOptions::DEFAULT_STEP)]
    step: f64,
    /// Compress node data (grid prediction + range coding).
    #[arg(long)]
    compress: bool,
}

impl SphereArgs {
    /// The library options these arguments ask for.
    fn options(&self) -> SphereOptions {
        let mut options = SphereOptions::default();
        options.radius = self.radius;
        options.patches = self.patches;
        options.grid = self.grid;
        options.spacing = self.spacing;
        options.step = self.step;
        options
    }
}

/// The `details` of the sphere's report.
#[derive(Debug, Serialize)]
struct SphereDetails {
    /// Sphere radius (model units).
    radius: f64,
    /// Nodes per patch side.
    grid: u32,
    /// Node spacing `|ax| = |ay|`.
    spacing: f64,
    /// Displacement step `|az|`.
    step: f64,
    /// Largest distance of a filled node from the sphere.
    radial_error_max: f64,
    /// The quantization bound, `step / 2`.
    radial_error_bound: f64,
    /// Smallest room between a patch's Voronoi cell and its square edge (negative: gaps).
    coverage_margin: f64,
}

/// Builds the sphere, measures its radial error, writes it.
pub(crate) fn run(args: &SphereArgs) -> anyhow::Result<()> {
    args.threads.init()?;
    let options = args.options();
    let progress = Progress::new("sphere", 3);
    let started = Instant::now();
    progress.step("build");
    let sphere = build_sphere(&options)?;
    let build_seconds = started.elapsed().as_secs_f64();
    let worst = radial_error_max(&sphere.scene, options.radius);
    let written = encode_and_write(
        &progress,
        &sphere.scene,
        &WriteOptions::with_compression(super::compression(args.compress)),
        &args.output,
    )?;
    drop(progress);
    let built = Built {
        options: &options,
        sphere: &sphere,
        worst,
        build_seconds,
        written: &written,
    };
    if args.json {
        print_json(&report(args, &built, started))?;
    }
    print_summary(&summary(args, &built), args.json)
}

/// A built and written sphere, as its report and summary describe it.
struct Built<'a> {
    /// The options it was built with.
    options: &'a SphereOptions,
    /// The sphere.
    sphere: &'a Sphere,
    /// Its largest radial error.
    worst: f64,
    /// Seconds spent building it.
    build_seconds: f64,
    /// What writing it took.
    written: &'a SceneWritten,
}

/// The largest distance of a filled node from the sphere of `radius`.
fn radial_error_max(scene: &Scene, radius: f64) -> f64 {
    scene
        .patches()
        .iter()
        .flat_map(|p| {
            p.filled_nodes()
                .map(|(_, _, q)| (q.as_dvec3().length() - radius).abs())
        })
        .fold(0.0f64, f64::max)
}

/// The `--json` report (its `seconds` measured from `started` now).
fn report(args: &SphereArgs, built: &Built<'_>, started: Instant) -> Report<SphereDetails> {
    let (options, sphere, written) = (built.options, built.sphere, built.written);
    let scene = &sphere.scene;
    let mut report = Report::new(
        &tool(),
        "sphere",
        "the perfect sphere",
        SphereDetails {
            radius: options.radius,
            grid: options.grid,
            spacing: options.spacing,
            step: options.step,
            radial_error_max: built.worst,
            radial_error_bound: options.step / 2.0,
            coverage_margin: sphere.coverage_margin,
        },
    );
    report.output = Some(args.output.display().to_string());
    report.counts = Counts::of(scene, written.bytes);
    report.diagonal = scene_diagonal(scene);
    report.stages.push("build", built.build_seconds);
    report.stages.push("encode", written.encode_seconds);
    report.stages.push("write", written.write_seconds);
    report.seconds = started.elapsed().as_secs_f64();
    report.threads = rayon::current_num_threads();
    report
}

/// The short human summary.
fn summary(args: &SphereArgs, built: &Built<'_>) -> String {
    let (options, sphere, written) = (built.options, built.sphere, built.written);
    let scene = &sphere.scene;
    let mut text = format!(
        "{}: {} patches, {} nodes, {} bytes\n  radial error max {:.6} (bound: step/2 = {:.6})\n",
        args.output.display(),
        scene.patches().len(),
        scene.filled_node_count(),
        written.bytes,
        built.worst,
        options.step / 2.0,
    );
    if sphere.coverage_margin >= 0.0 {
        text.push_str(&format!(
            "  coverage: no gaps (margin {:.3} units)\n",
            sphere.coverage_margin
        ));
    } else {
        text.push_str(&format!(
            "  coverage: GAPS up to {:.3} units wide: use more --patches or a larger --grid\n",
            -sphere.coverage_margin
        ));
    }
    text.push_str(&format!(
        "  time: build {:.1} ms, encode+write {:.1} ms\n",
        built.build_seconds * 1e3,
        (written.encode_seconds + written.write_seconds) * 1e3
    ));
    text
}

impl SphereArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .output_as(Some(&self.output), Written::Spatch)
            .json_on_stdout(self.json)
    }
}
