//! Visible sides: the openings of an open mesh, and which patches they concern.
//!
//! A renderer culls back faces because, on a closed surface, no eye outside the model ever
//! sees the back of a patch. On an open surface (a tube, a scan with holes, a sheet) the back
//! can show through an **opening**, a boundary loop of the mesh. Any line of sight from
//! outside to the back of the surface crosses a surface spanning one of the loops, and such a
//! spanning surface fits in the loop's bounding sphere. This pass records those spheres in the
//! scene ([`spatch_format::Opening`]) and marks the patches of an open mesh
//! [`Sides::ThroughOpenings`]; the renderer's automatic culling then draws a patch from behind
//! only in frames where an opening lies between the eye and it (so a bunny with a few small
//! holes in its base keeps culling nearly everything from most views).
//!
//! - A mesh without boundary edges records nothing: every patch stays [`Sides::Front`].
//! - Openings: boundary edges joined through shared vertices; each gives the centroid of its
//!   vertices and the largest distance from it to one of them (a sphere), and the plane
//!   through the centroid across which its vertices spread least (the smallest principal
//!   axis, by power iteration) with the largest distance of a vertex from it (a slab).
//! - More than [`MAX_OPENINGS`] openings (a scan full of small holes): the per-frame test would
//!   cost more than it saves, so every patch becomes [`Sides::Both`] and no opening is stored.
//!
//! - A mesh with a seam where two faces disagree whichever way they turn
//!   ([`Winding::Unknown`]) has no safe side: every patch becomes [`Sides::Both`].
//! - A mesh whose surface had mostly to be turned over, or whose file gave most faces a twin
//!   wound the other way (a two-sided export: preparation keeps one copy of each, and which
//!   copy came first says nothing about the outside), once oriented, is
//!   [`Winding::Turned`] (not oriented, the two-sided export is [`Winding::Unknown`]): every patch
//!   becomes [`Sides::Both`], and when every opening is stored the scene gets an
//!   [`InsideBox`], the mesh's box grown by the fit's reach. Wound outward, such a surface
//!   shows its back only to an eye inside the volume it closes (a room seen from inside) or
//!   through an opening, and the volume lies inside the box: from an eye outside it the
//!   renderer culls the patches as it culls [`Sides::ThroughOpenings`] ones.
//!
//! Orientation: the cap argument needs each piece wound consistently and facing out, so that
//! its back faces the inside of the piece closed over its openings (a bowl wound into its
//! hollow shows its back from below without any opening in between). The pipeline winds the
//! mesh so first (`spatch_mesh::orient_faces`; a concave piece of a scan, its hollow facing
//! the scanner, turns over too). But a mesh whose surface it had mostly to turn over is drawn
//! from both sides: such a file is as often a room meant to be seen from inside (its walls
//! facing the eye there) as an object exported the wrong way round, and only drawing both
//! sides shows both right.
//!
//! Cost: O(edges + vertices) once per conversion (a union-find over boundary vertices).

use glam::Vec3;
use spatch_format::{InsideBox, Opening, Patch, Sides};
use spatch_mesh::{FaceAdjacency, TriangleMesh};

/// Most openings stored per scene (see the module docs).
pub const MAX_OPENINGS: usize = 256;

/// What the pass found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct SideCounts {
    /// Boundary edges of the mesh (0: closed, every patch front-only).
    pub boundary_edges: usize,
    /// Openings (connected boundary loops) of the mesh.
    pub openings: usize,
    /// Patches that may be seen from behind (through an opening, or from anywhere).
    pub two_sided_patches: usize,
}

/// The openings of `mesh` (relative to its origin) and the sides its patches get.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshSides {
    /// The openings to store in the scene (empty for a closed mesh or too many openings).
    pub openings: Vec<Opening>,
    /// The sides of every patch fitted to the mesh.
    pub sides: Sides,
    /// The box outside which two-sided patches show their backs only through the openings
    /// (a mesh wound outward that its file wound the other way), else `None`.
    pub inside_box: Option<InsideBox>,
    /// What was found.
    pub counts: SideCounts,
}

/// How far the mesh's winding says where its outside is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Winding {
    /// Every piece wound consistently and outward, as the file had it.
    AsWound,
    /// Wound consistently and outward, but the file had most of it the other way (or gave
    /// most faces a twin wound the other way): it may be meant to be seen from inside.
    Turned,
    /// Some edge's faces cannot agree (a non-orientable seam): nothing says where the
    /// outside is.
    Unknown,
}

/// Finds the openings of `mesh` (see the module docs); `winding` says what the file's
/// winding tells. Patches of a [`Winding::Turned`] mesh are two-sided, and when every opening
/// is stored they get an inside box: the mesh's bounding box grown by `reach` (how far a
/// patch may stand off the mesh), outside which their backs show only through openings.
pub fn find_mesh_sides(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    winding: Winding,
    reach: f32,
) -> MeshSides {
    let boundary_edges = adjacency.boundary_edge_count();
    let sides = |sides, openings, inside_box, counts| MeshSides {
        openings,
        sides,
        inside_box,
        counts,
    };
    if boundary_edges == 0 && winding == Winding::AsWound {
        return sides(Sides::Front, Vec::new(), None, SideCounts::default());
    }
    let loops = boundary_loops(mesh, adjacency);
    let counts = SideCounts {
        boundary_edges,
        openings: loops.len(),
        two_sided_patches: 0,
    };
    if winding == Winding::Unknown || loops.len() > MAX_OPENINGS {
        return sides(Sides::Both, Vec::new(), None, counts);
    }
    let openings = loops.iter().filter_map(|l| bounding_opening(l)).collect();
    match winding {
        Winding::Turned => sides(Sides::Both, openings, grown_box(mesh, reach), counts),
        _ => sides(Sides::ThroughOpenings, openings, None, counts),
    }
}

