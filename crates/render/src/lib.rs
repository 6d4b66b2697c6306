//! A CPU rasterizer for spatial patches.
//!
//! [`render`] draws a [`Scene`](spatch_format::Scene) the way the original
//! work did, stage by stage: frustum visibility with a guard band and
//! splitting of partially visible patches ([`cull`](crate) / `split`),
//! back-face culling by normal cones, a per-patch plan choosing the mip
//! level, the optimized node-placing path or cell subdivision (bilinear in
//! fixed point, or C1 Catmull-Rom), node traversal by trilinear
//! interpolation of the projected box (or exact projection), shading in
//! patch space with a normal buffer (flat, Gouraud, deferred Phong), on a
//! tiled framebuffer rendered by a thread pool, with supersampling. A
//! triangle mode draws each cell as two triangles through a scan-line
//! rasterizer, which [`rasterize_triangles`] also offers for any mesh.
//!
//! Main types: [`Camera`] (OpenGL look-at, pixel centres at +0.5, row 0 at
//! the top), [`RenderOptions`], [`PreparedScene`] and [`Renderer`] for
//! repeated frames, [`RenderedImage`] (colour, depth, PNG encodings) and
//! [`RenderStats`].
//!
//! ```
//! use spatch_render::{render, Camera, PreparedScene, RenderOptions};
//! # use glam::{DVec3, Vec3};
//! # use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
//! # let frame = Frame::new(Vec3::new(-2.0, -2.0, 0.0), Vec3::X, Vec3::Y, Vec3::Z * 0.01)?;
//! # let patch = Patch::new(frame, GridSize::new(5, 5)?, vec![0; 25], None)?;
//! # let scene = Scene::new(DVec3::ZERO, ColourChannel::None, vec![patch])?;
//! let prepared = PreparedScene::new(&scene);
//! let (centre, radius) = prepared.bounding_sphere().unwrap();
//! let camera = Camera::framing(centre, radius, 40.0, 64, 64)?;
//! let out = render(&scene, &camera, &RenderOptions::default())?;
//! assert!(out.image.covered_count() > 0);
//! let png: Vec<u8> = out.image.encode_png()?;
//! # assert!(!png.is_empty());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod camera;
mod cell_bilinear;
mod cell_smooth;
mod cull;
mod error;
mod fixed;
mod framebuffer;
mod mesh;
mod mip;
mod normal_buffer;
mod options;
mod overlap;
mod plan;
mod prepare;
mod render;
mod shade;
mod shortcuts;
mod splat;
mod split;
mod stats;
#[cfg(test)]
mod test_rng;
mod tiles;
mod traverse;
mod triangle_raster;

pub use camera::{Camera, MAX_IMAGE_SIDE};
pub use error::{CameraProblem, RenderError};
pub use framebuffer::RenderedImage;
pub use mesh::{MeshColours, TriangleMesh};
pub use options::{CellScheme, Culling, Lighting, Projection, RenderMode, RenderOptions, Shading};
pub use prepare::PreparedScene;
pub use render::{rasterize_triangles, render, RenderOutput, Renderer};
pub use shortcuts::{measure_shortcuts, ShortcutCost, ShortcutCosts};
pub use stats::{RenderStats, StageTimes};

impl PreparedScene {
    /// The automatic camera for this scene (see [`Camera::framing`]).
    pub fn auto_camera(&self, width: u32, height: u32) -> Result<Camera, CameraProblem> {
        let (centre, radius) = self
            .bounding_sphere()
            .ok_or(CameraProblem::NothingToFrame)?;
        Camera::framing(centre, radius, Camera::DEFAULT_FOV_Y_DEGREES, width, height)
    }
}
