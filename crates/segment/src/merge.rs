//! Stage 3, merge: small regions join an adjacent region while the union's normals stay in a
//! cone of half-angle θ3 and the union still fits a patch.
//!
//! Input: a mesh, its face adjacency, a [`Segmentation`] (normally stage 2's), θ3
//! ([`SegmentOptions::merge_angle_deg`]), [`SegmentOptions::max_extent`] and
//! [`SegmentOptions::min_region_faces`]. Output: a [`Segmentation`] with the same or fewer
//! regions.
//!
//! Method: a region with fewer than `min_region_faces` faces is *small*. Every pair of adjacent
//! regions of which at least one is small is a candidate if the smallest cone holding both
//! regions' cones ([`NormalCone::union`]) has a half-angle of at most θ3 and the union still
//! fits a patch (below). Candidates wait in a binary heap keyed by the union's half-angle (the
//! most coplanar pair first; ties by region indices). The best candidate is merged: the region
//! with fewer faces joins the other, whose cone, sphere and neighbour set absorb it. Pairs
//! whose regions changed since they were pushed are re-tested when popped (lazy re-keying);
//! new pairs of the merged region are pushed at once.
//!
//! "Still fits a patch" is tested with bounding spheres: the smallest sphere holding both
//! regions' spheres ([`Sphere::union`]) must have a diameter of at most `max_extent`, which
//! guarantees the union fits a square patch of that side whatever in-plane orientation the
//! fitter picks (it may refuse unions that would just fit: a square's diameter is √2 times its
//! side). One exception, measured on the bunny: when the larger region is already wider than
//! a patch, the fitter tiles it with several patches anyway, and the small region joins it
//! (subject to θ3 alone) instead of costing a patch of its own; refusing those merges gave 20 %
//! more patches (2,719 instead of 2,268; see `docs/algorithms/segmenter.md`). A region that
//! fits one patch never grows beyond one patch by merging.
//!
//! A small region may merge with a large one: that removes a nearly empty patch, which is the
//! point of the stage. Both tests are conservative (the cones and spheres contain every
//! normal and vertex), so a merged region never exceeds θ3.
//!
//! Invariants: every face ends in exactly one region; regions stay connected (only adjacent
//! regions merge); every merged region's cone is within θ3; a merged region is within
//! `max_extent` unless its larger part already was not; deterministic.
//!
//! Cost: O(n) for the bounding spheres and the region adjacency, O(n log n) for the merges
//! (the smaller region's neighbours are moved into the larger's, so each region's neighbour
//! entries move O(log n) times); O(n) memory.
//!
//! Based on: the merge stage of the spatial-patch segmenter this project reproduces; greedy
//! pairwise merging with a priority queue as in Garland et al., *Hierarchical face clustering
//! on polygonal surfaces* (I3D 2001).

use std::cmp::Reverse;
use std::collections::{BTreeSet, BinaryHeap};

use glam::Vec3;
use spatch_mesh::{FaceAdjacency, TriangleMesh};

use crate::bounding_sphere::{bound_points, Sphere};
use crate::cone::NormalCone;
use crate::face_geometry::{compute_face_geometry, FaceGeometry};
use crate::priority::priority_key;
use crate::region::build_segmentation;
use crate::{check_inputs, SegmentError, SegmentOptions, Segmentation};

/// Stage 3: merges small regions of `regions` into neighbours (see the module docs).
pub fn merge_regions(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    regions: &Segmentation,
    options: &SegmentOptions,
) -> Result<Segmentation, SegmentError> {
    check_inputs(mesh, adjacency, options)?;
    regions.check_fits(mesh.face_count())?;
    let geometry = compute_face_geometry(mesh);
    merge_regions_with(mesh, &geometry, adjacency, regions, options)
}

/// The state of one region during merging.
struct Cluster {
    cone: Option<NormalCone>,
    sphere: Option<Sphere>,
    faces: usize,
    version: u32,
    alive: bool,
    neighbours: BTreeSet<u32>,
}

