//! Region extraction: rectangular, continuous, not-too-steep regions of a range image that
//! cover points no earlier view covered, each turned into a patch.
//!
//! Input: one view's [`RangeImage`] (with the cells it already emitted), the positions, the
//! list of points not covered yet, the steepest slope allowed in this pass and the
//! [`ExtractSettings`]. Output: patches, and the list of uncovered points shrunk by the
//! points they cover.
//!
//! Terms: a *cell* is the square between four neighbouring pixel centres (the nodes). A cell
//! is *valid* when its four corners are filled, no edge has a depth step above `jump` (a
//! diagonal `jump·√2`), and its slope (the angle between its normal and the view direction,
//! from the mean depth gradient) is within the pass's limit.
//!
//! Method:
//! 1. Each uncovered point is projected into its cell. If the cell is valid and the point is
//!    within `tolerance` of the cell's bilinear surface (measured along the normal), the point
//!    is covered and the cell is *needed*. Points of other surfaces (behind the front one),
//!    outliers, and points under steep or broken cells stay uncovered for later views.
//! 2. Emitted cells are the needed cells plus the valid cells around them (8-neighbours):
//!    this closes cells that hold no point (sampling gaps) and makes neighbouring patches
//!    overlap by a cell. A cell is emitted at most once per view.
//! 3. The image is cut into fixed tiles of `tile × tile` cells (the patch grid minus one), so
//!    a patch is a rectangle of at most `grid × grid` nodes and neighbouring tiles share their
//!    border nodes (no cracks within a view). The emitted cells of a tile form one patch over
//!    their bounding rectangle; nodes that are no emitted cell's corner are empty. When that
//!    patch's depth range needs an 8-bit step coarser than `max_step`, the tile's cells are
//!    split into 8-connected components, one patch each; a component that is still too deep
//!    is stored with 16-bit displacements.
//! 4. A patch's frame is the view's image axes scaled by the pixel size (`ax`, `ay`) and the
//!    view direction scaled by the quantization step (`az`), with its origin at the first
//!    node at the lowest height of the patch. Node colours are the pixel colours.
//!
//! Invariants: every covered point lies within `tolerance` of a drawable cell of an emitted
//! patch (before quantization, which adds at most half a step); the output order is the
//! tile order, so it is deterministic.
//!
//! Parallelism: step 1 is a map over the uncovered points and steps 2–4 a map over the
//! touched tiles (a tile reads and emits only its own cells, and `needed` is fixed by then);
//! both are collected in order, and the emitted marks are set after the tiles are built, so
//! the patches and the surviving point list do not depend on the thread count. The views
//! themselves stay in order, since each one sees only the points earlier views left.
//!
//! Cost: O(uncovered points) for step 1, O(cells of touched tiles) for steps 2–4; memory one
//! byte per cell for the needed marks.
//!
//! Based on: the rectangular region cutting of the spatial-patch paper (range images from
//! several directions, each view adding only the surface that earlier views missed).

use glam::Vec3;
use rayon::prelude::*;
use spatch_format::{DisplacementWidth, Frame, GridSize, Patch, Quantizer};

use crate::range_image::RangeImage;
use crate::{CloudError, PointId};

/// What region extraction needs besides the image.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ExtractSettings {
    /// Depth discontinuity threshold per pixel step (model units).
    pub(crate) jump: f32,
    /// Largest distance from a point to a cell surface for it to count as covered (model
    /// units).
    pub(crate) tolerance: f32,
    /// Cells per tile side (the patch grid minus one), ≥ 1.
    pub(crate) tile: usize,
    /// Target 8-bit displacement step (model units).
    pub(crate) target_step: f32,
    /// Coarsest 8-bit step before a patch is split or widened (model units).
    pub(crate) max_step: f32,
}

/// A view's range image plus the cells it has emitted so far.
#[derive(Clone, Debug)]
pub(crate) struct ViewState {
    /// The range image (heights after gap filling and smoothing).
    pub(crate) image: RangeImage,
    /// One flag per cell (`cy * (width − 1) + cx`).
    emitted: Vec<bool>,
}

