//! The Earth pipeline: colour map → heights → displaced globe mesh → patches.
//!
//! Inputs: [`EarthOptions`] (which maps, the globe, the patch density, the container
//! options). Output: [`EarthConversion`], the mesh pipeline's [`Conversion`] of the globe
//! with the Earth's own stages (`heights`, `globe`) first in its stage list, in place of
//! the mesh pipeline's `load` (the globe is built in memory), and what the globe was made
//! of ([`GlobeSummary`]). Each stage is a call into the module that owns it; this file only
//! wires them together and keeps the clock. Cost: that of the stages (the conversion
//! dominates).

use std::path::PathBuf;
use std::time::Instant;

use serde::Serialize;
use spatch_convert::{
    convert_with_progress, Conversion, ConvertInput, ConvertOptions, ProgressEvent, Stage,
    StageTime,
};

use crate::{
    build_globe, heights_from_colour, heights_from_elevation, ColourMap, EarthError,
    ElevationOptions, GlobeOptions, HueLevels, DEFAULT_MAX_MAP_WIDTH,
};

/// Patch density, as the original work's three Earth models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum Density {
    /// About 383 patches (node spacing 1.88 on the radius-128 globe).
    Low,
    /// About 1,128 patches (spacing 1.01).
    #[default]
    Medium,
    /// About 2,712 patches (spacing 0.62).
    High,
}

impl Density {
    /// Node spacing in model units on the radius-128 globe, calibrated so that the
    /// built-in map lands near the original's patch counts.
    pub fn spacing(self) -> f32 {
        match self {
            Self::Low => 1.88,
            Self::Medium => 1.01,
            Self::High => 0.62,
        }
    }
}

/// Where the heights come from.
#[derive(Debug, Clone, Default)]
#[non_exhaustive]
pub enum HeightSource {
    /// Estimated from the colour map's hues ([`heights_from_colour`]).
    #[default]
    Colour,
    /// Read from an equirectangular greyscale elevation map ([`heights_from_elevation`]).
    Elevation {
        /// The map (PNG).
        path: PathBuf,
        /// How to read its samples.
        options: ElevationOptions,
    },
}

/// What the Earth pipeline builds, and how.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct EarthOptions {
    /// The equirectangular colour map; `None`: the built-in 1024×512 map.
    pub colour: Option<PathBuf>,
    /// Colour maps wider than this (pixels) are halved until they fit. Default
    /// [`DEFAULT_MAX_MAP_WIDTH`].
    pub map_width: u32,
    /// Where the heights come from. Default: the colours.
    pub heights: HeightSource,
    /// The globe mesh (triangles, exaggeration).
    pub globe: GlobeOptions,
    /// Patch density; ignored when `convert.fit.spacing` is set.
    pub density: Density,
    /// The mesh pipeline's options (spacing, container compression, …).
    pub convert: ConvertOptions,
}

impl Default for EarthOptions {
    fn default() -> Self {
        Self {
            colour: None,
            map_width: DEFAULT_MAX_MAP_WIDTH,
            heights: HeightSource::Colour,
            globe: GlobeOptions::default(),
            density: Density::default(),
            convert: ConvertOptions::default(),
        }
    }
}

impl EarthOptions {
    /// The input for messages and reports: `globe from <the map that gives the heights>`.
    pub fn source_name(&self) -> String {
        match (&self.heights, &self.colour) {
            (HeightSource::Elevation { path, .. }, _) => format!("globe from {}", path.display()),
            (HeightSource::Colour, Some(map)) => format!("globe from {}", map.display()),
            (HeightSource::Colour, None) => "globe from the built-in map".to_owned(),
        }
    }
}

/// A step of the Earth pipeline, announced to the progress callback as it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum EarthStep {
    /// Reading the colour map.
    ColourMap,
    /// Heights from the colour or elevation map.
    Heights,
    /// The displaced globe mesh.
    Globe,
    /// A step of the mesh pipeline converting the globe.
    Convert(ProgressEvent),
}

impl EarthStep {
    /// Steps before the mesh pipeline's (colour map, heights, globe).
    pub const BEFORE_CONVERT: usize = 3;
}

/// What the globe was made of (the report's `details.globe`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GlobeSummary {
    /// Triangles of the globe mesh.
    pub triangles: usize,
    /// Subdivision frequency of the geodesic sphere.
    pub frequency: usize,
    /// Largest over smallest triangle area.
    pub area_ratio: f64,
    /// Width and height of the colour map used, in pixels.
    pub map: [u32; 2],
    /// `colour` or `elevation`.
    pub heights: &'static str,
    /// The height multiplier.
    pub exaggeration: f64,
}

