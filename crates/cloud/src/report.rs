//! What a conversion reports: counts, stage timings and (when measured) the error.

use serde::Serialize;

use crate::CloudErrorReport;

/// Wall time of one stage.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StageTime {
    /// Stage name: `filter`, `spacing`, `normals`, `range_images`, `extract`, `encode` (and
    /// `load`, `write` when the CLI adds them).
    pub name: &'static str,
    /// Wall time in seconds.
    pub seconds: f64,
}

/// Counts and timings of one point cloud conversion.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CloudReport {
    /// Points handed to the pipeline (before dropping non-finite ones).
    pub input_points: usize,
    /// Points dropped because a coordinate or normal was NaN or infinite.
    pub dropped_non_finite: u64,
    /// Points converted.
    pub points: usize,
    /// Patches in the scene.
    pub patches: usize,
    /// Grid nodes of all patches, filled or not.
    pub nodes: usize,
    /// Non-empty nodes.
    pub filled_nodes: usize,
    /// Bytes of the encoded `.spatch`.
    pub bytes: usize,
    /// Total wall time of the stages, in seconds.
    pub seconds: f64,
    /// Each stage's wall time, in pipeline order.
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
    /// Where the normals came from: `file` or `pca`.
    pub normals: &'static str,
    /// Pixels filled by gap interpolation, over all views.
    pub gap_pixels_filled: usize,
    /// Points no patch covers within the cover tolerance.
    pub uncovered_points: usize,
    /// Tiles split into several patches because of their depth range.
    pub split_tiles: usize,
    /// Patches with 16-bit displacements.
    pub wide_patches: usize,
    /// Whether the range images were smoothed.
    pub smoothed: bool,
    /// Colour channel of the scene: `none`, `rgb8` or `rgba8`.
    pub colour: &'static str,
    /// Length of the cloud's bounding-box diagonal (model units).
    pub diagonal: f64,
    /// What the pipeline worked around, as readable sentences.
    pub warnings: Vec<String>,
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
