//! Overlap trimming: level-0 cells that another patch already draws are
//! left out, once per scene ([`crate::PreparedScene::trimming_overlaps`]).
//!
//! Patches carry no connectivity, so models cover their surface with
//! overlapping patches: on the perfect sphere every point lies on 1.7
//! patches on average. Every covered pixel is then drawn about twice, and
//! the second draw loses the depth test or overwrites a sample of the same
//! surface. A cell of patch `P` is trimmed when a patch `Q` earlier in the
//! scene draws the same piece of surface:
//!
//! - `Q` faces the same way (`az` axes within 60°);
//! - each corner of the cell, in `Q`'s grid, is within [`HEIGHT_TOLERANCE`]
//!   of `Q`'s bilinear surface, and a box around it (a margin of
//!   `MIN_MARGIN + MAX_TAN · offset` cells) lies in `Q`'s drawn, untrimmed
//!   level-0 cells and in drawable cells of each coarser level;
//! - the cell's normal is within 1° of the normals of `Q`'s cells under its
//!   corners;
//! - the corners span at most [`MAX_SPAN`] of `Q`'s cells.
//!
//! Then the cell's image lies inside `Q`'s: a height offset `h` moves a
//! point by `h · tan θ` across `Q`'s plane at a view `θ` from the normal,
//! which the margin absorbs up to `tan θ = MAX_TAN`; and near a silhouette,
//! where one cell may face the eye while the other is culled as facing
//! away, the normal test bounds that rim to a fraction of a pixel.
//! Covers come earlier in the scene, so their trimmed cells are final when
//! a later patch relies on them.
//!
//! Coarser mip levels are kept whole: they are drawn when cells are below
//! a pixel, where the overdraw costs little.
//!
//! Cost: the neighbours of each patch by bounding spheres (a sweep over
//! them sorted along x); per pair, the nodes whose columns can fall inside
//! the cover's square get a point test, then each cell with four covered
//! corners a normal and span test. The pairs are searched in parallel, and
//! a serial pass in scene order keeps the cells that rest on trimmed ones
//! ([`trim_overlaps`]). See docs/algorithms/overlap.md.

use glam::DVec3;
use rayon::prelude::*;

use crate::grid::CELL_DRAW;
use crate::prepare::mip::MipLevel;
use crate::prepare::patch::PreparedPatch;

/// Largest distance between a trimmed cell's corners and the covering
/// surface, in units of the covering patch's node spacing.
pub(crate) const HEIGHT_TOLERANCE: f64 = 0.05;
/// Largest extent of a trimmed cell along each axis of the covering grid,
/// in its cells (so the margin around the corners covers the cell).
pub(crate) const MAX_SPAN: f64 = 1.5;
/// Smallest cosine between a trimmed cell's normal and the normals of the
/// cover's cells under its corners (1°): where the view is edge-on, one
/// cell can face the eye while the other is culled as facing away, and
/// this bounds the rim where that happens (`R · (1 − cos 1°)`, 0.3 px for
/// a sphere of radius 2000 px).
const MIN_NORMAL_COS: f64 = 0.999_847_695;
/// Margin kept around a trimmed corner inside the cover's drawn cells, in
/// its cells, on top of the height offset's reach.
const MIN_MARGIN: f64 = 0.05;
/// Steepest view (tangent of the angle from the normal) at which a trimmed
/// corner's height offset stays inside the margin.
const MAX_TAN: f64 = 20.0;
/// Smallest cosine between the normal axes of a trimmed patch and its cover.
const MIN_AXIS_COS: f64 = 0.5;

