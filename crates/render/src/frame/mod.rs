//! The frame driver: a frame planned on chunks of patches, binned into
//! bands, rasterized and resolved on the thread pool, assembled into the
//! image with its statistics. In use order: the image, the bins and
//! bands, the statistics, what each band is handed, the renderer, the
//! bands' order, the occlusion skip and counts, the shortcuts' costs.

pub(crate) mod band_tasks;
pub(crate) mod image;
pub(crate) mod occlusion;
pub(crate) mod occlusion_skip;
pub(crate) mod render;
pub(crate) mod schedule;
pub(crate) mod shortcuts;
pub(crate) mod stats;
pub(crate) mod tiles;
