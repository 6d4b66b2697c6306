//! `spatch from-cloud --plan`: one tile of a plan (`--tile K`), or every tile on this
//! machine with rayon plus the tiled scene's index (`-o DIR`, or `--plan-tile SIZE`, which
//! makes the plan first). Every tile converts with the plan's spacing, pixel factor and
//! grid, reading only its own and its buffer's points (docs/scale.md); a local run reads
//! the input once, spilling every tile's points to a file of its own first.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::Context;
use glam::DVec3;
use spatch_cloud::{cloud_to_scene, CloudError, CloudOptions, Scanner};
use spatch_format::{encode_scene, ColourChannel, Scene};
use spatch_tiling::{
    build_index, make_plan, read_spilled_tile, read_tile, spill_tiles, spilled_scan_shifts,
    tile_file_name, tile_scanners, Plan, PlanOptions, PlanTile, Spill, TileCloud, SPILL_BUDGET,
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

/// What a planned run knows of its input's scans (`spatch_scan::scan_viewpoints`).
#[derive(Clone, Debug, Default)]
pub(crate) struct PlanScans {
    /// Every scan's scanner, in stream order, when every scan has one (sight lines).
    pub(crate) scanners: Option<Vec<Scanner>>,
    /// Scans in the input.
    pub(crate) count: usize,
}

impl PlanScans {
    /// The scanners of the scans of `input` (read from headers only), with `options`.
    pub(crate) fn of(input: &Path, options: &spatch_scan::ScanOptions) -> anyhow::Result<Self> {
        let viewpoints = spatch_scan::scan_viewpoints(input, options).map_err(|e| match e {
            spatch_scan::ScanError::Bug(_) => anyhow::Error::new(InternalFailure(e.to_string())),
            e => anyhow::Error::msg(e.to_string()),
        })?;
        let scanners = viewpoints
            .iter()
            .map(|v| v.map(super::cloud_scanners::scanner_of))
            .collect::<Option<Vec<Scanner>>>();
        Ok(PlanScans {
            scanners,
            count: viewpoints.len(),
        })
    }

    /// Whether the scans are aligned once for every tile: the scanners are known and the
    /// options ask for the consensus and the alignment.
    fn aligned(&self, options: &CloudOptions) -> bool {
        self.scanners.is_some() && options.consensus && options.align_scans
    }
}

/// The options of every tile of `plan`: `base` with the plan's spacing, pixel factor and
/// grid, and its scan shifts (without them, no tile aligns its scans: each would move them
/// differently).
fn plan_options(plan: &Plan, base: &CloudOptions) -> anyhow::Result<CloudOptions> {
    let mut options = base.clone();
    options.spacing = Some(plan.spacing);
    options.pixel_factor = plan.pixel_factor;
    options.scan_shifts = plan
        .scan_shifts
        .as_ref()
        .map(|s| s.iter().map(|&t| DVec3::from_array(t)).collect());
    options.align_scans &= options.scan_shifts.is_some();
    options.tile_grid = Some(
        plan.grid
            .tile_grid()
            .context("the plan's grid is out of range")?,
    );
    Ok(options)
}

/// Converts one tile of `plan` from `input`, reading only its points and its buffer's.
pub(crate) fn convert_plan_tile(
    input: &Path,
    plan: &Plan,
    tile: &PlanTile,
    base: &CloudOptions,
    scans: &PlanScans,
) -> anyhow::Result<TileResult> {
    let grid = plan_options(plan, base)?.tile_grid.context("no grid")?;
    let points = read_tile(input, &grid, tile.key).map_err(anyhow::Error::msg)?;
    convert_tile_cloud(input, plan, tile, &points, base, scans)
}

/// Converts tile `tile` of `plan` given its points and its buffer's (`points.cloud`, placed
/// at the tile's lowest corner), each point with its scan's scanner when `scans` knows
/// them; a tile whose points hold no surface (too few, no extent) gives a scene with no
/// patch, so every tile has a file.
fn convert_tile_cloud(
    input: &Path,
    plan: &Plan,
    tile: &PlanTile,
    points: &TileCloud,
    base: &CloudOptions,
    scans: &PlanScans,
) -> anyhow::Result<TileResult> {
    let label = || format!("{} (tile {})", input.display(), tile.index);
    let mut options = plan_options(plan, base)?;
    options.only_tile = Some(tile.key);
    options.scanners = scans
        .scanners
        .as_ref()
        .map(|s| tile_scanners(s, &points.scan_points));
    let cloud = &points.cloud;
    let scene = match cloud_to_scene(cloud, &options) {
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
        own: points.own,
    })
}

