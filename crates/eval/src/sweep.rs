//! Error against time over a grid of settings (DESIGN §6, `spatch eval --sweep`).
//!
//! Two kinds of settings, measured differently because they change different things:
//!
//! - **conversion settings** — grid size, cone angle, displacement width — change the scene.
//!   Each is converted `repeats` times (the median time is kept) and its scene measured
//!   against the source (`node_to_surface`, `surface_to_patch`; the samples and the source's
//!   BVH are built once and shared). Not the full product: grid × width at the base cone
//!   angle, then cone angle × width at the base grid (4 × 2 + 2 × 2 = 12 conversions by
//!   default instead of 4 × 3 × 2 = 24), since the cone angle and the grid act on different
//!   stages (segmentation, fitting) and their interaction is small.
//! - **render settings** — trilinear or exact projection, bilinear or smooth cells — change
//!   only the image and the frame time. They are measured on the scenes of a few grids
//!   (`render_grids`, at the base cone angle and 8 bits), with the source's frames rendered
//!   once and shared ([`SourceViews`]).
//!
//! Each row is one setting; its Pareto flag is computed within its kind: conversion rows on
//! (conversion seconds, `surface_to_patch` rms / diagonal), render rows on (ms per frame,
//! −PSNR). Conversion time excludes reading the file (done once, reported apart) but includes
//! preparing the mesh, as `spatch convert` does.
//!
//! Cost: `conversions × (repeats + 1 error measurement)` pipeline runs and
//! `render_grids × projections × cells × views × (runs + 1)` frames.

use std::path::Path;
use std::time::Instant;

use glam::Vec3;
use serde::Serialize;
use spatch_convert::{convert, Conversion, ConvertInput, ConvertOptions};
use spatch_format::Scene;
use spatch_mesh::{load_mesh, prepare_mesh, sample_surface, Bvh, TriangleMesh};
use spatch_render::{CellScheme, PreparedScene, Projection};

use crate::geometric::{nearest_patch_cells, node_to_surface_distances, sample_count, ErrorStats};
use crate::image_error::{compare_views, median, ImageOptions, SourceViews};
use crate::pareto::pareto_front;
use crate::Counts;
use crate::EvalError;

/// The fitter's error budget (fraction of the node spacing) of [`Width::Sixteen`] rows:
/// small enough that every region with any relief gets a finer step and 16-bit codes.
pub const SIXTEEN_BIT_STEP_ERROR: f32 = 1e-4;

/// Displacement width of a conversion setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Width {
    /// The base options' budget (by default a tenth of the spacing): 8-bit codes unless a
    /// region's relief needs more.
    Eight,
    /// A budget of [`SIXTEEN_BIT_STEP_ERROR`] of the spacing: 16-bit codes for every region
    /// with relief (the `wide_patches` column shows how many).
    Sixteen,
}

impl Width {
    /// 8 or 16.
    pub fn bits(self) -> u8 {
        match self {
            Width::Eight => 8,
            Width::Sixteen => 16,
        }
    }

    /// The fitter's step budget for this width, given the base options' budget.
    fn step_error(self, base: f32) -> f32 {
        match self {
            Width::Eight => base,
            Width::Sixteen => SIXTEEN_BIT_STEP_ERROR.min(base),
        }
    }
}

impl Serialize for Width {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u8(self.bits())
    }
}

