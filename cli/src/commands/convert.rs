//! `spatch convert`: a mesh file to a `.spatch` scene, with a report.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use spatch_convert::{
    convert_with_progress, ColourGridReport, Conversion, ConvertInput, ConvertReport, EdgeStats,
    PrepareCounts, ProgressEvent, Stage,
};
use spatch_eval::{
    geometric_error, hole_fraction, GeometricError, HoleOptions, HoleReport, Report, Stages,
};
use spatch_fit::TextureDetail;

use super::pipeline_args::PipelineArgs;
use crate::failure::InternalFailure;
use crate::output::{print_json, print_summary, write_json_report, write_output};
use crate::progress::Progress;
use crate::report::{stages_from, tool, ConversionDetails, Holes};

/// Arguments of `spatch convert`.
#[derive(Debug, clap::Args)]
pub(crate) struct ConvertArgs {
    /// Input mesh: .obj (with .mtl and textures), .gltf, .glb (also quantized or
    /// meshopt-compressed, as gltfpack writes), .ply (faces, tristrips, or a raw range scan's
    /// range_grid, joined along the scanner's grid), .off or .stl (binary or ASCII).
    #[arg(value_name = "MESH")]
    input: PathBuf,
    /// Output .spatch file (`-`: standard output).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print the report (the --report JSON, docs/report-schema.md) as one object on
    /// standard output instead of the summary; refused with `-o -`.
    #[arg(long)]
    json: bool,
    /// A tile plan of this mesh (`spatch plan MESH --tile SIZE`): convert only tile
    /// `--tile K`'s faces (and its buffer's) at the plan's spacing, segmenting only the faces
    /// whose centroid lies in the tile, so tiles join with no seam and no patch twice
    /// (docs/scale.md, "Meshes").
    #[arg(long, value_name = "PLAN", requires = "tile", conflicts_with = "json")]
    plan: Option<PathBuf>,
    /// With `--plan`: the tile to convert (its index in the plan).
    #[arg(long, value_name = "K", requires = "plan")]
    tile: Option<usize>,
    #[command(flatten)]
    pipeline: PipelineArgs,
}

/// A finished conversion, written out.
pub(crate) struct Outcome {
    pub(crate) conversion: Conversion,
    /// The JSON report (written with `--report`, printed with `--json`).
    pub(crate) report: Report<ConversionDetails>,
    /// The human summary.
    pub(crate) text: String,
}

/// The progress bar's steps of a conversion: the pipeline's stages, writing, and the
/// measurements asked for.
pub(crate) fn conversion_steps(before: usize, args_no_error: bool, holes: bool) -> usize {
    before + Stage::ALL.len() + 1 + usize::from(!args_no_error) + usize::from(holes)
}

/// Shows a mesh-pipeline event on the bar.
pub(crate) fn show_event(progress: &Progress, event: ProgressEvent) {
    match event {
        ProgressEvent::Stage(stage) => progress.step(stage.name()),
        ProgressEvent::Count { done, total } => progress.count(done, total),
        _ => {}
    }
}

/// Converts `input`, writes `output` (and the report when asked), and returns what happened.
pub(crate) fn convert_and_write(
    input: &Path,
    output: &Path,
    args: &PipelineArgs,
) -> anyhow::Result<Outcome> {
    let options = args.options();
    let progress = Progress::new(
        &input.display().to_string(),
        conversion_steps(0, args.no_error, args.holes),
    );
    let started = Instant::now();
    let conversion = convert_with_progress(ConvertInput::Path(input), &options, &|event| {
        show_event(&progress, event)
    })
    .map_err(|e| classify(e, input))?;
    let mut finished = write_and_measure(&progress, conversion, output, args.no_error, started)?;
    warn_over_error_budget(&mut finished, options.fit.max_step_error);
    let holes = if args.holes {
        Some(timed_holes(&progress, || {
            measure_holes(&finished.conversion)
        })?)
    } else {
        None
    };
    drop(progress);
    let files = OutcomeFiles {
        input,
        output,
        report: args.report.as_deref(),
    };
    outcome_of(finished, holes, &files)
}

/// The hole fractions with and without edge patches.
type HolePair = (HoleReport, Option<HoleReport>);

/// The files a conversion read and wrote, as its report and summary name them.
struct OutcomeFiles<'a> {
    /// The input mesh.
    input: &'a Path,
    /// The written scene.
    output: &'a Path,
    /// The JSON report to write, if asked.
    report: Option<&'a Path>,
}