impl ViewState {
    /// A view with no emitted cells.
    pub(crate) fn new(image: RangeImage) -> ViewState {
        let cells = (image.geometry.width - 1) * (image.geometry.height - 1);
        ViewState {
            image,
            emitted: vec![false; cells],
        }
    }
}

/// Counts gathered while extracting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct ExtractCounts {
    /// Points covered.
    pub(crate) covered: usize,
    /// Tiles split into components because their depth range was too large.
    pub(crate) split_tiles: usize,
    /// Patches stored with 16-bit displacements.
    pub(crate) wide_patches: usize,
}

/// A valid cell's corner heights `[h00, h10, h01, h11]` and depth gradient.
#[derive(Clone, Copy, Debug)]
struct CellSurface {
    heights: [f32; 4],
    gradient: (f32, f32),
}

impl CellSurface {
    /// The bilinear height at `(tx, ty)` in `[0, 1]²`.
    fn height_at(&self, tx: f32, ty: f32) -> f32 {
        let [h00, h10, h01, h11] = self.heights;
        let bottom = h00 + (h10 - h00) * tx;
        let top = h01 + (h11 - h01) * tx;
        bottom + (top - bottom) * ty
    }
}

/// The surface of cell `(cx, cy)` when it is valid for slope `max_tan` (tangent of the
/// steepest angle).
fn valid_cell(
    image: &RangeImage,
    cx: usize,
    cy: usize,
    jump: f32,
    max_tan: f32,
) -> Option<CellSurface> {
    let w = image.geometry.width;
    let k = cy * w + cx;
    let heights = [
        image.depth[k],
        image.depth[k + 1],
        image.depth[k + w],
        image.depth[k + w + 1],
    ];
    if !heights.iter().all(|h| h.is_finite()) {
        return None;
    }
    let [h00, h10, h01, h11] = heights;
    let diagonal = jump * std::f32::consts::SQRT_2;
    let continuous = (h10 - h00).abs() <= jump
        && (h01 - h00).abs() <= jump
        && (h11 - h10).abs() <= jump
        && (h11 - h01).abs() <= jump
        && (h11 - h00).abs() <= diagonal
        && (h10 - h01).abs() <= diagonal;
    if !continuous {
        return None;
    }
    let inv = 0.5 / image.geometry.pixel;
    let gx = ((h10 - h00) + (h11 - h01)) * inv;
    let gy = ((h01 - h00) + (h11 - h10)) * inv;
    (gx * gx + gy * gy <= max_tan * max_tan).then_some(CellSurface {
        heights,
        gradient: (gx, gy),
    })
}