/// What a sweep varies and how it measures.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct SweepOptions {
    /// Grid sizes (nodes per patch side, 2..=257). Default 5, 9, 17, 33.
    pub grids: Vec<u32>,
    /// Cone angles in degrees (0, 89]. Default 15, 30, 45.
    pub cone_angles: Vec<f32>,
    /// Displacement widths. Default 8 and 16.
    pub widths: Vec<Width>,
    /// Node projections of the render rows. Default trilinear and exact.
    pub projections: Vec<Projection>,
    /// Cell schemes of the render rows. Default bilinear and smooth.
    pub cells: Vec<CellScheme>,
    /// Grids whose scenes (base cone angle, 8 bits) the render settings are measured on;
    /// each must be one of `grids`. Default 9, 17, 33.
    pub render_grids: Vec<u32>,
    /// Everything else of the conversion (spacing, overlap, sharp edges, …). Default:
    /// `ConvertOptions::default()`. Its grid, cone angle and step budget are overridden per
    /// row; its grid and cone angle are the *base* values the other parameter is swept
    /// around when they are among `grids` and `cone_angles` (otherwise the first of each).
    pub base: ConvertOptions,
    /// Views, image size, render options and timed frames of the render rows. Default: the
    /// 6 axis views at 500 × 500, 3 timed frames per view.
    pub image: ImageOptions,
    /// Conversions per setting; the median time is kept (1..=100). Default 3.
    pub repeats: usize,
    /// Seed of the source samples. Default 1.
    pub seed: u64,
}

impl Default for SweepOptions {
    fn default() -> Self {
        let mut image = ImageOptions::default();
        image.views.truncate(6);
        Self {
            grids: vec![5, 9, 17, 33],
            cone_angles: vec![15.0, spatch_segment_default_cone(), 45.0],
            widths: vec![Width::Eight, Width::Sixteen],
            projections: vec![Projection::Trilinear, Projection::Exact],
            cells: vec![CellScheme::Bilinear, CellScheme::Smooth],
            render_grids: vec![9, 17, 33],
            base: ConvertOptions::default(),
            image,
            repeats: 3,
            seed: 1,
        }
    }
}

/// The segmenter's default cone angle, read from the default options (this crate does not
/// depend on the segmenter itself).
fn spatch_segment_default_cone() -> f32 {
    ConvertOptions::default().segment.cone_angle_deg
}

/// Which kind of setting a row measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum RowKind {
    /// A conversion setting: time is conversion seconds.
    Conversion,
    /// A render setting on a fixed scene: time is ms per frame.
    Render,
}

/// The image figures of a render row.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RowImage {
    /// PSNR (dB) pooled over the views; `None` when identical to the source's image.
    pub psnr_db: Option<f64>,
    /// Hole fraction over the views.
    pub hole_fraction: f64,
    /// Mean depth error over the diagonal.
    pub depth_error_rel: f64,
}

/// One measured setting.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepRow {
    /// Conversion or render.
    pub kind: RowKind,
    /// Grid size of the scene.
    pub grid: u32,
    /// Cone angle of the scene (degrees).
    pub cone_angle: f32,
    /// Displacement width setting of the scene (8 or 16).
    pub width: Width,
    /// Node projection (render rows).
    pub projection: Option<Projection>,
    /// Cell scheme (render rows).
    pub cells: Option<CellScheme>,
    /// Sizes of the scene and of its encoded file (serialized as the keys
    /// `patches`, `nodes`, `filled_nodes` and `bytes`).
    #[serde(flatten)]
    pub counts: Counts,
    /// Patches with 16-bit displacements.
    pub wide_patches: usize,
    /// Median conversion wall time (seconds) of the scene.
    pub convert_seconds: f64,
    /// Median ms per frame (render rows).
    pub render_ms: Option<f64>,
    /// Nodes to the source.
    pub node_to_surface: ErrorStats,
    /// Source samples to the patches.
    pub surface_to_patch: ErrorStats,
    /// Image figures (render rows).
    pub image: Option<RowImage>,
    /// On the Pareto front of its kind.
    pub on_front: bool,
}

impl SweepRow {
    /// The two costs the Pareto front of this row's kind minimizes.
    pub fn costs(&self) -> (f64, f64) {
        match self.kind {
            RowKind::Conversion => (self.convert_seconds, self.surface_to_patch.rms_rel),
            RowKind::Render => (
                self.render_ms.unwrap_or(f64::NAN),
                self.image
                    .map_or(f64::NAN, |i| -i.psnr_db.unwrap_or(f64::INFINITY)),
            ),
        }
    }

