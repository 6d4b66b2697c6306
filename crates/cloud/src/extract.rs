//! Region extraction: rectangular, continuous, not-too-steep regions of a range image that
//! cover points no earlier view covered, each turned into a patch.
//!
//! Input: one view's [`RangeImage`] (with the cells it already emitted), the positions, the
//! list of points not covered yet, the steepest slope allowed in this pass and the
//! [`ExtractSettings`]. Output: the view's emitted cells grown by this pass, and the list of
//! uncovered points shrunk by the points they cover; [`cut_view`] turns a view's emitted
//! cells into patches.
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
//! 3. Once every pass is done, [`cut_view`] cuts the view's emitted cells into patches
//!    (`patch_cut.rs`: regions halved until they fit the grid), so cells a view added in
//!    several passes become whole patches.
//!
//! Invariants: every covered point lies within `tolerance` of a drawable cell of an emitted
//! patch (before quantization, which adds at most half a step); the patches come in the
//! order of `patch_cut.rs`, so the output is deterministic.
//!
//! Parallelism: step 1 is a map over the uncovered points, collected in order; the uncovered
//! list is shrunk in parallel too, in place and in order; the needed and emitted marks
//! follow sequentially from the candidates, so the patches and the surviving point list do
//! not depend on the thread count. The views themselves stay in order, since each one sees
//! only the points earlier views left.
//!
//! Cost: O(uncovered points) for step 1, O(needed cells) for step 2; memory one byte per
//! cell for the needed marks.
//!
//! Based on: the rectangular region cutting of the spatial-patch paper (range images from
//! several directions, each view adding only the surface that earlier views missed).

use glam::Vec3;
use rayon::prelude::*;
use spatch_format::Patch;

use crate::patch_cut::{cut_emitted, CutCounts, CutSettings};
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
    /// How a view's emitted cells become patches.
    pub(crate) cut: CutSettings,
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

impl std::ops::AddAssign for ExtractCounts {
    /// Adds another extraction's counts (a tile's, into the whole cloud's).
    fn add_assign(&mut self, other: Self) {
        self.covered += other.covered;
        self.split_tiles += other.split_tiles;
        self.wide_patches += other.wide_patches;
    }
}

