//! Integration tests of spatch-cloud (one binary; each module one area).
//!
//! - `any_extent`: spatial tiles, far outliers, the pixel budget, progress (issue 19).
//! - `clouds`: generators shared by the tests (planes, spheres, the sampled bunny, noise).
//! - `generated`: planes and spheres: coverage, accuracy, colour, far-from-origin clouds.
//! - `degenerate`: empty, single-point, duplicate, collinear and non-finite input; options.
//! - `determinism`: byte-identical output for 1 and 2 threads.
//! - `overlapping_scans`: two offset scans of one surface become one (issue 19).
//! - `real_scans`: the raw bunny scans (alone and registered together) and Hoppe's distcap.
//! - `sampled_bunny`: points sampled from `bun_zipper.ply`, clean and noisy with smoothing.
//! - `scanners`: scan sets with known scanners: sight lines, runs, scan alignment.

mod any_extent;
mod clouds;
mod degenerate;
mod determinism;
mod generated;
mod overlapping_scans;
mod real_scans;
mod sampled_bunny;
mod scanners;
