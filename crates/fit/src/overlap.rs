//! Which nodes a patch needs, and which neighbouring faces may fill them.
//!
//! A patch must draw every point of its region, and a cell is drawn only when its four corners
//! are filled. So the needed nodes are the corners of every cell the region's projection
//! touches (a conservative rasterization: triangle/square overlap by separating axes), widened
//! by `overlap` extra rings. Corners outside the region's own faces reach into the neighbours
//! by up to one cell, plus the extra rings: that overlap is what keeps cracks from showing
//! between patches.
//!
//! The surface under those outer nodes comes from the region's neighbourhood: faces reached
//! from the region across shared edges, ring by ring, that face the patch's z axis (tilted
//! at most [`crate::FitOptions::max_neighbour_tilt_deg`] from it) and whose footprint covers
//! at least one needed node. Walking only across edges and only through faces that face the axis
//! means the neighbourhood is one sheet of surface connected to the region: another layer of
//! the model (the back of a thin part, a fold behind) is never reached, so its faces can never
//! fill a node.
//!
//! What the tilt limit trades: a face tilted by θ rises `tan θ` cells per cell, so a corner it
//! fills one cell past the region sits that many cells above or below its neighbours, and the
//! cell between them is a chord across a wall the lattice cannot follow. On coarse meshes (the
//! bunny's 948- and 3,851-triangle versions) such cells stand out of the surface as fins and
//! saw-teeth, drawn up to 0.55 % of the reference's pixels past its silhouette; 75° removes
//! them. On CAD parts the same limit stops patches exactly at sharp creases, where the
//! renderer's half-pixel outline reach lets samples of one face's patch win pixels of the
//! other (more dark specks in patch mode), so it is not the default.
//!
//! Cost: O(cells touched) for the mask, O(faces visited × their node footprint) for the walk.

use std::collections::HashSet;

use glam::{Vec2, Vec3};
use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh};

use crate::lattice::Lattice;

/// Faces whose normal has `n·ẑ` at most this are never part of a patch's neighbourhood,
/// whatever the tilt limit: seen along −z they are edge-on or show their back.
pub(crate) const MIN_FACING: f32 = 1e-3;

/// True when the triangle `t` (grid coordinates) and the cell `[ci, ci+1] × [cj, cj+1]`
/// overlap (touching counts).
fn triangle_touches_cell(t: [Vec2; 3], ci: f32, cj: f32) -> bool {
    let corners = [
        Vec2::new(ci, cj),
        Vec2::new(ci + 1.0, cj),
        Vec2::new(ci, cj + 1.0),
        Vec2::new(ci + 1.0, cj + 1.0),
    ];
    for k in 0..3 {
        let e = t[(k + 1) % 3] - t[k];
        let n = e.perp();
        if n == Vec2::ZERO {
            continue;
        }
        let (mut tmin, mut tmax) = (f32::INFINITY, f32::NEG_INFINITY);
        for p in t {
            let d = n.dot(p);
            tmin = tmin.min(d);
            tmax = tmax.max(d);
        }
        let (mut cmin, mut cmax) = (f32::INFINITY, f32::NEG_INFINITY);
        for c in corners {
            let d = n.dot(c);
            cmin = cmin.min(d);
            cmax = cmax.max(d);
        }
        // A small tolerance so shared edges and exact touches count as overlap.
        let tol = 1e-5 * n.length();
        if tmax < cmin - tol || cmax < tmin - tol {
            return false;
        }
    }
    true
}

/// The needed-node mask of a region on `lattice` (row-major, `cols × rows`).
pub(crate) fn needed_nodes(
    mesh: &TriangleMesh,
    faces: &[FaceId],
    lattice: &Lattice,
    overlap: u32,
) -> Vec<bool> {
    let (cols, rows) = (lattice.cols, lattice.rows);
    let mut touched = vec![false; cols * rows];
    for &face in faces {
        let g = mesh.face_positions(face).map(|p| lattice.grid_point(p));
        let t = g.map(|p| Vec2::new(p.x, p.y));
        let lo = t[0].min(t[1]).min(t[2]);
        let hi = t[0].max(t[1]).max(t[2]);
        // Cells [c, c+1] whose span meets [lo, hi]; cell c exists for c in 0..len-1.
        let ci0 = (lo.x.floor() as i64 - 1).max(0) as usize;
        let cj0 = (lo.y.floor() as i64 - 1).max(0) as usize;
        let ci1 = (hi.x.floor().max(0.0) as usize).min(cols - 2);
        let cj1 = (hi.y.floor().max(0.0) as usize).min(rows - 2);
        for cj in cj0..=cj1 {
            for ci in ci0..=ci1 {
                let (fi, fj) = (ci as f32, cj as f32);
                if fi > hi.x || fi + 1.0 < lo.x || fj > hi.y || fj + 1.0 < lo.y {
                    continue;
                }
                if triangle_touches_cell(t, fi, fj) {
                    touched[lattice.index(ci, cj)] = true;
                }
            }
        }
    }
    // Cell corners, then `overlap` more rings: one dilation of radius 1 + overlap over the
    // cells' lower-left corners, applied separably (the cell (ci, cj) needs nodes ci..=ci+1).
    let mut needed = touched;
    dilate(&mut needed, cols, rows, 0, 1 + overlap as usize);
    if overlap > 0 {
        dilate(&mut needed, cols, rows, overlap as usize, 0);
    }
    needed
}

