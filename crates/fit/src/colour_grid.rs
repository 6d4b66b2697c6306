//! Colour grids: a patch's texture sampled finer than its nodes (container 1.2).
//!
//! A node carries one colour, so a textured region fitted at the geometry's spacing loses
//! its texture's detail. When the region's texel size `t` (model units, from its faces' UV
//! Jacobians) is finer than its node spacing `s`, the patch gets a colour grid of factor
//! `f = round(s / (texels_per_sample × t))` (clamped to 2..=64; below 2 no grid): every cell
//! cut into `f × f` colour cells. Input: the region's faces and neighbourhood and the node
//! window of the patch. Output: [`ColourGrid`] samples in the grid's row-major order.
//!
//! Each sample casts along −ẑ exactly as a node does (`node_cast`, on a lattice `f` times
//! finer over the patch's window; region faces first), and takes the mean colour of its own
//! footprint (`colour::node_colour` at the sample spacing), so a sample coarser than a texel
//! shows the texture's local mean rather than aliasing it. Samples at most
//! [`SINGLE_TAP_TEXELS`] texels apart (the usual case: `f` follows the texel size) read the
//! texture once, bilinearly, at their hit: their footprint spans about a texel, whose mean
//! the bilinear read already is, and the nine reads were most of the fit's time (Spot
//! converted 5 × slower with grids). A sample with no hit (outside the
//! surface; never read inside a drawable cell, whose four corners have hits) copies the
//! sample before it, which codes to almost nothing.
//!
//! Sample colours are rounded to multiples of [`COLOUR_GRID_STEP`] (error at most 2 levels
//! of 255, 42 dB and up): their prediction residuals then never use the two low bits, which
//! the container's range coder learns, so a photographic texture codes to about half the
//! bytes at no visible cost.
//!
//! Cost: O(samples + Σ face footprints on the fine lattice) per patch; memory one hit per
//! sample.

use spatch_format::{ColourGrid, GridSize};
use spatch_mesh::{FaceId, TriangleMesh};

use crate::colour::{node_colour, Footprint};
use crate::lattice::Lattice;
use crate::node_cast::{cast_nodes, Hit};

/// Step of the colour grid's RGB values (see the module docs); alpha is kept exact.
pub const COLOUR_GRID_STEP: u8 = 4;

/// `c` with its RGB rounded to the nearest multiple of [`COLOUR_GRID_STEP`] (at most 252).
pub fn quantize_sample(c: [u8; 4]) -> [u8; 4] {
    let step = u16::from(COLOUR_GRID_STEP);
    let q = |v: u8| ((((u16::from(v) + step / 2) / step) * step).min(255 - 255 % step)) as u8;
    [q(c[0]), q(c[1]), q(c[2]), c[3]]
}

/// The colour grid factor for a patch of node spacing `spacing` over a texture of texel
/// size `texel` (model units), `texels_per_sample` texels per colour sample; `None` below 2.
pub(crate) fn grid_factor(spacing: f32, texel: f64, texels_per_sample: f32) -> Option<u8> {
    if !(texels_per_sample > 0.0 && texel > 0.0) {
        return None;
    }
    let f = f64::from(spacing) / (texel * f64::from(texels_per_sample));
    let f = f.round().min(f64::from(ColourGrid::MAX_FACTOR));
    (f >= 2.0).then_some(f as u8)
}

/// The faces a patch's samples may hit: the region's, then its neighbourhood's.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SampleFaces<'a> {
    pub(crate) region: &'a [FaceId],
    pub(crate) around: &'a [FaceId],
}

/// Samples at most this many texels apart take one bilinear texture read at their hit
/// instead of the mean of their 3 × 3 footprint (module docs).
pub(crate) const SINGLE_TAP_TEXELS: f64 = 1.5;

/// The colour grid of factor `factor` over the node window starting at `(i0, j0)` of
/// `lattice`, `grid` nodes wide, its samples `texels` texels apart (module docs).
pub(crate) fn sample_colour_grid(
    mesh: &TriangleMesh,
    faces: SampleFaces<'_>,
    lattice: &Lattice,
    ((i0, j0), grid): ((usize, usize), GridSize),
    factor: u8,
    texels: f64,
) -> Option<ColourGrid> {
    let f = usize::from(factor);
    let (cols, rows) = ColourGrid::sample_size(grid, factor);
    let fine = Lattice {
        basis: lattice.basis,
        origin: lattice.origin
            + glam::DVec2::new(
                i0 as f64 * f64::from(lattice.spacing[0]),
                j0 as f64 * f64::from(lattice.spacing[1]),
            ),
        spacing: [lattice.spacing[0] / f as f32, lattice.spacing[1] / f as f32],
        cols,
        rows,
    };
    let needed = vec![true; cols * rows];
    let mut hits = vec![Hit::NONE; cols * rows];
    cast_nodes(mesh, faces.region, &fine, &needed, None, &mut hits);
    let locked: Vec<bool> = hits.iter().map(Hit::is_hit).collect();
    cast_nodes(mesh, faces.around, &fine, &needed, Some(&locked), &mut hits);
    let b = &fine.basis;
    let footprint = Footprint {
        ax: b.x * fine.spacing[0],
        ay: b.y * fine.spacing[1],
        axis: b.z,
    };
    let footprint = (texels > SINGLE_TAP_TEXELS).then_some(&footprint);
    let mut samples: Vec<[u8; 4]> = Vec::with_capacity(cols * rows);
    for (k, hit) in hits.iter().enumerate() {
        let colour = if hit.is_hit() {
            quantize_sample(node_colour(mesh, hit.face, hit.bary, footprint))
        } else if k % cols > 0 {
            samples[k - 1]
        } else if k >= cols {
            samples[k - cols]
        } else {
            [0, 0, 0, 255]
        };
        samples.push(colour);
    }
    ColourGrid::new(grid, factor, samples).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_follows_the_texel_size_within_its_range() {
        assert_eq!(grid_factor(0.1, 0.01, 1.0), Some(10));
        assert_eq!(grid_factor(0.1, 0.01, 2.0), Some(5));
        assert_eq!(grid_factor(0.1, 0.07, 1.0), None);
        assert_eq!(grid_factor(1.0, 1e-5, 1.0), Some(64));
        assert_eq!(grid_factor(0.1, 0.01, 0.0), None);
        assert_eq!(quantize_sample([0, 2, 253, 7]), [0, 4, 252, 7]);
        assert_eq!(quantize_sample([1, 130, 255, 255]), [0, 132, 252, 255]);
    }
}