/// Trims level 0 of every patch against its neighbours (see the module
/// header). Returns the number of cells trimmed.
///
/// Why two passes: a cover's trimmed cells must be final before a later
/// patch relies on them, which orders the patches. The geometric search
/// ignores trimming and runs on every patch at once; it records, for each
/// cell and cover, the cover's level-0 cells the corners' margins rest on.
/// A serial pass in scene order then trims a cell when one of its covers
/// has none of those cells trimmed: the same cells as a serial search, for
/// a fraction of its time on one core.
pub(crate) fn trim_overlaps(patches: &mut [PreparedPatch]) -> u64 {
    let neighbours = neighbours(patches);
    let shared: &[PreparedPatch] = patches;
    let normals: Vec<Vec<DVec3>> = shared.par_iter().map(cell_normals).collect();
    let found: Vec<Vec<Candidate>> = (0..shared.len())
        .into_par_iter()
        .map(|p| candidates(shared, &normals, p, &neighbours[p]))
        .collect();
    let cells = |p: &PreparedPatch| vec![false; p.level(0).cell_flags.len()];
    let mut trimmed: Vec<Vec<bool>> = patches.iter().map(cells).collect();
    let mut count = 0;
    for (p, list) in found.iter().enumerate() {
        // Covers come before `p`, so their trimmed cells are final here.
        let mut mine = std::mem::take(&mut trimmed[p]);
        for c in list {
            let cover = &trimmed[c.cover as usize];
            let ccols = patches[c.cover as usize].level(0).cols - 1;
            let untrimmed = |b: &[u8; 4]| {
                (b[1] as usize..=b[3] as usize).all(|j| {
                    let row = &cover[j * ccols..(j + 1) * ccols];
                    !row[b[0] as usize..=b[2] as usize].contains(&true)
                })
            };
            if !mine[c.cell as usize] && c.blocks.iter().all(untrimmed) {
                mine[c.cell as usize] = true;
                count += 1;
            }
        }
        trimmed[p] = mine;
    }
    patches
        .par_iter_mut()
        .zip(&trimmed)
        .filter(|(_, cells)| cells.contains(&true))
        .for_each(|(patch, cells)| patch.base_mut().trim_cells(cells));
    count
}

/// A level-0 cell of a patch that a cover draws unless the cover loses one
/// of the cells its corners' margins rest on.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    /// The cell (row-major).
    cell: u32,
    /// The covering patch (earlier in the scene).
    cover: u32,
    /// Per corner, the cover's level-0 cells under its margin: first
    /// column, first row, last column, last row.
    blocks: [[u8; 4]; 4],
}

/// The cells of patch `p` that its earlier neighbours `covers` draw as far
/// as geometry goes (none of the covers' cells trimmed), in cover order;
/// `normals` holds every patch's [`cell_normals`].
fn candidates(
    patches: &[PreparedPatch],
    normals: &[Vec<DVec3>],
    p: usize,
    covers: &[usize],
) -> Vec<Candidate> {
    let level = patches[p].level(0);
    let (cols, ccols) = (level.cols, level.cols - 1);
    let codes = &level.displacements;
    let mut corners = vec![None; cols * level.rows];
    let mut ranges = Vec::with_capacity(level.rows);
    let mut found = Vec::new();
    for &q in covers {
        let map = GridMap::new(&patches[p], &patches[q]);
        map.row_ranges(level, patches[q].level(0), &mut ranges);
        let cover = Cover::new(&patches[q], &normals[q]);
        for (j, range) in ranges.iter().enumerate() {
            for i in range.clone() {
                let k = j * cols + i;
                corners[k] = cover.covered_corner(map.at(i, j, codes[k]));
            }
        }
        for (j, pair) in ranges.windows(2).enumerate() {
            // Cells with all four corners in both rows' ranges.
            let (first, end) = (
                pair[0].start.max(pair[1].start),
                pair[0].end.min(pair[1].end),
            );
            for i in first..end.saturating_sub(1) {
                if !level.cell_is_drawable(i, j) {
                    continue;
                }
                let n = j * cols + i;
                let [Some(a), Some(b), Some(c), Some(d)] =
                    [n, n + 1, n + cols, n + cols + 1].map(|c| corners[c])
                else {
                    continue;
                };
                let four = [a, b, c, d];
                let normal = normals[p][j * ccols + i];
                let agree = four.iter().all(|c| normals_agree(c.normal, normal));
                if agree && span_fits(&four) {
                    found.push(Candidate {
                        cell: (j * ccols + i) as u32,
                        cover: q as u32,
                        blocks: four.map(|c| c.block),
                    });
                }
            }
        }
    }
    found
}

