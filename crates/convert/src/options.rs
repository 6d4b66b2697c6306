//! The pipeline's options: one field per stage.

use spatch_fit::FitOptions;
use spatch_format::WriteOptions;
use spatch_mesh::PrepareOptions;
use spatch_segment::SegmentOptions;

/// Options of [`convert`](crate::convert), one struct per stage.
///
/// The segmenter's `max_extent` is tied to the fitter's patch size: when it is left infinite
/// (its default), the pipeline sets it to `(grid - 1) × spacing`, so that merged regions fit
/// one patch.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub struct ConvertOptions {
    /// Welding and cleaning of the loaded mesh. Default: exact welding, drop degenerate and
    /// zero-area faces.
    pub prepare: PrepareOptions,
    /// The segmenter's cone and merge angles, region size limit and small-region threshold.
    pub segment: SegmentOptions,
    /// The fitter's spacing, grid, overlap, error budget and colour switch.
    pub fit: FitOptions,
    /// Container options (compression of node data). Default: uncompressed.
    pub write: WriteOptions,
}
