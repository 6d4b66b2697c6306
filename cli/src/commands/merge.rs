//! `spatch merge`: concatenation of scenes, each kept at full precision
//! however far apart they are (see `Scene::merge`).

use std::path::PathBuf;
use std::time::Instant;

use glam::DVec3;
use serde::Serialize;
use spatch_eval::{Counts, Report};
use spatch_format::{Scene, WriteOptions};

use crate::output::{encode_and_write, print_json, print_summary, read_spatch};
use crate::progress::Progress;
use crate::report::{scene_diagonal, tool};

/// Arguments of `spatch merge`.
#[derive(Debug, clap::Args)]
pub(crate) struct MergeArgs {
    /// Input .spatch files (two or more).
    #[arg(required = true, num_args = 2.., value_name = "FILE")]
    inputs: Vec<PathBuf>,
    /// Output .spatch file (`-`: standard output).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print a report (docs/report-schema.md: counts, stages, each input's patches in
    /// `details`) as one JSON object on standard output instead of the summary; refused
    /// with `-o -`.
    #[arg(long)]
    json: bool,
    /// Compress node data (grid prediction + range coding).
    #[arg(long)]
    compress: bool,
    /// Move an input by X,Y,Z model units (f64, exact) before merging; give
    /// it once per input, in input order, or not at all.
    #[arg(long, value_name = "X,Y,Z", value_parser = super::render::parse_vec3, allow_hyphen_values = true)]
    translate: Vec<DVec3>,
}

/// One input of a merge, in the report's `details.inputs`.
#[derive(Debug, Serialize)]
struct MergedInput {
    /// The file.
    input: String,
    /// Its patches.
    patches: usize,
    /// The shift applied to it (model units).
    translate: [f64; 3],
}

/// The `details` of a merge's report.
#[derive(Debug, Serialize)]
struct MergeDetails {
    /// The inputs, in order.
    inputs: Vec<MergedInput>,
}

/// Reads every input, merges, writes.
pub(crate) fn run(args: &MergeArgs) -> anyhow::Result<()> {
    if !args.translate.is_empty() && args.translate.len() != args.inputs.len() {
        anyhow::bail!(
            "--translate is given {} times for {} inputs: give it once per input or not at all",
            args.translate.len(),
            args.inputs.len()
        );
    }
    let progress = Progress::new("merge", 4);
    let started = Instant::now();
    progress.step("read");
    let mut scenes = Vec::with_capacity(args.inputs.len());
    let mut inputs = Vec::with_capacity(args.inputs.len());
    for (k, path) in args.inputs.iter().enumerate() {
        let scene = read_spatch(path)?.0;
        let shift = args.translate.get(k).copied().unwrap_or(DVec3::ZERO);
        inputs.push(MergedInput {
            input: path.display().to_string(),
            patches: scene.patches().len(),
            translate: shift.to_array(),
        });
        scenes.push(
            scene
                .translated(shift)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
        );
        progress.count(k + 1, args.inputs.len());
    }
    let read_seconds = started.elapsed().as_secs_f64();
    progress.step("merge");
    let merge_started = Instant::now();
    let merged = Scene::merge(scenes).map_err(|e| match &e {
        spatch_format::MergeError::ChannelMismatch { index, .. } => {
            anyhow::anyhow!("{}: {e}", args.inputs[*index].display())
        }
        _ => anyhow::Error::new(e),
    })?;
    let merge_seconds = merge_started.elapsed().as_secs_f64();
    let written = encode_and_write(
        &progress,
        &merged,
        &WriteOptions::with_compression(super::compression(args.compress)),
        &args.output,
    )?;
    drop(progress);
    let parts: Vec<String> = inputs.iter().map(|i| i.patches.to_string()).collect();
    let text = format!(
        "{}: {} patches ({}), {} bytes\n",
        args.output.display(),
        merged.patches().len(),
        parts.join(" + "),
        written.bytes
    );
    if args.json {
        let label = inputs
            .iter()
            .map(|i| i.input.as_str())
            .collect::<Vec<_>>()
            .join(" + ");
        let mut report = Report::new(&tool(), "merge", &label, MergeDetails { inputs });
        report.output = Some(args.output.display().to_string());
        report.counts = Counts::of(&merged, written.bytes);
        report.diagonal = scene_diagonal(&merged);
        report.stages.push("read", read_seconds);
        report.stages.push("merge", merge_seconds);
        report.stages.push("encode", written.encode_seconds);
        report.stages.push("write", written.write_seconds);
        report.seconds = started.elapsed().as_secs_f64();
        report.threads = 1;
        print_json(&report)?;
    }
    print_summary(&text, args.json)
}

impl MergeArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        let mut files = crate::overwrite_guard::Files::default()
            .output_as(Some(&self.output), Written::Spatch)
            .json_on_stdout(self.json);
        files
            .inputs
            .extend(self.inputs.iter().map(PathBuf::as_path));
        files
    }
}