/// Adds a warning to the report when the measured error exceeds what the
/// step error budget allows.
fn warn_over_error_budget(finished: &mut Measured, max_step_error: f32) {
    let budget_warning = finished.error.as_ref().and_then(|e| {
        spatch_convert::check_error_budget(
            finished.conversion.report.spacing,
            max_step_error,
            e.surface_to_patch.p95,
        )
    });
    if let Some(warning) = budget_warning {
        finished
            .conversion
            .report
            .warnings
            .push(warning.to_string());
    }
}

/// Runs `measure` as the `measuring holes` step of `progress`, with the seconds it took.
pub(crate) fn timed_holes<T>(
    progress: &Progress,
    measure: impl FnOnce() -> anyhow::Result<T>,
) -> anyhow::Result<(T, f64)> {
    progress.step("measuring holes");
    let start = Instant::now();
    let holes = measure()?;
    Ok((holes, start.elapsed().as_secs_f64()))
}

/// The report (written when asked) and the summary of a finished conversion.
fn outcome_of(
    finished: Measured,
    holes: Option<(HolePair, f64)>,
    files: &OutcomeFiles<'_>,
) -> anyhow::Result<Outcome> {
    let Measured {
        conversion,
        error,
        mut times,
    } = finished;
    let mut details = ConversionDetails::of(&conversion.report);
    if let Some(((with, without), seconds)) = holes {
        times.measured.push("holes", seconds);
        details.holes = Some(Holes::WithAndWithoutEdges {
            with_edges: with,
            without_edges: without,
        });
    }
    let seconds = times.seconds;
    let report = report_json(
        "convert",
        &files.input.display().to_string(),
        files.output,
        &conversion,
        error.as_ref(),
        times,
        details,
    );
    if let Some(path) = files.report {
        write_json_report(path, &report)?;
    }
    let mut text = summary(
        files.output,
        &conversion,
        error.as_ref(),
        seconds,
        files.report,
    );
    if let Some(Holes::WithAndWithoutEdges {
        with_edges: with,
        without_edges: without,
    }) = &report.details.holes
    {
        text.push_str(&holes_line(with, without.as_ref()));
    }
    Ok(Outcome {
        conversion,
        report,
        text,
    })
}

/// The summary's line on holes, with and without the edge patches.
fn holes_line(with: &HoleReport, without: Option<&HoleReport>) -> String {
    let without = without.map_or("n/a".to_owned(), |w| {
        format!(
            "{:.4} % ({:.4} % inside the outlines)",
            w.fraction * 100.0,
            w.interior_fraction * 100.0
        )
    });
    format!(
        "  holes over {} views: {:.4} % ({} of {} source pixels; {:.4} % inside the outlines); without edge patches {}\n",
        with.views.len(),
        with.fraction * 100.0,
        with.hole_pixels,
        with.source_pixels,
        with.interior_fraction * 100.0,
        without
    )
}

/// A conversion written out, with its geometric error when measured.
pub(crate) struct Measured {
    pub(crate) conversion: Conversion,
    pub(crate) error: Option<GeometricError>,
    pub(crate) times: Times,
}

/// Writes the scene to `output`, then measures its geometric error unless `no_error`
/// (the steps `write` and `measuring error` of `progress`).
pub(crate) fn write_and_measure(
    progress: &Progress,
    conversion: Conversion,
    output: &Path,
    no_error: bool,
    started: Instant,
) -> anyhow::Result<Measured> {
    progress.step("write");
    let write_started = Instant::now();
    write_output(output, &conversion.bytes)?;
    let write_seconds = write_started.elapsed().as_secs_f64();
    let seconds = started.elapsed().as_secs_f64();
    let mut measured = Stages::default();
    let error = (!no_error).then(|| {
        progress.step("measuring error");
        let start = Instant::now();
        let error = geometric_error(&conversion.scene, &conversion.mesh, 1);
        measured.push("error", start.elapsed().as_secs_f64());
        error
    });
    Ok(Measured {
        conversion,
        error,
        times: Times {
            seconds,
            write_seconds,
            measured,
        },
    })
}