/// For each patch, the patches before it whose bounding spheres meet its
/// own and whose normal axes are within 60° of its own, in index order. Why a
/// sweep over the spheres sorted by their low x: only pairs overlapping
/// along x are looked at (models hold thousands of patches).
fn neighbours(patches: &[PreparedPatch]) -> Vec<Vec<usize>> {
    let mut order: Vec<usize> = (0..patches.len()).collect();
    let low_x = |k: usize| patches[k].centre.x - patches[k].radius;
    order.sort_by(|&a, &b| low_x(a).total_cmp(&low_x(b)));
    let mut neighbours = vec![Vec::new(); patches.len()];
    for (n, &a) in order.iter().enumerate() {
        let (pa, high_x) = (&patches[a], patches[a].centre.x + patches[a].radius);
        for &b in order[n + 1..].iter().take_while(|&&b| low_x(b) <= high_x) {
            let pb = &patches[b];
            let meet = (pa.centre - pb.centre).length() < pa.radius + pb.radius;
            if meet && pa.rotation.z_axis.dot(pb.rotation.z_axis) >= MIN_AXIS_COS {
                neighbours[a.max(b)].push(a.min(b));
            }
        }
    }
    for list in &mut neighbours {
        list.sort_unstable();
    }
    neighbours
}

/// The normal (not unit, along model-space axes) of every level-0 cell of
/// `p`, row-major (meaningless for cells with an empty corner): the cross
/// product of its diagonals. With `A = ax + ay`, `B = ay - ax` and the
/// diagonals `A + α·az`, `B + β·az` (α, β their height-code differences),
/// it is `A×B + β·(A×az) + α·(az×B)`, three products fixed per patch. Why
/// once per patch and in this form: a patch covers about ten neighbours,
/// and the normal of its cell is read for every corner it covers
/// (callgrind, `profile_sphere 500 1 1 trimmed`: 30 M instructions as four
/// corners and a cross product per cell).
fn cell_normals(p: &PreparedPatch) -> Vec<DVec3> {
    let level = p.level(0);
    let (cols, rows) = (level.cols, level.rows);
    let [ax, ay, az] = p.axes;
    let (a, b) = (ax + ay, ay - ax);
    let (fixed, per_beta, per_alpha) = (a.cross(b), a.cross(az), az.cross(b));
    let d = |k: usize| level.displacements[k] as i32;
    let mut out = Vec::with_capacity((cols - 1) * (rows - 1));
    for j in 0..rows - 1 {
        for i in 0..cols - 1 {
            let k = j * cols + i;
            let alpha = (d(k + cols + 1) - d(k)) as f64;
            let beta = (d(k + cols) - d(k + 1)) as f64;
            out.push(fixed + per_beta * beta + per_alpha * alpha);
        }
    }
    out
}

/// True when the angle between `a` and `b` (any lengths) is within the
/// one of [`MIN_NORMAL_COS`]; without square roots.
fn normals_agree(a: DVec3, b: DVec3) -> bool {
    let dot = a.dot(b);
    dot > 0.0
        && dot * dot >= MIN_NORMAL_COS * MIN_NORMAL_COS * a.length_squared() * b.length_squared()
}

/// The affine map from a patch `p`'s level-0 grid (column, row, height
/// code) to a patch `q`'s (`u`, `v` in node spacings, `w` in height codes).
/// Why a map per pair: a corner's coordinates in the cover are then three
/// sums of products, instead of its model-space position and three dot
/// products (callgrind, `profile_sphere 500 1 1 trimmed`).
#[derive(Debug, Clone, Copy)]
struct GridMap {
    /// Coordinates of `p`'s node (0, 0) at height code 0.
    base: [f64; 3],
    /// Change per column of `p`.
    per_col: [f64; 3],
    /// Change per row of `p`.
    per_row: [f64; 3],
    /// Change per height code of `p`.
    per_code: [f64; 3],
}

impl GridMap {
    fn new(p: &PreparedPatch, q: &PreparedPatch) -> Self {
        let inverse = q.axes.map(|a| a / a.length_squared());
        let along = |x: DVec3| inverse.map(|inv| x.dot(inv));
        Self {
            base: along(p.origin - q.origin),
            per_col: along(p.axes[0]),
            per_row: along(p.axes[1]),
            per_code: along(p.axes[2]),
        }
    }

    /// `q`'s coordinates of `p`'s node `(i, j)` with height code `code`.
    #[inline]
    fn at(&self, i: usize, j: usize, code: u16) -> [f64; 3] {
        let (i, j, d) = (i as u32 as f64, j as u32 as f64, code as f64);
        std::array::from_fn(|k| {
            self.base[k] + i * self.per_col[k] + j * self.per_row[k] + d * self.per_code[k]
        })
    }

