//! `spatch export`: nodes as points or cells as welded patch meshes, in
//! PLY, OBJ, glTF or GLB.

use std::path::PathBuf;

use clap::ValueEnum;
use glam::DVec3;
use spatch_export::{export_scene, Content, ExportOptions, Format, PositionType};

use crate::output::{print_stdout, read_spatch, write_output};

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
    /// Output file (.ply, .obj, .gltf or .glb).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Output format [default: from the output's extension].
    #[arg(long, value_enum)]
    format: Option<FormatArg>,
    /// Write the drawable cells as triangles (one welded mesh per patch, with
    /// normals and vertex colours) instead of the nodes as points.
    #[arg(long)]
    cells: bool,
    /// Subtract this model-space point from every position (recorded in the
    /// file): keeps full f32 precision for tools that read f32 only.
    #[arg(long, value_name = "X,Y,Z", value_parser = super::render::parse_vec3, allow_hyphen_values = true)]
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

/// Reads the scene and writes the export.
pub(crate) fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let options = options(args)?;
    let (scene, _) = read_spatch(&args.input)?;
    let exported = export_scene(&scene, &options)
        .map_err(|e| anyhow::anyhow!("{}: {e}", args.output.display()))?;
    write_output(&args.output, &exported.bytes)?;
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
    print_stdout(&format!(
        "{}: {} of {} ({}{precision}), {} bytes\n",
        args.output.display(),
        options.format.name(),
        args.input.display(),
        what,
        exported.bytes.len()
    ))
}

impl ExportArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        let files = crate::overwrite_guard::Files::default().input(Some(&self.input));
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
