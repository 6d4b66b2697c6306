//! `spatch earth`: the Earth model from a colour map (and an elevation map
//! when given), converted by the mesh pipeline.

use std::path::PathBuf;
use std::time::Instant;

use spatch_convert::{convert_with_progress, ConvertInput, ConvertOptions};
use spatch_earth::{
    build_globe, heights_from_colour, heights_from_elevation, ColourMap, ElevationEncoding,
    ElevationOptions, GlobeOptions, HueLevels, DEFAULT_MAX_MAP_WIDTH,
};
use spatch_format::WriteOptions;

use super::convert::{report_json, summary, Progress, Times};
use crate::failure::InternalFailure;
use crate::output::{print_stdout, write_json_report, write_output};
use crate::report::set_detail;

/// Patch density, as the original work's three Earth models.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Level {
    /// About 383 patches (node spacing 1.88 on the radius-128 globe).
    Low,
    /// About 1,128 patches (spacing 1.01).
    Medium,
    /// About 2,712 patches (spacing 0.62).
    High,
}

impl Level {
    /// Node spacing in model units on the radius-128 globe, calibrated so
    /// that the built-in map lands near the original's patch counts.
    fn spacing(self) -> f32 {
        match self {
            Self::Low => 1.88,
            Self::Medium => 1.01,
            Self::High => 0.62,
        }
    }
}

/// How to read 16-bit elevation samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Encoding {
    /// 0..=65535.
    Unsigned,
    /// Two's complement −32768..=32767 (SRTM-style metres).
    Signed,
}

/// Arguments of `spatch earth`.
#[derive(Debug, clap::Args)]
pub(crate) struct EarthArgs {
    /// Output .spatch file.
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Equirectangular colour map (PNG or JPEG, longitude −180° at the left edge)
    /// [default: the built-in 1024×512 NASA Visible Earth map].
    #[arg(long, value_name = "MAP", visible_alias = "color")]
    colour: Option<PathBuf>,
    /// Equirectangular 8- or 16-bit greyscale elevation map (PNG); heights
    /// come from it instead of from the colours.
    #[arg(long, value_name = "DEM")]
    elevation: Option<PathBuf>,
    /// Patch density: low, medium or high (about 383, 1,128 or 2,712 patches).
    #[arg(long, value_enum, default_value_t = Level::Medium)]
    level: Level,
    /// Multiplies every height; the exaggerated relief must stay within the globe's radius.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    exaggeration: f64,
    /// Triangles of the globe mesh (a geodesic sphere of about this many).
    #[arg(long, default_value_t = 40_000)]
    triangles: usize,
    /// Colour maps wider than this are halved until they fit.
    #[arg(long, default_value_t = DEFAULT_MAX_MAP_WIDTH)]
    map_width: u32,
    /// Raw elevation sample value of sea level.
    #[arg(long, default_value_t = 0.0)]
    sea_level: f64,
    /// How 16-bit elevation samples are stored.
    #[arg(long, value_enum, default_value_t = Encoding::Unsigned)]
    elevation_encoding: Encoding,
    /// Raw elevation value meaning "no data" [default: −32768 for signed maps, none otherwise].
    #[arg(long, allow_negative_numbers = true)]
    void: Option<f64>,
    /// Node spacing in model units, overriding --level.
    #[arg(long)]
    spacing: Option<f32>,
    /// Write a JSON report (counts, bytes, stage timings, geometric error against the globe
    /// mesh; the shape of docs/report-schema.md).
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Compress node data (grid prediction + range coding).
    #[arg(long)]
    compress: bool,
    /// Skip measuring the geometric error.
    #[arg(long)]
    no_error: bool,
    /// Measure the hole fraction over 14 views (500 x 500) against the globe mesh:
    /// cracks at the seam or the poles would show here.
    #[arg(long)]
    holes: bool,
}

