//! The hole fraction of a scene against its source (DESIGN §6, image error).
//!
//! The source mesh is drawn by the project's scan-line triangle rasterizer and the scene by
//! the patch renderer, from the same camera at the same size, both without back-face culling
//! (so open surfaces and inconsistently wound sources count fully). A **hole pixel** is a
//! pixel whose centre the source covers and the patches (nodes projected exactly) leave
//! empty *at the source's depth*:
//! either nothing is drawn there, or what is drawn lies more than [`HOLE_DEPTH_TOLERANCE`] of
//! the source's bounding radius behind the source (the patches' far side seen through a
//! hole in their near side, which culling would have shown as empty). The hole fraction is
//! hole pixels over source pixels, per view and summed over the views.
//!
//! Views: [`standard_views`], the 6 axis directions and the 8 cube diagonals, each looking at
//! the centre of the source's bounding box from the distance where the source's bounding
//! sphere fills the narrower side of the image with a 5 % margin (as
//! `spatch_render::Camera::framing`), 500 × 500 pixels and 40° vertical field of view by
//! default. Up is +y, or +z for the two views along y.
//!
//! Cost: two renders per view (14 × 2 by default) at O(pixels + scene) each.

use glam::DVec3;
use serde::Serialize;
use spatch_format::Scene;
use spatch_render::{
    Camera, Culling, MeshColours, PreparedScene, Projection, RenderError, RenderOptions, Renderer,
    Shading, TriangleMesh as RasterMesh,
};

/// How far behind the source (as a fraction of its bounding-sphere radius) a patch pixel may
/// lie and still count as covering it. Larger than any patch's reconstruction error, smaller
/// than any wall thickness a hole could show through.
pub const HOLE_DEPTH_TOLERANCE: f64 = 0.02;

/// Default image side of the hole views (as the original work's viewport).
pub const HOLE_VIEW_SIDE: u32 = 500;

/// The 14 standard view directions (unit vectors from the target to the eye): ±x, ±y, ±z,
/// then the 8 diagonals (±1, ±1, ±1)/√3.
pub fn standard_views() -> Vec<DVec3> {
    let mut views = vec![
        DVec3::X,
        DVec3::NEG_X,
        DVec3::Y,
        DVec3::NEG_Y,
        DVec3::Z,
        DVec3::NEG_Z,
    ];
    for sx in [1.0, -1.0] {
        for sy in [1.0, -1.0] {
            for sz in [1.0, -1.0] {
                views.push(DVec3::new(sx, sy, sz).normalize());
            }
        }
    }
    views
}

/// How the hole fraction is measured.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct HoleOptions {
    /// View directions (from target to eye; any non-zero length). Default
    /// [`standard_views`]. Fewer views: faster, fewer sides of the model checked.
    pub views: Vec<DVec3>,
    /// Image width and height in pixels. Default [`HOLE_VIEW_SIDE`] × [`HOLE_VIEW_SIDE`].
    /// Larger images resolve narrower holes (a gap narrower than a pixel is usually missed)
    /// at a cost linear in pixels.
    pub size: [u32; 2],
    /// Vertical field of view, degrees. Default 40° (`Camera::DEFAULT_FOV_Y_DEGREES`).
    pub fov_y_degrees: f64,
    /// Render threads (0 = all cores). Default 0.
    pub threads: usize,
}

impl Default for HoleOptions {
    fn default() -> Self {
        Self {
            views: standard_views(),
            size: [HOLE_VIEW_SIDE, HOLE_VIEW_SIDE],
            fov_y_degrees: Camera::DEFAULT_FOV_Y_DEGREES,
            threads: 0,
        }
    }
}

/// Holes seen from one view.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ViewHoles {
    /// Direction from the target to the eye (unit).
    pub direction: [f64; 3],
    /// Pixels the source covers.
    pub source_pixels: usize,
    /// Of those, pixels the patches leave empty.
    pub hole_pixels: usize,
    /// `hole_pixels / source_pixels` (0 when the source covers nothing).
    pub fraction: f64,
}

/// Holes over all views.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HoleReport {
    /// One entry per view, in the order of [`HoleOptions::views`].
    pub views: Vec<ViewHoles>,
    /// Source pixels summed over the views.
    pub source_pixels: usize,
    /// Hole pixels summed over the views.
    pub hole_pixels: usize,
    /// `hole_pixels / source_pixels` over all views (0 when the source covers nothing).
    pub fraction: f64,
    /// Image width and height of each view.
    pub size: [u32; 2],
}

