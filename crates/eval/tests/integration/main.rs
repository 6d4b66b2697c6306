//! Integration tests of the geometric error.
//!
//! - `geometric`: known answers on generated shapes (an exact patch, a hole, a shifted
//!   scene), and the issue-4 targets on the Stanford bunny when `../shared/data` is present.

mod geometric;