/// The bounding box of `mesh`'s positions grown by `reach` and a few f32 steps, so that the
/// stored box still holds every patch fitted within `reach` of the mesh.
fn grown_box(mesh: &TriangleMesh, reach: f32) -> Option<InsideBox> {
    let b = mesh.bounds();
    let slack = reach.max(0.0) + 4.0 * f32::EPSILON * b.min.abs().max(b.max.abs()).max_element();
    InsideBox::new(b.min - slack, b.max + slack).ok()
}

/// Gives every patch of `patches` the sides `sides`; returns how many may be seen from behind.
pub fn apply_sides(patches: &mut [Patch], sides: Sides) -> usize {
    if sides == Sides::Front {
        return 0;
    }
    for patch in patches.iter_mut() {
        *patch = patch.clone().with_sides(sides);
    }
    patches.len()
}

/// The opening around one loop's points: a sphere about their centroid and a slab about
/// their flattest plane, each grown by a few f32 steps so the stored values still hold every
/// point.
fn bounding_opening(points: &[Vec3]) -> Option<Opening> {
    let centre = points.iter().copied().sum::<Vec3>() / points.len().max(1) as f32;
    let normal = flattest_direction(points, centre);
    let (radius, thickness) = points.iter().fold((0.0f32, 0.0f32), |(r, h), p| {
        let d = *p - centre;
        (r.max(d.length()), h.max(d.dot(normal).abs()))
    });
    let slack = 4.0 * f32::EPSILON * (centre.abs().max_element() + radius);
    Opening::new(centre, radius + slack, normal, thickness + slack).ok()
}

/// The unit direction along which `points` spread least about `centre` (the eigenvector of
/// the smallest eigenvalue of their scatter matrix), by power iteration on
/// `trace · I − scatter`; +z when the points give no direction.
fn flattest_direction(points: &[Vec3], centre: Vec3) -> Vec3 {
    let scatter = points.iter().fold(glam::Mat3::ZERO, |m, p| {
        let d = *p - centre;
        m + glam::Mat3::from_cols(d * d.x, d * d.y, d * d.z)
    });
    let trace = scatter.x_axis.x + scatter.y_axis.y + scatter.z_axis.z;
    let shifted = glam::Mat3::from_diagonal(Vec3::splat(trace)) - scatter;
    let mut v = Vec3::new(0.577, 0.579, 0.576);
    for _ in 0..64 {
        v = (shifted * v).normalize_or_zero();
        if v == Vec3::ZERO {
            return Vec3::Z;
        }
    }
    v
}

/// The boundary vertices' positions of each opening (boundary edges joined through shared
/// vertices), in order of each opening's first vertex.
fn boundary_loops(mesh: &TriangleMesh, adjacency: &FaceAdjacency) -> Vec<Vec<Vec3>> {
    let vertex_count = mesh.positions.len();
    let mut parent: Vec<u32> = (0..vertex_count as u32).collect();
    let mut on_boundary = vec![false; vertex_count];
    for (v0, v1, faces) in adjacency.edges() {
        if faces.len() != 1 {
            continue;
        }
        let (a, b) = (v0.index(), v1.index());
        on_boundary[a] = true;
        on_boundary[b] = true;
        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
        parent[ra.max(rb)] = ra.min(rb) as u32;
    }
    let mut loops: Vec<Vec<Vec3>> = Vec::new();
    let mut loop_of = vec![usize::MAX; vertex_count];
    for v in (0..vertex_count).filter(|&v| on_boundary[v]) {
        let r = root(&mut parent, v);
        if loop_of[r] == usize::MAX {
            loop_of[r] = loops.len();
            loops.push(Vec::new());
        }
        loops[loop_of[r]].push(mesh.positions[v]);
    }
    loops
}

/// The union-find root of `v`, halving paths on the way.
fn root(parent: &mut [u32], mut v: usize) -> usize {
    while parent[v] as usize != v {
        let up = parent[parent[v] as usize];
        parent[v] = up;
        v = up as usize;
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_opening_holds_every_point_of_its_loop() {
        let ring: Vec<Vec3> = (0..40)
            .map(|k| {
                let a = k as f32 * std::f32::consts::TAU / 40.0;
                Vec3::new(3.0 * a.cos(), 3.0 * a.sin(), 100.0)
            })
            .collect();
        let o = bounding_opening(&ring).unwrap();
        assert!((o.centre() - Vec3::new(0.0, 0.0, 100.0)).length() < 1e-4);
        assert!(ring.iter().all(|p| p.distance(o.centre()) <= o.radius()));
        assert!(o.radius() < 3.001);
        // A flat ring: its slab is the plane z = 100, thin.
        assert!(o.normal().z.abs() > 0.999, "{:?}", o.normal());
        assert!(o.half_thickness() < 1e-3);
        let tilted: Vec<Vec3> = ring
            .iter()
            .map(|p| Vec3::new(p.x, p.y, 100.0 + 0.5 * p.x))
            .collect();
        let t = bounding_opening(&tilted).unwrap();
        assert!(tilted
            .iter()
            .all(|p| (*p - t.centre()).dot(t.normal()).abs() <= t.half_thickness()));
        assert!(t.half_thickness() < 1e-3, "{}", t.half_thickness());
    }

    #[test]
    fn union_find_joins_chains() {
        let mut parent: Vec<u32> = (0..6).collect();
        for (a, b) in [(0, 1), (1, 2), (4, 5)] {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent[ra.max(rb)] = ra.min(rb) as u32;
        }
        assert_eq!(root(&mut parent, 2), 0);
        assert_eq!(root(&mut parent, 5), 4);
        assert_eq!(root(&mut parent, 3), 3);
    }
}
