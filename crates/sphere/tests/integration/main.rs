//! Integration tests of the perfect sphere.
//!
//! - `coverage`: no gaps between patches (random points on the sphere lie on
//!   a patch surface) and the file-size budget of the original work.

mod coverage;
