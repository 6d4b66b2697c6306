//! Patch cutting: the cells a view emitted become patches whose size follows the regions of
//! the range image instead of a fixed tiling of it.
//!
//! Input: one view's range image, its emitted cells (one flag per cell) and the
//! [`CutSettings`]. Output: patches over exactly those cells.
//!
//! Method:
//! 1. The emitted cells are split into 8-connected regions (one flood fill over the image).
//! 2. A region becomes one patch over its bounding rectangle when that rectangle has at most
//!    `grid` nodes a side. Otherwise it is cut in two at the middle of the rectangle's longer
//!    side, and each half is cut the same way. A region that fits is still cut in two when
//!    the halves cost fewer bytes (a frame record each, against one code per node of each
//!    bounding rectangle, empty nodes included: a sparse or L-shaped region is cheaper in
//!    pieces).
//! 3. A patch is stored with 8-bit codes when its depth range fits them with a step no
//!    coarser than `max_step` (spatch-format's `QuantizerPolicy`, shared with the mesh
//!    fitter), else with 16-bit codes: a steep region stays whole rather than
//!    being cut into strips (cutting a region at 40° slope to 8-bit depth ranges left pieces
//!    of about 60 filled nodes on the ten bunny scans).
//!
//! Pieces share the nodes along their cut (the same pixels), so no crack opens between the
//! patches of one view. Regions are visited in image order and halves low side first, so
//! the output is deterministic.
//!
//! Cost: O(cells) for the regions and O(cells · log cells) for the cuts; one byte a cell for
//! the visited marks.

use spatch_format::{DisplacementWidth, Frame, GridSize, Patch, Quantizer, QuantizerPolicy};

use crate::range_image::RangeImage;
use crate::CloudError;

/// Cell coordinates `(cx, cy)`.
type Cells = Vec<(usize, usize)>;

/// Bytes a patch costs besides its nodes: its frame record with a stored grid and width
/// (docs/format.md, FRAM).
const FRAME_BYTES: usize = 45;

/// How regions of cells are cut into patches.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CutSettings {
    /// Most nodes a patch side, ≥ 2.
    pub(crate) grid: usize,
    /// How a patch's codes are chosen: 8-bit codes of at least the target step while their
    /// step stays within the coarsest allowed, else 16-bit codes of the target step.
    pub(crate) quantizer: QuantizerPolicy,
}

/// Counts gathered while cutting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct CutCounts {
    /// Cuts made because a piece's bounding rectangle exceeded the grid.
    pub(crate) split_tiles: usize,
    /// Patches stored with 16-bit displacements.
    pub(crate) wide_patches: usize,
}

/// Cuts the emitted cells (`emitted[cy · (width − 1) + cx]`) of `image` into patches (see the
/// module documentation), appending them to `out`.
pub(crate) fn cut_emitted(
    image: &RangeImage,
    emitted: &[bool],
    settings: &CutSettings,
    counts: &mut CutCounts,
    out: &mut Vec<Patch>,
) -> Result<(), CloudError> {
    let (cw, ch) = (image.geometry.width - 1, image.geometry.height - 1);
    let mut seen = vec![false; emitted.len()];
    let mut stack = Vec::new();
    let mut region = Vec::new();
    for start in 0..emitted.len() {
        if !emitted[start] || seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        region.clear();
        while let Some(c) = stack.pop() {
            let (cx, cy) = (c % cw, c / cw);
            region.push((cx, cy));
            for ny in cy.saturating_sub(1)..(cy + 2).min(ch) {
                for nx in cx.saturating_sub(1)..(cx + 2).min(cw) {
                    let n = ny * cw + nx;
                    if emitted[n] && !seen[n] {
                        seen[n] = true;
                        stack.push(n);
                    }
                }
            }
        }
        region.sort_unstable_by_key(|&(cx, cy)| (cy, cx));
        cut_region(image, &region, settings, counts, out)?;
    }
    Ok(())
}

