//! `spatch export`: nodes as points or cells as welded patch meshes, in
//! PLY, OBJ, glTF or GLB.

use std::path::PathBuf;
use std::time::Instant;

use clap::ValueEnum;
use glam::DVec3;
use serde::Serialize;
use spatch_eval::{Counts, Report};
use spatch_export::{export_scene, Content, ExportOptions, Exported, Format, PositionType};

use crate::output::{print_json, print_summary, read_spatch, write_output};
use crate::progress::Progress;
use crate::report::{scene_diagonal, tool};

/// The file format of `spatch export`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum FormatArg {
    /// Binary little-endian PLY.
    Ply,
    /// Wavefront OBJ (text, f64 positions, `v x y z r g b` colours).
    Obj,
    /// glTF 2.0 JSON with the buffer embedded.
    Gltf,
    /// glTF 2.0 binary.
    Glb,
}

/// The PLY position type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum PositionsArg {
    /// float, or double when float would lose more than 1e-5 of a median patch.
    Auto,
    /// Always float.
    Float,
    /// Always double.
    Double,
}

/// Arguments of `spatch export`.
#[derive(Debug, clap::Args)]
pub(crate) struct ExportArgs {
    /// Input .spatch file (`-`: standard input, at most 1 GiB).
    #[arg(value_name = "FILE")]
    input: PathBuf,
    /// Output file (.ply, .obj, .gltf or .glb; `-`: standard output).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print a report (docs/report-schema.md: the input's counts, stages, what was
    /// written in `details`) as one JSON object on standard output instead of the
    /// summary; refused with `-o -`.
    #[arg(long)]
    json: bool,
    /// Output format [default: from the output's extension].
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Write the drawable cells as triangles (one welded mesh per patch, with
    /// normals and vertex colours) instead of the nodes as points.
    #[arg(long)]
    cells: bool,
    /// Subtract this model-space point from every position (recorded in the
    /// file): keeps full f32 precision for tools that read f32 only.
    #[arg(long, value_name = "X,Y,Z", value_parser = super::render_values::parse_vec3, allow_hyphen_values = true)]
    origin: Option<DVec3>,
    /// PLY position type.
    #[arg(long, value_enum, default_value = "auto")]
    positions: PositionsArg,
}

/// The library options of `args`, the format taken from the output's
/// extension when not given.
fn options(args: &ExportArgs) -> anyhow::Result<ExportOptions> {
    let format = match args.format {
        Some(FormatArg::Ply) => Format::Ply,
        Some(FormatArg::Obj) => Format::Obj,
        Some(FormatArg::Gltf) => Format::Gltf,
        Some(FormatArg::Glb) => Format::Glb,
        None => chosen_format(&args.output)?,
    };
    let content = if args.cells {
        Content::Cells
    } else {
        Content::Nodes
    };
    let mut options = ExportOptions::new(format, content);
    options.origin = args.origin.unwrap_or(DVec3::ZERO);
    options.positions = match args.positions {
        PositionsArg::Auto => PositionType::Auto,
        PositionsArg::Float => PositionType::F32,
        PositionsArg::Double => PositionType::F64,
    };
    Ok(options)
}

/// The format `output`'s extension names; PLY (the format of earlier
/// versions) when it has none, such as `-` or a named pipe.
fn chosen_format(output: &std::path::Path) -> anyhow::Result<Format> {
    if output.extension().is_none() {
        return Ok(Format::Ply);
    }
    Format::from_path(output).ok_or_else(|| {
        anyhow::anyhow!(
            "{}: cannot tell the format from the extension: use .ply, .obj, .gltf or .glb, or --format",
            output.display()
        )
    })
}

/// The `details` of an export's report.
#[derive(Debug, Serialize)]
struct ExportDetails {
    /// `ply`, `obj`, `gltf` or `glb`.
    format: &'static str,
    /// `nodes` (points) or `cells` (triangles).
    content: &'static str,
    /// Meshes (or point sets) written, one per patch with something to export.
    meshes: usize,
    /// Vertices written.
    vertices: usize,
    /// Triangles written (0 for points).
    triangles: usize,
    /// Whether positions were written as f64.
    f64_positions: bool,
    /// The point subtracted from every position.
    origin: [f64; 3],
    /// Bytes of the exported file.
    bytes: usize,
}

/// Reads the scene and writes the export.
pub(crate) fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let options = options(args)?;
    let progress = Progress::new("export", 3);
    let started = Instant::now();
    progress.step("read");
    let (scene, info) = read_spatch(&args.input)?;
    let read_seconds = started.elapsed().as_secs_f64();
    progress.step("export");
    let export_started = Instant::now();
    let exported = export_scene(&scene, &options)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.output.display()))?;
    let export_seconds = export_started.elapsed().as_secs_f64();
    progress.step("write");
    let write_started = Instant::now();
    write_output(&args.output, &exported.bytes)?;
    let write_seconds = write_started.elapsed().as_secs_f64();
    drop(progress);
    if args.json {
        let details = export_details(args, &options, &exported);
        let mut report = Report::new(
            &tool(),
            "export",
            &args.input.display().to_string(),
            details,
        );
        report.output = Some(args.output.display().to_string());
        report.counts = Counts::of(&scene, info.file_len);
        report.diagonal = scene_diagonal(&scene);
        report.stages.push("read", read_seconds);
        report.stages.push("export", export_seconds);
        report.stages.push("write", write_seconds);
        report.seconds = started.elapsed().as_secs_f64();
        report.threads = 1;
        print_json(&report)?;
    }
    print_summary(&summary(args, &options, &exported), args.json)
}

/// The `details` of the report of an export that wrote `exported`.
fn export_details(
    args: &ExportArgs,
    options: &ExportOptions,
    exported: &Exported,
) -> ExportDetails {
    ExportDetails {
        format: options.format.name(),
        content: if args.cells { "cells" } else { "nodes" },
        meshes: exported.meshes,
        vertices: exported.vertices,
        triangles: exported.triangles,
        f64_positions: exported.f64_positions,
        origin: options.origin.to_array(),
        bytes: exported.bytes.len(),
    }
}

/// The one-line summary of an export that wrote `exported`.
fn summary(args: &ExportArgs, options: &ExportOptions, exported: &Exported) -> String {
    let what = if args.cells {
        format!(
            "{} meshes, {} vertices, {} triangles",
            exported.meshes, exported.vertices, exported.triangles
        )
    } else {
        format!("{} points", exported.vertices)
    };
    let precision = if options.format == Format::Ply && exported.f64_positions {
        ", double positions"
    } else {
        ""
    };
    format!(
        "{}: {} of {} ({}{precision}), {} bytes\n",
        args.output.display(),
        options.format.name(),
        args.input.display(),
        what,
        exported.bytes.len()
    )
}

impl ExportArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        let files = crate::overwrite_guard::Files::default()
            .input(Some(&self.input))
            .json_on_stdout(self.json);
        let written = match self.format {
            Some(FormatArg::Ply) => Written::Ply,
            Some(FormatArg::Obj) => Written::Obj,
            Some(FormatArg::Gltf) => Written::Gltf,
            Some(FormatArg::Glb) => Written::Glb,
            // The extension chooses the format, so it cannot name another one.
            None => return files.output(Some(&self.output)),
        };
        files.output_as(Some(&self.output), written)
    }
}
