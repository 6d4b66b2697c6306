//! The coarse level of a tiled scene: every tile's patches with one node in
//! [`COARSE_STEP`] kept along each grid axis, joined into one small scene
//! ([`COARSE_FILE`] beside the index), so a far view of the whole scene reads one file of
//! about 1/16 of the nodes instead of every tile.
//!
//! Method: node `(step·i, step·j)` of a patch becomes node `(i, j)` of a patch with the
//! same frame origin, rotation, residual and displacement step and its node spacings
//! multiplied by the step taken (the step shrinks to `cols − 1` or `rows − 1` on a short
//! side, so every patch keeps at least 2 × 2 nodes); displacement codes and colours are
//! copied. When a side's last node is not a multiple of the step, one more coarse node
//! takes that last node's code and colour, one step on: the coarse patch reaches up to
//! `step − 1` fine cells past the fine one instead of stopping as far short of it (an
//! overlap hides in a far view, a gap between patches would not). A coarse cell is drawn
//! only when its four kept corners are filled: the level is for views where a coarse cell
//! is about a pixel or less. Openings (from meshes) are not carried.
//!
//! Cost: one pass over each tile's nodes; memory: the coarse patches.

use spatch_format::{FormatError, Frame, GridSize, Patch, Scene};

/// Nodes kept along each grid axis of a patch: one in this many.
pub const COARSE_STEP: usize = 4;

/// The coarse level's file name, beside the index.
pub const COARSE_FILE: &str = "coarse.spatch";

/// `patch` with one node in `step` kept along each axis (see the module documentation).
///
/// Errors: none for a valid patch (the frame and grid are rebuilt from valid parts).
pub fn coarse_patch(patch: &Patch, step: usize) -> Result<Patch, FormatError> {
    let grid = patch.grid();
    let (cols, rows) = (usize::from(grid.cols()), usize::from(grid.rows()));
    let (sx, sy) = (step.clamp(1, cols - 1), step.clamp(1, rows - 1));
    let (new_cols, new_rows) = ((cols - 1).div_ceil(sx) + 1, (rows - 1).div_ceil(sy) + 1);
    let frame = patch.frame();
    let [lx, ly, lz] = frame.lengths();
    let coarse_frame = Frame::from_parts(
        frame.origin(),
        frame.rotation(),
        [lx * sx as f32, ly * sy as f32, lz],
    )?
    .with_residual(frame.origin_residual())?;
    let picks: Vec<usize> = (0..new_rows)
        .flat_map(|j| {
            (0..new_cols).map(move |i| grid.index((i * sx).min(cols - 1), (j * sy).min(rows - 1)))
        })
        .collect();
    let displacements = picks.iter().map(|&k| patch.displacements()[k]).collect();
    let colours = patch
        .colours()
        .map(|c| picks.iter().map(|&k| c[k]).collect());
    let new_grid = GridSize::new(new_cols as u32, new_rows as u32)?;
    Ok(Patch::new(coarse_frame, new_grid, displacements, colours)?.with_sides(patch.sides()))
}

/// `scene` with every patch made coarse by `step`, at the same offset and channel; a
/// coarse patch with no filled node is left out.
///
/// Errors: as [`coarse_patch`].
pub fn coarse_scene(scene: &Scene, step: usize) -> Result<Scene, FormatError> {
    let mut patches = Vec::with_capacity(scene.patches().len());
    for patch in scene.patches() {
        let coarse = coarse_patch(patch, step)?;
        if coarse.filled_count() > 0 {
            patches.push(coarse);
        }
    }
    Scene::new(scene.offset(), scene.channel(), patches)
}

#[cfg(test)]
mod tests {
    use glam::{DVec3, Vec3};
    use spatch_format::{ColourChannel, EMPTY};

    use super::*;

