//! One module per subcommand: arguments → library options → library call →
//! report.

pub(crate) mod completions;
pub(crate) mod convert;
pub(crate) mod demo;
pub(crate) mod earth;
pub(crate) mod eval;
pub(crate) mod export;
pub(crate) mod from_cloud;
pub(crate) mod man;
pub(crate) mod merge;
pub(crate) mod render;
pub(crate) mod sphere;
pub(crate) mod stats;

use spatch_format::Compression;

/// The container compression for a `--compress` flag.
pub(crate) fn compression(compress: bool) -> Compression {
    if compress {
        Compression::Predictive
    } else {
        Compression::None
    }
}
