//! The error type of the Earth builder.

use std::path::PathBuf;

/// What can go wrong while building the Earth.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EarthError {
    /// An image could not be read or decoded.
    #[error("{}: cannot read image: {source}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// What the decoder said.
        source: image::ImageError,
    },
    /// An image has an unusable shape or pixel type.
    #[error("{}: {problem}", path.display())]
    UnusableImage {
        /// The file (or `<built-in>`).
        path: PathBuf,
        /// What is wrong.
        problem: String,
    },
    /// An option is out of range.
    #[error("invalid --{name}: {reason}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// Valid range.
        reason: &'static str,
    },
    /// The exaggerated relief is larger than the globe's radius.
    #[error(
        "invalid --exaggeration {exaggeration:?}: the relief would reach {relief:.3e} units, \
         more than the globe's radius {radius}; at most {largest:.4} with these heights"
    )]
    ReliefTooLarge {
        /// The exaggeration asked for.
        exaggeration: f64,
        /// The largest exaggerated height, in model units.
        relief: f64,
        /// The globe's radius, in model units.
        radius: f64,
        /// The largest exaggeration these heights allow.
        largest: f64,
    },
    /// The mesh crate refused the globe (a bug).
    #[error("internal error building the globe mesh (this is a bug): {0}")]
    Mesh(#[from] spatch_mesh::MeshError),
    /// The mesh pipeline refused the globe (a bug: the globe is a valid closed mesh).
    #[error("internal error converting the globe (this is a bug): {0}")]
    Convert(#[from] spatch_convert::ConvertError),
}

impl EarthError {
    /// Whether this is spatch's own failure rather than the input's.
    pub fn is_bug(&self) -> bool {
        matches!(self, Self::Mesh(_) | Self::Convert(_))
    }
}