    /// A `cols × rows` patch, tilted, its node `(i, j)` at code `i + 2j` (empty where
    /// `i == 5`), coloured by its index.
    fn patch(cols: u32, rows: u32) -> Patch {
        let frame = Frame::new(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.1, 0.0, 0.0),
            Vec3::new(0.0, 0.08, 0.06),
            Vec3::new(0.0, -0.006, 0.008),
        )
        .unwrap();
        let grid = GridSize::new(cols, rows).unwrap();
        let n = grid.node_count();
        let d = (0..n)
            .map(|k| {
                let (i, j) = (k % cols as usize, k / cols as usize);
                if i == 5 {
                    EMPTY
                } else {
                    (i + 2 * j) as u16
                }
            })
            .collect();
        let c = (0..n).map(|k| [k as u8, 1, 2, 255]).collect();
        Patch::new(frame, grid, d, Some(c)).unwrap()
    }

    #[test]
    fn coarse_nodes_are_the_fine_nodes_of_every_step_th_row_and_column() {
        let fine = patch(13, 9);
        let coarse = coarse_patch(&fine, 4).unwrap();
        assert_eq!((coarse.grid().cols(), coarse.grid().rows()), (4, 3));
        for j in 0..3 {
            for i in 0..4 {
                let (a, b) = (coarse.node_position(i, j), fine.node_position(4 * i, 4 * j));
                let (a, b) = (a.unwrap(), b.unwrap());
                assert!((a - b).length() < 1e-5, "({i}, {j}): {a} vs {b}");
                let k = fine.grid().index(4 * i, 4 * j);
                assert_eq!(
                    coarse.colours().unwrap()[coarse.grid().index(i, j)],
                    fine.colours().unwrap()[k]
                );
            }
        }
        // A last node off the step: one more coarse node, a step on, with its code.
        let ragged = coarse_patch(&patch(11, 9), 4).unwrap();
        assert_eq!((ragged.grid().cols(), ragged.grid().rows()), (4, 3));
        assert_eq!(ragged.displacement(3, 2), fine_code(10, 8));
        let [ax, _, az] = fine.frame().axes();
        let (a, b) = (ragged.node_local(3, 0).unwrap(), ax * 12.0 + az * 10.0);
        assert!((a - b).length() < 1e-5, "{a} vs {b}");
        // A side shorter than the step keeps its two ends; the empty column stays empty.
        let thin = coarse_patch(&patch(7, 2), 4).unwrap();
        assert_eq!((thin.grid().cols(), thin.grid().rows()), (3, 2));
        assert_eq!(thin.displacement(1, 1), fine_code(4, 1));
        assert_eq!(thin.displacement(2, 1), fine_code(6, 1));
        let empty_column = coarse_patch(&patch(11, 3), 5).unwrap();
        assert_eq!(empty_column.displacement(1, 0), None);
    }

    fn fine_code(i: usize, j: usize) -> Option<u16> {
        Some((i + 2 * j) as u16)
    }

    #[test]
    fn a_coarse_scene_keeps_offset_and_channel_and_drops_patches_left_empty() {
        let mut empty = patch(7, 2);
        // Only column 5 is filled: its coarse columns (0, 4 and 6) are all empty.
        let grid = empty.grid();
        let d = (0..grid.node_count())
            .map(|k| if k % 7 == 5 { 3 } else { EMPTY })
            .collect();
        empty = Patch::new(*empty.frame(), grid, d, None).unwrap();
        let offset = DVec3::new(1e6, -2e5, 30.0);
        let scene = Scene::new(
            offset,
            ColourChannel::None,
            vec![empty, {
                let p = patch(9, 9);
                Patch::new(*p.frame(), p.grid(), p.displacements().to_vec(), None).unwrap()
            }],
        )
        .unwrap();
        let coarse = coarse_scene(&scene, 4).unwrap();
        assert_eq!(coarse.offset(), offset);
        assert_eq!(coarse.channel(), ColourChannel::None);
        assert_eq!(coarse.patches().len(), 1);
        assert_eq!(coarse.node_count(), 9);
    }
}