/// The hole fraction of the scene, and of the scene without its edge patches (which the
/// pipeline appends last) when it has any.
fn measure_holes(c: &Conversion) -> anyhow::Result<HolePair> {
    let options = HoleOptions::default();
    let failed =
        |e: spatch_render::RenderError| InternalFailure(format!("cannot measure holes: {e}"));
    let with = hole_fraction(&c.scene, &c.mesh, &options).map_err(failed)?;
    let edge_count = c
        .report
        .edges
        .map_or(0, |e| e.edge_patches + e.corner_patches);
    if edge_count == 0 {
        return Ok((with, None));
    }
    let patches = c.scene.patches();
    let surface = spatch_format::Scene::new(
        c.scene.offset(),
        c.scene.channel(),
        patches[..patches.len() - edge_count].to_vec(),
    )
    .map_err(|e| InternalFailure(format!("cannot measure holes: {e}")))?;
    let without = hole_fraction(&surface, &c.mesh, &options).map_err(failed)?;
    Ok((with, Some(without)))
}

/// Adds the file to the error and marks spatch's own failures as internal (exit code 1).
fn classify(err: spatch_convert::ConvertError, input: &Path) -> anyhow::Error {
    use spatch_convert::ConvertError;
    let internal = matches!(
        &err,
        ConvertError::Encode(_) | ConvertError::Fit(spatch_fit::FitError::Bug(_))
    );
    if internal {
        anyhow::Error::new(InternalFailure(format!("{}: {err}", input.display())))
    } else if matches!(err, ConvertError::Load(_)) {
        // Loader errors already name the file.
        anyhow::Error::new(err)
    } else {
        anyhow::Error::new(err).context(format!("{}", input.display()))
    }
}

/// Where the time of a conversion command went.
pub(crate) struct Times {
    /// Wall time from the start to the written scene (seconds).
    pub(crate) seconds: f64,
    /// Of which writing the scene.
    pub(crate) write_seconds: f64,
    /// The measurements after that (error, holes).
    pub(crate) measured: Stages,
}

/// The shared JSON report of a conversion (docs/report-schema.md): the pipeline's stages and
/// `write`, the geometric error when measured (`measured` holds the measurements' times),
/// and the command's own figures (`details`).
pub(crate) fn report_json(
    command: &str,
    input: &str,
    output: &Path,
    c: &Conversion,
    error: Option<&GeometricError>,
    times: Times,
    details: ConversionDetails,
) -> Report<ConversionDetails> {
    let Times {
        seconds,
        write_seconds,
        measured,
    } = times;
    let r = &c.report;
    let mut report = Report::new(&tool(), command, input, details);
    report.output = Some(output.display().to_string());
    report.counts = r.counts;
    report.stages = stages_from(r.stages.iter().map(|s| (s.name, s.seconds)));
    report.stages.push("write", write_seconds);
    report.seconds = seconds;
    report.measure_seconds = measured.total();
    report.measure_stages = measured;
    report.threads = r.threads;
    report.diagonal = Some(r.diagonal);
    if let Some(e) = error {
        report
            .error
            .insert("node_to_surface".to_owned(), e.node_to_surface);
        report
            .error
            .insert("surface_to_patch".to_owned(), e.surface_to_patch);
    }
    report.warnings = r.warnings.clone();
    report
}

/// The short human summary.
pub(crate) fn summary(
    output: &Path,
    c: &Conversion,
    error: Option<&GeometricError>,
    seconds: f64,
    report: Option<&Path>,
) -> String {
    let r = &c.report;
    let mut text = format!(
        "{}: {} patches, {} nodes ({} filled), {} bytes, colour {}\n",
        output.display(),
        r.counts.patches,
        r.counts.nodes,
        r.counts.filled_nodes,
        r.counts.bytes,
        r.colour
    );
    let stages: Vec<String> = r
        .stages
        .iter()
        .filter(|s| !matches!(s.name, "adjacency" | "orient") || s.seconds >= 0.0005)
        .map(|s| format!("{} {:.0} ms", s.name, s.seconds * 1e3))
        .collect();
    text.push_str(&format!(
        "  time: {:.2} s with {} threads ({})\n",
        seconds,
        r.threads,
        stages.join(", ")
    ));
    if let Some(e) = error {
        text.push_str(&format!(
            "  error (% of diagonal): nodes to surface max {:.4} rms {:.4}; surface to patches max {:.4} rms {:.4}\n",
            e.node_to_surface.max_rel * 100.0,
            e.node_to_surface.rms_rel * 100.0,
            e.surface_to_patch.max_rel * 100.0,
            e.surface_to_patch.rms_rel * 100.0,
        ));
    }
    let lines = [
        repeats_line(&r.prepare),
        winding_line(r),
        r.edges.as_ref().map(|e| edges_line(e, r.edge_bytes)),
        r.texture.as_ref().map(texture_line),
        r.colour_grids.as_ref().map(colour_grids_line),
    ];
    for line in lines.into_iter().flatten() {
        text.push_str(&line);
    }
    for w in &r.warnings {
        text.push_str(&format!("  warning: {w}\n"));
    }
    if let Some(path) = report {
        text.push_str(&format!("  report: {}\n", path.display()));
    }
    text
}

