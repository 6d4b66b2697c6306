//! `spatch eval`: a scene against its source (error and time), or a sweep of settings with
//! an error-versus-time plot.

use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use serde_json::{json, Value};
use spatch_eval::sweep::SWEEP_CSV_COLUMNS;
use spatch_eval::{
    evaluate, load_source, per_patch_csv, run_sweep, sweep_csv, sweep_svg, Counts, EvalError,
    EvalOptions, Evaluation, LoadedSource, PatchError, Report, Source, SweepResult,
};

use super::eval_args::{EvalArgs, EVAL_VIEWS};
use crate::failure::InternalFailure;
use crate::output::{print_json, print_summary, read_spatch, write_json_report, write_output};
use crate::progress::Progress;
use crate::report::{new_report, set_detail, tool};

/// Patches listed as the worst in the report and the summary.
const WORST_LISTED: usize = 5;

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