/// Separable dilation of a mask: a node is set when any node within `before` steps below it
/// or `after` steps above it (along each axis in turn) is set.
fn dilate(mask: &mut [bool], cols: usize, rows: usize, before: usize, after: usize) {
    let mut tmp = vec![false; mask.len()];
    for j in 0..rows {
        for i in 0..cols {
            let lo = i.saturating_sub(after);
            let hi = (i + before).min(cols - 1);
            tmp[j * cols + i] = (lo..=hi).any(|k| mask[j * cols + k]);
        }
    }
    for j in 0..rows {
        for i in 0..cols {
            let lo = j.saturating_sub(after);
            let hi = (j + before).min(rows - 1);
            mask[j * cols + i] = (lo..=hi).any(|k| tmp[k * cols + i]);
        }
    }
}

/// Whether the face's footprint (grid bounding box) contains a needed node.
fn covers_needed(g: [Vec3; 3], lattice: &Lattice, needed: &[bool]) -> bool {
    let lo = g[0].min(g[1]).min(g[2]);
    let hi = g[0].max(g[1]).max(g[2]);
    let Some((i0, i1)) = Lattice::node_range(lo.x, hi.x, lattice.cols) else {
        return false;
    };
    let Some((j0, j1)) = Lattice::node_range(lo.y, hi.y, lattice.rows) else {
        return false;
    };
    (j0..=j1).any(|j| (i0..=i1).any(|i| needed[lattice.index(i, j)]))
}

/// The region's neighbourhood: faces outside the region (`region` sorted), reached across
/// shared edges within `rings` steps, facing +z at no more than `max_tilt_deg` and covering
/// a needed node. Sorted by id.
pub(crate) fn neighbourhood(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    region: &[FaceId],
    (lattice, needed): (&Lattice, &[bool]),
    (rings, max_tilt_deg): (u32, f32),
) -> Vec<FaceId> {
    let in_region = |f: FaceId| region.binary_search(&f).is_ok();
    let min_facing = max_tilt_deg.to_radians().cos().max(MIN_FACING);
    let mut seen: HashSet<FaceId> = HashSet::new();
    let mut accepted = Vec::new();
    let mut frontier: Vec<FaceId> = region.to_vec();
    for _ in 0..rings {
        let mut next = Vec::new();
        for &f in &frontier {
            if f.index() >= adjacency.face_count() {
                continue;
            }
            for &n in adjacency.neighbours(f) {
                if in_region(n) || !seen.insert(n) {
                    continue;
                }
                if mesh.face_normal(n).dot(lattice.basis.z) <= min_facing {
                    continue;
                }
                let g = mesh.face_positions(n).map(|p| lattice.grid_point(p));
                if covers_needed(g, lattice, needed) {
                    accepted.push(n);
                    next.push(n);
                }
            }
        }
        if next.is_empty() {
            break;
        }
        frontier = next;
    }
    accepted.sort_unstable();
    accepted
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touch_test_separates_and_touches() {
        let t = [
            Vec2::new(0.2, 0.2),
            Vec2::new(0.8, 0.2),
            Vec2::new(0.2, 0.8),
        ];
        assert!(triangle_touches_cell(t, 0.0, 0.0));
        assert!(!triangle_touches_cell(t, 1.0, 1.0));
        // The hypotenuse passes below the corner (1, 1) of cell (0, 0) but not into (1, 0)...
        let big = [
            Vec2::new(0.0, 0.0),
            Vec2::new(1.9, 0.0),
            Vec2::new(0.0, 1.9),
        ];
        assert!(!triangle_touches_cell(big, 1.0, 1.0));
        assert!(triangle_touches_cell(big, 1.0, 0.0));
    }

    #[test]
    fn dilation_grows_the_right_way() {
        let (cols, rows) = (5, 5);
        let mut m = vec![false; 25];
        m[2 * 5 + 2] = true;
        dilate(&mut m, cols, rows, 0, 1);
        let set: Vec<usize> = (0..25).filter(|&k| m[k]).collect();
        assert_eq!(set, vec![12, 13, 17, 18]);
    }
}