    /// `grid 17 / cone 30 / 8-bit` (then the render setting): no commas, so it fits a CSV
    /// field as it is.
    pub fn label(&self) -> String {
        let mut s = format!(
            "grid {} / cone {} / {}-bit",
            self.grid,
            self.cone_angle,
            self.width.bits()
        );
        if let (Some(p), Some(c)) = (self.projection, self.cells) {
            s.push_str(&format!(" / {} / {}", projection_name(p), cells_name(c)));
        }
        s
    }
}

/// `trilinear` or `exact`.
pub fn projection_name(p: Projection) -> &'static str {
    match p {
        Projection::Exact => "exact",
        _ => "trilinear",
    }
}

/// `bilinear` or `smooth`.
pub fn cells_name(c: CellScheme) -> &'static str {
    match c {
        CellScheme::Smooth => "smooth",
        _ => "bilinear",
    }
}

/// A whole sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SweepResult {
    /// Every row: conversion rows first, then render rows.
    pub rows: Vec<SweepRow>,
    /// Seconds to read the source file (once, not in any row).
    pub load_seconds: f64,
    /// Wall time of the whole sweep (seconds).
    pub seconds: f64,
    /// Worker threads of the conversions and renders.
    pub threads: usize,
    /// The source's bounding-box diagonal.
    pub diagonal: f64,
    /// Source samples per `surface_to_patch` measurement.
    pub samples: usize,
    /// Views of the render rows.
    pub views: usize,
    /// Image size of the render rows.
    pub image_size: [u32; 2],
    /// Timed frames per view of the render rows.
    pub runs: usize,
    /// Conversions per conversion setting.
    pub repeats: usize,
    /// The base grid and cone angle the other parameter was swept around.
    pub base_grid: u32,
    /// See `base_grid`.
    pub base_cone_angle: f32,
}

fn check(options: &SweepOptions) -> Result<(), EvalError> {
    let bad = |name, reason| Err(EvalError::InvalidOption { name, reason });
    if options.grids.is_empty() || options.grids.iter().any(|g| !(2..=257).contains(g)) {
        return bad("grids", "give at least one grid size in 2..=257");
    }
    if options.cone_angles.is_empty()
        || options
            .cone_angles
            .iter()
            .any(|a| !(a.is_finite() && *a > 0.0 && *a <= 89.0))
    {
        return bad("cone_angles", "give at least one angle in (0, 89] degrees");
    }
    if options.widths.is_empty() {
        return bad("widths", "give at least one of 8 and 16");
    }
    if options
        .render_grids
        .iter()
        .any(|g| !options.grids.contains(g))
    {
        return bad("render_grids", "every render grid must be one of the grids");
    }
    if !options.render_grids.is_empty()
        && (options.projections.is_empty() || options.cells.is_empty())
    {
        return bad("render", "give at least one projection and one cell scheme");
    }
    if !(1..=100).contains(&options.repeats) {
        return bad("repeats", "must be in 1..=100");
    }
    if options.image.views.is_empty() && !options.render_grids.is_empty() {
        return bad("views", "render rows need at least one view");
    }
    Ok(())
}

/// A conversion setting.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Setting {
    grid: u32,
    cone: f32,
    width: Width,
}

/// The conversion settings: grid × width at the base cone, cone × width at the base grid.
fn settings(options: &SweepOptions, base_grid: u32, base_cone: f32) -> Vec<Setting> {
    let mut out: Vec<Setting> = Vec::new();
    let mut add = |s: Setting| {
        if !out.contains(&s) {
            out.push(s);
        }
    };
    for &grid in &options.grids {
        for &width in &options.widths {
            add(Setting {
                grid,
                cone: base_cone,
                width,
            });
        }
    }
    for &cone in &options.cone_angles {
        for &width in &options.widths {
            add(Setting {
                grid: base_grid,
                cone,
                width,
            });
        }
    }
    out
}

