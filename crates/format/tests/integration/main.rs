//! Integration tests of the container.
//!
//! - `golden`: the committed v1 files decode to the scenes they document.
//! - `round_trip`: random scenes of every channel/width/grid combination
//!   survive write → read exactly, with and without compression.
//! - `corruption`: truncations, flipped bytes, lying counts, unknown
//!   versions and trailing bytes all give errors, never panics.
//! - `atomic`: a failed write leaves nothing under the output name.
//! - `far_merge`: merged scenes far apart keep each part's node positions
//!   (issue 22), through the ORGR section.

mod atomic;
mod corruption;
mod far_merge;
mod golden;
mod round_trip;
mod scenes;
