//! Bounding volume hierarchy over the triangles of a mesh: a binned-SAH build into a flat
//! node array, queried by [`ray`](crate::Bvh::ray_cast) casting and
//! [`closest point`](crate::Bvh::closest_point) search.
//!
//! Build: each node's triangles are split along the axis of largest centroid extent, at the
//! best of [`BIN_COUNT`] bin boundaries by the surface area heuristic (cost = area-weighted
//! triangle counts of the two sides); a node becomes a leaf at [`MAX_LEAF_SIZE`] triangles or
//! fewer, or when no split beats keeping it whole, or when all centroids coincide. Children
//! of a node are stored next to each other (`left`, `left + 1`). The build uses an explicit
//! work stack and only deterministic arithmetic, so the same mesh always gives the same tree.
//!
//! Invariants: every triangle is in exactly one leaf; a node's box contains its triangles and
//! children; the tree depth is at most [`MAX_DEPTH`] (deeper splits become leaves), which
//! bounds the fixed-size traversal stacks.
//!
//! Memory: the BVH copies each triangle's corners in leaf order (36 bytes per triangle) so
//! leaves read contiguous memory, plus 32 bytes per node (about `2F / 2` nodes). It does not
//! borrow the mesh.
//!
//! Cost: build O(F log F); a query visits O(log F) nodes for well-shaped meshes.
//!
//! Based on: Wald, *On fast Construction of SAH-based Bounding Volume Hierarchies*
//! (IEEE RT 2007) for binned SAH; Pharr, Jakob and Humphreys, *Physically Based Rendering*
//! (3rd ed., 2016), section 4.3, for the flat linear layout.

use glam::Vec3;

use crate::{Aabb, FaceId, TriangleMesh};

/// SAH bins per split.
pub const BIN_COUNT: usize = 12;
/// Largest number of triangles in a leaf.
pub const MAX_LEAF_SIZE: usize = 4;
/// Largest tree depth; traversal stacks are sized from it.
pub const MAX_DEPTH: usize = 60;

/// One node of the flat tree: a box, and either two children (`count == 0`, children at
/// `first` and `first + 1`) or a run of triangles (`count > 0`, leaf-order indices
/// `first..first + count`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Node {
    pub(crate) min: Vec3,
    pub(crate) first: u32,
    pub(crate) max: Vec3,
    pub(crate) count: u32,
}

impl Node {
    /// A node over `bounds` whose `first` and `count` are as the type says.
    fn over(bounds: Aabb, first: usize, count: usize) -> Node {
        Node {
            min: bounds.min,
            first: first as u32,
            max: bounds.max,
            count: count as u32,
        }
    }

    /// The node's box.
    #[inline]
    pub(crate) fn aabb(&self) -> Aabb {
        Aabb {
            min: self.min,
            max: self.max,
        }
    }
}

/// A BVH over a mesh's triangles (see the module docs). Queries take `&self` and allocate
/// nothing, so many threads can share one BVH.
#[derive(Clone, Debug)]
pub struct Bvh {
    pub(crate) nodes: Vec<Node>,
    /// Triangle corners in leaf order.
    pub(crate) corners: Vec<[Vec3; 3]>,
    /// Face id of each leaf-order triangle.
    pub(crate) faces: Vec<FaceId>,
    /// Length of the mesh's bounding-box diagonal (scale for tolerances).
    pub(crate) scale: f32,
}

/// The nodes of the tree over the triangles of `boxes` (centroids
/// `centroids`), node 0 the root, reordering `order` into leaf order. An
/// empty mesh gets one empty leaf whose box contains nothing.
fn build_nodes(order: &mut [u32], centroids: &[Vec3], boxes: &[Aabb]) -> Vec<Node> {
    let count = order.len();
    let empty = Node::over(Aabb::EMPTY, 0, 0);
    let mut nodes = Vec::with_capacity(count.max(1) * 2 / MAX_LEAF_SIZE.max(1) + 1);
    nodes.push(empty);
    // Work items: (node index, start, end, depth).
    let mut work = vec![(0usize, 0usize, count, 0usize)];
    while let Some((node, start, end, depth)) = work.pop() {
        let bounds = order[start..end]
            .iter()
            .fold(Aabb::EMPTY, |b, &t| b.union(boxes[t as usize]));
        let mid = if end - start <= MAX_LEAF_SIZE || depth >= MAX_DEPTH {
            None
        } else {
            split(&mut order[start..end], centroids, boxes, &bounds)
        };
        let Some(mid) = mid else {
            nodes[node] = Node::over(bounds, start, end - start);
            continue;
        };
        let left = nodes.len();
        nodes.extend([empty, empty]);
        nodes[node] = Node::over(bounds, left, 0);
        work.push((left + 1, start + mid, end, depth + 1));
        work.push((left, start, start + mid, depth + 1));
    }
    nodes
}

