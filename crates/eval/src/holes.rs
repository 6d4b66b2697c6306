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
    Camera, Culling, MeshColours, PreparedScene, Projection, RenderError, RenderOptions,
    RenderedImage, Renderer, Shading, TriangleMesh as RasterMesh,
};

use crate::interior::interior_of;

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
    /// Source pixels whose 5 × 5 square the source covers whole (../shared/MEASURES.md).
    pub interior_source_pixels: usize,
    /// Of those, pixels the patches leave empty.
    pub interior_hole_pixels: usize,
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
    /// Interior source pixels summed over the views (see [`ViewHoles`]).
    pub interior_source_pixels: usize,
    /// Interior hole pixels summed over the views.
    pub interior_hole_pixels: usize,
    /// `interior_hole_pixels / interior_source_pixels`: ../shared/MEASURES.md's hole
    /// fraction (0 when no pixel is interior).
    pub interior_fraction: f64,
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
        interior_source_pixels: 0,
        interior_hole_pixels: 0,
        interior_fraction: 0.0,
        size: options.size,
    };
    for &direction in &options.views {
        let camera = view_camera(centre, radius, direction, options)?;
        let reference = renderer.rasterize(&mesh, &camera)?.image;
        let patches = renderer.render(&prepared, &camera)?.image;
        let view = count_holes(&reference, &patches, tolerance, direction);
        report.source_pixels += view.source_pixels;
        report.hole_pixels += view.hole_pixels;
        report.interior_source_pixels += view.interior_source_pixels;
        report.interior_hole_pixels += view.interior_hole_pixels;
        report.views.push(view);
    }
    report.fraction = ratio(report.hole_pixels, report.source_pixels);
    report.interior_fraction = ratio(report.interior_hole_pixels, report.interior_source_pixels);
    Ok(report)
}

/// The holes of one view: source pixels of `reference` that `patches` leave empty or cover
/// more than `tolerance` behind, over every source pixel and over the interior ones.
fn count_holes(
    reference: &RenderedImage,
    patches: &RenderedImage,
    tolerance: f32,
    direction: DVec3,
) -> ViewHoles {
    let source = reference.depth();
    let interior = interior_of(reference);
    let mut view = ViewHoles {
        direction: direction.normalize().to_array(),
        source_pixels: 0,
        hole_pixels: 0,
        fraction: 0.0,
        interior_source_pixels: 0,
        interior_hole_pixels: 0,
    };
    let pixels = source.iter().zip(patches.depth()).zip(&interior);
    for ((&s, &p), &inner) in pixels.filter(|((s, _), _)| s.is_finite()) {
        let hole = !covers(s, p, tolerance);
        view.source_pixels += 1;
        view.hole_pixels += usize::from(hole);
        view.interior_source_pixels += usize::from(inner);
        view.interior_hole_pixels += usize::from(inner && hole);
    }
    view.fraction = ratio(view.hole_pixels, view.source_pixels);
    view
}

/// Whether a patch pixel at depth `patch` covers a source pixel at depth `source`: drawn,
/// and at most `tolerance` behind it (see [`HOLE_DEPTH_TOLERANCE`]).
#[inline]
pub fn covers(source: f32, patch: f32, tolerance: f32) -> bool {
    patch.is_finite() && patch <= source + tolerance
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

#[cfg(test)]
mod tests {
    use glam::Vec3;
    use spatch_format::{ColourChannel, Frame, GridSize, Patch, EMPTY};

    use super::*;

    /// A 20 × 20 square at z = 0 as two triangles, and as one patch of 21 × 21 nodes whose
    /// nodes `empty` are left out.
    fn square(empty: impl Fn(usize, usize) -> bool) -> (Scene, spatch_mesh::TriangleMesh) {
        let corners = [[0.0, 0.0], [20.0, 0.0], [20.0, 20.0], [0.0, 20.0]];
        let positions = corners.map(|[x, y]| Vec3::new(x, y, 0.0)).to_vec();
        let mesh = spatch_mesh::TriangleMesh::new(positions, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01).unwrap();
        let nodes = (0..21 * 21)
            .map(|k| if empty(k % 21, k / 21) { EMPTY } else { 0 })
            .collect();
        let patch = Patch::new(frame, GridSize::new(21, 21).unwrap(), nodes, None).unwrap();
        let scene = Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch]).unwrap();
        (scene, mesh)
    }

    /// Holes of [`square`] seen square-on in a `side`² image.
    fn holes(side: u32, empty: impl Fn(usize, usize) -> bool) -> HoleReport {
        let (scene, mesh) = square(empty);
        let options = HoleOptions {
            views: vec![DVec3::Z],
            size: [side, side],
            threads: 1,
            ..HoleOptions::default()
        };
        hole_fraction(&scene, &mesh, &options).unwrap()
    }

    #[test]
    fn a_missing_border_strip_is_a_hole_only_on_the_outline_and_a_gap_inside_is_both() {
        let whole = holes(50, |_, _| false);
        assert_eq!((whole.hole_pixels, whole.interior_hole_pixels), (0, 0));
        assert!(whole.interior_source_pixels > 0);
        assert!(whole.interior_source_pixels < whole.source_pixels);
        // The view frames the square's bounding sphere (radius 14.1) in 50 px with a 5 %
        // margin: a cell is about 1.7 px. The last column of cells left out is a strip
        // along the outline narrower than the erosion's 2 px: holes, none inside.
        let strip = holes(50, |i, _| i == 20);
        assert!(strip.hole_pixels > 20, "{strip:?}");
        assert_eq!(strip.interior_hole_pixels, 0, "{strip:?}");
        // At 200², cells of about 6.7 px: most of the same strip lies inside.
        let wide = holes(200, |i, _| i == 20);
        assert!(wide.interior_hole_pixels * 2 > wide.hole_pixels, "{wide:?}");
        // The nine middle nodes left out, a gap of 4 × 4 cells: every hole pixel is inside
        // the outline.
        let gap = holes(50, |i, j| (9..=11).contains(&i) && (9..=11).contains(&j));
        assert!(gap.hole_pixels > 0);
        assert_eq!(gap.interior_hole_pixels, gap.hole_pixels);
        assert!(gap.interior_fraction > gap.fraction);
    }
}
