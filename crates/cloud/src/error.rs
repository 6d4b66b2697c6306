//! The one error type of the crate, split by who is at fault.

use spatch_format::FormatError;

/// Why a point cloud could not be turned into patches.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CloudError {
    /// The cloud has no finite point at all.
    #[error("the point cloud is empty{}", dropped_note(*.dropped_non_finite))]
    EmptyCloud {
        /// Points dropped because a coordinate was NaN or infinite.
        dropped_non_finite: u64,
    },
    /// Too few points to estimate a spacing or a surface.
    #[error("the point cloud has {found} finite point(s); at least {needed} are needed to estimate a surface")]
    TooFewPoints {
        /// Finite points in the cloud.
        found: usize,
        /// The minimum.
        needed: usize,
    },
    /// Every point sits on (almost) the same spot, so there is no spacing to work with.
    #[error("the point cloud has no extent: its {points} points are all within {extent:e} of each other")]
    NoExtent {
        /// Finite points in the cloud.
        points: usize,
        /// Largest side of the bounding box.
        extent: f32,
    },
    /// An option is out of its documented range.
    #[error("invalid option `{option}`: {reason}")]
    InvalidOption {
        /// The option's field name in [`CloudOptions`](crate::CloudOptions).
        option: &'static str,
        /// What is wrong.
        reason: &'static str,
    },
    /// More points than the `u32` point ids can name.
    #[error("the point cloud has {points} points; at most {max} are supported")]
    TooManyPoints {
        /// Points in the cloud.
        points: usize,
        /// The limit.
        max: usize,
    },
    /// A per-point attribute does not have one entry per point.
    #[error("the point cloud has {found} {what} for {expected} points")]
    MismatchedAttribute {
        /// `colours` or `normals`.
        what: &'static str,
        /// Entries found.
        found: usize,
        /// Points in the cloud.
        expected: usize,
    },
    /// No view found a continuous surface: the points do not sample a surface (for example
    /// they lie on a line, or are too sparse for their spacing).
    #[error("no surface could be extracted from the {points} points (are they on a line, or scattered?)")]
    NoSurface {
        /// Points in the cloud.
        points: usize,
    },
    /// A tile's range images would need more pixels than the budget (its extent is too large
    /// for its spacing), and coarsening was not allowed.
    #[error("the range images of a tile would need {pixels} pixels (more than {budget}); use smaller tiles, or allow coarsening to enlarge the pixel")]
    PixelBudgetExceeded {
        /// Pixels the tile's images need over all views.
        pixels: usize,
        /// The budget per tile ([`PIXEL_BUDGET`](crate::PIXEL_BUDGET)).
        budget: usize,
    },
    /// The scene has no filled node, so no error can be measured against it.
    #[error("the scene has no filled node to measure against")]
    EmptyScene,
    /// An internal invariant failed: this is a bug.
    #[error("internal error (this is a bug): {what}")]
    Internal {
        /// The invariant that failed.
        what: &'static str,
    },
    /// A patch or the scene could not be built or encoded. The extractor builds valid frames
    /// and grids by construction, so this is a bug.
    #[error("building the scene failed (this is a bug): {0}")]
    Bug(#[from] FormatError),
}

fn dropped_note(dropped: u64) -> String {
    if dropped == 0 {
        String::new()
    } else {
        format!(" ({dropped} non-finite points were dropped)")
    }
}