impl Bvh {
    /// Builds the BVH of `mesh`'s triangles (positions relative to the mesh origin; queries use
    /// the same coordinates).
    pub fn new(mesh: &TriangleMesh) -> Bvh {
        let count = mesh.triangles.len();
        let corners_in: Vec<[Vec3; 3]> = mesh.faces().map(|f| mesh.face_positions(f)).collect();
        let centroids: Vec<Vec3> = corners_in
            .iter()
            .map(|c| (c[0] + c[1] + c[2]) * (1.0 / 3.0))
            .collect();
        let boxes: Vec<Aabb> = corners_in
            .iter()
            .map(|c| Aabb::from_points(c.iter().copied()))
            .collect();
        let mut order: Vec<u32> = (0..count as u32).collect();
        let nodes = build_nodes(&mut order, &centroids, &boxes);
        Bvh {
            nodes,
            corners: order.iter().map(|&t| corners_in[t as usize]).collect(),
            faces: order.iter().map(|&t| FaceId(t)).collect(),
            scale: mesh.diagonal(),
        }
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.faces.len()
    }

    /// Number of nodes in the flat tree.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bounding box of all triangles.
    pub fn bounds(&self) -> Aabb {
        self.nodes[0].aabb()
    }

    /// A distance below which two surface points count as the same, for this mesh:
    /// `1e-6` of the bounding-box diagonal. Useful as `t_min` when casting from a surface.
    pub fn epsilon(&self) -> f32 {
        self.scale * 1e-6
    }

    /// Whether the node at `index` is empty of triangles (only for an empty mesh's root).
    #[inline]
    pub(crate) fn is_empty_root(&self) -> bool {
        self.faces.is_empty()
    }
}

/// Partitions `order` by the best SAH split; returns the size of the left part, or `None`
/// when keeping the node whole is cheaper or no axis separates the centroids.
fn split(order: &mut [u32], centroids: &[Vec3], boxes: &[Aabb], bounds: &Aabb) -> Option<usize> {
    let bins = Bins::of(order, centroids)?;
    let bin_of = |t: u32| bins.bin(centroids[t as usize]);
    let (best, best_cost) = BinContents::fill(order, boxes, bin_of).best_boundary();
    // Leaf cost: every triangle tested; a split costs one extra box test on each side.
    let leaf_cost = half_area(bounds) * order.len() as f32;
    if !best_cost.is_finite() || (best_cost >= leaf_cost && order.len() <= 4 * MAX_LEAF_SIZE) {
        return None;
    }
    // Stable partition (deterministic, keeps input order within each side).
    let (mut left, mut right): (Vec<u32>, Vec<u32>) =
        order.iter().partition(|&&t| bin_of(t) < best);
    let mid = left.len();
    left.append(&mut right);
    order.copy_from_slice(&left);
    Some(mid)
}

/// How a node's centroids fall into its [`BIN_COUNT`] SAH bins: along `axis`, from `lo`,
/// `scale` bins per unit of length.
#[derive(Clone, Copy)]
struct Bins {
    axis: usize,
    lo: f32,
    scale: f32,
}

impl Bins {
    /// The bins of the centroids of `order`, along the axis of their largest extent; `None`
    /// when that extent is zero or not finite (no axis separates them).
    #[inline]
    fn of(order: &[u32], centroids: &[Vec3]) -> Option<Bins> {
        let centre_bounds = Aabb::from_points(order.iter().map(|&t| centroids[t as usize]));
        let extent = centre_bounds.size();
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let lo = centre_bounds.min[axis];
        let width = extent[axis];
        if width <= 0.0 || !width.is_finite() {
            return None;
        }
        let scale = BIN_COUNT as f32 / width;
        Some(Bins { axis, lo, scale })
    }

    /// The bin of a triangle whose centroid is `centroid`.
    #[inline]
    fn bin(&self, centroid: Vec3) -> usize {
        let b = ((centroid[self.axis] - self.lo) * self.scale) as usize;
        b.min(BIN_COUNT - 1)
    }
}

