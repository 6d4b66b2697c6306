//! Integration tests of the geometric error and of the texture detail conversions keep.
//!
//! - `geometric`: known answers on generated shapes (an exact patch, a hole, a shifted
//!   scene), and the issue-4 targets on the Stanford bunny when `../shared/data` is present.
//! - `texture_detail`: a generated checkerboard quad whose checks must survive, and the albedo
//!   PSNR of BoxTextured.glb (shared data).

mod geometric;
mod texture_detail;
