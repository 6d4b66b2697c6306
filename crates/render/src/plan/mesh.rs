//! Arbitrary triangle meshes through the scan-line rasterizer, with the
//! same camera, shading and framebuffer as patches (so a source mesh and
//! its patches can be compared pixel for pixel).
//!
//! Input is plain data: `f32` positions relative to an `f64` origin, index
//! triples, optional per-vertex or per-corner colours. Smooth vertex normals
//! (area-weighted face normals) serve Gouraud and Phong shading; flat
//! shading uses face normals. Triangles are counter-clockwise when seen
//! from their front (OpenGL). With back-face culling on, triangles facing
//! away are dropped; otherwise they are lit from their back side. Automatic
//! culling culls a closed mesh wound outward (every directed edge matched by
//! its reverse, once: no opening can show a back face; and a positive signed
//! volume: the fronts face out) and draws any other from both sides, as
//! OpenGL without culling does (a closed mesh wound inward would otherwise
//! show its inside).
//!
//! Cost: O(vertices + triangles) to set up, then the rasterizer.

use glam::{DVec3, Mat3, Vec3};

use crate::error::RenderError;
use crate::lighting::{pack_colour, ShadeFrame};
use crate::options::{Culling, Shading};
use crate::plan::work::{ChunkWork, FrameSetup};
use crate::raster::triangle_raster::{clip_and_project, ClipOutcome, ClipVertex, TRI_ATTRS};

/// Colours of a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum MeshColours<'a> {
    /// No colours: the lighting's base colour.
    None,
    /// One RGBA colour per vertex.
    PerVertex(&'a [[u8; 4]]),
    /// One RGBA colour per triangle corner (`3 × triangles`).
    PerCorner(&'a [[u8; 4]]),
}

impl MeshColours<'_> {
    /// The albedo (0-255 per channel) of corner `corner` of triangle `k`
    /// (vertices `t`): its vertex's or corner's colour, else `base`.
    #[inline(always)]
    fn albedo(&self, t: [u32; 3], k: usize, corner: usize, base: Vec3) -> Vec3 {
        let c = match *self {
            MeshColours::None => return base,
            MeshColours::PerVertex(c) => c[t[corner] as usize],
            MeshColours::PerCorner(c) => c[3 * k + corner],
        };
        Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)
    }
}

/// A triangle mesh to rasterize.
///
/// # Guarantees
/// Positions are finite, every index is in range, colour counts match.
#[derive(Debug, Clone, Copy)]
pub struct TriangleMesh<'a> {
    origin: DVec3,
    positions: &'a [Vec3],
    triangles: &'a [[u32; 3]],
    colours: MeshColours<'a>,
    /// Every directed edge is matched by its reverse exactly once, and the
    /// signed volume is positive.
    closed: bool,
}