/// The merge rules, fixed for a run.
struct Rules {
    max_half_angle: f32,
    max_extent: f32,
    min_faces: usize,
}

/// `(union half-angle key, lower region, higher region, its version, the other's version)`.
type Candidate = Reverse<(u32, u32, u32, u32, u32)>;

/// [`merge_regions`] on precomputed face geometry.
pub(crate) fn merge_regions_with(
    mesh: &TriangleMesh,
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    input: &Segmentation,
    options: &SegmentOptions,
) -> Result<Segmentation, SegmentError> {
    let rules = Rules {
        max_half_angle: options.merge_angle(),
        max_extent: options.max_extent,
        min_faces: options.min_region_faces,
    };
    let clusters = init_clusters(mesh, geometry, adjacency, input);
    let mut merging = Merging::new(clusters, rules);
    merging.run();
    let root = merging.roots();
    let labels: Vec<u32> = input.face_region.iter().map(|r| root[r.index()]).collect();
    let cones: Vec<Option<NormalCone>> = merging.clusters.iter().map(|c| c.cone).collect();
    build_segmentation(geometry, adjacency, &labels, &cones)
}

/// The merge in progress: the regions' clusters, which cluster each joined, and the
/// candidate pairs waiting.
struct Merging {
    clusters: Vec<Cluster>,
    /// For each input region, the cluster it joined (itself while it is alive).
    parent: Vec<u32>,
    heap: BinaryHeap<Candidate>,
    rules: Rules,
}

impl Merging {
    /// The merge of `clusters` before any step, every adjacent pair that passes the tests
    /// waiting.
    fn new(clusters: Vec<Cluster>, rules: Rules) -> Self {
        let parent: Vec<u32> = (0..clusters.len() as u32).collect();
        let mut heap: BinaryHeap<Candidate> = BinaryHeap::new();
        for a in 0..clusters.len() as u32 {
            for &b in clusters[a as usize].neighbours.range(a + 1..) {
                push_candidate(&clusters, &rules, a, b, &mut heap);
            }
        }
        Self {
            clusters,
            parent,
            heap,
            rules,
        }
    }

    /// Merges the best candidate until none is left (stale ones re-tested when popped).
    fn run(&mut self) {
        while let Some(Reverse((_, a, b, version_a, version_b))) = self.heap.pop() {
            let (ca, cb) = (&self.clusters[a as usize], &self.clusters[b as usize]);
            if !ca.alive || !cb.alive {
                continue;
            }
            if ca.version != version_a || cb.version != version_b {
                push_candidate(&self.clusters, &self.rules, a, b, &mut self.heap);
                continue;
            }
            // The larger region survives (ties: the lower index, which is `a`).
            let (keep, gone) = if cb.faces > ca.faces { (b, a) } else { (a, b) };
            let absorbed = self.absorb(keep, gone);
            self.push_pairs_of(keep, &absorbed);
        }
    }

    /// Joins cluster `gone` into `keep` (cone, sphere, faces, neighbours); returns `gone`'s
    /// former neighbours.
    fn absorb(&mut self, keep: u32, gone: u32) -> BTreeSet<u32> {
        let clusters = &mut self.clusters;
        let absorbed = std::mem::take(&mut clusters[gone as usize].neighbours);
        let (gone_cone, gone_sphere, gone_faces) = {
            let g = &mut clusters[gone as usize];
            g.alive = false;
            (g.cone, g.sphere, g.faces)
        };
        self.parent[gone as usize] = keep;
        {
            let k = &mut clusters[keep as usize];
            k.cone = union_cone(k.cone, gone_cone);
            k.sphere = union_sphere(k.sphere, gone_sphere);
            k.faces += gone_faces;
            k.version += 1;
            k.neighbours.remove(&gone);
        }
        for &u in &absorbed {
            if u == keep {
                continue;
            }
            let n = &mut clusters[u as usize].neighbours;
            n.remove(&gone);
            n.insert(keep);
            clusters[keep as usize].neighbours.insert(u);
        }
        absorbed
    }