/// The camera of one hole view: looks at the centre of `source`'s box from `direction`.
pub fn hole_view_camera(
    source: &spatch_mesh::TriangleMesh,
    direction: DVec3,
    options: &HoleOptions,
) -> Result<Camera, RenderError> {
    let mesh = raster_mesh(source)?;
    let (centre, radius) = mesh
        .bounding_sphere()
        .ok_or(spatch_render::CameraProblem::NothingToFrame)?;
    view_camera(centre, radius, direction, options)
}

/// Measures the hole fraction of `scene` against `source` (see the module docs). The scene
/// and the mesh must share model space (the scene's offset and the mesh's origin may differ).
pub fn hole_fraction(
    scene: &Scene,
    source: &spatch_mesh::TriangleMesh,
    options: &HoleOptions,
) -> Result<HoleReport, RenderError> {
    let mesh = raster_mesh(source)?;
    let (centre, radius) = mesh
        .bounding_sphere()
        .ok_or(spatch_render::CameraProblem::NothingToFrame)?;
    let prepared = PreparedScene::new(scene);
    let mut render_options = RenderOptions::default();
    render_options.shading = Shading::Flat;
    render_options.culling = Culling::None;
    // Trilinear node placement is not perspective-correct in depth; exact projection keeps
    // the patches' depth within their reconstruction error, so the depth test is fair.
    render_options.projection = Projection::Exact;
    let tolerance = (HOLE_DEPTH_TOLERANCE * radius) as f32;
    render_options.threads = options.threads;
    let mut renderer = Renderer::new(render_options)?;
    let mut report = HoleReport {
        views: Vec::with_capacity(options.views.len()),
        source_pixels: 0,
        hole_pixels: 0,
        fraction: 0.0,
        size: options.size,
    };
    for &direction in &options.views {
        let camera = view_camera(centre, radius, direction, options)?;
        let reference = renderer.rasterize(&mesh, &camera)?.image;
        let patches = renderer.render(&prepared, &camera)?.image;
        let (mut source_pixels, mut hole_pixels) = (0, 0);
        for (s, p) in reference.depth().iter().zip(patches.depth()) {
            if s.is_finite() {
                source_pixels += 1;
                if !(p.is_finite() && *p <= s + tolerance) {
                    hole_pixels += 1;
                }
            }
        }
        report.source_pixels += source_pixels;
        report.hole_pixels += hole_pixels;
        report.views.push(ViewHoles {
            direction: direction.normalize().to_array(),
            source_pixels,
            hole_pixels,
            fraction: ratio(hole_pixels, source_pixels),
        });
    }
    report.fraction = ratio(report.hole_pixels, report.source_pixels);
    Ok(report)
}

fn ratio(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        part as f64 / whole as f64
    }
}

fn raster_mesh(source: &spatch_mesh::TriangleMesh) -> Result<RasterMesh<'_>, RenderError> {
    RasterMesh::new(
        source.origin,
        &source.positions,
        &source.triangles,
        MeshColours::None,
    )
}

pub(crate) fn view_camera(
    centre: DVec3,
    radius: f64,
    direction: DVec3,
    options: &HoleOptions,
) -> Result<Camera, RenderError> {
    let dir = direction.normalize_or_zero();
    if dir == DVec3::ZERO || !dir.is_finite() {
        return Err(RenderError::InvalidOption {
            name: "views",
            reason: "view directions must be finite and non-zero",
        });
    }
    let [width, height] = options.size;
    let half_y = (options.fov_y_degrees.to_radians() / 2.0).tan();
    let half_x = half_y * f64::from(width) / f64::from(height.max(1));
    let half = half_x.min(half_y).atan();
    let radius = if radius > 0.0 {
        radius
    } else {
        1e-3 * (1.0 + centre.length())
    };
    let distance = radius / half.sin() * 1.05;
    let up = if dir.y.abs() > 0.99 {
        DVec3::Z
    } else {
        DVec3::Y
    };
    Ok(Camera::look_at(
        centre + dir * distance,
        centre,
        up,
        options.fov_y_degrees,
        width,
        height,
    )?)
}
