//! The raster kernels: what writes depth-tested samples into a band of
//! rows. They read projected nodes, cell flags and screen triangles and
//! know nothing of patches or plans. In use order: the band store,
//! bilinear cells (and nodes alone), cells drawn by the quarters they
//! hold, bilinear cells with exact outlines, bilinear cells by
//! pixel-centre coverage, Catmull-Rom cells, node splats, the scan-line
//! triangle rasterizer.

pub(crate) mod band;
pub(crate) mod band_box;
pub(crate) mod cell_bilinear;
#[cfg(test)]
mod cell_bilinear_tests;
pub(crate) mod cell_centres;
#[cfg(test)]
mod cell_centres_tests;
pub(crate) mod cell_edges;
pub(crate) mod cell_exact;
pub(crate) mod cell_quarters;
pub(crate) mod cell_smooth;
pub(crate) mod centre_piece;
pub(crate) mod gap_fill;
pub(crate) mod splat;
pub(crate) mod triangle_raster;
