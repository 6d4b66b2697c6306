//! `spatch demo`: converts a built-in model into a folder, with nothing to download.
//!
//! The model is Keenan Crane's "Spot" (public domain, see `cli/assets/spot/README.txt`): a
//! textured cow of 5,856 triangles, embedded in the binary. The demo writes it out as the
//! source, converts it, measures the geometric error and writes the scene and the report.

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::convert::{convert_and_write, PipelineArgs};
use crate::failure::InternalFailure;
use crate::output::{print_stdout, write_output};

/// The embedded source files: name in the output folder, bytes.
const SOURCE_FILES: [(&str, &[u8]); 3] = [
    ("spot.obj", include_bytes!("../../assets/spot/spot.obj")),
    (
        "spot_texture.png",
        include_bytes!("../../assets/spot/spot_texture.png"),
    ),
    ("README.txt", include_bytes!("../../assets/spot/README.txt")),
];

/// Arguments of `spatch demo`.
#[derive(Debug, clap::Args)]
pub(crate) struct DemoArgs {
    /// Folder to write everything into (created when missing).
    #[arg(short, long, value_name = "DIR", default_value = "spatch-demo")]
    output: PathBuf,
    #[command(flatten)]
    pipeline: PipelineArgs,
}

impl DemoArgs {
    /// The pipeline arguments, with the report always written into the folder.
    fn pipeline(&self) -> PipelineArgs {
        let mut p = self.pipeline.clone();
        p.report = Some(
            p.report
                .clone()
                .unwrap_or_else(|| self.output.join("report.json")),
        );
        p
    }
}

fn create_dir(dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the output folder", dir.display()))
}

/// Runs the demo and prints where everything went.
pub(crate) fn run(args: &DemoArgs) -> anyhow::Result<()> {
    args.pipeline.init_threads()?;
    let source_dir = args.output.join("source");
    create_dir(&source_dir)?;
    for (name, bytes) in SOURCE_FILES {
        write_output(&source_dir.join(name), bytes)?;
    }
    let source = source_dir.join("spot.obj");
    let scene_path = args.output.join("spot.spatch");
    let pipeline = args.pipeline();
    let outcome = convert_and_write(&source, &scene_path, &pipeline)?;
    if outcome.conversion.report.colour == "none" && !pipeline.no_colour {
        return Err(anyhow::Error::new(InternalFailure(
            "the built-in model lost its texture while loading (this is a bug)".to_owned(),
        )));
    }
    let report = pipeline
        .report
        .as_deref()
        .map_or_else(String::new, |p| p.display().to_string());
    let text = format!(
        "spatch demo: Keenan Crane's Spot (public domain), {} triangles, textured\n\
         {}\
         written to {}:\n  source/spot.obj, source/spot_texture.png   the source model\n  \
         spot.spatch                                the patches\n  {report}\n\
         next: spatch stats {} | spatch export {} -o nodes.ply\n",
        outcome.conversion.report.triangles,
        outcome.text,
        args.output.display(),
        scene_path.display(),
        scene_path.display(),
    );
    print_stdout(&text)
}
