//! What the rendering shortcuts save and cost: the same frame rendered with
//! trilinear and with exact projection, with bilinear and with smooth
//! cells, (when it is not the default) with the chosen mip limit and the
//! default one, and (when the caller passes both preparations) with
//! overlaps trimmed and kept, timed (median of a few runs) and compared by
//! PSNR.
//!
//! The reference of each pair is the costlier variant (exact projection,
//! smooth cells, the default mip limit, every overlap kept); every other
//! option is kept. Cost: `2 × runs` frames per pair.

use serde::Serialize;

use crate::camera::Camera;
use crate::error::RenderError;
use crate::frame::image::RenderedImage;
use crate::frame::render::Renderer;
use crate::options::{CellScheme, Projection, RenderOptions};
use crate::prepare::scene::PreparedScene;

/// One shortcut against its reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShortcutCost {
    /// Median frame time with the shortcut, ms.
    pub shortcut_ms: f64,
    /// Median frame time with the reference, ms.
    pub reference_ms: f64,
    /// PSNR of the shortcut's image against the reference's, dB; `None`
    /// (JSON null) when the images are identical.
    pub psnr_db: Option<f64>,
}

/// The costs of the two shortcuts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShortcutCosts {
    /// Trilinear (shortcut) versus exact (reference) node projection.
    pub trilinear_vs_exact: ShortcutCost,
    /// Bilinear (shortcut) versus smooth (reference) cells.
    pub bilinear_vs_smooth: ShortcutCost,
    /// The chosen mip limit (shortcut) versus the default one (reference);
    /// `None` (JSON null) when the default is chosen.
    pub mip_limit_vs_default: Option<ShortcutCost>,
    /// Overlaps trimmed at preparation (shortcut) versus kept (reference);
    /// `None` (JSON null) when not measured.
    pub trimmed_vs_kept_overlaps: Option<ShortcutCost>,
    /// Frames timed per variant.
    pub runs: usize,
}

fn time_variant(
    scene: &PreparedScene,
    camera: &Camera,
    options: RenderOptions,
    runs: usize,
) -> Result<(f64, RenderedImage), RenderError> {
    let mut renderer = Renderer::new(options)?;
    let mut image = renderer.render(scene, camera)?.image; // warm-up
    let mut times = Vec::with_capacity(runs);
    for _ in 0..runs {
        let out = renderer.render(scene, camera)?;
        times.push(out.stats.times_ms.total_wall);
        image = out.image;
    }
    times.sort_by(f64::total_cmp);
    Ok((times[times.len() / 2], image))
}

/// Measures the shortcuts on `scene` from `camera`, `runs` (≥ 1) frames
/// each; `overlaps` is the same scene prepared with
/// [`PreparedScene::trimming_overlaps`] and with [`PreparedScene::new`]
/// when the trimming is to be measured.
pub fn measure_shortcuts(
    scene: &PreparedScene,
    overlaps: Option<(&PreparedScene, &PreparedScene)>,
    camera: &Camera,
    options: &RenderOptions,
    runs: usize,
) -> Result<ShortcutCosts, RenderError> {
    let runs = runs.max(1);
    let scenes = |shortcut: &PreparedScene,
                  reference: &PreparedScene,
                  a: RenderOptions,
                  b: RenderOptions|
     -> Result<ShortcutCost, RenderError> {
        let (shortcut_ms, a) = time_variant(shortcut, camera, a, runs)?;
        let (reference_ms, b) = time_variant(reference, camera, b, runs)?;
        Ok(ShortcutCost {
            shortcut_ms,
            reference_ms,
            psnr_db: a.psnr(&b),
        })
    };
    let pair = |a: RenderOptions, b: RenderOptions| scenes(scene, scene, a, b);
    let with = |p: Projection, c: CellScheme| RenderOptions {
        projection: p,
        cells: c,
        ..*options
    };
    Ok(ShortcutCosts {
        trilinear_vs_exact: pair(
            with(Projection::Trilinear, options.cells),
            with(Projection::Exact, options.cells),
        )?,
        bilinear_vs_smooth: pair(
            with(options.projection, CellScheme::Bilinear),
            with(options.projection, CellScheme::Smooth),
        )?,
        mip_limit_vs_default: if options.mip_limit == RenderOptions::DEFAULT_MIP_LIMIT {
            None
        } else {
            let default = RenderOptions {
                mip_limit: RenderOptions::DEFAULT_MIP_LIMIT,
                ..*options
            };
            Some(pair(*options, default)?)
        },
        trimmed_vs_kept_overlaps: match overlaps {
            Some((trimmed, kept)) => Some(scenes(trimmed, kept, *options, *options)?),
            None => None,
        },
        runs,
    })
}