/// The converted Earth.
#[derive(Debug, Clone)]
pub struct EarthConversion {
    /// The mesh pipeline's result; its stages start with `heights` and `globe`.
    pub conversion: Conversion,
    /// What the globe was made of.
    pub globe: GlobeSummary,
}

/// Builds the globe of `options` and converts it to patches, calling `on_step` as each
/// step starts (and as the mesh pipeline reports; possibly from worker threads).
///
/// # Errors
/// [`EarthError`]: an unreadable or unusable map, an option out of range, relief larger
/// than the globe; [`EarthError::Convert`] and [`EarthError::Mesh`] are bugs.
pub fn convert_earth(
    options: &EarthOptions,
    on_step: &(dyn Fn(EarthStep) + Sync),
) -> Result<EarthConversion, EarthError> {
    let started = Instant::now();
    on_step(EarthStep::ColourMap);
    let map = match &options.colour {
        Some(path) => ColourMap::load(path, options.map_width)?,
        None => ColourMap::built_in()?,
    };
    on_step(EarthStep::Heights);
    let heights = match &options.heights {
        HeightSource::Elevation { path, options } => heights_from_elevation(path, options)?,
        HeightSource::Colour => heights_from_colour(&map, &HueLevels::default()),
    };
    let heights_seconds = started.elapsed().as_secs_f64();
    on_step(EarthStep::Globe);
    let globe_started = Instant::now();
    let globe = build_globe(&map, &heights, &options.globe)?;
    let globe_seconds = globe_started.elapsed().as_secs_f64();

    let mut convert_options = options.convert.clone();
    convert_options.fit.spacing = Some(
        convert_options
            .fit
            .spacing
            .unwrap_or(options.density.spacing()),
    );
    let mut conversion =
        convert_with_progress(ConvertInput::Mesh(globe.mesh), &convert_options, &|event| {
            on_step(EarthStep::Convert(event))
        })?;
    conversion.report.stages =
        earth_stages(heights_seconds, globe_seconds, &conversion.report.stages);
    let summary = GlobeSummary {
        triangles: conversion.report.triangles,
        frequency: globe.frequency,
        area_ratio: globe.area_ratio,
        map: [map.width(), map.height()],
        heights: match options.heights {
            HeightSource::Colour => "colour",
            HeightSource::Elevation { .. } => "elevation",
        },
        exaggeration: options.globe.exaggeration,
    };
    Ok(EarthConversion {
        conversion,
        globe: summary,
    })
}

/// The Earth's stage list: its own two stages, then the mesh pipeline's without its `load`
/// (the globe mesh was handed over in memory, so loading took no time).
fn earth_stages(heights: f64, globe: f64, pipeline: &[StageTime]) -> Vec<StageTime> {
    let own = [
        StageTime {
            name: "heights",
            seconds: heights,
        },
        StageTime {
            name: "globe",
            seconds: globe,
        },
    ];
    own.into_iter()
        .chain(
            pipeline
                .iter()
                .filter(|s| s.name != Stage::Load.name())
                .cloned(),
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_earth_stages_replace_the_pipeline_load() {
        let pipeline = [
            StageTime {
                name: "load",
                seconds: 0.0,
            },
            StageTime {
                name: "prepare",
                seconds: 0.5,
            },
        ];
        let names: Vec<&str> = earth_stages(1.0, 2.0, &pipeline)
            .iter()
            .map(|s| s.name)
            .collect();
        assert_eq!(names, ["heights", "globe", "prepare"]);
    }

    #[test]
    fn the_source_name_follows_the_heights() {
        let mut options = EarthOptions::default();
        assert_eq!(options.source_name(), "globe from the built-in map");
        options.colour = Some(PathBuf::from("map.jpg"));
        assert_eq!(options.source_name(), "globe from map.jpg");
        options.heights = HeightSource::Elevation {
            path: PathBuf::from("dem.png"),
            options: ElevationOptions::default(),
        };
        assert_eq!(options.source_name(), "globe from dem.png");
    }

    #[test]
    fn denser_levels_have_finer_spacing() {
        assert!(Density::High.spacing() < Density::Medium.spacing());
        assert!(Density::Medium.spacing() < Density::Low.spacing());
    }
}
