//! `spatch export`: nodes or cells as a PLY file.

use std::path::PathBuf;

use spatch_export::{export_cells_ply, export_nodes_ply};

use crate::output::{print_stdout, read_spatch, write_output};

/// Arguments of `spatch export`.
#[derive(Debug, clap::Args)]
pub(crate) struct ExportArgs {
    /// Input .spatch file (`-`: standard input, at most 1 GiB).
    #[arg(value_name = "FILE")]
    input: PathBuf,
    /// Output .ply file (binary little-endian).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Write the drawable cells as a triangle mesh instead of the nodes as points.
    #[arg(long)]
    cells: bool,
}

/// Reads the scene and writes the PLY.
pub(crate) fn run(args: &ExportArgs) -> anyhow::Result<()> {
    let (scene, _) = read_spatch(&args.input)?;
    let bytes = if args.cells {
        export_cells_ply(&scene)
    } else {
        export_nodes_ply(&scene)
    };
    write_output(&args.output, &bytes)?;
    print_stdout(&format!(
        "{}: {} {}, {} bytes\n",
        args.output.display(),
        if args.cells { "cells of" } else { "nodes of" },
        args.input.display(),
        bytes.len()
    ))
}

impl ExportArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .input(Some(&self.input))
            .output_as(Some(&self.output), Written::Ply)
    }
}
