//! `spatch plan`: streams a point cloud (or loads a mesh, tiled by face) and writes a tile
//! plan (docs/scale.md).

use std::path::PathBuf;
use std::time::Instant;

use spatch_cloud::CloudOptions;
use spatch_tiling::{make_plan, PlanOptions};

use crate::output::{print_summary, write_output};

/// Arguments of `spatch plan`.
#[derive(Debug, clap::Args)]
pub(crate) struct PlanArgs {
    /// Input point cloud, read as a stream: .ply (ASCII or binary), .las/.laz,
    /// .xyz/.txt/.pts, or a scan set with its poses (.e57, or a Stanford .conf whose scans
    /// are in those formats); or a mesh (.obj, .gltf/.glb, .off, .stl, or a .ply with faces),
    /// tiled by face for `spatch convert --plan`.
    #[arg(value_name = "INPUT")]
    input: PathBuf,
    /// Side of a tile, in model units. Each tile's range images (with its buffer) must fit
    /// the pixel budget of 16 M pixels over the views: about 90 m at 0.1 m spacing.
    #[arg(long, value_name = "SIZE")]
    tile: f64,
    /// Buffer around a tile whose points its conversion reads, in model units (default:
    /// 16 pixels, the gap filling and smoothing reach with room to spare; for a mesh, 4
    /// node spacings, at most a quarter tile: the surface border patches reach into).
    #[arg(long, value_name = "B")]
    buffer: Option<f64>,
    /// Point spacing every tile converts with (default: estimated on the most populous
    /// tile; for a mesh, the node spacing `spatch convert` derives for the whole mesh).
    #[arg(long)]
    spacing: Option<f32>,
    /// Pixel (node) spacing in multiples of the point spacing, shared by every tile.
    #[arg(long, default_value_t = CloudOptions::DEFAULT_PIXEL_FACTOR)]
    pixel_factor: f32,
    /// Output plan (JSON).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
}

impl PlanArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .input(Some(&self.input))
            .output_as(Some(&self.output), Written::Json)
    }

    /// The library options.
    pub(crate) fn plan_options(&self) -> PlanOptions {
        PlanOptions {
            tile: self.tile,
            buffer: self.buffer,
            spacing: self.spacing,
            pixel_factor: self.pixel_factor,
        }
    }
}

/// Plans, writes the plan, prints a summary.
pub(crate) fn run(args: &PlanArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let mesh = super::convert_plan::is_mesh(&args.input);
    let plan = if mesh {
        super::convert_plan::plan_mesh(&args.input, args.tile, args.buffer, args.spacing)?
    } else {
        let mut plan = make_plan(&args.input, &args.plan_options()).map_err(anyhow::Error::msg)?;
        // A scan set whose scanners are known: its scans aligned once, for every tile.
        let spill = args.output.with_extension("spill");
        super::tiled::plan_scan_shifts(&args.input, &mut plan, &spill)?;
        plan
    };
    write_output(&args.output, plan.to_json().as_bytes())?;
    let most = plan.tiles.iter().map(|t| t.points).max().unwrap_or(0);
    let items = if mesh { "faces" } else { "points" };
    print_summary(
        &format!(
            "{}: {} tiles of {} (buffer {:.4}) over {} {items}, at most {} a tile; spacing {:.4e}, pixel {:.4e}; {:.2} s\n",
            args.output.display(),
            plan.tiles.len(),
            plan.grid.size,
            plan.grid.buffer,
            plan.points,
            most,
            plan.spacing,
            plan.spacing * plan.pixel_factor,
            started.elapsed().as_secs_f64()
        ),
        false,
    )
}