    /// Per row of `p`'s level-0 nodes (`lp`), the columns whose nodes can
    /// fall inside `q`'s level-0 square (`lq`), into `out` (empty ranges
    /// elsewhere). A node's `u` and `v` are affine in its column, so each
    /// row's columns follow from four linear bounds, widened by `p`'s
    /// height range. Why: most of a neighbour's nodes lie outside the
    /// square (callgrind, `profile_sphere 500 1 1 trimmed`: trimming 267 →
    /// 227 M instructions).
    fn row_ranges(&self, lp: &MipLevel, lq: &MipLevel, out: &mut Vec<std::ops::Range<usize>>) {
        let (d0, d1) = (lp.d_range.0 as f64, lp.d_range.1 as f64);
        // [0, top) along each of q's axes: `base + j·per_row + i·per_col + d·per_code`.
        let axes = [0, 1].map(|a| {
            let per_code = self.per_code[a];
            let top = [lq.cols - 1, lq.rows - 1][a] as f64;
            let slack = (per_code * d0).min(per_code * d1)..=(per_code * d0).max(per_code * d1);
            (self.base[a], self.per_row[a], self.per_col[a], slack, top)
        });
        out.clear();
        for j in 0..lp.rows {
            let (mut lo, mut hi) = (0.0f64, (lp.cols - 1) as f64);
            for (base, per_row, per_col, slack, top) in &axes {
                // base + j·per_row + i·per_col + s in [0, top) for some s in slack.
                let at = base + j as f64 * per_row;
                let (need_lo, need_hi) = (-at - slack.end(), top - at - slack.start());
                if per_col.abs() < 1e-12 {
                    if !(need_lo <= 0.0 && 0.0 <= need_hi) {
                        hi = -1.0;
                    }
                    continue;
                }
                let (a, b) = (need_lo / per_col, need_hi / per_col);
                // Plain compares: the operands are finite or the row is
                // dropped below, and `f64::min`'s NaN rules cost a dozen
                // instructions a call here.
                let (first, last) = if a < b { (a, b) } else { (b, a) };
                lo = if first > lo { first } else { lo };
                hi = if last < hi { last } else { hi };
            }
            // Whole columns in [lo, hi]: truncation after the bounds checks
            // (NaN fails them) floors non-negative values.
            let range = if lo <= hi && hi >= 0.0 {
                let first = lo as usize + usize::from(lo > (lo as usize) as f64);
                first..hi as usize + 1
            } else {
                0..0
            };
            out.push(range);
        }
    }
}

/// True when the grid points of a cell's corners span at most
/// [`MAX_SPAN`] cells along each axis.
fn span_fits(corners: &[Corner]) -> bool {
    let axis = |a: usize| {
        let vals = corners.iter().map(|c| c.uv[a]);
        let lo = vals.clone().fold(f64::INFINITY, f64::min);
        let hi = vals.fold(f64::NEG_INFINITY, f64::max);
        hi - lo <= MAX_SPAN
    };
    axis(0) && axis(1)
}

/// A corner of a cell to trim, as its cover sees it.
#[derive(Debug, Clone, Copy)]
struct Corner {
    /// Grid point in the cover's level 0 (node units).
    uv: [f64; 2],
    /// Normal of the cover's cell holding it (not unit).
    normal: DVec3,
    /// The cover's level-0 cells under the margin around it: first column,
    /// first row, last column, last row.
    block: [u8; 4],
}

/// One patch seen as a cover: the tests of [`Cover::covered_corner`], with
/// the per-patch factors computed once.
struct Cover<'a> {
    patch: &'a PreparedPatch,
    /// Its [`cell_normals`].
    normals: &'a [DVec3],
    /// `|az|` over the smaller node spacing: a height code difference in
    /// node spacings.
    height_scale: f64,
    /// Every level-0 cell is drawn: a margin inside the square is inside
    /// drawn cells.
    base_whole: bool,
    /// Every cell of every coarser level is drawn: level 0's margin test
    /// then stands for them all (every level spans the same extent).
    coarse_whole: bool,
}

impl<'a> Cover<'a> {
    fn new(patch: &'a PreparedPatch, normals: &'a [DVec3]) -> Self {
        let spacing = patch.axes[0].length().min(patch.axes[1].length());
        Self {
            patch,
            normals,
            height_scale: patch.axes[2].length() / spacing,
            base_whole: patch.level(0).draws_every_cell(),
            coarse_whole: (1..patch.level_count()).all(|m| patch.level(m).draws_every_cell()),
        }
    }