impl std::ops::AddAssign<CutCounts> for ExtractCounts {
    /// Adds the counts of cutting one view's cells into patches.
    fn add_assign(&mut self, cut: CutCounts) {
        self.split_tiles += cut.split_tiles;
        self.wide_patches += cut.wide_patches;
    }
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

/// Marks the cells one view emits in one pass (see the module documentation); the
/// patches are cut from them by [`cut_view`] once every pass is done.
///
/// `uncovered` is shrunk to the points still uncovered afterwards.
///
/// With `sides` (the points' normals turned toward their scanners,
/// `CloudOptions::scanners`), a point whose normal faces away from the view is not covered
/// by it: it lies on the other side of a thin part, for a view of that side.
pub(crate) fn extract_view(
    state: &mut ViewState,
    (positions, sides): (&[Vec3], Option<&[Vec3]>),
    uncovered: &mut Vec<PointId>,
    pass: &PassLimits,
    settings: &ExtractSettings,
    counts: &mut ExtractCounts,
    marks: &mut CellMarks,
) -> Result<(), CloudError> {
    let points = (positions, sides);
    let candidate = candidate_cells(&state.image, points, uncovered, pass.max_tan, settings);
    let geometry = state.image.geometry;
    let (cw, ch) = (geometry.width - 1, geometry.height - 1);
    let CellMarks { needed, seen } = marks;
    needed.resize(needed.len().max(cw * ch), false);
    let mut needed_list = mark_needed(&candidate, needed, &state.emitted);
    if pass.min_cells > 1 {
        seen.resize(seen.len().max(cw * ch), false);
        drop_small_regions((needed, seen), &mut needed_list, cw, ch, pass.min_cells);
    }
    counts.covered += drop_covered(uncovered, &candidate, needed, &state.emitted);
    emit_around(state, &needed_list, settings.jump, pass.max_tan);
    for &c in &needed_list {
        needed[c] = false;
    }
    Ok(())
}

/// Per uncovered point, the cell of `image` that would cover it in a pass of slope
/// `max_tan` (step 1 of the module documentation), or [`NO_CELL`].
fn candidate_cells(
    image: &RangeImage,
    (positions, sides): (&[Vec3], Option<&[Vec3]>),
    uncovered: &[PointId],
    max_tan: f32,
    settings: &ExtractSettings,
) -> Vec<u32> {
    let geometry = image.geometry;
    let (cw, ch) = (geometry.width - 1, geometry.height - 1);
    // Converted once: a `usize` to `f32` is several instructions, and this bound is tested
    // for every point (87 M instructions of the covering 1 M scan set's workers, callgrind).
    let (right, top) = (cw as f32, ch as f32);
    // Points are independent, so this runs in parallel; the ordered collect keeps the result
    // thread-independent.
    uncovered
        .par_iter()
        .with_min_len(POINTS_PER_TASK)
        .map(|&id| {
            if faces_away(sides, id, geometry.basis.direction) {
                return NO_CELL;
            }
            let (fx, fy, h) = geometry.project(positions[id.index()]);
            if !(fx >= 0.0 && fy >= 0.0 && fx < right && fy < top) {
                return NO_CELL;
            }
            // Truncation is the floor here (non-negative, and below 2^23 cells a side),
            // without a libm call; through `i32`, whose saturating conversion is shorter
            // than `usize`'s (124 M of the covering 1 M scan set's worker instructions).
            let (ix, iy) = (fx as i32, fy as i32);
            let (cx, cy, x, y) = (ix as usize, iy as usize, ix as f32, iy as f32);
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
        .collect()
}

/// Marks in `needed` the `candidate` cells the view has not emitted yet, and lists them in
/// the order of their first point.
fn mark_needed(candidate: &[u32], needed: &mut [bool], emitted: &[bool]) -> Vec<usize> {
    // Sequential, over every candidate: collecting the hits in parallel first (a list of up
    // to 4 bytes a point) took the model only from 4.51 to 4.50 G instructions on the evenly
    // spread 1 M scan set (sequential −58 M, workers +94 M).
    let mut needed_list = Vec::new();
    for &c in candidate {
        let c = c as usize;
        if c != NO_CELL as usize && !needed[c] && !emitted[c] {
            needed[c] = true;
            needed_list.push(c);
        }
    }
    needed_list
}

/// Drops from `uncovered` the points whose `candidate` cell is `needed` or already
/// `emitted` (they are covered); gives how many.
fn drop_covered(
    uncovered: &mut Vec<PointId>,
    candidate: &[u32],
    needed: &[bool],
    emitted: &[bool],
) -> usize {
    let before = uncovered.len();
    retain_by_cell(uncovered, candidate, |c| {
        c == NO_CELL || !(needed[c as usize] || emitted[c as usize])
    });
    before - uncovered.len()
}

/// Emits the needed cells and the valid cells around them (step 2 of the module
/// documentation), each once per view.
fn emit_around(state: &mut ViewState, needed_list: &[usize], jump: f32, max_tan: f32) {
    let geometry = state.image.geometry;
    let (cw, ch) = (geometry.width - 1, geometry.height - 1);
    for &c in needed_list {
        let (cx, cy) = (c % cw, c / cw);
        for ny in cy.saturating_sub(1)..(cy + 2).min(ch) {
            for nx in cx.saturating_sub(1)..(cx + 2).min(cw) {
                let n = ny * cw + nx;
                if !state.emitted[n] && valid_cell(&state.image, nx, ny, jump, max_tan).is_some() {
                    state.emitted[n] = true;
                }
            }
        }
    }
}

/// Keeps the points whose cell passes `keep` (`cells[i]`: the cell of `points[i]`), in order.
///
/// In place and in parallel: each block of points is compacted on its own, then the kept
/// runs are moved down one after the other (a `memmove` each). A sequential `retain` was
/// 124 M sequential instructions of the evenly spread 1 M scan set (callgrind); a parallel
/// filter and collect would hold a second list.
fn retain_by_cell(points: &mut Vec<PointId>, cells: &[u32], keep: impl Fn(u32) -> bool + Sync) {
    let kept: Vec<usize> = points
        .par_chunks_mut(POINTS_PER_TASK)
        .zip(cells.par_chunks(POINTS_PER_TASK))
        .map(|(block, block_cells)| {
            let mut n = 0;
            for (i, &c) in block_cells.iter().enumerate() {
                if keep(c) {
                    block[n] = block[i];
                    n += 1;
                }
            }
            n
        })
        .collect();
    let mut end = 0;
    for (b, &n) in kept.iter().enumerate() {
        let start = b * POINTS_PER_TASK;
        points.copy_within(start..start + n, end);
        end += n;
    }
    points.truncate(end);
}

/// Per-cell marks of [`extract_view`], kept from call to call and cleared cell by cell
/// after each (all false between calls), instead of two zeroed arrays of every cell per
/// view and pass (100 `calloc`s on the 1 M scan sets, whose clearing took 17.5 M sequential
/// instructions).
#[derive(Clone, Debug, Default)]
pub(crate) struct CellMarks {
    /// Cells that cover a point in this pass.
    needed: Vec<bool>,
    /// Cells visited by `drop_small_regions`.
    seen: Vec<bool>,
}

/// Cuts the cells a view emitted over all passes into patches (`patch_cut.rs`). Returns the
/// patches in region order and the counts.
pub(crate) fn cut_view(
    state: &ViewState,
    settings: &ExtractSettings,
) -> Result<(Vec<Patch>, CutCounts), CloudError> {
    let mut counts = CutCounts::default();
    let mut patches = Vec::new();
    cut_emitted(
        &state.image,
        &state.emitted,
        &settings.cut,
        &mut counts,
        &mut patches,
    )?;
    Ok((patches, counts))
}

/// Uncovered points handed to one parallel task at least (smaller lists are not worth the
/// split).
const POINTS_PER_TASK: usize = 4096;

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
/// `seen` is all false on entry and on return.
fn drop_small_regions(
    (needed, seen): (&mut [bool], &mut [bool]),
    needed_list: &mut Vec<usize>,
    cw: usize,
    ch: usize,
    min_cells: usize,
) {
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
            for ny in cy.saturating_sub(1)..(cy + 2).min(ch) {
                for nx in cx.saturating_sub(1)..(cx + 2).min(cw) {
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
    // Every seen cell was needed: the list holds them all.
    for &c in needed_list.iter() {
        seen[c] = false;
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
    (positions, sides): (&[Vec3], Option<&[Vec3]>),
    uncovered: &mut Vec<PointId>,
    tolerance: f32,
    settings: &ExtractSettings,
) -> usize {
    let image = &state.image;
    let geometry = image.geometry;
    let (cw, ch) = (geometry.width - 1, geometry.height - 1);
    let before = uncovered.len();
    let stays = |id: PointId| {
        if faces_away(sides, id, geometry.basis.direction) {
            return true;
        }
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

/// Whether point `id`'s oriented normal (when the points have `sides`) faces away from a view
/// along `direction` (not a grazing angle's worth toward it, as the range images draw).
fn faces_away(sides: Option<&[Vec3]>, id: PointId, direction: Vec3) -> bool {
    sides.is_some_and(|sides| {
        let n = sides[id.index()];
        // The dot first: the zero test (an unknown normal faces every view) is then
        // needed only for the points it would turn away.
        n.dot(direction) < crate::range_image::MIN_POINT_COSINE && n != Vec3::ZERO
    })
}
