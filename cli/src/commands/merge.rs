//! `spatch merge`: concatenation of scenes, each kept at full precision
//! however far apart they are (see `Scene::merge`), streamed: one input in memory at a
//! time (`spatch_format::MergeWriter`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::DVec3;
use serde::Serialize;
use spatch_eval::{Counts, Report};
use spatch_format::{MergeError, MergeWriter, Scene, WriteOptions};
use spatch_tiling::SceneIndex;

use crate::output::{is_stdout, print_json, print_summary, read_spatch, write_error};
use crate::progress::Progress;
use crate::report::tool;

use super::tiled_scene::is_index;

/// Arguments of `spatch merge`.
#[derive(Debug, clap::Args)]
pub(crate) struct MergeArgs {
    /// Input .spatch files (two or more), or one tiled-scene index (INDEX.json: its
    /// tiles with patches, in index order). Read one at a time: memory holds one input.
    #[arg(required = true, num_args = 1.., value_name = "FILE")]
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
    #[arg(long, value_name = "X,Y,Z", value_parser = super::render_values::parse_vec3, allow_hyphen_values = true)]
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

/// Reads the inputs one at a time into a streaming merge writer, then writes the output:
/// memory holds one input scene, whatever the number of inputs.
pub(crate) fn run(args: &MergeArgs) -> anyhow::Result<()> {
    let paths = input_paths(args)?;
    let progress = Progress::new("merge", 2);
    let started = Instant::now();
    progress.step("read");
    let options = WriteOptions::with_compression(super::compression(args.compress));
    let mut writer =
        MergeWriter::new(&scratch_folder(&args.output), options).map_err(write_error)?;
    let (inputs, totals) = push_inputs(args, &paths, &mut writer, &progress)?;
    let read_seconds = started.elapsed().as_secs_f64();
    progress.step("write");
    let write_started = Instant::now();
    let bytes = if is_stdout(&args.output) {
        writer.write_to(&mut std::io::stdout().lock())
    } else {
        writer.write_to_file(&args.output)
    }
    .map_err(write_error)? as usize;
    drop(progress);
    let parts: Vec<String> = inputs.iter().map(|i| i.patches.to_string()).collect();
    let text = format!(
        "{}: {} patches ({}), {} bytes\n",
        args.output.display(),
        totals.counts.patches,
        parts.join(" + "),
        bytes
    );
    if args.json {
        let stages = [
            ("read", read_seconds),
            ("write", write_started.elapsed().as_secs_f64()),
        ];
        let mut report = merge_report(args, inputs, &totals, bytes, stages);
        report.seconds = started.elapsed().as_secs_f64();
        print_json(&report)?;
    }
    print_summary(&text, args.json)
}

/// Reads every input of `paths`, shifted by its `--translate`, into
/// `writer`: what each brought and the totals.
fn push_inputs(
    args: &MergeArgs,
    paths: &[PathBuf],
    writer: &mut MergeWriter,
    progress: &Progress,
) -> anyhow::Result<(Vec<MergedInput>, Totals)> {
    let mut inputs = Vec::with_capacity(paths.len());
    let mut totals = Totals::default();
    for (k, path) in paths.iter().enumerate() {
        let shift = args.translate.get(k).copied().unwrap_or(DVec3::ZERO);
        let scene = read_spatch(path)?
            .0
            .translated(shift)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        inputs.push(MergedInput {
            input: path.display().to_string(),
            patches: scene.patches().len(),
            translate: shift.to_array(),
        });
        totals.add(&scene);
        writer.push(scene).map_err(|e| match &e {
            MergeError::ChannelMismatch { .. } => anyhow::anyhow!("{}: {e}", path.display()),
            _ => anyhow::Error::new(e),
        })?;
        progress.count(k + 1, paths.len());
    }
    Ok((inputs, totals))
}

/// The `--json` report of a merge that wrote `bytes` bytes (its total
/// seconds left for the caller).
fn merge_report(
    args: &MergeArgs,
    inputs: Vec<MergedInput>,
    totals: &Totals,
    bytes: usize,
    stages: [(&'static str, f64); 2],
) -> Report<MergeDetails> {
    let label = inputs
        .iter()
        .map(|i| i.input.as_str())
        .collect::<Vec<_>>()
        .join(" + ");
    let mut report = Report::new(&tool(), "merge", &label, MergeDetails { inputs });
    report.output = Some(args.output.display().to_string());
    report.counts = Counts {
        bytes,
        ..totals.counts
    };
    report.diagonal = totals.bounds.map(|(lo, hi)| (hi - lo).length());
    for (name, seconds) in stages {
        report.stages.push(name, seconds);
    }
    report.threads = 1;
    report
}

/// The counts and bounds of the merged scene, gathered input by input.
#[derive(Default)]
struct Totals {
    counts: Counts,
    bounds: Option<(DVec3, DVec3)>,
}

impl Totals {
    fn add(&mut self, scene: &Scene) {
        let counts = Counts::of(scene, 0);
        self.counts.patches += counts.patches;
        self.counts.nodes += counts.nodes;
        self.counts.filled_nodes += counts.filled_nodes;
        if let Some((lo, hi)) = scene.bounds() {
            self.bounds = Some(match self.bounds {
                Some((a, b)) => (a.min(lo), b.max(hi)),
                None => (lo, hi),
            });
        }
    }
}

/// The files to merge: the inputs, or the tiles with patches of one tiled-scene index
/// (in index order).
fn input_paths(args: &MergeArgs) -> anyhow::Result<Vec<PathBuf>> {
    let index = match args.inputs.as_slice() {
        [one] if is_index(one) => one,
        [one] => anyhow::bail!(
            "{}: merge needs two or more .spatch files, or one tiled-scene index (index.json)",
            one.display()
        ),
        _ => {
            if !args.translate.is_empty() && args.translate.len() != args.inputs.len() {
                anyhow::bail!(
                    "--translate is given {} times for {} inputs: give it once per input or not at all",
                    args.translate.len(),
                    args.inputs.len()
                );
            }
            return Ok(args.inputs.clone());
        }
    };
    if !args.translate.is_empty() {
        anyhow::bail!(
            "{}: --translate moves separate inputs; a tiled scene is merged as it lies",
            index.display()
        );
    }
    let scene_index = SceneIndex::read(index).map_err(anyhow::Error::msg)?;
    let tiles: Vec<PathBuf> = scene_index
        .tiles
        .iter()
        .filter(|t| t.patches > 0)
        .map(|t| SceneIndex::tile_path(index, t))
        .collect();
    if tiles.is_empty() {
        anyhow::bail!("{}: no tile of this index holds a patch", index.display());
    }
    Ok(tiles)
}

/// Where the merge writer keeps its scratch files: the output's folder (`-`: the
/// system's temporary folder).
fn scratch_folder(output: &Path) -> PathBuf {
    if is_stdout(output) {
        return std::env::temp_dir();
    }
    match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
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
