//! Which creases the surface patches already cover, so that edge patches go only where the
//! surface patches leave a gap.
//!
//! A crease needs an edge patch only when the surface patches on its two sides stop short of
//! it. Often they do not: a crease inside one region is crossed by that region's patch, and
//! the fitter's rectangle ends exactly on a straight crease that bounds its region (a cube's
//! faces). So each crease is probed: points on both of its faces, at a few distances from the
//! edge up to most of a surface cell, are tested against the surface patches. A point is
//! covered when some patch that faces the point's face (the angle between the patch's z axis
//! and the face normal under [`MAX_FACING_ANGLE_DEG`]) has a drawable cell (four filled
//! corners) above or below it whose bilinear surface passes within a tolerance of it along
//! the patch's z axis; a crease is covered when all its probes are. The facing test keeps the
//! patch on the other side of a sharp fold, which passes near the probes, from counting.
//!
//! Corners are probed the same way after the edge patches are made, against the surface and
//! edge patches together (`covered_corner`).
//!
//! Probes: along the edge every half surface spacing (at least one, at most
//! [`MAX_PROBES_ALONG`]), across it at [`PROBE_OFFSETS`] surface spacings on each face (never
//! beyond 90 % of the face's height over the edge, so a probe stays on a sliver face).
//! Tolerance: [`COVER_TOLERANCE`] node spacings of the covering patch (or of the edge
//! spacing, if larger), well above the distance from a bilinear cell to the source inside a
//! region and well below the width of a gap. A patch coarser than the edge spacing (a
//! textured model's untextured or less detailed regions) cuts a fold's corner in proportion
//! to its own cells, so its tolerance scales with them.
//!
//! **Soft creases** (angle under [`EdgeOptions::soft_crease_deg`](crate::EdgeOptions)): a
//! surface patch that reaches over the crease with drawable cells (the fitter fills nodes
//! beyond its region wherever the neighbouring face still faces it, so its height field
//! holds there) covers it within [`SOFT_COVER_TOLERANCE`] of its cells. A bilinear cell
//! straddling a fold of angle φ passes up to `a (1 − a) tan φ ≤ tan(φ) / 4` cells inside it
//! (`a` where the fold splits the cell), 0.30 at 50°: the corner cut of sampling a shallow
//! fold at that spacing, which the same patches make across every facet edge just below the
//! crease angle. Only a crease whose faces the patches do not reach (no drawable cell) or
//! a sharper fold needs an edge patch.
//!
//! Cost: building the index is O(patches × cells each box meets); a probe tests the patches
//! whose boxes contain it, O(1) each.

use std::collections::HashMap;

use glam::{IVec3, Vec3};
use spatch_format::Patch;
use spatch_mesh::{FaceId, TriangleMesh, VertexId};

use crate::sharp_edges::{Crease, SharpEdges};

/// Distances of the probes from the edge, in surface node spacings. The gap a surface patch
/// leaves at a crease is under one cell wide, so probes up to 0.8 find it.
pub const PROBE_OFFSETS: [f32; 3] = [0.1, 0.45, 0.8];

/// Largest number of probe positions along one crease (per face and offset).
pub const MAX_PROBES_ALONG: usize = 32;

/// How far (in surface node spacings, along the patch's z axis) a patch surface may pass
/// from a probe and still cover it. A bilinear cell across a 50° crease inside a region
/// passes about 0.12 spacings from it.
pub const COVER_TOLERANCE: f32 = 0.2;

/// Largest angle (degrees) between a patch's z axis and a face's normal for the patch to
/// cover points of that face (either orientation, so a face wound the other way still counts).
pub const MAX_FACING_ANGLE_DEG: f32 = 70.0;

/// How far (in node spacings of the covering patch, along its z axis) a patch surface may
/// pass from a probe on a soft crease and still cover it: above the `tan(φ) / 4` corner cut
/// of a cell straddling a fold of φ up to 50°.
pub const SOFT_COVER_TOLERANCE: f32 = 0.35;

/// One surface patch, with what the point test needs precomputed.
struct Indexed<'a> {
    patch: &'a Patch,
    origin: Vec3,
    axes: [Vec3; 3],
    lengths: [f32; 3],
    lo: Vec3,
    hi: Vec3,
    /// Its node spacing (the larger of x and y), or the edge spacing if larger.
    cell: f32,
    /// Its position in the patches the index was built from.
    source: usize,
}