    /// Pushes the new pairs of `keep` after it absorbed a cluster with neighbours
    /// `absorbed`: all its pairs while it is still small, else those with `absorbed`.
    fn push_pairs_of(&mut self, keep: u32, absorbed: &BTreeSet<u32>) {
        let clusters = &self.clusters;
        if clusters[keep as usize].faces < self.rules.min_faces {
            let all: Vec<u32> = clusters[keep as usize].neighbours.iter().copied().collect();
            for u in all {
                push_candidate(clusters, &self.rules, keep, u, &mut self.heap);
            }
        } else {
            for &u in absorbed {
                if u != keep {
                    push_candidate(clusters, &self.rules, keep, u, &mut self.heap);
                }
            }
        }
    }

    /// Every input region's surviving cluster. Chains are short: a region joins one with at
    /// least as many faces, so each link at least doubles the size (≤ log2 n links).
    fn roots(&self) -> Vec<u32> {
        let parent = &self.parent;
        (0..parent.len() as u32)
            .map(|r| {
                let mut x = r;
                while parent[x as usize] != x {
                    x = parent[x as usize];
                }
                x
            })
            .collect()
    }
}

/// Clusters for the input regions: cone (none when every face is degenerate), bounding sphere
/// of the faces' corners, face count and adjacent regions.
fn init_clusters(
    mesh: &TriangleMesh,
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    input: &Segmentation,
) -> Vec<Cluster> {
    let mut corners: Vec<Vec3> = Vec::new();
    let mut clusters: Vec<Cluster> = input
        .regions
        .iter()
        .map(|region| {
            corners.clear();
            let mut has_normal = false;
            for &f in &region.faces {
                corners.extend(mesh.face_positions(f));
                has_normal |= geometry.normals[f.index()].is_some();
            }
            Cluster {
                cone: has_normal.then(|| region.cone()),
                sphere: bound_points(&corners),
                faces: region.faces.len(),
                version: 0,
                alive: true,
                neighbours: BTreeSet::new(),
            }
        })
        .collect();
    for f in 0..input.face_region.len() {
        let a = input.face_region[f];
        for g in adjacency.neighbours(spatch_mesh::FaceId(f as u32)) {
            let b = input.face_region[g.index()];
            if a != b {
                clusters[a.index()].neighbours.insert(b.0);
            }
        }
    }
    clusters
}

fn union_cone(a: Option<NormalCone>, b: Option<NormalCone>) -> Option<NormalCone> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.union(&b)),
        (a, None) => a,
        (None, b) => b,
    }
}

fn union_sphere(a: Option<Sphere>, b: Option<Sphere>) -> Option<Sphere> {
    match (a, b) {
        (Some(a), Some(b)) => Some(a.union(&b)),
        (a, None) => a,
        (None, b) => b,
    }
}

/// Pushes the pair `(a, b)` with its current versions when one of them is small and their
/// union passes both tests.
fn push_candidate(
    clusters: &[Cluster],
    rules: &Rules,
    a: u32,
    b: u32,
    heap: &mut BinaryHeap<Candidate>,
) {
    let (a, b) = (a.min(b), a.max(b));
    let (ca, cb) = (&clusters[a as usize], &clusters[b as usize]);
    if ca.faces >= rules.min_faces && cb.faces >= rules.min_faces {
        return;
    }
    let half = union_cone(ca.cone, cb.cone).map_or(0.0, |c| c.half_angle);
    if half > rules.max_half_angle {
        return;
    }
    if let Some(s) = union_sphere(ca.sphere, cb.sphere) {
        // A union beyond one patch is refused unless the larger region is beyond one patch
        // already: the fitter tiles that one anyway, and the small region rides along.
        let larger = if ca.faces >= cb.faces { ca } else { cb };
        let fits_alone = larger
            .sphere
            .is_none_or(|l| l.diameter() <= rules.max_extent);
        if s.diameter() > rules.max_extent && fits_alone {
            return;
        }
    }
    heap.push(Reverse((priority_key(half), a, b, ca.version, cb.version)));
}