/// Extracts the patches of one view for one pass (see the module documentation).
///
/// `uncovered` is shrunk to the points still uncovered afterwards.
pub(crate) fn extract_view(
    state: &mut ViewState,
    positions: &[Vec3],
    uncovered: &mut Vec<PointId>,
    pass: &PassLimits,
    settings: &ExtractSettings,
    counts: &mut ExtractCounts,
) -> Result<Vec<Patch>, CloudError> {
    let max_tan = pass.max_tan;
    let image = &state.image;
    let geometry = image.geometry;
    let (cw, ch) = (geometry.width - 1, geometry.height - 1);
    // Per uncovered point: the cell that would cover it, or NO_CELL. Points are independent,
    // so this runs in parallel; the ordered collect keeps the result thread-independent.
    let candidate: Vec<u32> = uncovered
        .par_iter()
        .with_min_len(POINTS_PER_TASK)
        .map(|&id| {
            let (fx, fy, h) = geometry.project(positions[id.index()]);
            if !(fx >= 0.0 && fy >= 0.0 && fx < cw as f32 && fy < ch as f32) {
                return NO_CELL;
            }
            // Truncation is the floor here (non-negative), without a libm call.
            let (cx, cy) = (fx as usize, fy as usize);
            let (x, y) = (cx as f32, cy as f32);
            let Some(cell) = valid_cell(image, cx, cy, settings.jump, max_tan) else {
                return NO_CELL;
            };
            let (gx, gy) = cell.gradient;
            // Vertical distance × cos(slope) = distance along the cell normal.
            let vertical = (h - cell.height_at(fx - x, fy - y)).abs();
            if vertical > settings.tolerance * (1.0 + gx * gx + gy * gy).sqrt() {
                return NO_CELL;
            }
            (cy * cw + cx) as u32
        })
        .collect();
    let mut needed = vec![false; cw * ch];
    let mut needed_list = Vec::new();
    for &c in &candidate {
        let c = c as usize;
        if c != NO_CELL as usize && !needed[c] && !state.emitted[c] {
            needed[c] = true;
            needed_list.push(c);
        }
    }
    if pass.min_cells > 1 {
        drop_small_regions(&mut needed, &mut needed_list, cw, ch, pass.min_cells);
    }
    let before = uncovered.len();
    // In place and sequential: a parallel filter and collect cost more than the test.
    let mut next = candidate.iter();
    uncovered.retain(|_| {
        let c = next.next().map_or(NO_CELL, |&c| c) as usize;
        !(c != NO_CELL as usize && (needed[c] || state.emitted[c]))
    });
    counts.covered += before - uncovered.len();
    if needed_list.is_empty() {
        return Ok(Vec::new());
    }

    // Tiles that hold a needed cell or one of its neighbours.
    let tile = settings.tile;
    let (tiles_x, tiles_y) = (cw.div_ceil(tile), ch.div_ceil(tile));
    let mut tile_touched = vec![false; tiles_x * tiles_y];
    for &c in &needed_list {
        let (cx, cy) = (c % cw, c / cw);
        for ny in cy.saturating_sub(1)..=(cy + 1).min(ch - 1) {
            for nx in cx.saturating_sub(1)..=(cx + 1).min(cw - 1) {
                tile_touched[(ny / tile) * tiles_x + nx / tile] = true;
            }
        }
    }
    let is_needed_near = |cx: usize, cy: usize| {
        (cy.saturating_sub(1)..=(cy + 1).min(ch - 1))
            .any(|ny| (cx.saturating_sub(1)..=(cx + 1).min(cw - 1)).any(|nx| needed[ny * cw + nx]))
    };
    // Tiles are disjoint sets of cells, so each is built on its own (in parallel) and the
    // results are joined in tile order.
    let touched: Vec<usize> = (0..tile_touched.len())
        .filter(|&t| tile_touched[t])
        .collect();
    let built: Vec<TilePatches> = touched
        .par_iter()
        .map(|&t| {
            let (tx, ty) = (t % tiles_x, t / tiles_x);
            let mut cells = Vec::new();
            for cy in ty * tile..((ty + 1) * tile).min(ch) {
                for cx in tx * tile..((tx + 1) * tile).min(cw) {
                    let c = cy * cw + cx;
                    if state.emitted[c] || !is_needed_near(cx, cy) {
                        continue;
                    }
                    if valid_cell(&state.image, cx, cy, settings.jump, max_tan).is_some() {
                        cells.push((cx, cy));
                    }
                }
            }
            let mut tile_counts = ExtractCounts::default();
            let mut patches = Vec::new();
            let result = build_patches(
                &state.image,
                &cells,
                settings,
                true,
                &mut tile_counts,
                &mut patches,
            );
            TilePatches {
                cells,
                patches: result.map(|()| patches),
                counts: tile_counts,
            }
        })
        .collect();
    let mut patches = Vec::new();
    for tile in built {
        for &(cx, cy) in &tile.cells {
            state.emitted[cy * cw + cx] = true;
        }
        counts.split_tiles += tile.counts.split_tiles;
        counts.wide_patches += tile.counts.wide_patches;
        patches.extend(tile.patches?);
    }
    Ok(patches)
}

