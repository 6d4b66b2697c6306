//! `spatch from-cloud --plan`: one tile of a plan (`--tile K`), or every tile on this
//! machine with rayon plus the tiled scene's index (`-o DIR`, or `--plan-tile SIZE`, which
//! makes the plan first). Every tile converts with the plan's spacing, pixel factor and
//! grid, reading only its own and its buffer's points (docs/scale.md).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use rayon::prelude::*;
use spatch_cloud::{cloud_to_scene, CloudError, CloudOptions};
use spatch_format::{encode_scene, ColourChannel, Scene};
use spatch_tiling::{
    build_index, make_plan, read_tile_points, tile_file_name, Plan, PlanOptions, PlanTile,
};

use crate::failure::InternalFailure;
use crate::output::{print_summary, write_output};

/// One converted tile.
pub(crate) struct TileResult {
    /// The scene's bytes.
    pub(crate) bytes: Vec<u8>,
    /// Patches.
    pub(crate) patches: usize,
    /// Grid nodes.
    pub(crate) nodes: usize,
    /// Points read (own and buffer).
    pub(crate) points: usize,
    /// Points the tile owns.
    pub(crate) own: u64,
}

/// The options of every tile of `plan`: `base` with the plan's spacing, pixel factor and
/// grid.
fn plan_options(plan: &Plan, base: &CloudOptions) -> anyhow::Result<CloudOptions> {
    let mut options = base.clone();
    options.spacing = Some(plan.spacing);
    options.pixel_factor = plan.pixel_factor;
    options.tile_grid = Some(
        plan.grid
            .tile_grid()
            .context("the plan's grid is out of range")?,
    );
    Ok(options)
}

/// Converts one tile of `plan` from `input`; a tile whose points hold no surface (too few,
/// no extent) gives a scene with no patch, so every tile has a file.
pub(crate) fn convert_plan_tile(
    input: &Path,
    plan: &Plan,
    tile: &PlanTile,
    base: &CloudOptions,
) -> anyhow::Result<TileResult> {
    let label = || format!("{} (tile {})", input.display(), tile.index);
    let mut options = plan_options(plan, base)?;
    options.only_tile = Some(tile.key);
    let grid = options.tile_grid.context("no grid")?;
    let (cloud, own) = read_tile_points(input, &grid, tile.key).map_err(anyhow::Error::msg)?;
    let scene = match cloud_to_scene(&cloud, &options) {
        Ok(conversion) => conversion.scene,
        Err(
            CloudError::NoSurface { .. }
            | CloudError::EmptyCloud { .. }
            | CloudError::TooFewPoints { .. }
            | CloudError::NoExtent { .. },
        ) => Scene::new(cloud.origin, ColourChannel::None, Vec::new())
            .map_err(|e| InternalFailure(format!("{}: empty scene: {e}", label())))?,
        Err(e @ (CloudError::Bug(_) | CloudError::Internal { .. })) => {
            return Err(InternalFailure(format!("{}: {e}", label())).into())
        }
        Err(e) => return Err(anyhow::anyhow!("{}: {e}", label())),
    };
    let bytes = encode_scene(&scene, &options.write)
        .map_err(|e| InternalFailure(format!("{}: encoding: {e}", label())))?;
    Ok(TileResult {
        bytes,
        patches: scene.patches().len(),
        nodes: scene.node_count(),
        points: cloud.positions.len(),
        own,
    })
}

/// `--plan P --tile K -o FILE`.
pub(crate) fn run_one(
    input: &Path,
    plan_path: &Path,
    tile: usize,
    output: &Path,
    base: &CloudOptions,
) -> anyhow::Result<()> {
    let plan = Plan::read(plan_path).map_err(anyhow::Error::msg)?;
    let entry = plan
        .tile(tile)
        .map_err(|e| anyhow::anyhow!("{}: {e}", plan_path.display()))?;
    let started = Instant::now();
    let result = convert_plan_tile(input, &plan, entry, base)?;
    write_output(output, &result.bytes)?;
    print_summary(
        &format!(
            "{}: tile {} of {}: {} patches, {} nodes from {} points ({} its own), {} bytes, {:.2} s\n",
            output.display(),
            tile,
            plan.tiles.len(),
            result.patches,
            result.nodes,
            result.points,
            result.own,
            result.bytes.len(),
            started.elapsed().as_secs_f64()
        ),
        false,
    )
}

/// `--plan P -o DIR` or `--plan-tile SIZE -o DIR`: every tile, then `DIR/index.json`.
pub(crate) fn run_all(
    input: &Path,
    plan: PlanSource<'_>,
    dir: &Path,
    base: &CloudOptions,
) -> anyhow::Result<()> {
    let started = Instant::now();
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let plan = match plan {
        PlanSource::File(path) => Plan::read(path).map_err(anyhow::Error::msg)?,
        PlanSource::Make(options) => {
            let plan = make_plan(input, &options).map_err(anyhow::Error::msg)?;
            write_output(&dir.join("plan.json"), plan.to_json().as_bytes())?;
            plan
        }
    };
    let results: Vec<(usize, usize, u64)> = plan
        .tiles
        .par_iter()
        .map(|tile| {
            let result = convert_plan_tile(input, &plan, tile, base)?;
            write_output(&dir.join(tile_file_name(tile.index)), &result.bytes)?;
            Ok((result.patches, result.nodes, result.own))
        })
        .collect::<anyhow::Result<_>>()?;
    let index = build_index(&plan, dir).map_err(anyhow::Error::msg)?;
    let index_path = dir.join("index.json");
    write_output(&index_path, index.to_json().as_bytes())?;
    let patches: usize = results.iter().map(|r| r.0).sum();
    let nodes: usize = results.iter().map(|r| r.1).sum();
    let seconds = started.elapsed().as_secs_f64();
    print_summary(
        &format!(
            "{}: {} tiles, {} patches, {} nodes from {} points in {:.2} s ({:.0} points/s, {} threads)\n",
            index_path.display(),
            plan.tiles.len(),
            patches,
            nodes,
            plan.points,
            seconds,
            plan.points as f64 / seconds.max(1e-9),
            rayon::current_num_threads(),
        ),
        false,
    )
}

/// Where a local run's plan comes from.
pub(crate) enum PlanSource<'a> {
    /// A plan file.
    File(&'a Path),
    /// Made from the input with these options (and written as `DIR/plan.json`).
    Make(PlanOptions),
}

/// The single input of a planned run, or why there is not one.
pub(crate) fn single_input(inputs: &[PathBuf]) -> anyhow::Result<&Path> {
    match inputs {
        [one] => Ok(one),
        _ => anyhow::bail!("--plan and --plan-tile take exactly one input cloud"),
    }
}
