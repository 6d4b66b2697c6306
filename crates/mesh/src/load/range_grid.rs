//! A raw range scan's grid (a PLY `range_grid` element) to triangles.
//!
//! Input: per grid sample, in rows of `cols` (`obj_info num_cols` and `num_rows` in the
//! header), a list of zero or one vertex index (no measurement, or the vertex measured
//! there), and the vertex positions. Output: triangles over those vertices, as a scanner's
//! own software joins its samples: each square of four neighbouring samples `a b` above
//! `c d` gives `(a, c, b)` and `(b, c, d)`, each kept when its three samples exist and none
//! of its edges is [`JUMP_FACTOR`] times the median step between row neighbours or longer, so
//! depth jumps and silhouettes stay open. Triangles wind in the grid's image order, which on
//! the Stanford scans faces them away from the scanner; the converter turns them outward.
//!
//! Cost: one pass over the grid, O(samples), and one median, O(samples).
//!
//! Based on: the range-grid PLY files of the Stanford 3D Scanning Repository (Cyberware
//! scans: `obj_info num_cols`, `num_rows`, `element range_grid` with `vertex_indices`
//! lists); `bench/range_grid_mesh.py` applies the same rule.

use glam::DVec3;

use crate::error::PlyProblem;

/// Edges this many times the median row step or longer are depth jumps, not surface.
pub(crate) const JUMP_FACTOR: f64 = 4.0;

/// The grid's size from the header's `obj_info` lines (`num_cols N`, `num_rows N`), if
/// both are there.
pub(crate) fn grid_size<'a>(obj_infos: impl IntoIterator<Item = &'a str>) -> Option<[usize; 2]> {
    let (mut cols, mut rows) = (None, None);
    for info in obj_infos {
        let mut words = info.split_whitespace();
        let (key, value) = (words.next(), words.next().and_then(|v| v.parse().ok()));
        match key {
            Some("num_cols") => cols = value,
            Some("num_rows") => rows = value,
            _ => {}
        }
    }
    Some([cols?, rows?])
}

/// Triangles of a `cols × rows` range grid whose samples list their vertex in `cells`
/// (row by row, as read), over `positions`.
pub(crate) fn range_grid_triangles(
    cells: impl ExactSizeIterator<Item = impl AsRef<[i64]>>,
    [cols, rows]: [usize; 2],
    positions: &[DVec3],
) -> Result<Vec<[u32; 3]>, PlyProblem> {
    if cols.checked_mul(rows) != Some(cells.len()) {
        return Err(PlyProblem::RangeGridSize {
            cols: cols as u64,
            rows: rows as u64,
            samples: cells.len() as u64,
        });
    }
    if cols == 0 || rows == 0 {
        return Ok(Vec::new());
    }
    let grid = sample_vertices(cells, positions.len())?;
    let Some(limit) = median_row_step(&grid, cols, positions).map(|m| m * JUMP_FACTOR) else {
        return Ok(Vec::new());
    };
    let mut triangles = Vec::new();
    let short = |t: [u32; 3]| {
        let p = t.map(|i| positions[i as usize]);
        (0..3).all(|k| p[k].distance(p[(k + 1) % 3]) < limit)
    };
    for r in 0..rows.saturating_sub(1) {
        for c in 0..cols - 1 {
            let at = |dr: usize, dc: usize| grid[(r + dr) * cols + c + dc];
            let (a, b, cc, d) = (at(0, 0), at(0, 1), at(1, 0), at(1, 1));
            for corners in [[a, cc, b], [b, cc, d]] {
                if let [Some(x), Some(y), Some(z)] = corners {
                    if short([x, y, z]) {
                        triangles.push([x, y, z]);
                    }
                }
            }
        }
    }
    Ok(triangles)
}

/// Each sample's vertex, `None` for an empty list; a longer list or an index outside the
/// `vertex_count` vertices is refused.
fn sample_vertices(
    cells: impl Iterator<Item = impl AsRef<[i64]>>,
    vertex_count: usize,
) -> Result<Vec<Option<u32>>, PlyProblem> {
    cells
        .enumerate()
        .map(|(sample, list)| match *list.as_ref() {
            [] => Ok(None),
            [index] if (0..vertex_count as i64).contains(&index) => Ok(Some(index as u32)),
            [index] => Err(PlyProblem::RangeGridIndex {
                sample: sample as u64,
                index,
                vertex_count: vertex_count as u64,
            }),
            ref more => Err(PlyProblem::RangeGridList {
                sample: sample as u64,
                len: more.len() as u64,
            }),
        })
        .collect()
}