/// The surface patches in a uniform grid of boxes, for point coverage queries.
pub(crate) struct SurfaceCoverage<'a> {
    patches: Vec<Indexed<'a>>,
    cell: f32,
    buckets: HashMap<IVec3, Vec<u32>>,
    min_facing: f32,
    /// Per patch the index was built from (in order): left out of the queries.
    disabled: Vec<bool>,
}

impl<'a> SurfaceCoverage<'a> {
    /// Indexes `surface` (in the mesh's coordinates); `spacing` is the edge spacing, the
    /// smallest cell a tolerance is measured in (see [`SurfaceCoverage::covers`]).
    pub(crate) fn new(surface: impl IntoIterator<Item = &'a Patch>, spacing: f32) -> Self {
        let mut patches = Vec::new();
        let mut count = 0;
        for (source, patch) in surface.into_iter().enumerate() {
            count = source + 1;
            let Some((lo, hi)) = patch.bounds() else {
                continue;
            };
            let frame = patch.frame();
            let lengths = frame.lengths();
            let cell = spacing.max(lengths[0]).max(lengths[1]);
            // Boxes padded by the largest tolerance a query may use.
            let pad = Vec3::splat(cell * COVER_TOLERANCE.max(SOFT_COVER_TOLERANCE));
            patches.push(Indexed {
                patch,
                origin: frame.origin(),
                axes: frame.unit_axes(),
                lengths,
                lo: lo - pad,
                hi: hi + pad,
                cell,
                source,
            });
        }
        // Cells about as large as a typical patch: each patch lands in a few cells and each
        // cell holds a few patches. Never under a sixteenth of the largest patch, which would
        // otherwise land in up to (its extent / cell)³ cells.
        let mut extents: Vec<f32> = patches
            .iter()
            .map(|p| (p.hi - p.lo).max_element())
            .collect();
        extents.sort_unstable_by(f32::total_cmp);
        let median = extents.get(extents.len() / 2).copied().unwrap_or(0.0);
        let largest = extents.last().copied().unwrap_or(0.0);
        let cell = Some(median.max(largest / 16.0))
            .filter(|c| c.is_finite() && *c > 0.0)
            .unwrap_or(1.0);
        let mut buckets: HashMap<IVec3, Vec<u32>> = HashMap::new();
        for (k, p) in patches.iter().enumerate() {
            let (a, b) = (key(p.lo, cell), key(p.hi, cell));
            for z in a.z..=b.z {
                for y in a.y..=b.y {
                    for x in a.x..=b.x {
                        buckets
                            .entry(IVec3::new(x, y, z))
                            .or_default()
                            .push(k as u32);
                    }
                }
            }
        }
        Self {
            patches,
            cell,
            buckets,
            min_facing: MAX_FACING_ANGLE_DEG.to_radians().cos(),
            disabled: vec![false; count],
        }
    }

    /// Leaves the `source`-th patch the index was built from out of the queries (`false`)
    /// or takes it back (`true`).
    pub(crate) fn set_enabled(&mut self, source: usize, enabled: bool) {
        self.disabled[source] = !enabled;
    }

    /// Whether some patch facing `normal` (a unit face normal) has a drawable surface within
    /// `tolerance` of its cells (at least the edge spacing) of `p` along its z axis.
    pub(crate) fn covers(&self, p: Vec3, normal: Vec3, tolerance: f32) -> bool {
        let Some(candidates) = self.buckets.get(&key(p, self.cell)) else {
            return false;
        };
        candidates.iter().any(|&k| {
            let q = &self.patches[k as usize];
            !self.disabled[q.source]
                && p.cmpge(q.lo).all()
                && p.cmple(q.hi).all()
                && q.axes[2].dot(normal).abs() >= self.min_facing
                && Self::patch_covers(q, p, tolerance * q.cell)
        })
    }

    fn patch_covers(q: &Indexed<'_>, p: Vec3, tolerance: f32) -> bool {
        let local = p - q.origin;
        let u = local.dot(q.axes[0]) / q.lengths[0];
        let v = local.dot(q.axes[1]) / q.lengths[1];
        let grid = q.patch.grid();
        let (cols, rows) = (f32::from(grid.cols()), f32::from(grid.rows()));
        // A hair of slack past the last node: a probe on the patch's border counts.
        const SLACK: f32 = 1e-3;
        if !(u >= -SLACK && v >= -SLACK && u <= cols - 1.0 + SLACK && v <= rows - 1.0 + SLACK) {
            return false;
        }
        let i = (u.max(0.0) as usize).min(usize::from(grid.cols()) - 2);
        let j = (v.max(0.0) as usize).min(usize::from(grid.rows()) - 2);
        if !q.patch.cell_is_drawable(i, j) {
            return false;
        }
        let code = |a, b| f32::from(q.patch.displacement(a, b).unwrap_or(0));
        let (fu, fv) = (
            (u - i as f32).clamp(0.0, 1.0),
            (v - j as f32).clamp(0.0, 1.0),
        );
        let bottom = code(i, j) * (1.0 - fu) + code(i + 1, j) * fu;
        let top = code(i, j + 1) * (1.0 - fu) + code(i + 1, j + 1) * fu;
        let height = (bottom * (1.0 - fv) + top * fv) * q.lengths[2];
        (local.dot(q.axes[2]) - height).abs() <= tolerance
    }
}