/// What every row of a sweep measures against: the mesh as read, the
/// same prepared as the pipeline prepares it (preparation does not depend
/// on the swept settings), its BVH and the source samples.
struct SweepSource {
    raw: TriangleMesh,
    mesh: TriangleMesh,
    bvh: Bvh,
    samples: Vec<Vec3>,
    /// The prepared mesh's diagonal.
    diagonal: f64,
}

impl SweepSource {
    /// The source at `path`, its load time in seconds beside it.
    fn load(path: &Path, options: &SweepOptions) -> Result<(Self, f64), EvalError> {
        let load_start = Instant::now();
        let raw = load_mesh(path)?.mesh;
        let load_seconds = load_start.elapsed().as_secs_f64();
        let (mesh, _) = prepare_mesh(&raw, &options.base.prepare);
        if mesh.face_count() == 0 || mesh.diagonal() <= 0.0 {
            return Err(EvalError::NoSurface {
                path: path.to_path_buf(),
            });
        }
        let bvh = Bvh::new(&mesh);
        let samples: Vec<Vec3> = sample_surface(&mesh, sample_count(&mesh), options.seed)
            .into_iter()
            .map(|s| s.point)
            .collect();
        let diagonal = f64::from(mesh.diagonal());
        let source = Self {
            raw,
            mesh,
            bvh,
            samples,
            diagonal,
        };
        Ok((source, load_seconds))
    }
}

/// The swept value nearest the base options: the base's own when swept,
/// else the first.
fn base_settings(options: &SweepOptions) -> (u32, f32) {
    let grid = options.base.fit.grid;
    let grid = if options.grids.contains(&grid) {
        grid
    } else {
        options.grids[0]
    };
    let cone = options.base.segment.cone_angle_deg;
    let cone = if options.cone_angles.contains(&cone) {
        cone
    } else {
        options.cone_angles[0]
    };
    (grid, cone)
}

/// The source converted with `setting`, and the median of the
/// conversion's times over the sweep's repeats.
fn convert_setting(
    source: &SweepSource,
    setting: Setting,
    options: &SweepOptions,
    label: &str,
) -> Result<(Conversion, f64), EvalError> {
    let mut convert_options = options.base.clone();
    convert_options.fit.grid = setting.grid;
    convert_options.fit.max_step_error = setting.width.step_error(options.base.fit.max_step_error);
    convert_options.segment = convert_options
        .segment
        .clone()
        .with_cone_angle_deg(setting.cone);
    let run = || {
        convert(ConvertInput::Mesh(source.raw.clone()), &convert_options).map_err(|source| {
            EvalError::Convert {
                setting: label.to_string(),
                source,
            }
        })
    };
    let c = run()?;
    let mut times = vec![c.report.seconds];
    for _ in 1..options.repeats {
        times.push(run()?.report.seconds);
    }
    Ok((c, median(&mut times)))
}

/// The conversion row of `setting`: the scene's counts, its conversion
/// time and its geometric error against the source.
fn conversion_row(
    source: &SweepSource,
    setting: Setting,
    c: &Conversion,
    convert_seconds: f64,
) -> SweepRow {
    let mut node_d = node_to_surface_distances(&c.scene, &source.mesh, &source.bvh);
    let (mut sample_d, _) = nearest_patch_cells(&c.scene, source.mesh.origin, &source.samples);
    SweepRow {
        kind: RowKind::Conversion,
        grid: setting.grid,
        cone_angle: setting.cone,
        width: setting.width,
        projection: None,
        cells: None,
        counts: c.report.counts,
        wide_patches: c.report.wide_patches,
        convert_seconds,
        render_ms: None,
        node_to_surface: ErrorStats::from_distances(&mut node_d, source.diagonal),
        surface_to_patch: ErrorStats::from_distances(&mut sample_d, source.diagonal),
        image: None,
        on_front: false,
    }
}

