//! Tests that run the built `spatch` binary in a temporary folder.
//!
//! - `sphere`: `spatch sphere` output, its bounds and determinism.
//! - `stats`: the human table and the JSON keys.
//! - `export`: standard PLY headers and counts.
//! - `earth`: the three levels, the shared maps, bad maps.
//! - `merge`: patch counts add up; incompatible scenes refused; the streamed merge writes
//!   the in-memory merge's bytes; a tiled-scene index merges into one file.
//! - `mesh_tiles`: a mesh tiled by face joins with no duplicate and covers the surface.
//! - `render`: PNG, depth and stats outputs, camera flags, `--bench`, bad input.
//! - `occlusion_skip`: the same PNG bytes with and without `--occlusion-skip` (sphere,
//!   bunny, mannequin; several drawing paths), skipped pieces counted and all hidden.
//! - `convert`: `spatch convert` report keys, determinism, bad input; `spatch demo`.
//! - `from_cloud`: `spatch from-cloud` scene, report keys and error targets, determinism,
//!   bad clouds.
//! - `golden`: small renders (shadings, modes, the sphere, textured Spot, an open tube, a
//!   concave crease) compared pixel for pixel with `testdata/golden/render/`.
//! - `issue_22_thin`: thin meshes convert to patches, unsampleable ones are refused naming
//!   `--spacing`, a cube with flipped triangles warns about its error.
//! - `eval`: `spatch eval` against meshes and clouds (error both ways, images, per-patch CSV,
//!   known offsets), bad input, and a tiny `--sweep` with its Pareto front checked.
//! - `scan_inputs`: `spatch from-cloud` on bun.conf, several inputs of several formats
//!   (LAZ, XYZ, PTS), `--columns`, malformed scan files.
//! - `range_grid`: `--range-grid on/off` on a thin sheet scanned from both sides; `--align-scans`.
//! - `scan_plan`: a `.conf` scan set planned and converted tile by tile (issue 18).
//! - `scan_tiles`: structured scan sets through tiles keep their scanners and are aligned
//!   once for every tile (issue 19).
//! - `report_schema`: every command's JSON report parses into the shared shape.
//! - `stability`: the stiff and extreme cases of issue #8, one test per case (see its
//!   module docs).
//! - `output_safety`: issue 20 — outputs that name inputs, symlinks, FIFOs, devices, kept
//!   modes, temporary files after a kill, endless streams, one-line usage errors, completions
//!   and the manual page.
//! - `conventions`: issue 20 — `-q`, `--json` on every reporting command (and refused
//!   with an output on standard output), `--threads` on every command that works, no
//!   progress without a terminal.
//! - `tiled`: issue 18 — `spatch plan`, `from-cloud --plan` one tile and every tile (the
//!   same bytes), `spatch index`, `spatch render INDEX` reading only the tiles in view.
//! - `readme_tour`: every command of the README's tour, as written.
//! - `view`: issue 17 — `spatch view` without a display, scripted screenshots equal to
//!   `spatch render` of the printed command, the overlay strip, `--bench-orbit`, bad
//!   scripts, several scenes, and the window under Xvfb (skipped without `xvfb-run`).
//! - `bad_input`: missing, truncated and corrupt files give one error line,
//!   exit code 2 and no output file.

mod bad_input;
mod conventions;
mod convert;
mod earth;
mod edges;
mod eval;
mod export;
mod from_cloud;
mod golden;
mod issue_22_thin;
mod merge;
mod mesh_tiles;
mod occlusion_skip;
mod output_safety;
mod range_grid;
mod readme_tour;
mod render;
mod repeated_faces;
mod report_schema;
mod scan_inputs;
mod scan_plan;
mod scan_tiles;
mod sphere;
mod stability;
mod stats;
mod test_command;
mod tiled;
mod view;
mod winding;
