//! Integration tests of spatch-scan.
//!
//! - `bunny_conf`: the ten Stanford bunny scans through `bun.conf` line up (skips without
//!   ../shared/data).
//! - `e57_stream`: the streamed E57 reader gives what the whole read gives, chunk by chunk.
//! - `formats`: LAS 1.2-1.4, LAZ, E57 (with poses), PTS and XYZ round trips, several files,
//!   malformed files.
//! - `range_grids`: PLY `range_grid` scans and E57 scans with row/column indices give
//!   sight lines toward their scanner (also after a pose); `ignore_range_grids`.
//! - `writers`: writing the small test files with the formats' own crates.

mod bunny_conf;
mod e57_stream;
mod formats;
mod range_grids;
mod writers;