/// The render rows: each of `scenes` (with its conversion row) drawn
/// under every swept projection and cell scheme, compared with the
/// source's frames.
fn render_rows(
    source: &SweepSource,
    scenes: &[(SweepRow, Scene)],
    options: &SweepOptions,
    progress: &dyn Fn(&str),
) -> Result<Vec<SweepRow>, EvalError> {
    if scenes.is_empty() {
        return Ok(Vec::new());
    }
    progress("rendering the source");
    // The source in colour only when the sweep's scenes sample colour.
    let mut image = options.image.clone();
    image.colour_source &= options.base.fit.colour;
    let views = SourceViews::render(&source.mesh, &image)?;
    let count = scenes.len() * options.projections.len() * options.cells.len();
    let mut rows = Vec::new();
    for (scene_row, scene) in scenes {
        let prepared = PreparedScene::new(scene);
        for &projection in &options.projections {
            for &cells in &options.cells {
                progress(&format!(
                    "rendering {}/{count}: grid {}, {}, {}",
                    rows.len() + 1,
                    scene_row.grid,
                    projection_name(projection),
                    cells_name(cells)
                ));
                let mut render = options.image.render;
                render.projection = projection;
                render.cells = cells;
                let image = compare_views(&views, &prepared, render, options.image.runs)?;
                rows.push(SweepRow {
                    kind: RowKind::Render,
                    projection: Some(projection),
                    cells: Some(cells),
                    render_ms: Some(image.patch_ms),
                    image: Some(RowImage {
                        psnr_db: image.psnr_db,
                        hole_fraction: image.hole_fraction,
                        depth_error_rel: image.mean_depth_error_rel,
                    }),
                    on_front: false,
                    ..scene_row.clone()
                });
            }
        }
    }
    Ok(rows)
}

/// Marks the rows on the Pareto front of their kind (error against time).
fn mark_fronts(rows: &mut [SweepRow]) {
    for kind in [RowKind::Conversion, RowKind::Render] {
        let index: Vec<usize> = (0..rows.len()).filter(|&k| rows[k].kind == kind).collect();
        let costs: Vec<(f64, f64)> = index.iter().map(|&k| rows[k].costs()).collect();
        for (&k, on) in index.iter().zip(pareto_front(&costs)) {
            rows[k].on_front = on;
        }
    }
}

/// Runs the sweep on the mesh at `path`, calling `progress` with a line per step.
pub fn run_sweep(
    path: &Path,
    options: &SweepOptions,
    progress: &dyn Fn(&str),
) -> Result<SweepResult, EvalError> {
    check(options)?;
    let started = Instant::now();
    let (base_grid, base_cone) = base_settings(options);
    progress("reading the source");
    let (source, load_seconds) = SweepSource::load(path, options)?;
    let plan = settings(options, base_grid, base_cone);
    let mut rows = Vec::new();
    let mut render_scenes = Vec::new();
    for (k, &setting) in plan.iter().enumerate() {
        let label = format!(
            "grid {} / cone {} / {}-bit",
            setting.grid,
            setting.cone,
            setting.width.bits()
        );
        progress(&format!("converting {}/{}: {label}", k + 1, plan.len()));
        let (c, seconds) = convert_setting(&source, setting, options, &label)?;
        progress(&format!("measuring {}/{}: {label}", k + 1, plan.len()));
        let row = conversion_row(&source, setting, &c, seconds);
        if setting.cone == base_cone
            && setting.width == Width::Eight
            && options.render_grids.contains(&setting.grid)
        {
            render_scenes.push((row.clone(), c.scene));
        }
        rows.push(row);
    }
    rows.extend(render_rows(&source, &render_scenes, options, progress)?);
    mark_fronts(&mut rows);
    let threads = match options.image.render.threads {
        0 => rayon::current_num_threads(),
        n => n,
    };
    Ok(SweepResult {
        rows,
        load_seconds,
        seconds: started.elapsed().as_secs_f64(),
        threads,
        diagonal: source.diagonal,
        samples: source.samples.len(),
        views: options.image.views.len(),
        image_size: options.image.size,
        runs: options.image.runs,
        repeats: options.repeats,
        base_grid,
        base_cone_angle: base_cone,
    })
}