    /// The corner at grid coordinates `[u, v, w]` of this patch when it
    /// covers it: the point lies near its surface and a margin inside its
    /// drawn cells at every level (see the module header).
    fn covered_corner(&self, [u, v, w]: [f64; 3]) -> Option<Corner> {
        let q = self.patch;
        let base = q.level(0);
        // `u, v` at least 0 and inside the grid (NaN fails too), so the
        // truncations below are floors.
        let inside = |u: f64, v: f64, level: &MipLevel| {
            u >= 0.0 && v >= 0.0 && u < cells_f64(level.cols) && v < cells_f64(level.rows)
        };
        // Why this test first: most points of a neighbour lie outside the
        // cover's square (callgrind, `profile_sphere 500 1 1 trimmed`).
        if !inside(u, v, base) {
            return None;
        }
        let (fi, fj) = (floor_index(u), floor_index(v));
        let (fu, fv) = (u - fi as i32 as f64, v - fj as i32 as f64);
        let d = |i: usize, j: usize| base.displacements[j * base.cols + i] as f64;
        let h = (d(fi, fj) * (1.0 - fu) + d(fi + 1, fj) * fu) * (1.0 - fv)
            + (d(fi, fj + 1) * (1.0 - fu) + d(fi + 1, fj + 1) * fu) * fv;
        // Distance to the cover's surface along its normal, in spacings.
        let offset = (w - h).abs() * self.height_scale;
        if offset > HEIGHT_TOLERANCE {
            return None;
        }
        let margin = MIN_MARGIN + offset * MAX_TAN;
        // The cells of `level` under the margin, when it lies inside it.
        let block = |level: &MipLevel| {
            let s = level.spacing as f64;
            let (u0, v0) = ((u - margin) / s, (v - margin) / s);
            let (u1, v1) = ((u + margin) / s, (v + margin) / s);
            (inside(u0, v0, level) && inside(u1, v1, level)).then(|| {
                [
                    floor_index(u0),
                    floor_index(v0),
                    floor_index(u1),
                    floor_index(v1),
                ]
            })
        };
        let base_block = block(base).filter(|b| self.base_whole || block_is_drawn(base, b))?;
        // A coarser level with every cell drawn spans level 0's extent, so
        // level 0's test stands for it.
        let all_levels = self.coarse_whole
            || (1..q.level_count())
                .map(|m| q.level(m))
                .all(|l| l.draws_every_cell() || block(l).is_some_and(|b| block_is_drawn(l, &b)));
        all_levels.then(|| Corner {
            uv: [u, v],
            normal: self.normals[fj * (base.cols - 1) + fi],
            // Grids have at most 256 nodes a side.
            block: base_block.map(|x| x as u8),
        })
    }
}

/// `n - 1` (the cells along a grid side of `n` nodes) as `f64`. Why
/// through `i32`: `usize` to `f64` takes a dozen instructions on x86-64,
/// `i32` one (callgrind, `profile_sphere 500 1 1 trimmed`).
fn cells_f64(n: usize) -> f64 {
    (n as i32 - 1) as f64
}

/// The floor of a grid coordinate already checked to lie inside its grid
/// (truncation, through `i32` for the same reason as [`cells_f64`]).
fn floor_index(x: f64) -> usize {
    x as i32 as usize
}