fn key(p: Vec3, cell: f32) -> IVec3 {
    // Clamped so a far-away point cannot overflow the cell index.
    (p / cell)
        .floor()
        .clamp(Vec3::splat(-1e9), Vec3::splat(1e9))
        .as_ivec3()
}

/// For each crease of `sharp` (in order), whether the surface patches cover it (see the
/// module docs). `spacing` is the surface node spacing; creases under `soft_crease_deg` are
/// soft.
pub(crate) fn covered_creases(
    mesh: &TriangleMesh,
    sharp: &SharpEdges,
    coverage: &SurfaceCoverage<'_>,
    spacing: f32,
    soft_crease_deg: f32,
) -> Vec<bool> {
    sharp
        .creases
        .iter()
        .map(|c| {
            let tolerance = crease_tolerance(c, soft_crease_deg);
            crease_probes(mesh, c, spacing).all(|(p, n)| coverage.covers(p, n, tolerance))
        })
        .collect()
}

/// The tolerance (in cells) that covers probes of `crease`: [`SOFT_COVER_TOLERANCE`] under
/// `soft_crease_deg`, else [`COVER_TOLERANCE`].
pub(crate) fn crease_tolerance(crease: &Crease, soft_crease_deg: f32) -> f32 {
    if crease.angle_deg < soft_crease_deg {
        SOFT_COVER_TOLERANCE
    } else {
        COVER_TOLERANCE
    }
}

/// Whether the patches of `coverage` cover the corner at vertex `corner`, whose faces are
/// `around`: probes on each face along the bisector of its angle at the corner, at
/// [`PROBE_OFFSETS`] surface spacings (never beyond 45 % of the face's shorter side there).
pub(crate) fn covered_corner(
    mesh: &TriangleMesh,
    corner: VertexId,
    around: &[FaceId],
    coverage: &SurfaceCoverage<'_>,
    spacing: f32,
) -> bool {
    let p = mesh.positions[corner.index()];
    around.iter().all(|&f| {
        let others: Vec<Vec3> = mesh.triangles[f.index()]
            .iter()
            .filter(|&&v| v != corner.0)
            .map(|&v| mesh.positions[v as usize] - p)
            .collect();
        let [a, b] = others[..] else {
            return true;
        };
        let reach = 0.45 * a.length().min(b.length());
        let inward = (a.normalize_or_zero() + b.normalize_or_zero()).normalize_or_zero();
        let normal = mesh.face_normal(f);
        PROBE_OFFSETS.into_iter().all(|o| {
            let probe = p + inward * (o * spacing).min(reach);
            coverage.covers(probe, normal, COVER_TOLERANCE)
        })
    })
}

/// The probe points of one crease, each with its face's unit normal.
fn crease_probes(
    mesh: &TriangleMesh,
    crease: &Crease,
    spacing: f32,
) -> impl Iterator<Item = (Vec3, Vec3)> {
    let a = mesh.positions[crease.v0.index()];
    let b = mesh.positions[crease.v1.index()];
    span_probes(mesh, crease, [a, b], spacing, &PROBE_OFFSETS, false)
}