/// Uncovered points handed to one parallel task at least (smaller lists are not worth the
/// split).
const POINTS_PER_TASK: usize = 4096;

/// What one tile of a view produced.
struct TilePatches {
    /// The tile's emitted cells.
    cells: Vec<(usize, usize)>,
    /// Its patches.
    patches: Result<Vec<Patch>, CloudError>,
    /// Its split and wide patches.
    counts: ExtractCounts,
}

/// Marks "no cell" in the per-point candidate list.
const NO_CELL: u32 = u32::MAX;

/// The limits of one pass over the views.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PassLimits {
    /// Tangent of the steepest accepted slope.
    pub(crate) max_tan: f32,
    /// Smallest region (8-connected needed cells) that becomes patches; smaller ones are
    /// left for later views and passes.
    pub(crate) min_cells: usize,
}

/// Unmarks the needed cells of 8-connected regions smaller than `min_cells`.
fn drop_small_regions(
    needed: &mut [bool],
    needed_list: &mut Vec<usize>,
    cw: usize,
    ch: usize,
    min_cells: usize,
) {
    let mut seen = vec![false; needed.len()];
    let mut stack = Vec::new();
    let mut region = Vec::new();
    let mut dropped = Vec::new();
    for &start in needed_list.iter() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        stack.push(start);
        region.clear();
        while let Some(c) = stack.pop() {
            region.push(c);
            let (cx, cy) = (c % cw, c / cw);
            for ny in cy.saturating_sub(1)..=(cy + 1).min(ch - 1) {
                for nx in cx.saturating_sub(1)..=(cx + 1).min(cw - 1) {
                    let n = ny * cw + nx;
                    if needed[n] && !seen[n] {
                        seen[n] = true;
                        stack.push(n);
                    }
                }
            }
        }
        if region.len() < min_cells {
            dropped.extend_from_slice(&region);
        }
    }
    for &c in &dropped {
        needed[c] = false;
    }
    needed_list.retain(|&c| needed[c]);
}

/// Marks as covered the uncovered points that lie beside an emitted cell of this view, within
/// one cell horizontally and `tolerance` of the cell's surface extended to them; such points
/// sit at the border of a patch, within `sqrt(tolerance² + pixel²)` of its surface, and need
/// no patch of their own. Returns how many were covered.
pub(crate) fn absorb_border_points(
    state: &ViewState,
    positions: &[Vec3],
    uncovered: &mut Vec<PointId>,
    tolerance: f32,
    settings: &ExtractSettings,
) -> usize {
    let image = &state.image;
    let geometry = image.geometry;
    let (cw, ch) = (geometry.width - 1, geometry.height - 1);
    let before = uncovered.len();
    let stays = |id: PointId| {
        let (fx, fy, h) = geometry.project(positions[id.index()]);
        let (x, y) = (fx.floor(), fy.floor());
        if !(x >= -1.0 && y >= -1.0 && x <= cw as f32 && y <= ch as f32) {
            return true;
        }
        let (cx, cy) = (x as isize, y as isize);
        for ny in (cy - 1).max(0)..=(cy + 1).min(ch as isize - 1) {
            for nx in (cx - 1).max(0)..=(cx + 1).min(cw as isize - 1) {
                let (ux, uy) = (nx as usize, ny as usize);
                if !state.emitted[uy * cw + ux] {
                    continue;
                }
                // Emitted cells were valid; re-read their surface without a slope limit.
                let Some(cell) = valid_cell(image, ux, uy, settings.jump, f32::INFINITY) else {
                    continue;
                };
                let (gx, gy) = cell.gradient;
                let surface = cell.height_at(fx - nx as f32, fy - ny as f32);
                if (h - surface).abs() <= tolerance * (1.0 + gx * gx + gy * gy).sqrt() {
                    return false;
                }
            }
        }
        true
    };
    *uncovered = uncovered
        .par_iter()
        .with_min_len(POINTS_PER_TASK)
        .copied()
        .filter(|&id| stays(id))
        .collect();
    before - uncovered.len()
}