/// `--plan P --tile K -o FILE`.
pub(crate) fn run_one(
    input: &Path,
    plan_path: &Path,
    tile: usize,
    output: &Path,
    base: &CloudOptions,
    scans: &PlanScans,
) -> anyhow::Result<()> {
    let plan = Plan::read(plan_path).map_err(anyhow::Error::msg)?;
    let entry = plan
        .tile(tile)
        .map_err(|e| anyhow::anyhow!("{}: {e}", plan_path.display()))?;
    let started = Instant::now();
    let result = convert_plan_tile(input, &plan, entry, base, scans)?;
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

/// `--plan P -o DIR` or `--plan-tile SIZE -o DIR`: every tile, then `DIR/index.json`. A
/// plan made here (`--plan-tile`) gets the scan shifts of a scan set whose scans are
/// aligned, computed from the spill before any tile converts, and is written with them.
pub(crate) fn run_all(
    input: &Path,
    plan: PlanSource<'_>,
    dir: &Path,
    base: &CloudOptions,
    scans: &PlanScans,
) -> anyhow::Result<()> {
    let started = Instant::now();
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let (mut plan, made) = match plan {
        PlanSource::File(path) => (Plan::read(path).map_err(anyhow::Error::msg)?, false),
        PlanSource::Make(options) => (
            make_plan(input, &options).map_err(anyhow::Error::msg)?,
            true,
        ),
    };
    let spill_dir = dir.join(".spill");
    let spill_started = Instant::now();
    let spill = spill_input(input, &plan, &spill_dir)?;
    let spill_seconds = spill_started.elapsed().as_secs_f64();
    if made {
        add_scan_shifts(&mut plan, &spill, base, scans).inspect_err(|_| {
            let _ = std::fs::remove_dir_all(&spill_dir);
        })?;
        write_output(&dir.join("plan.json"), plan.to_json().as_bytes())?;
    }
    let results = convert_spilled(input, &plan, &spill, &spill_dir, dir, base, scans)?;
    let index = build_index(&plan, dir).map_err(anyhow::Error::msg)?;
    let index_path = dir.join("index.json");
    write_output(&index_path, index.to_json().as_bytes())?;
    let patches: usize = results.iter().map(|r| r.0).sum();
    let nodes: usize = results.iter().map(|r| r.1).sum();
    let seconds = started.elapsed().as_secs_f64();
    print_summary(
        &format!(
            "{}: {} tiles, {} patches, {} nodes from {} points in {:.2} s ({:.0} points/s, {} threads; spill {:.2} s)\n",
            index_path.display(),
            plan.tiles.len(),
            patches,
            nodes,
            plan.points,
            seconds,
            plan.points as f64 / seconds.max(1e-9),
            rayon::current_num_threads(),
            spill_seconds,
        ),
        false,
    )
}

/// A converted tile's patches, nodes and own points.
type TileCounts = (usize, usize, u64);

/// Gives `plan` the scan shifts of its scan set from its `spill` when `scans` are aligned
/// with `options` (`spatch_tiling::spilled_scan_shifts`).
fn add_scan_shifts(
    plan: &mut Plan,
    spill: &Spill,
    options: &CloudOptions,
    scans: &PlanScans,
) -> anyhow::Result<()> {
    if let Some(scanners) = scans.scanners.as_ref().filter(|_| scans.aligned(options)) {
        let shifts = spilled_scan_shifts(spill, scanners, options, plan.spacing)
            .map_err(anyhow::Error::msg)?;
        plan.scan_shifts = Some(shifts.iter().map(|t| t.to_array()).collect());
    }
    Ok(())
}

/// `spatch plan` of a scan set: the plan's scan shifts (with the default options), from a
/// spill into the folder `spill_dir`, removed afterwards.
pub(crate) fn plan_scan_shifts(
    input: &Path,
    plan: &mut Plan,
    spill_dir: &Path,
) -> anyhow::Result<()> {
    let scans = PlanScans::of(input, &spatch_scan::ScanOptions::default())?;
    let mut options = CloudOptions::default();
    options.consensus = scans.count > 1;
    if !scans.aligned(&options) {
        return Ok(());
    }
    let spill = spill_input(input, plan, spill_dir)?;
    let added = add_scan_shifts(plan, &spill, &options, &scans);
    std::fs::remove_dir_all(spill_dir)
        .with_context(|| format!("{}: cannot remove", spill_dir.display()))?;
    added
}

/// One streamed pass over `input` spilling every tile of `plan` into `spill_dir` (created;
/// removed again when the pass fails).
fn spill_input(input: &Path, plan: &Plan, spill_dir: &Path) -> anyhow::Result<Spill> {
    let grid = plan
        .grid
        .tile_grid()
        .context("the plan's grid is out of range")?;
    std::fs::create_dir_all(spill_dir)
        .with_context(|| format!("{}: cannot create", spill_dir.display()))?;
    let keys: Vec<[i64; 3]> = plan.tiles.iter().map(|t| t.key).collect();
    spill_tiles(input, &grid, &keys, spill_dir, SPILL_BUDGET).map_err(|e| {
        let _ = std::fs::remove_dir_all(spill_dir);
        anyhow::Error::msg(e)
    })
}

/// Every tile of `plan` from its `spill` (in `spill_dir`): as many workers as rayon has
/// threads take the tiles, largest first,
/// one at a time each (so at most that many tiles are in memory: a nested rayon loop could
/// steal another whole tile while it waits), each conversion using the rayon pool, each
/// spill file removed once its tile is written. Returns each tile's patches, nodes and own
/// points.
fn convert_spilled(
    input: &Path,
    plan: &Plan,
    spill: &Spill,
    spill_dir: &Path,
    dir: &Path,
    base: &CloudOptions,
    scans: &PlanScans,
) -> anyhow::Result<Vec<TileCounts>> {
    let mut order: Vec<usize> = (0..plan.tiles.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(spill.tiles[i].points));
    let (next, failed) = (AtomicUsize::new(0), AtomicBool::new(false));
    let convert = |i: usize| -> anyhow::Result<TileCounts> {
        let tile = &plan.tiles[i];
        let (cloud, own) = read_spilled_tile(spill, i).map_err(anyhow::Error::msg)?;
        let scan_points = spill.tiles[i].scan_points.clone();
        let points = TileCloud {
            cloud,
            own,
            scan_points,
        };
        let result = convert_tile_cloud(input, plan, tile, &points, base, scans)?;
        drop(points);
        write_output(&dir.join(tile_file_name(tile.index)), &result.bytes)?;
        remove_spill(&spill.tiles[i].path)?;
        Ok((result.patches, result.nodes, result.own))
    };
    let worker = || -> anyhow::Result<Vec<(usize, TileCounts)>> {
        let mut done = Vec::new();
        while let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
            if failed.load(Ordering::Relaxed) {
                break;
            }
            let result = convert(i).inspect_err(|_| failed.store(true, Ordering::Relaxed))?;
            done.push((i, result));
        }
        Ok(done)
    };
    let workers = rayon::current_num_threads().clamp(1, plan.tiles.len().max(1));
    let results = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers).map(|_| scope.spawn(worker)).collect();
        let mut all = Vec::new();
        for handle in handles {
            let done = handle
                .join()
                .map_err(|_| InternalFailure("a tile worker panicked".to_string()))??;
            all.extend(done);
        }
        anyhow::Ok(all)
    });
    let mut results = results.inspect_err(|_| {
        // A failed run leaves no spill behind (its error is what is reported).
        let _ = std::fs::remove_dir_all(spill_dir);
    })?;
    std::fs::remove_dir(spill_dir)
        .with_context(|| format!("{}: cannot remove", spill_dir.display()))?;
    results.sort_by_key(|r| r.0);
    Ok(results.into_iter().map(|r| r.1).collect())
}

/// Removes a tile's spill file (absent when the tile received no point).
fn remove_spill(path: &Path) -> anyhow::Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(anyhow::Error::new(e).context(format!("{}: cannot remove", path.display())))
        }
        _ => Ok(()),
    }
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
