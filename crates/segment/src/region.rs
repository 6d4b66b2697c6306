//! The output types ([`RegionId`], [`Region`], [`Segmentation`]) and the step every stage ends
//! with: turning a per-face labelling into a [`Segmentation`].
//!
//! Input of [`build_segmentation`]: the [`FaceGeometry`], the adjacency, one label per face
//! and, per label, a cone known to contain the normals of its faces (or `None`). Output: the
//! regions numbered in order of their lowest face, each with its faces sorted ascending, a
//! tight cone ([`fit_cone`], never wider than the stage's cone), its area and its central face
//! ([`find_central_faces`]).
//!
//! Invariants: every face is in exactly one region; `face_region[f]` names the region whose
//! `faces` hold `f`; no region is empty; the numbering depends only on the labelling's
//! partition, not on the label values.
//!
//! Cost: O(n) for the renumbering and bucketing, O(n · FIT_ITERATIONS) for the cones,
//! O(n log n) for the central faces.
//!
//! Based on: counting sort (Knuth, *TAOCP* vol. 3, §5.2).

use std::fmt;

use glam::Vec3;
use spatch_mesh::{FaceAdjacency, FaceId};

use crate::central_face::find_central_faces;
use crate::cone::{fit_cone, NormalCone};
use crate::face_geometry::FaceGeometry;
use crate::{MismatchProblem, SegmentError};

/// Index of a region in [`Segmentation::regions`].
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RegionId(pub u32);

impl RegionId {
    /// The sentinel for "no region" (`u32::MAX`).
    pub const INVALID: Self = Self(u32::MAX);

    /// The id as a `usize`, for indexing slices.
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }

    /// Whether this is not the `INVALID` sentinel.
    #[inline]
    pub const fn is_valid(self) -> bool {
        self.0 != u32::MAX
    }
}

impl fmt::Debug for RegionId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_valid() {
            write!(f, "r#{}", self.0)
        } else {
            f.write_str("r#INVALID")
        }
    }
}

impl fmt::Display for RegionId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

/// A connected set of faces whose normals fit in a cone.
///
/// # Guarantees
/// `faces` is non-empty, sorted ascending and connected through the face adjacency;
/// `axis` is a unit vector; every non-degenerate face's normal is within `half_angle` of
/// `axis` (a region of only degenerate faces has axis `+z` and half-angle 0).
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// The faces, sorted ascending.
    pub faces: Vec<FaceId>,
    /// Unit cone axis: a tight bounding cone's axis, close to the area-weighted mean normal.
    pub axis: Vec3,
    /// Radians: every face normal is within this angle of `axis`.
    pub half_angle: f32,
    /// Total area of the faces (model units squared).
    pub area: f32,
    /// The central face: the face farthest (along the surface) from the region's border.
    pub seed: FaceId,
}

impl Region {
    /// The region's bounding cone.
    pub fn cone(&self) -> NormalCone {
        NormalCone {
            axis: self.axis,
            half_angle: self.half_angle,
        }
    }
}

/// A partition of a mesh's faces into regions.
///
/// # Guarantees
/// `face_region[f]` is valid for every face and names the region whose `faces` contain `f`;
/// regions are ordered by their lowest face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Segmentation {
    /// The regions, in order of their lowest face.
    pub regions: Vec<Region>,
    /// The region of every face.
    pub face_region: Vec<RegionId>,
}

impl Segmentation {
    /// Number of regions.
    pub fn len(&self) -> usize {
        self.regions.len()
    }

    /// Whether there are no regions (the mesh has no faces).
    pub fn is_empty(&self) -> bool {
        self.regions.is_empty()
    }

    /// The region holding `face`.
    ///
    /// # Panics
    /// When `face` is not a face of the segmented mesh.
    pub fn region_of(&self, face: FaceId) -> RegionId {
        self.face_region[face.index()]
    }

    /// Checks that this segmentation labels `face_count` faces with existing regions (what a
    /// later stage relies on).
    pub fn check_fits(&self, face_count: usize) -> Result<(), SegmentError> {
        let mismatch = |problem| Err(SegmentError::SegmentationMismatch { problem });
        if self.face_region.len() != face_count {
            return mismatch(MismatchProblem::FaceCount {
                mesh_faces: face_count,
                labelled: self.face_region.len(),
            });
        }
        let regions = self.regions.len();
        if let Some(face) = self.face_region.iter().position(|r| r.index() >= regions) {
            return mismatch(MismatchProblem::RegionOutOfRange {
                face: face as u32,
                region: self.face_region[face].0,
                regions,
            });
        }
        Ok(())
    }
}

/// Label of a face not yet placed in a region, inside the stages.
pub(crate) const UNLABELLED: u32 = u32::MAX;

