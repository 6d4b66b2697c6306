//! Triangle strips (a PLY `tristrips` element) to triangles.
//!
//! Input: index lists as read; `-1` (or `4294967295` in an unsigned list) ends a strip and starts the next (several strips may share
//! one list, and a file may hold several lists). Output: counter-clockwise triangles.
//!
//! Within a strip, triangle `k` is `(s[k], s[k+1], s[k+2])` for even `k` and
//! `(s[k+1], s[k], s[k+2])` for odd `k`, so every triangle keeps the first one's winding; the
//! parity restarts at each `-1`. Triangles with a repeated index (the degenerate joins that
//! stitch strips together) are dropped, but still count for the parity. Any other negative
//! index, or one past the vertex count, is refused.
//!
//! Cost: one pass, O(indices).
//!
//! Based on: the strip conventions of OpenGL `GL_TRIANGLE_STRIP` and of the PLY files written by
//! the Stanford scanning repository's tools (restart index -1).

use crate::error::PlyProblem;

/// Whether an index is the strip restart marker: `-1`, or its unsigned 32-bit spelling (a
/// `uint` list).
fn is_restart(index: i64) -> bool {
    index == -1 || index == i64::from(u32::MAX)
}

/// Triangles of the strips in `lists` over `vertex_count` vertices.
pub(crate) fn strips_to_triangles(
    lists: impl IntoIterator<Item = impl AsRef<[i64]>>,
    vertex_count: usize,
) -> Result<Vec<[u32; 3]>, PlyProblem> {
    let mut triangles = Vec::new();
    for (list_index, list) in lists.into_iter().enumerate() {
        let list = list.as_ref();
        if let Some(&bad) = list
            .iter()
            .find(|&&i| !is_restart(i) && (i < 0 || i as u64 >= vertex_count as u64))
        {
            return Err(PlyProblem::StripIndexOutOfRange {
                strip: list_index as u64,
                index: bad,
                vertex_count: vertex_count as u64,
            });
        }
        for strip in list.split(|&i| is_restart(i)) {
            push_strip(strip, &mut triangles);
        }
    }
    Ok(triangles)
}

/// Appends the non-degenerate triangles of one strip (indices already checked).
fn push_strip(strip: &[i64], triangles: &mut Vec<[u32; 3]>) {
    for (k, w) in strip.windows(3).enumerate() {
        let (a, b, c) = (w[0] as u32, w[1] as u32, w[2] as u32);
        if a == b || b == c || a == c {
            continue;
        }
        triangles.push(if k % 2 == 0 { [a, b, c] } else { [b, a, c] });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parity_alternates_and_restarts() {
        // A strip of four vertices, a restart, then a strip of three.
        let t = strips_to_triangles([vec![0, 1, 2, 3, -1, 4, 5, 6]], 7).unwrap();
        assert_eq!(t, vec![[0, 1, 2], [2, 1, 3], [4, 5, 6]]);
    }

    #[test]
    fn degenerate_joins_are_dropped_but_keep_parity() {
        // 0 1 2 3 | join 3 3 4 | 4 5 6: the triangles (2,3,3), (3,3,4), (3,4,4) are joins.
        let t = strips_to_triangles([vec![0, 1, 2, 3, 3, 4, 4, 5, 6]], 7).unwrap();
        assert_eq!(t, vec![[0, 1, 2], [2, 1, 3], [4, 5, 6]]);
    }

    #[test]
    fn bad_indices_are_refused() {
        assert_eq!(
            strips_to_triangles([vec![0, 1, 2], vec![0, 1, 9]], 3),
            Err(PlyProblem::StripIndexOutOfRange {
                strip: 1,
                index: 9,
                vertex_count: 3
            })
        );
        assert!(strips_to_triangles([vec![0, -2, 1]], 3).is_err());
        assert_eq!(strips_to_triangles([vec![0, 1]], 3), Ok(vec![]));
    }
}
