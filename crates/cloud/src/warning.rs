//! What a conversion worked around, as typed values (the CLI prints their `Display`).

use std::fmt;

use serde::{Serialize, Serializer};

/// Something the pipeline worked around instead of failing.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CloudWarning {
    /// Points alone in their tile (with its buffer fewer than
    /// [`OUTLIER_TILE_POINTS`](crate::OUTLIER_TILE_POINTS) points) were dropped: no surface
    /// can be made of them.
    OutliersDropped {
        /// Points dropped.
        points: usize,
        /// Tiles they occupied.
        tiles: usize,
    },
    /// A tile's range images needed more pixels than the budget, and coarsening was allowed
    /// ([`CloudOptions::allow_coarsening`](crate::CloudOptions::allow_coarsening)): its pixel
    /// was enlarged.
    PixelsCoarsened {
        /// Pixels the tile's images would have needed.
        pixels: usize,
        /// The budget per tile.
        budget: usize,
        /// How many times the pixel was enlarged.
        factor: f32,
        /// The pixel size used for that tile (model units).
        pixel: f32,
    },
}

impl fmt::Display for CloudWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CloudWarning::OutliersDropped { points, tiles } => write!(
                f,
                "{points} outlier points ({tiles} tiles holding almost nothing) were dropped: \
                 no surface can be made of them"
            ),
            CloudWarning::PixelsCoarsened {
                pixels,
                budget,
                factor,
                pixel,
            } => write!(
                f,
                "a tile's range images would need {pixels} pixels (budget {budget}): its pixel \
                 was enlarged {factor:.2} times, to {pixel:.3e} (coarsening was allowed)"
            ),
        }
    }
}

impl Serialize for CloudWarning {
    /// As its sentence, like every warning of the shared report.
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}
