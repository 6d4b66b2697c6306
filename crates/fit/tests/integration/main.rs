//! Integration tests of the patch fitter, on generated shapes.
//!
//! - `support`: mesh builders shared by the test modules (sheets, folds, slabs).
//! - `coverage`: exact planes, split regions sharing their seams, error bounds on a cap.
//! - `layers`: a node never takes a layer of surface behind or in front of its region.
//! - `colour`: colour only when the source has it; determinism across thread counts.
//! - `colour_grid`: a textured quad keeps a checkerboard finer than its nodes.

mod colour;
mod colour_grid;
mod coverage;
mod layers;
mod support;
