//! Integration tests of the container.
//!
//! - `golden`: the committed v1 files decode to the scenes they document.
//! - `round_trip`: random scenes of every channel/width/grid combination
//!   survive write → read exactly, with and without compression.
//! - `corruption`: truncations, flipped bytes, lying counts, unknown
//!   versions and trailing bytes all give errors, never panics.
//! - `two_sided`: the visible sides and openings of container 1.1 (`SIDE`, `OPEN`): round
//!   trip, 1.0 bytes when nothing needs them, merge, lying sections.
//! - `container_spec`: docs/format.md against the reader: the raw-length rule of every
//!   section (§3.2) and the exact f32 evaluation of node positions (§1.1).
//! - `atomic`: a failed write leaves nothing under the output name.
//! - `colour_grids`: colour grids (1.2, `CGRD`): round trip, layout, merge, files without
//!   grids unchanged.
//! - `merge_writer`: the streaming merge writes the in-memory merge's bytes.
//! - `far_merge`: merged scenes far apart keep each part's node positions
//!   (issue 22), through the ORGR section.

mod atomic;
mod colour_grids;
mod container_spec;
mod corruption;
mod far_merge;
mod golden;
mod merge_writer;
mod round_trip;
mod scenes;
mod section_bytes;
mod two_sided;
