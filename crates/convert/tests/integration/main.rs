//! Integration tests of the conversion pipeline.
//!
//! - `pipeline`: generated shapes in memory: stages, counts, determinism, bad input.
//! - `issue_22_thin_shapes`: thin meshes yield patches (refined spacing), or a clear error;
//! - `shared_models`: the real models of `../shared/data` (skipped when absent): colour for
//!   textured ones, none for the rest, no panic on any.

mod issue_22_thin_shapes;
mod pipeline;
mod shared_models;
