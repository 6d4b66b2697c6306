//! `spatch index`: the tiled scene index of a plan's tile files (docs/scale.md), for runs
//! that converted the tiles elsewhere (GNU parallel, Dask).

use std::path::PathBuf;

use spatch_tiling::{build_index, Plan};

use crate::output::{print_summary, write_output};

/// Arguments of `spatch index`.
#[derive(Debug, clap::Args)]
pub(crate) struct IndexArgs {
    /// The plan the tiles were converted with.
    #[arg(value_name = "PLAN")]
    plan: PathBuf,
    /// The folder holding the tiles (`tile_00000.spatch`, ...); the index is written there
    /// as `index.json`.
    #[arg(value_name = "DIR")]
    dir: PathBuf,
}

impl IndexArgs {
    /// The files this run reads (the index is named by the folder).
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        crate::overwrite_guard::Files::default().input(Some(&self.plan))
    }
}

/// Reads every tile, writes the index.
pub(crate) fn run(args: &IndexArgs) -> anyhow::Result<()> {
    let plan = Plan::read(&args.plan).map_err(anyhow::Error::msg)?;
    let index = build_index(&plan, &args.dir).map_err(anyhow::Error::msg)?;
    let path = args.dir.join("index.json");
    write_output(&path, index.to_json().as_bytes())?;
    let patches: usize = index.tiles.iter().map(|t| t.patches).sum();
    print_summary(
        &format!(
            "{}: {} tiles, {} patches\n",
            path.display(),
            index.tiles.len(),
            patches
        ),
        false,
    )
}
