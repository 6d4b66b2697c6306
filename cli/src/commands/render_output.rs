//! What `spatch render` writes: the PNG, the depth file and its camera,
//! the `--stats` file, the `--json` report and the one-line summary.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::ValueEnum;
use serde::Serialize;
use serde_json::json;
use spatch_eval::{Counts, Report, Stages};
use spatch_render::{Camera, OcclusionStats, RenderStats, RenderedImage, ShortcutCosts};

use super::frame_bench::BenchReport;
use crate::failure::{render_failure, InternalFailure};
use crate::output::print_summary;
use crate::report::tool;

/// The depth file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum DepthFormatArg {
    /// 16-bit greyscale PNG, linear between near and far.
    Png,
    /// 32-bit float TIFF of eye depth in model units, with a camera JSON.
    Tiff,
    /// OpenEXR, one 32-bit float channel `Z` of eye depth in model units
    /// (the TIFF's values, bit for bit), with a camera JSON.
    Exr,
}

/// `chosen`, or the format `path`'s extension names.
pub(super) fn depth_format(
    chosen: Option<DepthFormatArg>,
    path: &std::path::Path,
) -> DepthFormatArg {
    chosen.unwrap_or_else(|| {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if ext.eq_ignore_ascii_case("tif") || ext.eq_ignore_ascii_case("tiff") {
            DepthFormatArg::Tiff
        } else if ext.eq_ignore_ascii_case("exr") {
            DepthFormatArg::Exr
        } else {
            DepthFormatArg::Png
        }
    })
}

/// The camera as reports show it.
#[derive(Debug, Serialize)]
pub(super) struct CameraJson {
    eye: [f64; 3],
    target: [f64; 3],
    up: [f64; 3],
    fov_y_degrees: f64,
}

impl CameraJson {
    /// What reports show of `camera`.
    pub(super) fn of(camera: &Camera) -> Self {
        Self {
            eye: camera.eye().to_array(),
            target: camera.target().to_array(),
            up: camera.up().to_array(),
            fov_y_degrees: camera.fov_y_degrees(),
        }
    }
}

/// The `--stats` file: the frame's statistics, the camera, and the cost of the shortcuts.
#[derive(Debug, Serialize)]
pub(super) struct StatsFile<'a> {
    #[serde(flatten)]
    pub(super) stats: &'a RenderStats,
    pub(super) input: String,
    pub(super) overlap_cells_trimmed: u64,
    pub(super) overlap_cells_trimmable: u64,
    pub(super) camera: CameraJson,
    pub(super) shortcuts: ShortcutCosts,
    /// How much of the frame's drawing ends up hidden.
    pub(super) occlusion: OcclusionStats,
}

/// The `details` of the `--json` report.
#[derive(Debug, Serialize)]
pub(super) struct RenderDetails<'a> {
    /// The frame's statistics (as in `--stats`).
    pub(super) stats: &'a RenderStats,
    pub(super) camera: CameraJson,
    /// The `--bench` timings, `null` without it.
    pub(super) bench: Option<BenchReport>,
}

/// `--stats`' file as pretty JSON.
pub(super) fn stats_file_bytes(file: StatsFile<'_>) -> anyhow::Result<Vec<u8>> {
    let mut text = serde_json::to_string_pretty(&file).context("statistics")?;
    text.push('\n');
    Ok(text.into_bytes())
}

/// The image files asked for, encoded: the PNG at `output` and the depth
/// file at `depth` in its format with, for a float format, its camera
/// beside it.
pub(super) fn image_files(
    output: Option<&Path>,
    depth: Option<(&Path, DepthFormatArg)>,
    camera: &Camera,
    image: &RenderedImage,
) -> anyhow::Result<Vec<(PathBuf, Vec<u8>)>> {
    let mut files = Vec::new();
    if let Some(path) = output {
        files.push((
            path.to_path_buf(),
            image.encode_png().map_err(render_failure)?,
        ));
    }
    let Some((path, format)) = depth else {
        return Ok(files);
    };
    let (width, height, depth) = (image.width(), image.height(), image.depth());
    let float = match format {
        DepthFormatArg::Png => None,
        DepthFormatArg::Tiff => Some(spatch_export::encode_depth_tiff(width, height, depth)),
        DepthFormatArg::Exr => Some(spatch_export::encode_depth_exr(width, height, depth)),
    };
    match float {
        Some(bytes) => {
            files.push((
                path.to_path_buf(),
                bytes.map_err(|e| InternalFailure(e.to_string()))?,
            ));
            let camera_path = path.with_extension("camera.json");
            files.push((camera_path, depth_camera_json(camera, image)?));
        }
        None => files.push((
            path.to_path_buf(),
            image.encode_depth_png().map_err(render_failure)?,
        )),
    }
    Ok(files)
}

/// The camera of a float depth image, enough to turn its pixels back into
/// model-space points.
fn depth_camera_json(camera: &Camera, image: &RenderedImage) -> anyhow::Result<Vec<u8>> {
    let value = json!({
        "projection": "perspective",
        "eye": camera.eye().to_array(),
        "target": camera.target().to_array(),
        "up": camera.up().to_array(),
        "fov_y_degrees": camera.fov_y_degrees(),
        "width": image.width(),
        "height": image.height(),
        "near": image.near(),
        "far": image.far(),
        "depth": "distance along the view direction (target - eye) in model units; NaN where no surface; row 0 is the top; pixel centres at +0.5",
    });
    let mut text = serde_json::to_string_pretty(&value).context("camera")?;
    text.push('\n');
    Ok(text.into_bytes())
}

/// The `--json` report of a render of `input` (to `output`): `details`,
/// the scene's `counts` and diagonal, the stages and the threads.
pub(super) fn render_report<'a>(
    (input, output): (&Path, Option<&Path>),
    details: RenderDetails<'a>,
    counts: Option<(Counts, Option<f64>)>,
    stages: Stages,
    threads: usize,
) -> Report<RenderDetails<'a>> {
    let input = input.display().to_string();
    let mut report = Report::new(&tool(), "render", &input, details);
    report.output = output.map(|p| p.display().to_string());
    if let Some((counts, diagonal)) = counts {
        report.counts = counts;
        report.diagonal = diagonal;
    }
    report.seconds = stages.total();
    report.stages = stages;
    report.threads = threads;
    report
}

/// The summary on standard output: `--bench`'s table, or the line of the
/// image written to `output`.
pub(super) fn print_result(
    output: Option<&Path>,
    s: &RenderStats,
    bench: Option<&BenchReport>,
) -> anyhow::Result<()> {
    if let Some(bench) = bench {
        return print_summary(&bench.table(), false);
    }
    let Some(path) = output else {
        return Ok(());
    };
    let drawn = s.patches - s.patches_culled_frustum - s.patches_culled_backface;
    print_summary(
        &format!(
            "{}: {}x{}, {} of {} patches drawn, {:.2} ms\n",
            path.display(),
            s.image[0],
            s.image[1],
            drawn,
            s.patches,
            s.times_ms.total_wall
        ),
        false,
    )
}