/// The CSV columns of [`sweep_csv`], in order.
pub const SWEEP_CSV_COLUMNS: [&str; 23] = [
    "kind",
    "grid",
    "cone_angle",
    "width",
    "projection",
    "cells",
    "patches",
    "nodes",
    "filled_nodes",
    "bytes",
    "wide_patches",
    "convert_seconds",
    "render_ms",
    "node_to_surface_max_rel",
    "node_to_surface_rms_rel",
    "surface_to_patch_max_rel",
    "surface_to_patch_rms_rel",
    "surface_to_patch_p95_rel",
    "psnr_db",
    "hole_fraction",
    "depth_error_rel",
    "pareto",
    "label",
];

/// The rows as CSV (header [`SWEEP_CSV_COLUMNS`]); fields that do not apply to a row's kind
/// are empty, and a PSNR of identical images is `inf`.
pub fn sweep_csv(result: &SweepResult) -> String {
    let mut out = SWEEP_CSV_COLUMNS.join(",");
    out.push('\n');
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
    for r in &result.rows {
        let diag = result.diagonal;
        let p95_rel = if diag > 0.0 {
            r.surface_to_patch.p95 / diag
        } else {
            0.0
        };
        let fields = [
            match r.kind {
                RowKind::Conversion => "conversion".to_owned(),
                RowKind::Render => "render".to_owned(),
            },
            r.grid.to_string(),
            r.cone_angle.to_string(),
            r.width.bits().to_string(),
            r.projection
                .map_or(String::new(), |p| projection_name(p).to_owned()),
            r.cells.map_or(String::new(), |c| cells_name(c).to_owned()),
            r.counts.patches.to_string(),
            r.counts.nodes.to_string(),
            r.counts.filled_nodes.to_string(),
            r.counts.bytes.to_string(),
            r.wide_patches.to_string(),
            format!("{}", r.convert_seconds),
            opt(r.render_ms),
            format!("{:e}", r.node_to_surface.max_rel),
            format!("{:e}", r.node_to_surface.rms_rel),
            format!("{:e}", r.surface_to_patch.max_rel),
            format!("{:e}", r.surface_to_patch.rms_rel),
            format!("{p95_rel:e}"),
            r.image.map_or(String::new(), |i| {
                i.psnr_db.map_or("inf".to_owned(), |p| format!("{p}"))
            }),
            opt(r.image.map(|i| i.hole_fraction)),
            opt(r.image.map(|i| i.depth_error_rel)),
            (r.on_front as u8).to_string(),
            format!("\"{}\"", r.label()),
        ];
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plan_is_not_the_full_product() {
        let options = SweepOptions::default();
        let plan = settings(&options, 17, 30.0);
        // 4 grids × 2 widths at 30°, then 15° and 45° × 2 widths at grid 17.
        assert_eq!(plan.len(), 12);
        assert!(plan.contains(&Setting {
            grid: 17,
            cone: 45.0,
            width: Width::Sixteen
        }));
        assert!(!plan.contains(&Setting {
            grid: 5,
            cone: 45.0,
            width: Width::Eight
        }));
    }

    #[test]
    fn options_are_checked() {
        let o = SweepOptions {
            render_grids: vec![65],
            ..SweepOptions::default()
        };
        assert!(matches!(
            check(&o),
            Err(EvalError::InvalidOption {
                name: "render_grids",
                ..
            })
        ));
        let o = SweepOptions {
            cone_angles: vec![90.0],
            ..SweepOptions::default()
        };
        assert!(check(&o).is_err());
        assert!(check(&SweepOptions::default()).is_ok());
    }
}
