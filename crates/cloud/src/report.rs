//! What a conversion reports: counts, stage timings and (when measured) the error.

use serde::Serialize;
pub use spatch_report::{Counts, StageTime};

use crate::{CloudErrorReport, CloudWarning};

/// Counts and timings of one point cloud conversion.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CloudReport {
    /// Points handed to the pipeline (before dropping non-finite ones).
    pub input_points: usize,
    /// Points dropped because a coordinate or normal was NaN or infinite.
    pub dropped_non_finite: u64,
    /// Points converted.
    pub points: usize,
    /// Sizes of the scene and of its encoded `.spatch` (serialized as the
    /// keys `patches`, `nodes`, `filled_nodes` and `bytes`).
    #[serde(flatten)]
    pub counts: Counts,
    /// Total wall time of the stages, in seconds.
    pub seconds: f64,
    /// Each stage's wall time, in pipeline order: `filter`, `sort`,
    /// `spacing`, `normals`, `consensus`, `tiles`, `range_images`, `extract`, `encode`
    /// (and `load`, `write` when the CLI adds them); over several tiles, `range_images` and
    /// `extract` are the sums over the tiles.
    pub stages: Vec<StageTime>,
    /// Worker threads available to the parallel stages.
    pub threads: usize,
    /// Point spacing `s` (model units): estimated, or as given in the options.
    pub spacing: f32,
    /// Mean distance from a point to its nearest neighbour (model units; 0 when the spacing
    /// was given).
    pub mean_nearest: f32,
    /// Pixel (node) spacing used (model units).
    pub pixel: f32,
    /// View directions.
    pub views: usize,
    /// Where the normals came from: `file`, `pca`, or `pca+sight` (PCA normals turned toward
    /// each point's scanner, [`CloudOptions::scanners`](crate::CloudOptions::scanners)).
    pub normals: &'static str,
    /// Pixels filled by gap interpolation, over all views.
    pub gap_pixels_filled: usize,
    /// Points no patch covers within the cover tolerance.
    pub uncovered_points: usize,
    /// Points dropped as outliers (alone in a tile, `tiles.rs`).
    pub outlier_points: usize,
    /// Spatial tiles converted (1 when the whole cloud's images fit the pixel budget).
    pub tiles: usize,
    /// Side of the tiles (model units) when the cloud was tiled.
    pub tile_size: Option<f64>,
    /// Tiles split into several patches because of their depth range.
    pub split_tiles: usize,
    /// Points moved onto their block's plane (`consensus.rs`; 0 when off).
    pub consensus_points: usize,
    /// Length of the longest translation a scan was moved by before the consensus
    /// ([`CloudOptions::align_scans`](crate::CloudOptions::align_scans)); 0 when no scan
    /// was moved.
    pub scan_shift: f64,
    /// The translation of every scan (one per scan of
    /// [`CloudOptions::scanners`](crate::CloudOptions::scanners), in their order), when the
    /// scans were aligned: computed, or as given in
    /// [`CloudOptions::scan_shifts`](crate::CloudOptions::scan_shifts). Empty otherwise.
    pub scan_shifts: Vec<[f64; 3]>,
    /// Patches with 16-bit displacements.
    pub wide_patches: usize,
    /// Whether the range images were smoothed.
    pub smoothed: bool,
    /// Colour channel of the scene: `none`, `rgb8` or `rgba8`.
    pub colour: &'static str,
    /// Length of the cloud's bounding-box diagonal (model units).
    pub diagonal: f64,
    /// What the pipeline worked around (serialized as sentences).
    pub warnings: Vec<CloudWarning>,
    /// The geometric error, when it was measured.
    pub error: Option<CloudErrorReport>,
}

impl CloudReport {
    /// The seconds of the stage called `name`, if it ran.
    pub fn stage_seconds(&self, name: &str) -> Option<f64> {
        self.stages
            .iter()
            .find(|s| s.name == name)
            .map(|s| s.seconds)
    }
}
