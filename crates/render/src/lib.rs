//! A CPU rasterizer for spatial patches.
//!
//! [`render`] draws a [`Scene`](spatch_format::Scene) the way the original
//! work did, stage by stage: frustum visibility with a guard band and
//! splitting of partially visible patches, back-face culling by normal
//! cones, a per-patch plan choosing the mip level, the optimized
//! node-placing path, node splats or cell subdivision (bilinear in fixed
//! point, or C1 Catmull-Rom), node traversal by trilinear interpolation of
//! the projected box (or exact projection), shading in patch space with a
//! normal buffer (flat, Gouraud, deferred Phong), on a tiled framebuffer
//! rendered by a thread pool, with supersampling. A triangle mode draws
//! each cell as two triangles through a scan-line rasterizer, which
//! [`rasterize_triangles`] also offers for any mesh.
//!
//! Main types: [`Camera`] (OpenGL look-at, pixel centres at +0.5, row 0 at
//! the top), [`RenderOptions`], [`PreparedScene`] and [`Renderer`] for
//! repeated frames, [`RenderedImage`] (colour, depth, PNG encodings) and
//! [`RenderStats`].
//!
//! # Layers
//!
//! The modules form one layered order: a module uses only modules of its
//! own layer or of a layer above it in this list, and within a layer the
//! uses form no circle; each layer lists its modules in use order (a
//! module uses only those before it). The integration test `layers`
//! checks this on every `crate::` path outside the tests.
//!
//! 1. Vocabulary, shared by every stage: `error`, `options`, `fixed`
//!    (fixed-point formats and the projected node), `grid` (cell flags,
//!    closing and edge masks, node weights, cells drawn by quarters),
//!    `camera`, `lighting`
//!    (Blinn-Phong in patch space, packed normals and colours).
//! 2. `prepare/`, once per scene: normal reconstruction and slots, the
//!    normal buffer, the corner fill and level 1's cells by quarters, the
//!    mip pyramid, the normal cone, the prepared patch, overlap trimming,
//!    the prepared scene.
//! 3. `raster/`, the kernels that write samples into a band: the band
//!    store, bilinear cells and nodes, cells by quarters, Catmull-Rom
//!    cells, node splats, the scan-line triangle rasterizer.
//! 4. `plan/`, once per frame and patch: culling, splitting, lane
//!    conversions, projection, cell measurement, the cells by quarters a
//!    frame draws, subdivision, counters,
//!    the chunk's work, attributes, cells as triangles, the piece, the
//!    chunk, meshes.
//! 5. `shade/`, the deferred resolve: the Phong items, the per-pixel
//!    resolve pass.
//! 6. `frame/`, the frame driver: the image, bins and bands, statistics,
//!    the [`Renderer`], the projection shortcuts' costs.
//!
//! Planning sits above the raster kernels because it sizes their work
//! (subdivision limits, splat footprints, triangle clipping); the kernels
//! know nothing of patches. See docs/architecture.md.
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
mod error;
mod fixed;
mod frame;
mod grid;
mod isa;
mod lighting;
mod options;
mod plan;
mod prepare;
mod raster;
mod shade;
#[cfg(test)]
mod test_rng;
#[cfg(target_arch = "x86_64")]
mod wide;

pub use camera::{Camera, MAX_IMAGE_SIDE};
pub use error::{CameraProblem, RenderError};
pub use frame::image::{encode_rgba_png, RenderedImage};
pub use frame::occlusion::OcclusionStats;
pub use frame::render::{rasterize_triangles, render, RenderOutput, Renderer};
pub use frame::shortcuts::{measure_shortcuts, ShortcutCost, ShortcutCosts};
pub use frame::stats::{BandStats, RenderStats, StageTimes};
pub use options::{CellScheme, Culling, Lighting, Projection, RenderMode, RenderOptions, Shading};
pub use plan::mesh::{MeshColours, TriangleMesh};
pub use prepare::scene::PreparedScene;
