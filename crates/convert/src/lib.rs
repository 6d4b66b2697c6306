//! The mesh → spatial-patch pipeline of spatch, with per-stage timings.
//!
//! [`convert`] runs, in order: load (from a file, or take a [`TriangleMesh`](spatch_mesh::TriangleMesh) as given),
//! prepare (weld duplicate vertices, drop degenerate faces), adjacency, segment (the
//! three-stage segmenter of `spatch-segment`), fit (`spatch-fit`), sharp edges, sides (the
//! openings of an open mesh, through which its patches may be seen from behind) and encode (the `.spatch`
//! bytes). It returns a [`Conversion`]: the [`Scene`](spatch_format::Scene), the encoded
//! bytes, the prepared mesh (for measuring error against it) and a [`ConvertReport`] with the
//! wall time of every stage and the counts of every step.
//!
//! A conversion that yields no patch at all is refused ([`ConvertError::NoPatches`], naming
//! the spacing); [`check_error_budget`] turns a measured error far above the fitter's budget
//! into a warning.
//!
//! The CLI (`spatch convert`, `spatch demo`) and the evaluation sweeps share this crate, so
//! they always measure the same pipeline.
//!
//! ```no_run
//! use spatch_convert::{convert, ConvertInput, ConvertOptions};
//!
//! let conversion = convert(ConvertInput::Path("bunny.ply".as_ref()), &ConvertOptions::default())?;
//! println!("{} patches in {:.2} s", conversion.report.counts.patches, conversion.report.seconds);
//! std::fs::write("bunny.spatch", &conversion.bytes)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]

mod budget;
mod colour_budget;
mod colour_error;
mod error;
mod grid_resampling;
mod grid_sharing;
mod options;
mod owned;
mod pipeline;
mod report;
mod sides;

pub use budget::{check_error_budget, ErrorBudgetWarning, FAR_ABOVE_BUDGET};
pub use colour_budget::{ColourBudget, ColourGridReport};
pub use error::ConvertError;
pub use options::ConvertOptions;
pub use owned::{world_centroid, PartOwner};
pub use pipeline::{
    convert, convert_part, convert_with_progress, Conversion, ConvertInput, ProgressEvent, Stage,
};
pub use report::{ConvertReport, Counts, OrientCounts, PrepareCounts, StageTime};
pub use sides::{apply_sides, find_mesh_sides, MeshSides, SideCounts, Winding, MAX_OPENINGS};
/// The sharp-edge stage's options and counts, re-exported for callers of the pipeline.
pub use spatch_edges::{EdgeOptions, EdgeStats};
