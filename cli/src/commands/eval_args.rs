//! The flags of `spatch eval` and the library options they give.

use std::path::PathBuf;

use spatch_eval::sweep::Width;
use spatch_eval::{views_for_count, ImageOptions, SweepOptions, MAX_VIEWS};
use spatch_render::RenderOptions;

use super::render_values::{CellsArg, CullArg, ModeArg, ProjectionArg, ShadingArg};
use super::ThreadsArg;

/// Default number of views of `spatch eval` (the 6 axes and 8 diagonals).
pub(super) const EVAL_VIEWS: usize = 14;
/// Default number of views of the sweep's render rows (the 6 axes).
const SWEEP_VIEWS: usize = 6;

/// Arguments of `spatch eval`.
#[derive(Debug, clap::Args)]
pub(crate) struct EvalArgs {
    /// The .spatch scene to measure (not with --sweep).
    #[arg(
        value_name = "SCENE",
        required_unless_present = "sweep",
        conflicts_with = "sweep"
    )]
    pub(super) scene: Option<PathBuf>,
    /// The source the scene was made from: a mesh (.obj, .gltf, .glb, .ply, .off, .stl) or a point
    /// cloud (.xyz, .txt, .pts, or a .ply without faces). A source that does not overlap the
    /// scene (bounding boxes apart even when each is grown by 1 % of the larger diagonal) is
    /// refused before anything is measured.
    #[arg(
        long,
        value_name = "MESH|CLOUD",
        required_unless_present = "sweep",
        conflicts_with = "sweep"
    )]
    pub(super) source: Option<PathBuf>,
    /// Views of the image error: 1-14 take the standard views in order (6 axes, then 8
    /// diagonals), more are spread evenly (up to 256) [default: 14; 6 with --sweep].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=MAX_VIEWS as i64))]
    views: Option<u16>,
    /// Side of the square images of the image error, in pixels (16-4096).
    #[arg(long, value_name = "PX", default_value_t = 500, value_parser = clap::value_parser!(u32).range(16..=4096))]
    size: u32,
    /// Timed frames per view (after one warm-up), of the patches and of the source mesh alike;
    /// the medians are reported (1-100).
    #[arg(long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    runs: u32,
    /// Patches, or every cell as two triangles through the scan-line rasterizer (the
    /// baseline the patch renders' specks and times compare with; not with --sweep).
    #[arg(long, value_enum, default_value_t = ModeArg::Patches, conflicts_with = "sweep")]
    mode: ModeArg,
    /// Back-face culling of the patch renders, as `spatch render --cull` (the source is
    /// culled only where it is closed, whatever this says; not with --sweep).
    #[arg(long, value_enum, default_value_t = CullArg::Auto, conflicts_with = "sweep")]
    cull: CullArg,
    /// Node projection of the patch renders (not with --sweep, which tries both).
    #[arg(long, value_enum, default_value_t = ProjectionArg::Trilinear, conflicts_with = "sweep")]
    projection: ProjectionArg,
    /// Cell filling of the patch renders (not with --sweep, which tries both).
    #[arg(long, value_enum, default_value_t = CellsArg::Bilinear, conflicts_with = "sweep")]
    cells: CellsArg,
    /// Shading of both the source and the patch renders (not with --sweep); `unlit` compares
    /// the albedo alone (colour and texture, no light), as `spatch render --shading unlit`.
    #[arg(long, value_enum, default_value_t = ShadingArg::Phong, conflicts_with = "sweep")]
    pub(super) shading: ShadingArg,
    /// Draw coloured patches' cells by pixel-centre coverage, as `spatch
    /// render --exact-outlines`.
    #[arg(long, conflicts_with = "sweep")]
    exact_outlines: bool,
    /// Let the cells of patches with a colour grid reach about half a pixel
    /// past the outline (sub-nodes) instead of the default pixel-centre
    /// coverage: fuze, unlit, 30.3 -> 27.9 dB against its source. Scenes
    /// without colour grids draw the same either way.
    #[arg(long)]
    no_exact_grid_outlines: bool,
    /// Draw the patches with the gap fill, as `spatch render --gap-fill`.
    #[arg(long, conflicts_with = "sweep")]
    gap_fill: bool,
    /// Splat limit of the patch renders in pixels (see `spatch render
    /// --splat-limit`; 0 = off, the default; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_SPLAT_LIMIT, conflicts_with = "sweep")]
    splat_limit: f32,
    /// Geometry limit of the patch renders in pixels (see `spatch render
    /// --geometry-limit`; 0 = off, the default; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_GEOMETRY_LIMIT, conflicts_with = "sweep")]
    geometry_limit: f32,
    /// Geometry tolerance of the patch renders in node spacings (see
    /// `spatch render --geometry-tolerance`; 0 = none, the default).
    #[arg(long, value_name = "T", default_value_t = RenderOptions::DEFAULT_GEOMETRY_TOLERANCE, conflicts_with = "sweep")]
    geometry_tolerance: f32,
    /// Mip limit of the patch renders in pixels (see `spatch render
    /// --mip-limit`; 0.1..=16, default 3; not with --sweep): what a
    /// coarser level costs in PSNR and holes.
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_MIP_LIMIT, conflicts_with = "sweep")]
    mip_limit: f32,
    /// Mip tolerance of the patch renders in pixels (see `spatch render
    /// --mip-tolerance`; 0..=2, default 0.25, 0 = off; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_MIP_TOLERANCE, conflicts_with = "sweep")]
    mip_tolerance: f32,
    /// Level-one limit of the patch renders in pixels (see `spatch render
    /// --level-one-limit`; 0 = off, the default; not with --sweep).
    #[arg(
        long,
        value_name = "PX",
        default_value_t = 0.0,
        conflicts_with = "sweep"
    )]
    level_one_limit: f32,
    /// Centre limit of the patch renders in pixels (see `spatch render
    /// --centre-limit`; 0 = off; not with --sweep).
    #[arg(long, value_name = "PX", default_value_t = RenderOptions::DEFAULT_CENTRE_LIMIT, conflicts_with = "sweep")]
    centre_limit: f32,
    /// Skip the image error (geometric error only).
    #[arg(long, conflicts_with = "sweep")]
    pub(super) no_images: bool,
    /// Write the error of every patch as CSV (to find the worst patch).
    #[arg(long, value_name = "FILE", conflicts_with = "sweep")]
    pub(super) per_patch: Option<PathBuf>,
    /// Print the JSON report (docs/report-schema.md) instead of the summary.
    #[arg(long, conflicts_with = "sweep")]
    pub(super) json: bool,
    /// Also write the JSON report to this file.
    #[arg(long, value_name = "FILE", conflicts_with = "sweep")]
    pub(super) report: Option<PathBuf>,
    #[command(flatten)]
    pub(super) threads: ThreadsArg,
    /// Sweep conversion and render settings on this mesh, writing sweep.csv, sweep.json and
    /// sweep.svg (error against time, Pareto front marked) into --out.
    #[arg(long, value_name = "MESH", requires = "out")]
    pub(super) sweep: Option<PathBuf>,
    /// Folder for the sweep's files (created if missing).
    #[arg(long, value_name = "DIR", requires = "sweep")]
    pub(super) out: Option<PathBuf>,
    /// Sweep: grid sizes (nodes per patch side, 2-257).
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "5,9,17,33", requires = "sweep", value_parser = clap::value_parser!(u32).range(2..=257))]
    grids: Vec<u32>,
    /// Sweep: cone angles in degrees (0-89].
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "15,30,45", requires = "sweep", value_parser = cone_angle)]
    cone_angles: Vec<f32>,
    /// Sweep: displacement widths, 8 and/or 16.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "8,16", requires = "sweep", value_parser = width)]
    widths: Vec<u8>,
    /// Sweep: grids whose scenes the render settings (trilinear/exact x bilinear/smooth) are
    /// measured on; each must be one of --grids.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_value = "9,17,33", requires = "sweep", value_parser = clap::value_parser!(u32).range(2..=257))]
    render_grids: Vec<u32>,
    /// Sweep: leave out the render rows.
    #[arg(long, requires = "sweep")]
    no_render: bool,
    /// Sweep: conversions per setting; the median time is kept (1-100).
    #[arg(long, value_name = "N", default_value_t = 3, requires = "sweep", value_parser = clap::value_parser!(u32).range(1..=100))]
    repeats: u32,
}