/// Builds the patch (or patches) over `cells` of one tile.
fn build_patches(
    image: &RangeImage,
    cells: &[(usize, usize)],
    settings: &ExtractSettings,
    may_split: bool,
    counts: &mut ExtractCounts,
    out: &mut Vec<Patch>,
) -> Result<(), CloudError> {
    let Some(&(first_x, first_y)) = cells.first() else {
        return Ok(());
    };
    let (mut i0, mut j0, mut i1, mut j1) = (first_x, first_y, first_x, first_y);
    for &(cx, cy) in cells {
        i0 = i0.min(cx);
        j0 = j0.min(cy);
        i1 = i1.max(cx);
        j1 = j1.max(cy);
    }
    let (cols, rows) = (i1 - i0 + 2, j1 - j0 + 2);
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
    let height_of = |k: usize| image.depth[(j0 + k / cols) * width + i0 + k % cols];
    let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
    for k in (0..filled.len()).filter(|&k| filled[k]) {
        low = low.min(height_of(k));
        high = high.max(height_of(k));
    }
    let range = high - low;
    let mut quantizer =
        Quantizer::for_range(range, settings.target_step, DisplacementWidth::Bits8)?;
    if quantizer.step() > settings.max_step {
        if may_split {
            let components = split_components(cells);
            if components.len() > 1 {
                counts.split_tiles += 1;
                for component in components {
                    build_patches(image, &component, settings, false, counts, out)?;
                }
                return Ok(());
            }
        }
        quantizer = Quantizer::for_range(range, settings.target_step, DisplacementWidth::Bits16)?;
        counts.wide_patches += 1;
    }
    let mut displacements = vec![spatch_format::EMPTY; cols * rows];
    for (k, d) in displacements.iter_mut().enumerate() {
        if filled[k] {
            *d = quantizer
                .quantize(height_of(k) - low)
                .ok_or(CloudError::Internal {
                    what: "a node height fell outside its patch's quantizer range",
                })?;
        }
    }
    let colours = image.colour.as_ref().map(|colour| {
        (0..cols * rows)
            .map(|k| colour[(j0 + k / cols) * width + i0 + k % cols])
            .collect()
    });
    let basis = geometry.basis;
    let frame = Frame::new(
        geometry.point_at(i0, j0, low),
        basis.u * geometry.pixel,
        basis.w * geometry.pixel,
        basis.direction * quantizer.step(),
    )?;
    let grid = GridSize::new(cols as u32, rows as u32)?;
    out.push(Patch::new(frame, grid, displacements, colours)?);
    Ok(())
}

/// The 8-connected components of `cells`, each in the order of `cells`.
fn split_components(cells: &[(usize, usize)]) -> Vec<Vec<(usize, usize)>> {
    let mut label = vec![usize::MAX; cells.len()];
    let mut components: Vec<Vec<(usize, usize)>> = Vec::new();
    let mut stack = Vec::new();
    for start in 0..cells.len() {
        if label[start] != usize::MAX {
            continue;
        }
        let id = components.len();
        label[start] = id;
        stack.push(start);
        let mut members = Vec::new();
        while let Some(a) = stack.pop() {
            members.push(a);
            let (ax, ay) = cells[a];
            for (b, &(bx, by)) in cells.iter().enumerate() {
                if label[b] == usize::MAX && ax.abs_diff(bx) <= 1 && ay.abs_diff(by) <= 1 {
                    label[b] = id;
                    stack.push(b);
                }
            }
        }
        members.sort_unstable();
        components.push(members.into_iter().map(|m| cells[m]).collect());
    }
    components
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_follow_8_connectivity() {
        let cells = [(0, 0), (1, 1), (5, 5), (6, 5), (9, 0)];
        let parts = split_components(&cells);
        assert_eq!(
            parts,
            vec![vec![(0, 0), (1, 1)], vec![(5, 5), (6, 5)], vec![(9, 0)]]
        );
    }
}