/// Cuts one set of cells (row-major order) into patches, halving it until each piece fits.
fn cut_region(
    image: &RangeImage,
    cells: &[(usize, usize)],
    settings: &CutSettings,
    counts: &mut CutCounts,
    out: &mut Vec<Patch>,
) -> Result<(), CloudError> {
    let whole = Extent::of(image, cells);
    let fits = whole.cols <= settings.grid && whole.rows <= settings.grid;
    if cells.len() > 1 {
        let (low, high) = halves(cells, &whole);
        let split = if fits {
            let parts = Extent::of(image, &low).nodes() + Extent::of(image, &high).nodes();
            FRAME_BYTES + parts < whole.nodes()
        } else {
            counts.split_tiles += 1;
            true
        };
        if split {
            cut_region(image, &low, settings, counts, out)?;
            return cut_region(image, &high, settings, counts, out);
        }
    }
    let quantizer = settings.quantizer.choose(whole.range)?;
    if quantizer.width() == DisplacementWidth::Bits16 {
        counts.wide_patches += 1;
    }
    out.push(build_patch(image, cells, &whole, &quantizer)?);
    Ok(())
}

/// The cells on either side of the middle of the bounding rectangle's longer side (both
/// non-empty when there are two or more cells), each in the order of `cells`.
fn halves(cells: &[(usize, usize)], extent: &Extent) -> (Cells, Cells) {
    // `cols − 1` cells wide: the first half holds `(cols − 1) / 2` columns, at least one.
    if extent.cols >= extent.rows {
        let cut = extent.i0 + (extent.cols - 1).div_ceil(2);
        cells.iter().partition(|&&(cx, _)| cx < cut)
    } else {
        let cut = extent.j0 + (extent.rows - 1).div_ceil(2);
        cells.iter().partition(|&&(_, cy)| cy < cut)
    }
}

/// The bounding rectangle and the depth range of a set of cells.
struct Extent {
    /// First node column.
    i0: usize,
    /// First node row.
    j0: usize,
    /// Node columns (cells + 1).
    cols: usize,
    /// Node rows (cells + 1).
    rows: usize,
    /// Lowest corner height.
    low: f32,
    /// Highest minus lowest corner height.
    range: f32,
}

impl Extent {
    /// The extent of `cells` (not empty) in `image`.
    fn of(image: &RangeImage, cells: &[(usize, usize)]) -> Extent {
        let width = image.geometry.width;
        let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
        let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
        for &(cx, cy) in cells {
            i0 = i0.min(cx);
            j0 = j0.min(cy);
            i1 = i1.max(cx);
            j1 = j1.max(cy);
            let k = cy * width + cx;
            for h in [k, k + 1, k + width, k + width + 1].map(|k| image.depth[k]) {
                low = low.min(h);
                high = high.max(h);
            }
        }
        Extent {
            i0,
            j0,
            cols: i1 - i0 + 2,
            rows: j1 - j0 + 2,
            low,
            range: high - low,
        }
    }

    /// Nodes of the bounding rectangle (empty ones included).
    fn nodes(&self) -> usize {
        self.cols * self.rows
    }
}