fn cone_angle(s: &str) -> Result<f32, String> {
    let v: f32 = s.trim().parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && v > 0.0 && v <= 89.0 {
        Ok(v)
    } else {
        Err("must be in (0, 89] degrees".to_owned())
    }
}

fn width(s: &str) -> Result<u8, String> {
    match s.trim() {
        "8" => Ok(8),
        "16" => Ok(16),
        _ => Err("must be 8 or 16".to_owned()),
    }
}

impl EvalArgs {
    /// The render options of the image error.
    pub(super) fn render_options(&self) -> RenderOptions {
        let mut render = RenderOptions::default();
        render.mode = self.mode.into();
        render.culling = self.cull.into();
        render.projection = self.projection.into();
        render.cells = self.cells.into();
        self.shading.apply(&mut render);
        render.exact_outlines = self.exact_outlines;
        render.exact_grid_outlines = !self.no_exact_grid_outlines;
        render.gap_fill = self.gap_fill;
        render.threads = self.threads.count();
        render.splat_limit = self.splat_limit;
        render.geometry_limit = self.geometry_limit;
        render.geometry_tolerance = self.geometry_tolerance;
        render.centre_limit = self.centre_limit;
        render.mip_limit = self.mip_limit;
        render.mip_tolerance = self.mip_tolerance;
        render.level_one_limit = self.level_one_limit;
        // The eval times whole frames only: no clock reads per patch.
        render.stage_times = false;
        render
    }

    pub(super) fn image_options(&self, default_views: usize) -> anyhow::Result<ImageOptions> {
        let count = self.views.map_or(default_views, usize::from);
        let mut image = ImageOptions::default();
        image.views = views_for_count(count)
            .ok_or_else(|| anyhow::anyhow!("--views must be in 1..={MAX_VIEWS}"))?;
        image.size = [self.size, self.size];
        image.render = self.render_options();
        image.runs = self.runs as usize;
        Ok(image)
    }

    pub(super) fn sweep_options(&self) -> anyhow::Result<SweepOptions> {
        let mut options = SweepOptions::default();
        options.grids = self.grids.clone();
        options.cone_angles = self.cone_angles.clone();
        options.widths = self
            .widths
            .iter()
            .map(|&w| {
                if w == 16 {
                    Width::Sixteen
                } else {
                    Width::Eight
                }
            })
            .collect();
        options.render_grids = if self.no_render {
            Vec::new()
        } else {
            self.render_grids.clone()
        };
        options.image = self.image_options(SWEEP_VIEWS)?;
        options.repeats = self.repeats as usize;
        Ok(options)
    }
}

impl EvalArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .input(self.scene.as_deref())
            .input(self.source.as_deref())
            .input(self.sweep.as_deref())
            .output_as(self.per_patch.as_deref(), Written::Csv)
            .output_as(self.report.as_deref(), Written::Json)
            .json_on_stdout(self.json)
    }
}
