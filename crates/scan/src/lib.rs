//! Scanner inputs for spatch: registered scan sets and lidar/scanner file formats, read into
//! one [`PointCloud`](spatch_mesh::PointCloud) in a common frame.
//!
//! The main items:
//! - [`load_scans`] with [`ScanOptions`] → [`LoadedScans`]: any number of inputs, each a
//!   cloud file or a Stanford `.conf` scan set, posed and merged;
//! - [`read_conf`] / [`parse_conf`] → [`ScanSetFile`] of [`ScanEntry`]s: the pose files;
//! - [`Pose`]: a rigid transform (rotation, then translation);
//! - [`merge_scans`] of [`PosedScan`]s → the cloud and a [`ScanSummary`] per scan;
//! - the readers on their own: [`read_las`] (LAS 1.0-1.4, LAZ), [`read_e57`] (every scan with
//!   its pose; [`stream_e57`] a chunk at a time), text clouds through [`parse_columns`] and `spatch_mesh::load::xyz`;
//! - [`Viewpoint`]: where a structured scan's scanner was (PLY `range_grid` scans, E57 scans
//!   with row and column indices), giving each point its sight line when merged;
//!   [`scan_viewpoints`] gives them from the headers alone, for streamed runs;
//! - [`measure_alignment`] → [`ScanAlignment`]: how well the scans of a set line up;
//! - [`ScanError`] (the one error type) and [`ScanWarning`].
//!
//! Formats, the pose convention and how it was worked out: `docs/algorithms/scan.md`.
//!
//! ```
//! use glam::{DQuat, DVec3};
//! use spatch_scan::{merge_scans, Pose, PosedScan};
//!
//! let half_turn = Pose::new(DQuat::from_rotation_y(std::f64::consts::PI), DVec3::X)?;
//! let scans = vec![
//!     PosedScan { positions: vec![DVec3::X], ..PosedScan::default() },
//!     PosedScan { positions: vec![DVec3::X], pose: half_turn, ..PosedScan::default() },
//! ];
//! let (cloud, summaries) = merge_scans(scans, &mut Vec::new())?;
//! assert!((cloud.world_position(1) - DVec3::ZERO).length() < 1e-6);
//! assert_eq!(summaries[1].points, 1..2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod alignment;
mod columns;
mod conf;
mod e57;
mod e57_stream;
mod error;
mod las;
mod load;
mod pose;
mod scan_set;
mod set_viewpoints;
mod viewpoint;
mod warning;

pub use alignment::{measure_alignment, ScanAlignment};
pub use columns::parse_columns;
pub use conf::{parse_conf, read_conf, ScanEntry, ScanSetFile};
pub use e57::read_e57;
pub use e57_stream::{stream_e57, E57Chunk, E57Streamed};
pub use error::{ColumnSpecProblem, ConfProblem, ScanError};
pub use las::{intensity_to_grey, read_las, rgb16_to_bytes, LAS_CHUNK};
pub use load::{is_scan_set, load_scans, LoadedScans, ScanOptions};
pub use pose::{Pose, PoseProblem};
pub use scan_set::{merge_scans, sight_lines_of, PosedScan, ScanSummary, MAX_POINTS};
pub use set_viewpoints::scan_viewpoints;
pub use viewpoint::Viewpoint;
pub use warning::ScanWarning;
