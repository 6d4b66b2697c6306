//! Integration tests of the Earth builder.
//!
//! - `globe`: triangle count and size uniformity, no cracks at the seam or
//!   the poles, texture coordinates continuous, heights applied.
//! - `maps`: the built-in and shared colour maps, the shared relief map.

mod globe;
mod maps;
