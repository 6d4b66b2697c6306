//! Tests that run the built `spatch` binary in a temporary folder.
//!
//! - `sphere`: `spatch sphere` output, its bounds and determinism.
//! - `stats`: the human table and the JSON keys.
//! - `export`: standard PLY headers and counts.
//! - `merge`: patch counts add up; incompatible scenes refused.
//! - `bad_input`: missing, truncated and corrupt files give one error line,
//!   exit code 2 and no output file.

mod bad_input;
mod export;
mod merge;
mod sphere;
mod stats;
mod test_command;