impl<'a> TriangleMesh<'a> {
    /// Checks and wraps mesh data. Positions are relative to `origin`.
    pub fn new(
        origin: DVec3,
        positions: &'a [Vec3],
        triangles: &'a [[u32; 3]],
        colours: MeshColours<'a>,
    ) -> Result<Self, RenderError> {
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(RenderError::NonFiniteVertex { vertex });
        }
        if !origin.is_finite() {
            return Err(RenderError::InvalidOption {
                name: "origin",
                reason: "must be finite",
            });
        }
        for (triangle, t) in triangles.iter().enumerate() {
            if let Some(&vertex) = t.iter().find(|&&v| v as usize >= positions.len()) {
                return Err(RenderError::TriangleIndexOutOfRange {
                    triangle,
                    vertex,
                    vertex_count: positions.len(),
                });
            }
        }
        let check = |what, expected: usize, found: usize| {
            if expected == found {
                Ok(())
            } else {
                Err(RenderError::MeshColourCount {
                    what,
                    expected,
                    found,
                })
            }
        };
        match colours {
            MeshColours::None => {}
            MeshColours::PerVertex(c) => check("one per vertex", positions.len(), c.len())?,
            MeshColours::PerCorner(c) => {
                check("one per triangle corner", 3 * triangles.len(), c.len())?
            }
        }
        Ok(Self {
            origin,
            positions,
            triangles,
            colours,
            closed: is_closed(triangles) && faces_out(positions, triangles),
        })
    }

    /// True when the mesh is closed and consistently wound (each directed
    /// edge appears once and its reverse once) with its fronts facing out
    /// (positive signed volume), so back faces never show from outside it.
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    /// The origin of the positions.
    pub fn origin(&self) -> DVec3 {
        self.origin
    }

    /// Model-space box of the vertices used by triangles, or `None`.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut it = self
            .triangles
            .iter()
            .flatten()
            .map(|&v| self.positions[v as usize]);
        let first = it.next()?;
        let (lo, hi) = it.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
        Some((self.origin + lo.as_dvec3(), self.origin + hi.as_dvec3()))
    }

    /// A bounding sphere `(centre, radius)`: the box centre and the farthest
    /// vertex from it.
    pub fn bounding_sphere(&self) -> Option<(DVec3, f64)> {
        let (lo, hi) = self.bounds()?;
        let c = (lo + hi) * 0.5;
        let local = (c - self.origin).as_vec3();
        let r = self
            .triangles
            .iter()
            .flatten()
            .map(|&v| (self.positions[v as usize] - local).length())
            .fold(0.0f32, f32::max);
        Some((c, r as f64))
    }

    /// Area-weighted vertex normals (unit, or zero for unused vertices).
    pub(crate) fn vertex_normals(&self) -> Vec<Vec3> {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for t in self.triangles {
            let [a, b, c] = t.map(|v| self.positions[v as usize]);
            let n = (b - a).cross(c - a);
            for &v in t {
                normals[v as usize] += n;
            }
        }
        for n in &mut normals {
            *n = n.normalize_or_zero();
        }
        normals
    }

    pub(crate) fn triangle_count(&self) -> usize {
        self.triangles.len()
    }
}

/// Sets up the triangles `range` of `mesh` into `work`.
pub(crate) fn plan_mesh_chunk(
    work: &mut ChunkWork,
    mesh: &TriangleMesh<'_>,
    normals: &[Vec3],
    range: std::ops::Range<usize>,
    world: &ShadeFrame,
    setup: &FrameSetup<'_>,
) {
    work.reset(setup.options.stage_times);
    let frame = MeshFrame::new(mesh, normals, world, setup);
    for k in range {
        plan_triangle(work, mesh, k, &frame);
    }
    work.counters.setup_ns += work.clock.lap();
}

/// What every triangle of a mesh is set up with in a frame: the camera in
/// the mesh's coordinates, the shading and the culling.
struct MeshFrame<'a> {
    /// The eye relative to the mesh's origin.
    eye_local: Vec3,
    /// Mesh position to window clip `(X, Y, W)`: `map · p + t0`.
    map: Mat3,
    t0: Vec3,
    near: f32,
    /// The image's size in pixels.
    size: (f32, f32),
    /// `setup.options.shading`, kept beside the fields read per triangle.
    shading: Shading,
    /// Triangles facing away are dropped.
    cull: bool,
    normals: &'a [Vec3],
    world: &'a ShadeFrame,
    setup: &'a FrameSetup<'a>,
}

impl<'a> MeshFrame<'a> {
    /// The frame of `mesh` (smooth vertex `normals`, light `world`) under
    /// `setup`; automatic culling culls closed meshes only.
    fn new(
        mesh: &TriangleMesh<'_>,
        normals: &'a [Vec3],
        world: &'a ShadeFrame,
        setup: &'a FrameSetup<'a>,
    ) -> Self {
        let view = setup.view;
        let (map, t0) = view.local_map(mesh.origin, [DVec3::X, DVec3::Y, DVec3::Z]);
        Self {
            eye_local: (view.eye - mesh.origin).as_vec3(),
            map,
            t0,
            near: view.near as f32,
            size: (view.width as f32, view.height as f32),
            shading: setup.options.shading,
            cull: match setup.options.culling {
                Culling::Auto => mesh.closed,
                Culling::Back => true,
                Culling::None => false,
            },
            normals,
            world,
            setup,
        }
    }
}