/// Builds the [`Segmentation`] of a complete labelling (see the module docs). `cones[l]`, when
/// given, must contain the normals of every face labelled `l`.
pub(crate) fn build_segmentation(
    geometry: &FaceGeometry,
    adjacency: &FaceAdjacency,
    labels: &[u32],
    cones: &[Option<NormalCone>],
) -> Result<Segmentation, SegmentError> {
    let face_count = geometry.face_count();
    let Renumbered {
        face_region,
        old_of_new,
    } = renumber_labels(labels, cones.len(), face_count)?;
    let region_count = old_of_new.len();
    let by_region = RegionFaces::sort(&face_region, region_count, face_count);
    let seeds = find_central_faces(geometry, adjacency, &face_region, region_count, None);
    let mut fit = RegionFit {
        geometry,
        normals: Vec::new(),
        weights: Vec::new(),
    };
    let mut regions = Vec::with_capacity(region_count);
    for (r, &old) in old_of_new.iter().enumerate() {
        let faces = by_region.faces(r).to_vec();
        regions.push(fit.region(faces, cones[old as usize], seeds[r]));
    }
    Ok(Segmentation {
        regions,
        face_region,
    })
}

/// A labelling renumbered to region ids.
struct Renumbered {
    /// The region of every face.
    face_region: Vec<RegionId>,
    /// The label each region had (indexed by region).
    old_of_new: Vec<u32>,
}

/// Renumbers the labels (each below `label_count`) in order of first appearance (= lowest
/// face).
fn renumber_labels(
    labels: &[u32],
    label_count: usize,
    face_count: usize,
) -> Result<Renumbered, SegmentError> {
    let mut renumber = vec![UNLABELLED; label_count];
    let mut old_of_new: Vec<u32> = Vec::new();
    let mut face_region = Vec::with_capacity(face_count);
    for &label in labels {
        let slot = renumber
            .get_mut(label as usize)
            .ok_or(SegmentError::Internal {
                what: "a face was left without a region or with an unknown label",
            })?;
        if *slot == UNLABELLED {
            *slot = old_of_new.len() as u32;
            old_of_new.push(label);
        }
        face_region.push(RegionId(*slot));
    }
    Ok(Renumbered {
        face_region,
        old_of_new,
    })
}

/// The faces bucketed by region: region `r`'s faces are `sorted[offsets[r]..offsets[r + 1]]`.
struct RegionFaces {
    offsets: Vec<u32>,
    sorted: Vec<FaceId>,
}

impl RegionFaces {
    /// Counting sort of faces by region; faces come out ascending within each region.
    fn sort(face_region: &[RegionId], region_count: usize, face_count: usize) -> Self {
        let mut offsets = vec![0u32; region_count + 1];
        for r in face_region {
            offsets[r.index() + 1] += 1;
        }
        for i in 0..region_count {
            offsets[i + 1] += offsets[i];
        }
        let mut cursor = offsets.clone();
        let mut sorted = vec![FaceId(0); face_count];
        for (f, r) in face_region.iter().enumerate() {
            sorted[cursor[r.index()] as usize] = FaceId(f as u32);
            cursor[r.index()] += 1;
        }
        RegionFaces { offsets, sorted }
    }

    /// Region `r`'s faces, ascending.
    fn faces(&self, r: usize) -> &[FaceId] {
        &self.sorted[self.offsets[r] as usize..self.offsets[r + 1] as usize]
    }
}

/// Fits each region's cone and area, reusing the buffers of the normals and their weights.
struct RegionFit<'g> {
    geometry: &'g FaceGeometry,
    normals: Vec<Vec3>,
    weights: Vec<f32>,
}

impl RegionFit<'_> {
    /// The region of `faces` with central face `seed`: its area and its tight cone, never
    /// wider than `bound` (`+z` with half-angle 0 when every face is degenerate).
    fn region(&mut self, faces: Vec<FaceId>, bound: Option<NormalCone>, seed: FaceId) -> Region {
        let geometry = self.geometry;
        self.normals.clear();
        self.weights.clear();
        let mut area = 0.0f64;
        for &f in &faces {
            area += f64::from(geometry.areas[f.index()]);
            if let Some(n) = geometry.normals[f.index()] {
                self.normals.push(n);
                self.weights.push(geometry.areas[f.index()]);
            }
        }
        let cone = fit_cone(&self.normals, &self.weights, bound).unwrap_or(NormalCone {
            axis: Vec3::Z,
            half_angle: 0.0,
        });
        Region {
            faces,
            axis: cone.axis,
            half_angle: cone.half_angle,
            area: area as f32,
            seed,
        }
    }
}
