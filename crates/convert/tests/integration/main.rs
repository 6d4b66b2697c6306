//! Integration tests of the conversion pipeline.
//!
//! - `pipeline`: generated shapes in memory: stages, counts, determinism, bad input.
//! - `shared_models`: the real models of `../shared/data` (skipped when absent): colour for
//!   textured ones, none for the rest, no panic on any.

mod pipeline;
mod shared_models;