/// What each SAH bin holds: the box and the number of its triangles.
struct BinContents {
    boxes: [Aabb; BIN_COUNT],
    counts: [usize; BIN_COUNT],
}

impl BinContents {
    /// The bins of the triangles of `order` (boxes `boxes`), each in bin `bin_of(t)`.
    #[inline]
    fn fill(order: &[u32], boxes: &[Aabb], bin_of: impl Fn(u32) -> usize) -> BinContents {
        let mut bin_boxes = [Aabb::EMPTY; BIN_COUNT];
        let mut bin_counts = [0usize; BIN_COUNT];
        for &t in order.iter() {
            let b = bin_of(t);
            bin_boxes[b] = bin_boxes[b].union(boxes[t as usize]);
            bin_counts[b] += 1;
        }
        BinContents {
            boxes: bin_boxes,
            counts: bin_counts,
        }
    }

    /// The best bin boundary by the SAH (the first bin of the right side) and its cost;
    /// the cost is infinite when no boundary has triangles on both sides.
    #[inline]
    fn best_boundary(&self) -> (usize, f32) {
        let (right_area, right_count) = self.right_of_boundaries();
        let (mut best, mut best_cost) = (0usize, f32::INFINITY);
        let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
        for b in 0..BIN_COUNT - 1 {
            acc = acc.union(self.boxes[b]);
            cnt += self.counts[b];
            if cnt == 0 || right_count[b + 1] == 0 {
                continue;
            }
            let cost = half_area(&acc) * cnt as f32 + right_area[b + 1] * right_count[b + 1] as f32;
            if cost < best_cost {
                best_cost = cost;
                best = b + 1;
            }
        }
        (best, best_cost)
    }

    /// The half area of the box and the count of the triangles right of each boundary
    /// `b` (bins `b..`), for `b` from 1.
    #[inline]
    fn right_of_boundaries(&self) -> ([f32; BIN_COUNT], [usize; BIN_COUNT]) {
        // Sweep from the right to get the area and count right of each boundary.
        let mut right_area = [0.0f32; BIN_COUNT];
        let mut right_count = [0usize; BIN_COUNT];
        let (mut acc, mut cnt) = (Aabb::EMPTY, 0);
        for b in (1..BIN_COUNT).rev() {
            acc = acc.union(self.boxes[b]);
            cnt += self.counts[b];
            right_area[b] = half_area(&acc);
            right_count[b] = cnt;
        }
        (right_area, right_count)
    }
}

#[inline]
fn half_area(b: &Aabb) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    let d = b.max - b.min;
    d.x * d.y + d.y * d.z + d.z * d.x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_mesh(n: u32) -> TriangleMesh {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                positions.push(Vec3::new(x as f32, y as f32, ((x * y) % 3) as f32 * 0.1));
            }
        }
        for y in 0..n {
            for x in 0..n {
                let i = y * (n + 1) + x;
                triangles.push([i, i + 1, i + n + 2]);
                triangles.push([i, i + n + 2, i + n + 1]);
            }
        }
        TriangleMesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn every_triangle_is_in_exactly_one_leaf_and_boxes_nest() {
        let mesh = grid_mesh(20);
        let bvh = Bvh::new(&mesh);
        let mut seen = vec![0u32; mesh.triangles.len()];
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let node = bvh.nodes[i];
            if node.count > 0 {
                for k in node.first..node.first + node.count {
                    seen[bvh.faces[k as usize].index()] += 1;
                    for c in bvh.corners[k as usize] {
                        assert!(node.aabb().contains(c));
                    }
                }
            } else {
                for child in [node.first as usize, node.first as usize + 1] {
                    let c = bvh.nodes[child];
                    assert!(node.aabb().contains(c.min) && node.aabb().contains(c.max));
                    stack.push(child);
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
    }

    #[test]
    fn build_is_deterministic() {
        let mesh = grid_mesh(12);
        let a = Bvh::new(&mesh);
        let b = Bvh::new(&mesh);
        assert_eq!(a.faces, b.faces);
        assert_eq!(a.nodes.len(), b.nodes.len());
    }

    #[test]
    fn coincident_triangles_do_not_recurse_forever() {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        let triangles = vec![[0, 1, 2]; 100];
        let mesh = TriangleMesh::new(positions, triangles).unwrap();
        let bvh = Bvh::new(&mesh);
        assert_eq!(bvh.node_count(), 1);
        assert_eq!(bvh.triangle_count(), 100);
    }
}
