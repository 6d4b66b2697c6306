//! The Earth model of the original work.
//!
//! With no relief data, heights are estimated from the colour map
//! ([`heights_from_colour`]): blue ocean stays at sea level, green land
//! becomes plateaus and brown land mountains, and the height field is
//! smoothed. With an elevation map ([`heights_from_elevation`]) the heights
//! come from it instead. [`build_globe`] then makes a sphere of triangles of
//! similar size (a geodesic icosphere, no pole slivers), gives each corner
//! equirectangular texture coordinates (with the seam at ±180° and the poles
//! handled), displaces each vertex along its normal by the bilinearly
//! interpolated height, and attaches the colour map as the texture. The
//! conversion to patches is the mesh pipeline's (`spatch-convert`);
//! [`convert_earth`] runs the whole chain from [`EarthOptions`].
//!
//! ```
//! use spatch_earth::{build_globe, heights_from_colour, ColourMap, GlobeOptions, HueLevels};
//!
//! let map = ColourMap::from_rgba(4, 2, [20, 40, 160, 255].repeat(8))?; // all ocean
//! let heights = heights_from_colour(&map, &HueLevels::default());
//! let globe = build_globe(&map, &heights, &GlobeOptions::default())?;
//! assert!(globe.mesh.triangles.len() > 39_000);
//! # Ok::<(), spatch_earth::EarthError>(())
//! ```
#![forbid(unsafe_code)]

mod colour_map;
mod elevation;
mod error;
mod globe_mesh;
mod heightmap;
mod hue;
mod pipeline;

pub use colour_map::{ColourMap, DEFAULT_MAP_JPEG, DEFAULT_MAX_MAP_WIDTH};
pub use elevation::{heights_from_elevation, ElevationEncoding, ElevationOptions};
pub use error::EarthError;
pub use globe_mesh::{build_globe, equirectangular_uv, Globe, GlobeOptions};
pub use heightmap::HeightMap;
pub use hue::{heights_from_colour, HueLevels};
pub use pipeline::{
    convert_earth, Density, EarthConversion, EarthOptions, EarthStep, GlobeSummary, HeightSource,
};