/// The summary's line on repeated faces, when there were any.
fn repeats_line(prepared: &PrepareCounts) -> Option<String> {
    (prepared.dropped_duplicate + prepared.kept_repeats > 0).then(|| {
        format!(
            "  repeated faces: {} dropped ({} of them wound the other way), {} kept (flaps of copies)\n",
            prepared.dropped_duplicate, prepared.dropped_mirrored, prepared.kept_repeats
        )
    })
}

/// The summary's line on the winding pass, when it turned faces over or
/// found edges that cannot agree.
fn winding_line(r: &ConvertReport) -> Option<String> {
    let o = r
        .orient
        .filter(|o| o.flipped_faces + o.conflicting_edges > 0)?;
    Some(format!(
        "  winding: {} of {} faces turned over ({} of {} pieces wound inward){}\n",
        o.flipped_faces,
        r.triangles,
        o.inward_pieces,
        o.pieces,
        match (o.conflicting_edges, o.wound_inward) {
            (0, false) => String::new(),
            (0, true) => "; most of it faced in: every patch drawn from both sides".to_owned(),
            (n, _) => format!("; {n} edges cannot agree: every patch drawn from both sides"),
        }
    ))
}

/// The summary's line on sharp edges and the `edge_bytes` their patches
/// add.
fn edges_line(e: &EdgeStats, edge_bytes: usize) -> String {
    format!(
        "  sharp edges: {} creases in {} chains{}, {} corners; {} edge + {} corner patches, {} bytes\n",
        e.creases,
        e.chains,
        // Why said: a scene whose creases all lie inside surface
        // patches (the built-in Earth's 12) read as found and lost.
        match e.covered_creases {
            0 => String::new(),
            n => format!(" ({n} covered by the surface patches)"),
        },
        e.corners,
        e.edge_patches,
        e.corner_patches,
        edge_bytes
    )
}

/// The summary's line on texture-driven node density.
fn texture_line(t: &TextureDetail) -> String {
    format!(
        "  texture: {} textured regions, {:.2} texels per node (asked {:.2}{}), {:.0} texels; nodes {:.0} against {:.0} texture-blind (budget {:.0})\n",
        t.textured_regions,
        t.texels_per_node,
        t.texels_per_node_wanted,
        if t.budget_limited { ", held by the budget" } else { "" },
        t.texels,
        t.nodes,
        t.blind_nodes,
        t.budget_nodes,
    )
}

/// The summary's line on colour grids.
fn colour_grids_line(g: &ColourGridReport) -> String {
    format!(
        "  colour grids: {} patches ({} sharing another's), {} samples, up to {}x{} per cell (asked {}){}, {} bytes (budget {})\n",
        g.patches,
        g.shared,
        g.samples,
        g.max_factor,
        g.max_factor,
        g.wanted_factor,
        match (g.budget_limited, g.floor_limited) {
            (_, true) => ", lowered by the budget down to the colour floor",
            (true, false) => ", held by the budget",
            _ => "",
        },
        g.bytes,
        g.budget_bytes,
    )
}

/// Converts a mesh and prints a summary (or the report, with `--json`).
pub(crate) fn run(args: &ConvertArgs) -> anyhow::Result<()> {
    args.pipeline.threads.init()?;
    if !args.input.is_file() {
        return Err(anyhow::anyhow!("{}: no such file", args.input.display()))
            .context("cannot read the input mesh");
    }
    if let (Some(plan), Some(tile)) = (&args.plan, args.tile) {
        let (input, output) = (&args.input, &args.output);
        return super::convert_plan::run_tile(input, plan, tile, output, &args.pipeline);
    }
    let outcome = convert_and_write(&args.input, &args.output, &args.pipeline)?;
    if args.json {
        print_json(&outcome.report)?;
    }
    print_summary(&outcome.text, args.json)
}

impl ConvertArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .input(Some(&self.input))
            .input(self.plan.as_deref())
            .output_as(Some(&self.output), Written::Spatch)
            .output_as(self.pipeline.report.as_deref(), Written::Json)
            .json_on_stdout(self.json)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_stage_has_a_name() {
        for s in Stage::ALL {
            assert!(!s.name().is_empty());
        }
    }
}
