//! `spatch merge`: concatenation of scenes, each kept at full precision
//! however far apart they are (see `Scene::merge`).

use std::path::PathBuf;

use glam::DVec3;
use spatch_format::{encode_scene, Scene, WriteOptions};

use crate::output::{print_stdout, read_spatch, write_output};

/// Arguments of `spatch merge`.
#[derive(Debug, clap::Args)]
pub(crate) struct MergeArgs {
    /// Input .spatch files (two or more).
    #[arg(required = true, num_args = 2.., value_name = "FILE")]
    inputs: Vec<PathBuf>,
    /// Output .spatch file.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Compress node data (grid prediction + range coding).
    #[arg(long)]
    compress: bool,
    /// Move an input by X,Y,Z model units (f64, exact) before merging; give
    /// it once per input, in input order, or not at all.
    #[arg(long, value_name = "X,Y,Z", value_parser = super::render::parse_vec3, allow_hyphen_values = true)]
    translate: Vec<DVec3>,
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
    let mut scenes = Vec::with_capacity(args.inputs.len());
    for (k, path) in args.inputs.iter().enumerate() {
        let scene = read_spatch(path)?.0;
        let shift = args.translate.get(k).copied().unwrap_or(DVec3::ZERO);
        scenes.push(
            scene
                .translated(shift)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?,
        );
    }
    let counts: Vec<usize> = scenes.iter().map(|s| s.patches().len()).collect();
    let merged = Scene::merge(scenes).map_err(|e| match &e {
        spatch_format::MergeError::ChannelMismatch { index, .. } => {
            anyhow::anyhow!("{}: {e}", args.inputs[*index].display())
        }
        _ => anyhow::Error::new(e),
    })?;
    let bytes = encode_scene(
        &merged,
        &WriteOptions::with_compression(super::compression(args.compress)),
    )?;
    write_output(&args.output, &bytes)?;
    let parts: Vec<String> = counts.iter().map(usize::to_string).collect();
    print_stdout(&format!(
        "{}: {} patches ({}), {} bytes\n",
        args.output.display(),
        merged.patches().len(),
        parts.join(" + "),
        bytes.len()
    ))
}

impl MergeArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        let mut files =
            crate::overwrite_guard::Files::default().output_as(Some(&self.output), Written::Spatch);
        files
            .inputs
            .extend(self.inputs.iter().map(PathBuf::as_path));
        files
    }
}
