//! Surface patches and shapes for the tests.

use glam::Vec3;
use spatch_edges::{generate_edge_patches, EdgeOptions, EdgeStats};
use spatch_eval::{hole_fraction, HoleOptions, HoleReport};
use spatch_fit::{default_spacing, fit_regions, FitOptions, FitRegion};
use spatch_format::{ColourChannel, Patch, Scene};
use spatch_mesh::{
    build_face_adjacency, prepare_mesh, FaceAdjacency, PrepareOptions, TriangleMesh,
};
use spatch_segment::{segment, SegmentOptions};

/// A prepared mesh, its adjacency, the fitter's spacing and its surface patches.
pub(crate) struct Fitted {
    pub(crate) mesh: TriangleMesh,
    pub(crate) adjacency: FaceAdjacency,
    pub(crate) spacing: f32,
    pub(crate) surface: Vec<Patch>,
    pub(crate) channel: ColourChannel,
}

impl Fitted {
    /// Edge patches with `options`.
    pub(crate) fn edges(&self, options: &EdgeOptions) -> (Vec<Patch>, EdgeStats) {
        generate_edge_patches(
            &self.mesh,
            &self.adjacency,
            &self.surface,
            self.spacing,
            options,
        )
        .unwrap()
    }

    /// Holes against the source with edge patches made with `options` (six 300² views in
    /// debug builds, the full set in release), and the edge patches' stats.
    pub(crate) fn holes_with(&self, options: &EdgeOptions) -> (HoleReport, EdgeStats) {
        let (edges, stats) = self.edges(options);
        let mut holes = HoleOptions::default();
        if cfg!(debug_assertions) {
            holes.views.truncate(6);
            holes.size = [300, 300];
        }
        let found = hole_fraction(&self.scene(&edges), &self.mesh, &holes).unwrap();
        (found, stats)
    }

    /// The scene of the surface patches, plus `extra`.
    pub(crate) fn scene(&self, extra: &[Patch]) -> Scene {
        let mut patches = self.surface.clone();
        patches.extend_from_slice(extra);
        Scene::new(self.mesh.origin, self.channel, patches).unwrap()
    }
}

/// Prepares `mesh` and fits it as the convert pipeline does (default options).
pub(crate) fn fit(mesh: TriangleMesh) -> Fitted {
    fit_with_spacing(mesh, None)
}

/// As [`fit`], with the node spacing given (or derived from the mesh for `None`).
pub(crate) fn fit_with_spacing(mesh: TriangleMesh, spacing: Option<f32>) -> Fitted {
    let (mesh, _) = prepare_mesh(&mesh, &PrepareOptions::default());
    let adjacency = build_face_adjacency(&mesh);
    let spacing = spacing.unwrap_or_else(|| default_spacing(&mesh).unwrap());
    let mut fit_options = FitOptions::default();
    fit_options.spacing = Some(spacing);
    let mut segment_options = SegmentOptions::default();
    segment_options.max_extent = (fit_options.grid - 1) as f32 * spacing;
    let (segmentation, _) = segment(&mesh, &adjacency, &segment_options).unwrap();
    let regions: Vec<FitRegion<'_>> = segmentation
        .regions
        .iter()
        .map(|r| FitRegion {
            faces: &r.faces,
            axis: r.axis,
        })
        .collect();
    let out = fit_regions(&mesh, &adjacency, &regions, &fit_options).unwrap();
    Fitted {
        surface: out.patches,
        channel: out.channel,
        mesh,
        adjacency,
        spacing,
    }
}

/// A plain mesh from a fixture shape.
pub(crate) fn mesh_of(shape: &spatch_fixtures::Shape) -> TriangleMesh {
    TriangleMesh::new(
        shape.positions.iter().map(|&p| Vec3::from(p)).collect(),
        shape.triangles.clone(),
    )
    .unwrap()
}

/// A closed frustum about z: height 1, radius `1.5 ∓ cot(θ)/2` at the bottom and top, so the
/// top rim's faces meet at `rim_angle_deg` between their normals (the bottom rim at 180° −
/// that). `segments` facets around.
pub(crate) fn frustum(rim_angle_deg: f32, segments: u32) -> TriangleMesh {
    let delta = 1.0 / rim_angle_deg.to_radians().tan();
    let (r_bottom, r_top) = (1.5 + delta / 2.0, 1.5 - delta / 2.0);
    let mut positions = Vec::new();
    for (z, r) in [(-0.5f32, r_bottom), (0.5, r_top)] {
        for j in 0..segments {
            let a = std::f32::consts::TAU * j as f32 / segments as f32;
            positions.push(Vec3::new(r * a.cos(), r * a.sin(), z));
        }
    }
    let (bc, tc) = (2 * segments, 2 * segments + 1);
    positions.push(Vec3::new(0.0, 0.0, -0.5));
    positions.push(Vec3::new(0.0, 0.0, 0.5));
    let mut triangles = Vec::new();
    for j in 0..segments {
        let k = (j + 1) % segments;
        let (b0, b1, t0, t1) = (j, k, segments + j, segments + k);
        triangles.push([b0, b1, t1]);
        triangles.push([b0, t1, t0]);
        triangles.push([tc, t0, t1]);
        triangles.push([bc, b1, b0]);
    }
    TriangleMesh::new(positions, triangles).unwrap()
}