/// True when every cell of `level` in `block` (first column, first row,
/// last column, last row) is drawn.
fn block_is_drawn(level: &MipLevel, block: &[usize; 4]) -> bool {
    let ccols = level.cols - 1;
    (block[1]..=block[3]).all(|j| {
        let row = &level.cell_flags[j * ccols..(j + 1) * ccols];
        row[block[0]..=block[2]].iter().all(|f| f & CELL_DRAW != 0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};

    use crate::camera::Camera;
    use crate::frame::render::Renderer;
    use crate::options::RenderOptions;
    use crate::prepare::scene::PreparedScene;

    /// A flat 9 × 9 patch with unit spacing at `origin`, axes `ax, ay` and
    /// normal axis of length 0.01 completing them, every code `d`.
    fn flat(origin: Vec3, ax: Vec3, ay: Vec3, d: u16) -> Patch {
        let frame = Frame::new(origin, ax, ay, ax.cross(ay) * 0.01).unwrap();
        Patch::new(frame, GridSize::new(9, 9).unwrap(), vec![d; 81], None).unwrap()
    }

    fn scene(patches: Vec<Patch>) -> Scene {
        Scene::new(DVec3::ZERO, ColourChannel::None, patches).unwrap()
    }

    /// The cells of each patch's level 0 that are not drawn, as `(i, j)`.
    fn undrawn(prepared: &PreparedScene) -> Vec<Vec<(usize, usize)>> {
        prepared
            .patches
            .iter()
            .map(|p| {
                let l = p.level(0);
                (0..l.rows - 1)
                    .flat_map(|j| (0..l.cols - 1).map(move |i| (i, j)))
                    .filter(|&(i, j)| !l.cell_is_drawable(i, j))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn the_later_patch_loses_exactly_the_cells_inside_the_earlier_one() {
        // Patch 0 spans x 0..8, patch 1 x 4..12, both y 0..8 in one plane.
        let s = scene(vec![
            flat(Vec3::ZERO, Vec3::X, Vec3::Y, 7),
            flat(Vec3::new(4.0, 0.0, 0.0), Vec3::X, Vec3::Y, 7),
        ]);
        let prepared = PreparedScene::trimming_overlaps(&s);
        // Patch 1's cells with corners a margin inside patch 0: columns
        // 0..=2 (x up to 7), rows 1..=6 (y 0 and 8 lie on patch 0's border).
        let expected: Vec<(usize, usize)> =
            (1..=6).flat_map(|j| (0..=2).map(move |i| (i, j))).collect();
        let mut got = undrawn(&prepared);
        got.iter_mut()
            .for_each(|cells| cells.sort_by_key(|&(i, j)| (j, i)));
        assert_eq!(got, vec![vec![], expected]);
        assert_eq!(prepared.trimmed_cells(), 18);
        assert_eq!(PreparedScene::new(&s).trimmed_cells(), 0);
    }

    #[test]
    fn a_cell_never_rests_on_a_trimmed_cell() {
        // Patches 0, 1, 2 span x 0..8, 4..12 and 6..14 of one plane. Patch 1
        // loses columns 0..=2 (x 4..7) to patch 0. Patch 2 loses column 0
        // (x 6..7) to patch 0 and columns 2..=4 (x 8..11) to patch 1; its
        // column 1 (x 7..8) lies inside patch 1 too, but the margin around
        // its corners at x = 7 rests on patch 1's trimmed column 2.
        let s = scene(vec![
            flat(Vec3::ZERO, Vec3::X, Vec3::Y, 7),
            flat(Vec3::new(4.0, 0.0, 0.0), Vec3::X, Vec3::Y, 7),
            flat(Vec3::new(6.0, 0.0, 0.0), Vec3::X, Vec3::Y, 7),
        ]);
        let prepared = PreparedScene::trimming_overlaps(&s);
        let rows = |cols: &[usize]| -> Vec<(usize, usize)> {
            (1..=6)
                .flat_map(|j| cols.iter().map(move |&i| (i, j)))
                .collect()
        };
        let mut got = undrawn(&prepared);
        got.iter_mut()
            .for_each(|cells| cells.sort_by_key(|&(i, j)| (j, i)));
        assert_eq!(got, vec![vec![], rows(&[0, 1, 2]), rows(&[0, 2, 3, 4])]);
        assert_eq!(prepared.trimmed_cells(), 42);
    }

    #[test]
    fn opposite_faces_and_offset_surfaces_are_not_trimmed() {
        // Facing the other way (a thin sheet seen from behind).
        let flipped = flat(Vec3::new(4.0, 8.0, 0.0), Vec3::X, -Vec3::Y, 7);
        // The same orientation 0.1 cell above (beyond the tolerance).
        let raised = flat(Vec3::new(4.0, 0.0, 0.1), Vec3::X, Vec3::Y, 7);
        // 0.04 cell above: within it.
        let near = flat(Vec3::new(4.0, 0.0, 0.04), Vec3::X, Vec3::Y, 7);
        for (patch, trimmed) in [(flipped, 0), (raised, 0), (near, 18)] {
            let s = scene(vec![flat(Vec3::ZERO, Vec3::X, Vec3::Y, 7), patch]);
            assert_eq!(
                PreparedScene::trimming_overlaps(&s).trimmed_cells(),
                trimmed
            );
        }
    }

    #[test]
    fn trimming_covers_the_same_pixels_from_any_side() {
        // Three overlapping patches of one plane, seen from the front at
        // several angles (up to 75° from the normal): the trimmed scene
        // must cover exactly the pixels the untrimmed one covers; with the
        // gap fill, whose sparser lattice meets the outline differently,
        // all but a pixel in a thousand.
        let s = scene(vec![
            flat(Vec3::ZERO, Vec3::X, Vec3::Y, 7),
            flat(Vec3::new(4.3, 1.7, 0.0), Vec3::X, Vec3::Y, 7),
            flat(
                Vec3::new(3.0, -2.0, 0.0),
                Vec3::new(0.6, 0.8, 0.0),
                Vec3::new(-0.8, 0.6, 0.0),
                7,
            ),
        ]);
        let (trimmed, kept) = (PreparedScene::trimming_overlaps(&s), PreparedScene::new(&s));
        assert!(trimmed.trimmed_cells() > 20, "{}", trimmed.trimmed_cells());
        let filled = RenderOptions {
            gap_fill: true,
            ..Default::default()
        };
        for options in [RenderOptions::default(), filled] {
            covers_the_same_pixels(&trimmed, &kept, options);
        }
    }

    /// [`trimming_covers_the_same_pixels_from_any_side`] with `options`.
    fn covers_the_same_pixels(
        trimmed: &PreparedScene,
        kept: &PreparedScene,
        options: RenderOptions,
    ) {
        let mut renderer = Renderer::new(options).unwrap();
        for (k, tilt) in [0.0f64, 30.0, 60.0, 75.0].into_iter().enumerate() {
            let (s, c) = (tilt.to_radians().sin(), tilt.to_radians().cos());
            let turn = k as f64 * 1.3;
            let eye = DVec3::new(
                6.0 + 30.0 * s * turn.cos(),
                3.0 + 30.0 * s * turn.sin(),
                30.0 * c,
            );
            let camera = Camera::look_at(eye, DVec3::new(6.0, 3.0, 0.0), DVec3::Z, 35.0, 160, 160)
                .or_else(|_| {
                    Camera::look_at(eye, DVec3::new(6.0, 3.0, 0.0), DVec3::Y, 35.0, 160, 160)
                })
                .unwrap();
            let mut covered = |p: &PreparedScene| -> Vec<bool> {
                let out = renderer.render(p, &camera).unwrap();
                out.image.depth().iter().map(|d| d.is_finite()).collect()
            };
            let (a, b) = (covered(trimmed), covered(kept));
            let n = a.iter().filter(|&&c| c).count();
            let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
            assert!(n > 2000, "view {k}");
            let allowed = if options.gap_fill { n / 1000 } else { 0 };
            assert!(
                differ <= allowed,
                "view {k} at {tilt}°: {differ} pixels differ"
            );
        }
    }

    #[test]
    fn the_sphere_loses_a_third_of_its_cells_and_no_pixel() {
        let s = spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())
            .unwrap()
            .scene;
        let (trimmed, kept) = (PreparedScene::trimming_overlaps(&s), PreparedScene::new(&s));
        // 1362 patches of 16 × 16 cells; 1.7 patches over each point.
        let cells = 1362 * 256;
        assert!(
            trimmed.trimmed_cells() * 4 > cells,
            "{}",
            trimmed.trimmed_cells()
        );
        let camera = trimmed.auto_camera(500, 500).unwrap();
        // The same levels for both: trimmed grids are no longer full, so
        // the mip tolerance would take only the kept ones coarser.
        let options = RenderOptions {
            mip_tolerance: 0.0,
            ..RenderOptions::default()
        };
        let mut renderer = Renderer::new(options).unwrap();
        let a = renderer
            .render(&trimmed, &camera)
            .unwrap()
            .image
            .covered_count();
        let b = renderer
            .render(&kept, &camera)
            .unwrap()
            .image
            .covered_count();
        // Only silhouette pixels seen edge-on may differ (measured: 22 of
        // 175,200).
        assert!(a.abs_diff(b) * 2000 < b, "{a} against {b}");
    }
}