/// The patch over `cells` with the bounding rectangle and depth range `extent`: the corners
/// of the cells are its filled nodes, every other node is empty.
fn build_patch(
    image: &RangeImage,
    cells: &[(usize, usize)],
    extent: &Extent,
    quantizer: &Quantizer,
) -> Result<Patch, CloudError> {
    let Extent {
        i0,
        j0,
        cols,
        rows,
        low,
        ..
    } = *extent;
    let mut filled = vec![false; cols * rows];
    for &(cx, cy) in cells {
        let k = (cy - j0) * cols + (cx - i0);
        filled[k] = true;
        filled[k + 1] = true;
        filled[k + cols] = true;
        filled[k + cols + 1] = true;
    }
    let geometry = image.geometry;
    let width = geometry.width;
    let pixel_of = |k: usize| (j0 + k / cols) * width + i0 + k % cols;
    let mut displacements = vec![spatch_format::EMPTY; cols * rows];
    for (k, d) in displacements.iter_mut().enumerate() {
        if filled[k] {
            *d =
                quantizer
                    .quantize(image.depth[pixel_of(k)] - low)
                    .ok_or(CloudError::Internal {
                        what: "a node height fell outside its patch's quantizer range",
                    })?;
        }
    }
    let colours = image
        .colour
        .as_ref()
        .map(|colour| (0..cols * rows).map(|k| colour[pixel_of(k)]).collect());
    let basis = geometry.basis;
    let frame = Frame::new(
        geometry.point_at(i0, j0, low),
        basis.u * geometry.pixel,
        basis.w * geometry.pixel,
        basis.direction * quantizer.step(),
    )?;
    let grid = GridSize::new(cols as u32, rows as u32)?;
    Ok(Patch::new(frame, grid, displacements, colours)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_split_the_longer_side_in_the_middle() {
        let cells = [(2, 5), (3, 5), (4, 5), (5, 5), (2, 6)];
        let extent = Extent {
            i0: 2,
            j0: 5,
            cols: 5,
            rows: 3,
            low: 0.0,
            range: 0.0,
        };
        let (low, high) = halves(&cells, &extent);
        assert_eq!(low, vec![(2, 5), (3, 5), (2, 6)]);
        assert_eq!(high, vec![(4, 5), (5, 5)]);
    }

    const SETTINGS: CutSettings = CutSettings {
        grid: 33,
        quantizer: QuantizerPolicy {
            target_step: 0.01,
            max_step: 0.05,
            fine_step: 0.01,
        },
    };

    /// Cuts the cells of `image` where `emitted(cx, cy)` holds.
    fn cut(image: &RangeImage, emitted: impl Fn(usize, usize) -> bool) -> Vec<Patch> {
        let (cw, ch) = (image.geometry.width - 1, image.geometry.height - 1);
        let mask: Vec<bool> = (0..cw * ch).map(|c| emitted(c % cw, c / cw)).collect();
        let mut out = Vec::new();
        let mut counts = CutCounts::default();
        cut_emitted(image, &mask, &SETTINGS, &mut counts, &mut out).unwrap();
        out
    }

    #[test]
    fn a_region_that_fits_is_one_patch_over_its_rectangle() {
        let image = RangeImage::from_fn(60, 60, |i, j| 0.3 * i as f32 + 0.1 * j as f32);
        // 20 × 25 cells at (7, 3): one patch of 21 × 26 nodes, every node filled.
        let patches = cut(&image, |cx, cy| {
            (7..27).contains(&cx) && (3..28).contains(&cy)
        });
        assert_eq!(patches.len(), 1);
        let grid = patches[0].grid();
        assert_eq!((grid.cols(), grid.rows()), (21, 26));
        assert_eq!(patches[0].filled_count(), 21 * 26);
    }

    #[test]
    fn a_large_region_is_halved_into_pieces_that_share_their_cut() {
        let image = RangeImage::from_fn(80, 20, |i, _| 0.05 * i as f32);
        // 70 × 10 cells: halved to 35 and 35 cells (36 nodes, too wide), then again.
        let patches = cut(&image, |cx, cy| cx < 70 && cy < 10);
        assert_eq!(patches.len(), 4);
        let cols: usize = patches.iter().map(|p| p.grid().cols() as usize - 1).sum();
        assert_eq!(cols, 70, "the pieces' cells tile the region exactly");
        assert!(patches
            .iter()
            .all(|p| p.grid().cols() <= 33 && p.grid().rows() == 11));
    }

    #[test]
    fn a_sparse_region_is_cut_where_its_empty_nodes_cost_more_than_a_frame() {
        let image = RangeImage::from_fn(40, 40, |_, _| 1.0);
        // An L: a 30-cell row and a 30-cell column joined at a corner; its rectangle would
        // hold 31 × 31 nodes, mostly empty.
        let patches = cut(&image, |cx, cy| cy == 0 && cx < 30 || cx == 0 && cy < 30);
        assert!(patches.len() >= 2);
        let nodes: usize = patches.iter().map(|p| p.grid().node_count()).sum();
        assert!(nodes < 31 * 31 / 4, "{nodes} nodes");
    }

    #[test]
    fn a_steep_region_stays_whole_with_16_bit_codes() {
        // Depth range 40 over 33 nodes: an 8-bit step of 0.16 > 0.05.
        let image = RangeImage::from_fn(40, 40, |i, _| 1.25 * i as f32);
        let patches = cut(&image, |cx, cy| cx < 32 && cy < 32);
        assert_eq!(patches.len(), 1);
        assert_eq!(patches[0].displacement_width(), DisplacementWidth::Bits16);
    }
}