/// The median distance between horizontally neighbouring samples that both exist; `None`
/// when no two do.
fn median_row_step(grid: &[Option<u32>], cols: usize, positions: &[DVec3]) -> Option<f64> {
    let mut steps: Vec<f64> = grid
        .chunks_exact(cols)
        .flat_map(|row| row.windows(2))
        .filter_map(|pair| match pair {
            [Some(a), Some(b)] => Some(positions[*a as usize].distance(positions[*b as usize])),
            _ => None,
        })
        .collect();
    if steps.is_empty() {
        return None;
    }
    let middle = steps.len() / 2;
    let (_, median, _) = steps.select_nth_unstable_by(middle, f64::total_cmp);
    Some(*median)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 × 3 grid of unit steps in x and y, sample (c, r) at (c, r, 0), with the samples
    /// listed in `missing` left empty.
    fn grid(missing: &[usize]) -> (Vec<Vec<i64>>, Vec<DVec3>) {
        let mut positions = Vec::new();
        let mut cells = Vec::new();
        for k in 0..12 {
            if missing.contains(&k) {
                cells.push(Vec::new());
            } else {
                cells.push(vec![positions.len() as i64]);
                positions.push(DVec3::new((k % 4) as f64, (k / 4) as f64, 0.0));
            }
        }
        (cells, positions)
    }

    #[test]
    fn every_square_of_four_samples_gives_two_triangles_and_a_gap_takes_its_own() {
        let (cells, positions) = grid(&[]);
        let t = range_grid_triangles(cells.iter(), [4, 3], &positions).unwrap();
        assert_eq!(t.len(), 2 * 3 * 2);
        // The first square: (a, c, b) and (b, c, d) in image order.
        assert_eq!(t[..2], [[0, 4, 1], [1, 4, 5]]);
        // Sample 5 empty: the four squares around it keep one triangle each at most.
        let (cells, positions) = grid(&[5]);
        let t = range_grid_triangles(cells.iter(), [4, 3], &positions).unwrap();
        assert_eq!(t.len(), 12 - 6);
    }

    #[test]
    fn a_depth_jump_leaves_its_triangles_out() {
        let (cells, mut positions) = grid(&[]);
        // Sample 6 (column 2, row 1) four steps behind: its edges are over 4 steps long.
        positions[6].z = 4.0;
        let t = range_grid_triangles(cells.iter(), [4, 3], &positions).unwrap();
        assert_eq!(t.len(), 12 - 6, "{t:?}");
        assert!(t.iter().all(|t| !t.contains(&6)));
    }

    #[test]
    fn a_grid_of_the_wrong_size_or_a_bad_list_is_refused() {
        let (cells, positions) = grid(&[]);
        assert!(matches!(
            range_grid_triangles(cells.iter(), [5, 3], &positions),
            Err(PlyProblem::RangeGridSize { samples: 12, .. })
        ));
        let mut bad = cells.clone();
        bad[3] = vec![12];
        assert!(matches!(
            range_grid_triangles(bad.iter(), [4, 3], &positions),
            Err(PlyProblem::RangeGridIndex {
                sample: 3,
                index: 12,
                ..
            })
        ));
        bad[3] = vec![-1];
        assert!(matches!(
            range_grid_triangles(bad.iter(), [4, 3], &positions),
            Err(PlyProblem::RangeGridIndex { index: -1, .. })
        ));
        bad[3] = vec![1, 2];
        assert!(matches!(
            range_grid_triangles(bad.iter(), [4, 3], &positions),
            Err(PlyProblem::RangeGridList { sample: 3, len: 2 })
        ));
    }

    #[test]
    fn an_empty_grid_has_no_triangles() {
        let none: [Vec<i64>; 0] = [];
        assert_eq!(
            range_grid_triangles(none.iter(), [0, 0], &[]),
            Ok(Vec::new())
        );
        assert_eq!(
            range_grid_triangles(none.iter(), [0, 7], &[]),
            Ok(Vec::new())
        );
    }

    #[test]
    fn the_size_comes_from_both_obj_info_lines() {
        let infos = ["is_cyberware_data 1", "num_cols 512", "num_rows 400"];
        assert_eq!(grid_size(infos), Some([512, 400]));
        assert_eq!(grid_size(["num_cols 512"]), None);
        assert_eq!(grid_size(["num_cols x", "num_rows 4"]), None);
    }
}