/// Builds the globe, converts it, writes the scene and the report.
pub(crate) fn run(args: &EarthArgs) -> anyhow::Result<()> {
    let progress = Progress::new("earth");
    let started = Instant::now();
    progress.step("colour map");
    let map = match &args.colour {
        Some(path) => ColourMap::load(path, args.map_width)?,
        None => ColourMap::built_in()?,
    };
    progress.step("heights");
    let heights = match &args.elevation {
        Some(path) => {
            let mut options = ElevationOptions::default();
            options.sea_level = args.sea_level;
            options.void = args.void;
            options.encoding = match args.elevation_encoding {
                Encoding::Unsigned => ElevationEncoding::Unsigned,
                Encoding::Signed => ElevationEncoding::Signed,
            };
            heights_from_elevation(path, &options)?
        }
        None => heights_from_colour(&map, &HueLevels::default()),
    };
    let heights_seconds = started.elapsed().as_secs_f64();
    progress.step("globe mesh");
    let mut globe_options = GlobeOptions::default();
    globe_options.triangles = args.triangles;
    globe_options.exaggeration = args.exaggeration;
    let globe_started = Instant::now();
    let globe = build_globe(&map, &heights, &globe_options)?;
    let globe_seconds = globe_started.elapsed().as_secs_f64();

    let mut options = ConvertOptions::default();
    options.fit.spacing = Some(args.spacing.unwrap_or(args.level.spacing()));
    options.write = WriteOptions::with_compression(super::compression(args.compress));
    let mut conversion =
        convert_with_progress(ConvertInput::Mesh(globe.mesh), &options, &|stage| {
            progress.step(stage.name())
        })
        .map_err(|e| {
            anyhow::Error::new(InternalFailure(format!("converting the globe failed: {e}")))
        })?;
    // The globe stages come first in the report, as the pipeline's load stage would.
    conversion.report.stages.retain(|s| s.name != "load");
    conversion.report.stages.insert(
        0,
        spatch_convert::StageTime {
            name: "globe",
            seconds: globe_seconds,
        },
    );
    conversion.report.stages.insert(
        0,
        spatch_convert::StageTime {
            name: "heights",
            seconds: heights_seconds,
        },
    );
    progress.step("write");
    let write_started = Instant::now();
    write_output(&args.output, &conversion.bytes)?;
    let write_seconds = write_started.elapsed().as_secs_f64();
    let seconds = started.elapsed().as_secs_f64();
    let mut measured = spatch_eval::Stages::default();
    let error = (!args.no_error).then(|| {
        progress.step("measuring error");
        let start = Instant::now();
        let error = spatch_eval::geometric_error(&conversion.scene, &conversion.mesh, 1);
        measured.push("error", start.elapsed().as_secs_f64());
        error
    });
    let holes = if args.holes {
        progress.step("measuring holes");
        let start = Instant::now();
        let report = spatch_eval::hole_fraction(
            &conversion.scene,
            &conversion.mesh,
            &spatch_eval::HoleOptions::default(),
        )
        .map_err(|e| anyhow::Error::new(InternalFailure(format!("measuring holes failed: {e}"))))?;
        measured.push("holes", start.elapsed().as_secs_f64());
        Some(report)
    } else {
        None
    };
    drop(progress);
    let source_name = match (&args.elevation, &args.colour) {
        (Some(dem), _) => format!("globe from {}", dem.display()),
        (None, Some(map)) => format!("globe from {}", map.display()),
        (None, None) => "globe from the built-in map".to_owned(),
    };
    let mut report = report_json(
        "earth",
        &source_name,
        &args.output,
        &conversion,
        error.as_ref(),
        Times {
            seconds,
            write_seconds,
            measured,
        },
    )?;
    set_detail(
        &mut report,
        "globe",
        &serde_json::json!({
            "triangles": conversion.report.triangles,
            "frequency": globe.frequency,
            "area_ratio": globe.area_ratio,
            "map": [map.width(), map.height()],
            "heights": if args.elevation.is_some() { "elevation" } else { "colour" },
            "exaggeration": args.exaggeration,
        }),
    )?;
    if let Some(holes) = &holes {
        set_detail(&mut report, "holes", holes)?;
    }
    if let Some(path) = &args.report {
        write_json_report(path, &report)?;
    }
    let mut text = summary(
        &args.output,
        &conversion,
        error.as_ref(),
        seconds,
        args.report.as_deref(),
    );
    if let Some(holes) = &holes {
        text.push_str(&format!(
            "  holes: {:.4} % of the globe's pixels over {} views ({} of {})\n",
            holes.fraction * 100.0,
            holes.views.len(),
            holes.hole_pixels,
            holes.source_pixels
        ));
    }
    print_stdout(&format!(
        "{source_name}: {} triangles\n{text}",
        conversion.report.triangles
    ))
}

impl EarthArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        use crate::overwrite_guard::Written;
        crate::overwrite_guard::Files::default()
            .input(self.colour.as_deref())
            .input(self.elevation.as_deref())
            .output_as(Some(&self.output), Written::Spatch)
            .output_as(self.report.as_deref(), Written::Json)
    }
}