/// Culls, shades, clips and projects triangle `k` of `mesh` into `work`,
/// lit from its back side when it faces away, and counts it.
#[inline(always)]
fn plan_triangle(work: &mut ChunkWork, mesh: &TriangleMesh<'_>, k: usize, frame: &MeshFrame<'_>) {
    let t = mesh.triangles[k];
    let p = t.map(|v| mesh.positions[v as usize]);
    let face = (p[1] - p[0]).cross(p[2] - p[0]);
    let front = face.dot(frame.eye_local - p[0]) > 0.0;
    if frame.cull && !front {
        work.counters.triangles_culled += 1;
        return;
    }
    let sign = if front { 1.0 } else { -1.0 };
    let setup = frame.setup;
    let albedo = |corner: usize| mesh.colours.albedo(t, k, corner, setup.base_colour);
    let vertex = |corner: usize| -> ClipVertex {
        let n = frame.normals[t[corner] as usize] * sign;
        ClipVertex {
            clip: frame.map * p[corner] + frame.t0,
            attrs: corner_attributes(frame, n, albedo(corner)),
        }
    };
    let flat = if frame.shading == Shading::Flat {
        let mean = (albedo(0) + albedo(1) + albedo(2)) / 3.0;
        let face_n = face.normalize_or_zero() * sign;
        pack_colour(setup.material.shade(face_n, frame.world, mean))
    } else {
        0
    };
    let tri = [vertex(0), vertex(1), vertex(2)];
    let outcome = clip_and_project(&tri, frame.near, frame.size, 0, flat, &mut work.triangles);
    match outcome {
        ClipOutcome::Dropped => {}
        ClipOutcome::Whole => work.counters.triangles += 1,
        ClipOutcome::Clipped(c) => {
            work.counters.triangles += c as u64;
            work.counters.triangles_clipped += 1;
        }
    }
}

/// The attributes a triangle's corner of normal `n` and albedo `a`
/// interpolates under the frame's shading: normal and albedo (Phong), the
/// lit colour (Gouraud), or none (flat: one colour per triangle).
#[inline(always)]
fn corner_attributes(frame: &MeshFrame<'_>, n: Vec3, a: Vec3) -> [f32; TRI_ATTRS] {
    match frame.shading {
        Shading::Phong => [n.x, n.y, n.z, a.x, a.y, a.z],
        Shading::Gouraud => {
            let c = frame.setup.material.shade(n, frame.world, a);
            [c.x, c.y, c.z, 0.0, 0.0, 0.0]
        }
        Shading::Flat => [0.0; TRI_ATTRS],
    }
}

/// Whether every directed edge of `triangles` appears exactly once and its
/// reverse exactly once (a closed, consistently wound surface). O(T log T).
fn is_closed(triangles: &[[u32; 3]]) -> bool {
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .collect();
    if edges.is_empty() {
        return false;
    }
    edges.sort_unstable();
    let once = edges.windows(2).all(|w| w[0] != w[1]);
    once && edges
        .iter()
        .all(|&(a, b)| a != b && edges.binary_search(&(b, a)).is_ok())
}

/// Whether the signed volume `Σ det(a, b, c) / 6` of `triangles` (about
/// their first vertex, in f64) is positive: a closed surface wound so its
/// fronts face out. O(T).
fn faces_out(positions: &[Vec3], triangles: &[[u32; 3]]) -> bool {
    let Some(first) = triangles.first() else {
        return false;
    };
    let o = positions[first[0] as usize].as_dvec3();
    let volume: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| positions[v as usize].as_dvec3() - o);
            a.dot(b.cross(c))
        })
        .sum();
    volume > 0.0
}

#[cfg(test)]
mod tests {
    use super::{faces_out, is_closed};
    use glam::Vec3;

    #[test]
    fn a_closed_mesh_faces_out_only_with_a_positive_volume() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        let outward = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
        assert!(is_closed(&outward) && faces_out(&p, &outward));
        let inward = outward.map(|[a, b, c]| [a, c, b]);
        assert!(is_closed(&inward) && !faces_out(&p, &inward));
        assert!(!faces_out(&p, &[]));
    }

    #[test]
    fn closed_means_every_edge_once_each_way() {
        let tetra = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
        assert!(is_closed(&tetra));
        // An opening: one face removed.
        assert!(!is_closed(&tetra[..3]));
        // One face flipped: inconsistent winding.
        let flipped = [[0, 1, 2], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
        assert!(!is_closed(&flipped));
        // A face repeated twice over an edge: not manifold.
        let doubled = [tetra[0], tetra[1], tetra[2], tetra[3], tetra[0], [0, 1, 2]];
        assert!(!is_closed(&doubled));
        assert!(!is_closed(&[]));
    }
}
