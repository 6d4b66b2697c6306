//! The pipeline's options: one field per stage.

use spatch_edges::EdgeOptions;
use spatch_fit::FitOptions;
use spatch_format::WriteOptions;
use spatch_mesh::PrepareOptions;
use spatch_segment::SegmentOptions;

use crate::ColourBudget;

/// Options of [`convert`](crate::convert), one struct per stage.
///
/// The segmenter's `max_extent` is tied to the fitter's patch size: when it is left infinite
/// (its default), the pipeline sets it to `(grid - 1) × spacing`, so that merged regions fit
/// one patch.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct ConvertOptions {
    /// Welding and cleaning of the loaded mesh. Default: exact welding, drop degenerate and
    /// zero-area faces.
    pub prepare: PrepareOptions,
    /// Wind every connected piece of the mesh consistently and outward before segmenting
    /// (`spatch_mesh::orient_faces`). Default `true`: segmentation, culling and the openings'
    /// rule assume it, and a partly flipped source would otherwise show its inside; a source
    /// wound mostly inward is marked two-sided (see `sides.rs`). Tiles' parts
    /// ([`convert_part`](crate::convert_part)) keep the source's winding either way.
    pub orient: bool,
    /// The segmenter's cone and merge angles, region size limit and small-region threshold.
    pub segment: SegmentOptions,
    /// The fitter's spacing, grid, overlap, error budget and colour switch.
    pub fit: FitOptions,
    /// Container options (compression of node data). Default: uncompressed.
    pub write: WriteOptions,
    /// Sharp-edge patches added after fitting (crease angle, resolution, strip width), or
    /// `None` to leave them out. Default: `Some(EdgeOptions::default())`. They close the
    /// gaps surface patches leave along creases, at the cost of bytes (see
    /// docs/algorithms/edges.md). Their colour follows [`FitOptions::colour`].
    pub sharp_edges: Option<EdgeOptions>,
    /// Bytes the colour grids (`spatch_fit::FitOptions::colour_grid_texels`) may take; their
    /// factors are lowered until they fit. Default [`ColourBudget::DEFAULT_SCALE`] × the file
    /// without them. More: sharper texture, larger files.
    pub colour_budget: ColourBudget,
    /// The least PSNR (dB, RGB, over every fitted sample of the scene's grids) the colour
    /// budget may take the colour grids down to; the lowering stops at the coarsest grids
    /// within it, even over the budget. Default [`ColourBudget::DEFAULT_FLOOR_DB`] (30); `0`:
    /// no floor, the budget alone decides. Higher: sharper texture on files whose budget
    /// binds (small files above all), more bytes.
    pub colour_floor_db: f32,
}

impl Default for ConvertOptions {
    fn default() -> Self {
        Self {
            prepare: PrepareOptions::default(),
            orient: true,
            segment: SegmentOptions::default(),
            fit: FitOptions::default(),
            write: WriteOptions::default(),
            sharp_edges: Some(EdgeOptions::default()),
            colour_budget: ColourBudget::default(),
            colour_floor_db: ColourBudget::DEFAULT_FLOOR_DB,
        }
    }
}
