//! Splitting of partially visible patches.
//!
//! A patch whose box is neither inside the guard band nor outside the
//! frustum (see [`crate::plan::cull`]) is cut in two along its longer side (the
//! halves share the middle row of nodes, so no crack opens), and each half
//! is classified again with its own, tighter box. Halves outside are
//! dropped, halves inside are drawn like whole patches, and a single cell
//! that is still partial is handed over to the triangle rasterizer, which
//! clips it exactly against the near plane. Hence geometry behind the eye is
//! never projected, and nothing visible is dropped.
//!
//! Input: a level-0 grid, the frustum and the patch's local map. Output:
//! node ranges to draw and single cells to clip. Cost: O(nodes · depth) for
//! the displacement ranges; the recursion depth is at most
//! `log2(cols) + log2(rows)` (8 for 17 × 17), run on an explicit stack.

use glam::{Mat3, Vec3};

use crate::plan::cull::{BoxClass, Frustum};
use crate::prepare::mip::MipLevel;

/// An inclusive range of nodes of a grid: `i0..=i1` × `j0..=j1`, at least
/// one cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NodeRange {
    pub(crate) i0: usize,
    pub(crate) j0: usize,
    pub(crate) i1: usize,
    pub(crate) j1: usize,
}

impl NodeRange {
    /// The whole grid of `level`.
    pub(crate) fn whole(level: &MipLevel) -> Self {
        Self::of_grid([level.cols, level.rows])
    }

    /// Every node of a `[cols, rows]` grid.
    pub(crate) fn of_grid([cols, rows]: [usize; 2]) -> Self {
        Self {
            i0: 0,
            j0: 0,
            i1: cols - 1,
            j1: rows - 1,
        }
    }

    /// Its nodes per row and rows of nodes: `(cols, rows)`.
    #[inline(always)]
    pub(crate) fn size(&self) -> (usize, usize) {
        (self.i1 - self.i0 + 1, self.j1 - self.j0 + 1)
    }

