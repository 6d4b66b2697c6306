//! `spatch demo`: converts a built-in model into a folder, with nothing to download.
//!
//! The model is Keenan Crane's "Spot" (public domain, see `cli/assets/spot/README.txt`): a
//! textured cow of 5,856 triangles, embedded in the binary. The demo writes it out as the
//! source, converts it, measures the geometric error, renders the patches with the automatic
//! camera and writes the scene, the picture and the report.

use std::path::{Path, PathBuf};

use anyhow::Context;

use super::convert::convert_and_write;
use super::pipeline_args::PipelineArgs;
use crate::failure::InternalFailure;
use crate::output::{print_summary, write_output};

/// The embedded source files: name in the output folder, bytes.
const SOURCE_FILES: [(&str, &[u8]); 4] = [
    ("spot.obj", include_bytes!("../../assets/spot/spot.obj")),
    ("spot.mtl", include_bytes!("../../assets/spot/spot.mtl")),
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
    /// Side of the rendered square picture, in pixels.
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(16..=4096))]
    size: u32,
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

/// Renders `scene` with the automatic camera into a PNG at `path`.
fn render_picture(scene: &spatch_format::Scene, path: &Path, size: u32) -> anyhow::Result<()> {
    use spatch_render::{render, Camera, PreparedScene, RenderOptions};
    let internal = |what: &str, e: &dyn std::fmt::Display| {
        anyhow::Error::new(InternalFailure(format!(
            "cannot {what} the demo picture: {e}"
        )))
    };
    let (centre, radius) = PreparedScene::new(scene)
        .bounding_sphere()
        .ok_or_else(|| internal("frame", &"the scene is empty"))?;
    // The automatic framing distance, seen from the cow's front-left (the automatic camera's
    // three-quarter direction mirrored in x and z: Spot faces +x).
    let auto =
        Camera::framing(centre, radius, 35.0, size, size).map_err(|e| internal("frame", &e))?;
    let [x, y, z] = Camera::THREE_QUARTER_DIRECTION;
    let distance = (auto.eye() - centre).length();
    let eye = centre + glam::DVec3::new(-x, y, -z).normalize() * distance;
    let camera = Camera::look_at(eye, centre, glam::DVec3::Y, 35.0, size, size)
        .map_err(|e| internal("frame", &e))?;
    let out =
        render(scene, &camera, &RenderOptions::default()).map_err(|e| internal("render", &e))?;
    let png = out.image.encode_png().map_err(|e| internal("encode", &e))?;
    write_output(path, &png)
}

fn create_dir(dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)
        .with_context(|| format!("{}: cannot create the output folder", dir.display()))
}

/// Runs the demo and prints where everything went.
pub(crate) fn run(args: &DemoArgs) -> anyhow::Result<()> {
    args.pipeline.threads.init()?;
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
    let picture = args.output.join("spot.png");
    render_picture(&outcome.conversion.scene, &picture, args.size)?;
    let report = pipeline
        .report
        .as_deref()
        .map_or_else(String::new, |p| p.display().to_string());
    let text = format!(
        "spatch demo: Keenan Crane's Spot (public domain), {} triangles, textured\n\
         {}\
         written to {}:\n  source/spot.obj, spot.mtl, spot_texture.png   the source model\n  \
         spot.spatch                                   the patches\n  \
         spot.png                                      the patches rendered by spatch render\n  {report}\n\
         next: spatch stats {}\n      spatch export {} -o nodes.ply\n",
        outcome.conversion.report.triangles,
        outcome.text,
        args.output.display(),
        scene_path.display(),
        scene_path.display(),
    );
    print_summary(&text, false)
}
