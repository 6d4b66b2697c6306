//! What the readers worked around: warnings, never prints.

use std::fmt;
use std::path::PathBuf;

use spatch_mesh::LoadWarning;

/// A problem that leaves a usable cloud.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ScanWarning {
    /// A warning from the mesh crate's reader of one scan.
    Load {
        /// The scan file.
        path: PathBuf,
        /// What the reader said.
        warning: LoadWarning,
    },
    /// Other scans of the set have colours, this one none: its points are white.
    ColoursMissing {
        /// The scan file.
        path: PathBuf,
    },
    /// This scan has normals but another has none, so no scan's normals are used (the
    /// pipeline estimates them for all).
    NormalsDropped {
        /// The scan file.
        path: PathBuf,
    },
    /// The file has intensities but no colours: the intensity is used as a grey level.
    IntensityAsGrey {
        /// The scan file.
        path: PathBuf,
    },
}

impl fmt::Display for ScanWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScanWarning::Load { path, warning } => write!(f, "{}: {warning}", path.display()),
            ScanWarning::ColoursMissing { path } => write!(
                f,
                "{}: has no colours while other scans do; its points are white",
                path.display()
            ),
            ScanWarning::NormalsDropped { path } => write!(
                f,
                "{}: its normals are not used because another scan has none",
                path.display()
            ),
            ScanWarning::IntensityAsGrey { path } => {
                write!(f, "{}: no colours; intensity shown as grey", path.display())
            }
        }
    }
}