    /// The displacement range of the used nodes inside, or `None` if none.
    pub(crate) fn d_range(&self, level: &MipLevel) -> Option<(u16, u16)> {
        // The whole level's is kept with it. Why: scanning the nodes cost
        // ≈ 3 M instructions per 500² sphere frame (callgrind,
        // `profile_sphere 500 1`).
        if *self == Self::whole(level) {
            let draws = level.drawable_cells > 0 || !level.quartered.is_empty();
            return draws.then_some(level.d_range);
        }
        let mut lo = u16::MAX;
        let mut hi = 0u16;
        for j in self.j0..=self.j1 {
            let row = j * level.cols;
            for k in row + self.i0..=row + self.i1 {
                if level.used[k] {
                    lo = lo.min(level.displacements[k]);
                    hi = hi.max(level.displacements[k]);
                }
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// The box of this range in local coordinates `(i, j, d)`.
    pub(crate) fn local_box(&self, d: (u16, u16)) -> (Vec3, Vec3) {
        (
            Vec3::new(self.i0 as f32, self.j0 as f32, d.0 as f32),
            Vec3::new(self.i1 as f32, self.j1 as f32, d.1 as f32),
        )
    }
}

/// What splitting one patch produced.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct SplitCounts {
    /// Pieces dropped as outside.
    pub(crate) dropped: u32,
}

/// What splitting a patch leaves: the pieces to draw and the single cells
/// to clip, with the scratch stack; kept by a chunk and reused from patch
/// to patch.
#[derive(Debug, Default)]
pub(crate) struct SplitWork {
    pub(crate) stack: Vec<NodeRange>,
    /// Pieces inside the guard band.
    pub(crate) pieces: Vec<NodeRange>,
    /// Single partial cells, as their `(i, j)`.
    pub(crate) cells: Vec<(usize, usize)>,
}

/// Splits `root` of `level` (local map `(map, t0)`) until every piece is
/// inside (pushed to `work.pieces`), outside (dropped) or a single partial
/// cell (pushed to `work.cells`).
pub(crate) fn split_patch(
    level: &MipLevel,
    frustum: &Frustum,
    (map, t0): (&Mat3, Vec3),
    root: NodeRange,
    work: &mut SplitWork,
) -> SplitCounts {
    let SplitWork {
        stack,
        pieces,
        cells,
    } = work;
    let mut counts = SplitCounts::default();
    stack.clear();
    stack.push(root);
    while let Some(r) = stack.pop() {
        let Some(d) = r.d_range(level) else {
            continue;
        };
        let (lo, hi) = r.local_box(d);
        match frustum.classify(map, t0, lo, hi) {
            BoxClass::Outside => counts.dropped += 1,
            BoxClass::Inside => pieces.push(r),
            BoxClass::Partial => {
                let (w, h) = (r.i1 - r.i0, r.j1 - r.j0);
                if w == 1 && h == 1 {
                    if level.cell_is_drawable(r.i0, r.j0) {
                        cells.push((r.i0, r.j0));
                    }
                } else if w >= h {
                    let mid = r.i0 + w / 2;
                    stack.push(NodeRange { i1: mid, ..r });
                    stack.push(NodeRange { i0: mid, ..r });
                } else {
                    let mid = r.j0 + h / 2;
                    stack.push(NodeRange { j1: mid, ..r });
                    stack.push(NodeRange { j0: mid, ..r });
                }
            }
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use spatch_format::{Frame, GridSize, Patch};

    #[test]
    fn a_patch_crossing_the_near_plane_splits_into_inside_pieces_and_clipped_cells() {
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let patch = Patch::new(frame, GridSize::new(9, 9).unwrap(), vec![0; 81], None).unwrap();
        let level = &crate::prepare::mip::build_mip_pyramid(&patch)[0];
        // Map (i, j, d) -> (X, Y, W) = (50 W, 50 W, i - 3.5): W crosses near = 1 at i = 4.5.
        let map = Mat3::from_cols(Vec3::new(50.0, 50.0, 1.0), Vec3::ZERO, Vec3::ZERO);
        let t0 = Vec3::new(-175.0, -175.0, -3.5);
        let f = Frustum {
            width: 100.0,
            height: 100.0,
            near: 1.0,
            far: 100.0,
            guard: 0.1,
        };
        let mut work = SplitWork::default();
        let counts = split_patch(level, &f, (&map, t0), NodeRange::whole(level), &mut work);
        let (pieces, cells) = (&work.pieces, &work.cells);
        // Cells with i in 4..5 straddle the near plane; those at i < 4 are behind it.
        assert!(cells.iter().all(|&(i, _)| i == 4));
        assert_eq!(cells.len(), 8);
        assert!(pieces.iter().all(|p| p.i0 >= 5));
        assert!(counts.dropped > 0);
    }

    #[test]
    fn the_whole_levels_displacement_range_is_that_of_its_used_nodes() {
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        // Empty nodes, and a filled node (300) that belongs to no drawable cell.
        let mut d: Vec<u16> = (0..81).map(|k| (k * 37 % 200) as u16 + 5).collect();
        for k in [0, 1, 9, 40, 41, 49, 50, 80, 79, 71, 70] {
            d[k] = spatch_format::EMPTY;
        }
        d[8] = 300;
        d[7] = spatch_format::EMPTY;
        d[16] = spatch_format::EMPTY;
        let patch = Patch::new(frame, GridSize::new(9, 9).unwrap(), d, None).unwrap();
        for (m, level) in crate::prepare::mip::build_mip_pyramid(&patch)
            .iter()
            .enumerate()
        {
            let whole = NodeRange::whole(level);
            let used = (0..level.cols * level.rows).filter(|&k| level.used[k]);
            let ds: Vec<u16> = used.map(|k| level.displacements[k]).collect();
            let scanned = ds.iter().min().map(|&lo| (lo, *ds.iter().max().unwrap()));
            assert_eq!(whole.d_range(level), scanned);
            if m == 0 {
                assert_ne!(scanned.map(|s| s.1), Some(300));
            }
        }
    }
}
