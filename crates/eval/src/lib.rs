//! Measuring spatch scenes against their source, and the error-versus-time trade-off.
//!
//! The measures of DESIGN §6:
//!
//! - geometric error ([`geometric`]): [`node_to_surface`] (every filled node to the nearest
//!   point of the source) and [`surface_to_patch`] (points sampled uniformly on the source to
//!   the nearest point of the patch surface, drawable cells as bilinear quads, which reveals
//!   holes and cracks); [`geometric_error`] does both with `max(100_000, 10 × faces)` samples.
//!   Each gives an [`ErrorStats`] (max, RMS, 95th percentile, absolute and relative to the
//!   source's bounding-box diagonal); [`ErrorHistogram`] bins the distances;
//! - the hole fraction ([`holes`]; over every source pixel, and inside the outlines as
//!   ../shared/MEASURES.md counts it, [`interior_mask`]) and the full image error
//!   ([`mod@image_error`]: PSNR, holes, specks ([`find_specks`]), depth error, frame times)
//!   of the patch renderer against the source drawn by the
//!   triangle rasterizer from the same cameras ([`standard_views`]: 6 axes and 8 diagonals),
//!   in its colours and textures when the scene has colour ([`source_colours`]);
//! - per-patch errors beside the quantization-only bound `|az| / 2` ([`per_patch`]);
//! - [`evaluate()`]: all of them for one scene against a mesh or a point cloud ([`load_source`]),
//!   each measurement timed (what `spatch eval` prints).
//!
//! The trade-off: [`run_sweep`] converts and renders a mesh over a grid of settings and
//! measures each ([`sweep`]); [`pareto_front`] marks the settings worth choosing and
//! [`sweep_svg`] plots error against time (what `spatch eval --sweep` writes).
//!
//! And the JSON report every command shares ([`Report`], docs/report-schema.md).
//!
//! ```
//! use glam::Vec3;
//! use spatch_format::{ColourChannel, Frame, GridSize, Patch, Scene};
//! use spatch_mesh::{Bvh, TriangleMesh};
//!
//! // A unit square and one patch lying exactly on it.
//! let mesh = TriangleMesh::new(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)],
//!     vec![[0, 1, 2], [2, 1, 3]],
//! )?;
//! let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z * 0.01)?;
//! let patch = Patch::new(frame, GridSize::new(2, 2)?, vec![0; 4], None)?;
//! let scene = Scene::new(mesh.origin, ColourChannel::None, vec![patch])?;
//! let error = spatch_eval::geometric_error(&scene, &mesh, 7);
//! assert!(error.node_to_surface.max < 1e-6);
//! assert!(error.surface_to_patch.max < 1e-6);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod error;
pub mod evaluate;
pub mod geometric;
pub mod histogram;
pub mod holes;
pub mod image_error;
pub mod interior;
pub mod overlap;
pub mod pareto;
pub mod per_patch;
pub mod plot;
pub mod report;
pub mod source_colours;
pub mod specks;
pub mod sweep;

pub use error::EvalError;
pub use evaluate::{
    evaluate, load_source, CloudFigures, EvalOptions, Evaluation, LoadedSource, Source,
    CLOUD_IMAGE_NOTE,
};
pub use geometric::{
    cloud_error_entries, geometric_error, nearest_patch_cells, node_to_surface, sample_count,
    sampled_surface_to_patch, surface_to_patch, ErrorStats, GeometricError, NO_PATCH, QUERY_BATCH,
    SAMPLE_CHUNK,
};
pub use histogram::{ErrorHistogram, HISTOGRAM_EDGES};
pub use holes::{
    hole_fraction, hole_view_camera, standard_views, HoleOptions, HoleReport, ViewHoles,
    HOLE_DEPTH_TOLERANCE, HOLE_VIEW_SIDE,
};
pub use image_error::{
    compare_views, image_error, image_view_camera, views_for_count, ImageError, ImageOptions,
    SourceViews, ViewError, MAX_VIEWS,
};
pub use interior::{interior_mask, MEASURES_RADIUS};
pub use overlap::{source_overlap, Overlap, OVERLAP_TOLERANCE};
pub use pareto::{dominates, pareto_front};
pub use per_patch::{
    per_patch_csv, per_patch_errors, quantization_bound, PatchError, QuantizationBound,
    BOUND_SLACK_REL,
};
pub use plot::sweep_svg;
pub use report::{Counts, Report, Stages, REPORT_SCHEMA};
pub use source_colours::SourceDrawing;
pub use specks::{find_specks, Specks, SPECK_DARKER_BY};
pub use sweep::{run_sweep, sweep_csv, SweepOptions, SweepResult, SweepRow};
