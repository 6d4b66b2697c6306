//! Point clouds to spatial patches.
//!
//! A point cloud has no surface, so this crate makes one the way the spatial-patch paper did:
//! it takes orthographic range images of the cloud from view directions spread evenly over
//! the sphere (flushing the points into a z-buffer per view), fills the one- or two-pixel
//! sampling gaps by interpolating depth (never across a depth discontinuity), optionally
//! smooths noisy scans with an edge-preserving filter, and cuts rectangular, continuous,
//! not-too-steep regions into patches. Each view only adds patches where points are not yet
//! covered by an earlier one.
//!
//! The main items:
//! - [`cloud_to_scene`] with [`CloudOptions`] (and [`SmoothOptions`]) → [`CloudConversion`]
//!   (the [`Scene`](spatch_format::Scene), its bytes and a [`CloudReport`] with per-stage
//!   wall times);
//! - [`measure_cloud_error`] → [`CloudErrorReport`]: `cloud_to_patch` (every point to the
//!   patch surface) and `node_to_cloud` (every node to the nearest point), with the
//!   distances themselves from [`cloud_error_distances`]; [`measure_cloud_error_in_order`] for a
//!   conversion's own cloud, from the conversion's spatial order of the points
//!   ([`PointOrder`]);
//! - [`PatchSurface`]: the drawable cells of a scene as bilinear quads in a bounding volume
//!   hierarchy, for exact nearest-point queries (the error measures of `spatch-eval` use it
//!   too), and [`distance_to_quad`] for one cell;
//! - the stages on their own: [`PointTree`] and [`estimate_spacing`], [`estimate_normals`],
//!   [`view_directions`];
//! - spatial tiles for clouds of any extent ([`TileGrid`]; each tile under its own
//!   [`PIXEL_BUDGET`]), progress counts ([`cloud_to_scene_with_progress`], [`Progress`]) and
//!   typed warnings ([`CloudWarning`]);
//! - typed ids [`PointId`], [`ViewId`]; the error type [`CloudError`].
//!
//! Algorithms, parameters and measured figures: `docs/algorithms/cloud.md`.
//!
//! ```
//! use glam::{DVec3, Vec3};
//! use spatch_cloud::{cloud_to_scene, measure_cloud_error, CloudOptions};
//! use spatch_mesh::PointCloud;
//!
//! // A gently curved sheet sampled on a 60 x 60 grid.
//! let positions: Vec<Vec3> = (0..3600)
//!     .map(|k| {
//!         let (x, y) = ((k % 60) as f32 * 0.1, (k / 60) as f32 * 0.1);
//!         Vec3::new(x, y, 0.02 * (x - 3.0) * (x - 3.0))
//!     })
//!     .collect();
//! let cloud = PointCloud { origin: DVec3::ZERO, positions, colours: None, normals: None };
//! let conversion = cloud_to_scene(&cloud, &CloudOptions::default())?;
//! assert!(conversion.report.counts.filled_nodes < cloud.len());
//! let error = measure_cloud_error(&cloud, &conversion.scene, conversion.report.spacing)?;
//! assert!(error.cloud_to_patch.distance.rms < 0.5 * f64::from(conversion.report.spacing));
//! # Ok::<(), spatch_cloud::CloudError>(())
//! ```
#![forbid(unsafe_code)]

mod bucket_sort;
mod cell_grid;
mod consensus;
mod directions;
mod error;
mod error_metrics;
mod extract;
mod finite;
mod gap_fill;
mod ids;
mod morton_order;
mod neighbour_grid;
mod normal_cones;
mod normals;
mod options;
mod patch_cut;
mod patch_surface;
mod pipeline;
mod point_hierarchy;
mod progress;
mod quad_distance;
mod range_image;
mod report;
mod scan_shifts;
mod scanners;
mod smooth;
mod spacing;
mod stage_laps;
mod surface_stages;
mod tile_convert;
mod tiles;
mod warning;

pub use consensus::{CONSENSUS_MIN_POINTS, TWO_SIDED_MIN_POINTS};
pub use directions::{view_directions, ViewBasis};
pub use error::CloudError;
pub use error_metrics::{
    cloud_error_distances, measure_cloud_error, measure_cloud_error_in_order, CloudErrorDistances,
    CloudErrorReport, CloudToPatch, DistanceStats,
};
pub use ids::{PointId, ViewId};
pub use morton_order::PointOrder;
pub use normals::{estimate_normals, smallest_eigenvector};
pub use options::{CloudOptions, SmoothOptions};
pub use patch_surface::{PatchSurface, LEAF_QUADS, NO_PATCH, PRUNE_SLACK};
pub use pipeline::{
    cloud_to_scene, cloud_to_scene_owned, cloud_to_scene_with_progress, CloudConversion,
    BORDER_TOLERANCE, FRONT_BAND, MIN_REGION_CELLS, PIXEL_BUDGET,
};
pub use progress::{Progress, ProgressFn, Stage};
pub use quad_distance::{bilinear, distance_to_quad, Quad};
pub use report::{CloudReport, Counts, StageTime};
pub use scan_shifts::{scan_shift_sums, ScanShiftSums};
pub use scanners::{Scanner, Scanners, MAX_SCANS};
pub use spacing::{
    estimate_spacing, PointTree, SpacingEstimate, SPACING_NEIGHBOURS, SPACING_SAMPLES,
    SPACING_SUBSET,
};
pub use tiles::{TileGrid, OUTLIER_TILE_POINTS, TILE_BUFFER_PIXELS};
pub use warning::CloudWarning;