/// The probe points of the stretch from `a` to `b` of `crease` (both on its line), each
/// with its face's unit normal: every half `spacing` along it (at the middles of equal
/// parts, and also at both ends when `with_ends`), at `offsets` surface spacings across.
pub(crate) fn span_probes<'a>(
    mesh: &TriangleMesh,
    crease: &Crease,
    [a, b]: [Vec3; 2],
    spacing: f32,
    offsets: &'a [f32],
    with_ends: bool,
) -> impl Iterator<Item = (Vec3, Vec3)> + 'a {
    let length = (b - a).length();
    let t = (b - a).normalize_or_zero();
    let along = ((length / (0.5 * spacing)).ceil() as usize).clamp(1, MAX_PROBES_ALONG);
    // Positions along the span, as fractions: the middles of `along` equal parts, or their
    // ends.
    let (first, last, shift) = if with_ends {
        (0, along, 0.0)
    } else {
        (0, along - 1, 0.5)
    };
    // For each face: the unit direction into the face, perpendicular to the edge, the face's
    // height over the edge, and its normal.
    let sides = [0, 1].map(|k| {
        let (f, normal) = (crease.faces[k], crease.normals[k]);
        let [p0, p1, p2] = mesh.face_positions(f);
        let apex = [p0, p1, p2]
            .into_iter()
            .max_by(|x, y| {
                let dx = (*x - a).reject_from_normalized(t).length_squared();
                let dy = (*y - a).reject_from_normalized(t).length_squared();
                dx.total_cmp(&dy)
            })
            .unwrap_or(p0);
        let across = (apex - a).reject_from_normalized(t);
        (across.normalize_or_zero(), across.length(), normal)
    });
    (first..=last).flat_map(move |m| {
        let on_edge = a + t * (length * (m as f32 + shift) / along as f32);
        sides.into_iter().flat_map(move |(dir, height, normal)| {
            offsets
                .iter()
                .map(move |&f| (on_edge + dir * (f * spacing).min(0.9 * height), normal))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use spatch_format::{Frame, GridSize};

    /// A flat 5 × 5 patch on z = 0 with unit spacing, nodes at height `code × 0.01`.
    fn flat_patch(fill: impl Fn(usize, usize) -> bool) -> Patch {
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01).unwrap();
        let mut codes = vec![0u16; 25];
        for (k, c) in codes.iter_mut().enumerate() {
            if !fill(k % 5, k / 5) {
                *c = spatch_format::EMPTY;
            }
        }
        Patch::new(frame, GridSize::new(5, 5).unwrap(), codes, None).unwrap()
    }

    #[test]
    fn points_on_drawable_cells_are_covered() {
        let patches = [flat_patch(|_, _| true)];
        let coverage = SurfaceCoverage::new(&patches, 0.1);
        let up = Vec3::Z;
        assert!(coverage.covers(Vec3::new(2.3, 3.7, 0.05), up, 0.1));
        assert!(
            coverage.covers(Vec3::new(2.3, 3.7, 0.05), -up, 0.1),
            "either orientation"
        );
        assert!(
            coverage.covers(Vec3::new(4.0, 4.0, 0.0), up, 0.1),
            "the far corner counts"
        );
        assert!(
            !coverage.covers(Vec3::new(2.3, 3.7, 0.2), up, 0.1),
            "too far above"
        );
        assert!(
            !coverage.covers(Vec3::new(4.2, 1.0, 0.0), up, 0.1),
            "beyond the last node"
        );
        let steep = Vec3::new(0.0, 80f32.to_radians().sin(), 80f32.to_radians().cos());
        assert!(
            !coverage.covers(Vec3::new(2.3, 3.7, 0.0), steep, 0.1),
            "a face seen edge-on"
        );
    }

    #[test]
    fn a_cell_with_an_empty_corner_covers_nothing() {
        let patches = [flat_patch(|i, j| !(i == 3 && j == 3))];
        let coverage = SurfaceCoverage::new(&patches, 0.1);
        // Node (3, 3) is a corner of cells (2..=3, 2..=3): all four are holes.
        assert!(!coverage.covers(Vec3::new(3.5, 3.5, 0.0), Vec3::Z, 0.1));
        assert!(!coverage.covers(Vec3::new(2.5, 2.5, 0.0), Vec3::Z, 0.1));
        assert!(coverage.covers(Vec3::new(1.5, 1.5, 0.0), Vec3::Z, 0.1));
    }

    #[test]
    fn tolerances_are_in_cells_of_the_covering_patch() {
        // Unit cells, edge spacing a tenth of them: the patch's own cells set the scale.
        let patches = [flat_patch(|_, _| true)];
        let coverage = SurfaceCoverage::new(&patches, 0.1);
        let p = Vec3::new(2.3, 1.7, 0.3);
        assert!(!coverage.covers(p, Vec3::Z, COVER_TOLERANCE));
        assert!(coverage.covers(p, Vec3::Z, SOFT_COVER_TOLERANCE));
        assert!(coverage.covers(Vec3::new(2.3, 1.7, 0.15), Vec3::Z, COVER_TOLERANCE));
        // An edge spacing coarser than the patch's cells sets the scale instead.
        let coarse = SurfaceCoverage::new(&patches, 2.0);
        assert!(coarse.covers(p, Vec3::Z, COVER_TOLERANCE));
    }
}
