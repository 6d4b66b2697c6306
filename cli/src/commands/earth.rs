//! `spatch earth`: the Earth model from a colour map (and an elevation map
//! when given), converted by the mesh pipeline (`spatch_earth::convert_earth`);
//! this file only turns arguments into options and prints.

use std::path::PathBuf;
use std::time::Instant;

use spatch_convert::Conversion;
use spatch_earth::{
    convert_earth, Density, EarthError, EarthOptions, EarthStep, ElevationEncoding,
    ElevationOptions, GlobeSummary, HeightSource, DEFAULT_MAX_MAP_WIDTH,
};
use spatch_eval::{hole_fraction, HoleOptions, HoleReport};
use spatch_format::WriteOptions;

use super::convert::{
    conversion_steps, report_json, show_event, summary, timed_holes, write_and_measure, Measured,
};
use super::ThreadsArg;
use crate::failure::InternalFailure;
use crate::output::{print_json, print_summary, write_json_report};
use crate::progress::Progress;
use crate::report::{ConversionDetails, Holes};

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
    /// Output .spatch file (`-`: standard output).
    #[arg(short, long, value_name = "FILE")]
    output: PathBuf,
    /// Print the report (the --report JSON, docs/report-schema.md) as one object on
    /// standard output instead of the summary; refused with `-o -`.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    threads: ThreadsArg,
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

impl EarthArgs {
    /// The library options these arguments ask for.
    fn options(&self) -> EarthOptions {
        let mut options = EarthOptions::default();
        options.colour = self.colour.clone();
        options.map_width = self.map_width;
        if let Some(path) = &self.elevation {
            let mut elevation = ElevationOptions::default();
            elevation.sea_level = self.sea_level;
            elevation.void = self.void;
            elevation.encoding = match self.elevation_encoding {
                Encoding::Unsigned => ElevationEncoding::Unsigned,
                Encoding::Signed => ElevationEncoding::Signed,
            };
            options.heights = HeightSource::Elevation {
                path: path.clone(),
                options: elevation,
            };
        }
        options.globe.triangles = self.triangles;
        options.globe.exaggeration = self.exaggeration;
        options.density = match self.level {
            Level::Low => Density::Low,
            Level::Medium => Density::Medium,
            Level::High => Density::High,
        };
        options.convert.fit.spacing = self.spacing;
        // The globe's density levels give the original work's patch counts: its colour map
        // is sampled at the level's spacing, neither refined by texels nor given colour grids.
        options.convert.fit.texels_per_node = 0.0;
        options.convert.fit.colour_grid_texels = 0.0;
        options.convert.write = WriteOptions::with_compression(super::compression(self.compress));
        options
    }
}

/// Builds the globe, converts it, writes the scene and the report.
pub(crate) fn run(args: &EarthArgs) -> anyhow::Result<()> {
    args.threads.init()?;
    let options = args.options();
    let progress = Progress::new(
        "earth",
        conversion_steps(EarthStep::BEFORE_CONVERT, args.no_error, args.holes),
    );
    let started = Instant::now();
    let earth =
        convert_earth(&options, &|step| show_earth_step(&progress, step)).map_err(earth_failure)?;
    let finished = write_and_measure(
        &progress,
        earth.conversion,
        &args.output,
        args.no_error,
        started,
    )?;
    let holes = if args.holes {
        Some(timed_holes(&progress, || {
            globe_holes(&finished.conversion)
        })?)
    } else {
        None
    };
    drop(progress);
    let done = Finished {
        measured: finished,
        globe: earth.globe,
        holes,
    };
    report_and_print(args, &options.source_name(), done)
}

/// A written and measured Earth conversion.
struct Finished {
    /// The conversion, its geometric error and times.
    measured: Measured,
    /// What the globe was made of.
    globe: GlobeSummary,
    /// The hole fraction and the seconds it took, when measured.
    holes: Option<(HoleReport, f64)>,
}

/// Shows an Earth pipeline step on the bar.
fn show_earth_step(progress: &Progress, step: EarthStep) {
    match step {
        EarthStep::ColourMap => progress.step("colour map"),
        EarthStep::Heights => progress.step("heights"),
        EarthStep::Globe => progress.step("globe mesh"),
        EarthStep::Convert(event) => show_event(progress, event),
        _ => {}
    }
}

/// Marks spatch's own failures as internal (exit code 1).
fn earth_failure(e: EarthError) -> anyhow::Error {
    if e.is_bug() {
        anyhow::Error::new(InternalFailure(e.to_string()))
    } else {
        anyhow::Error::new(e)
    }
}

/// The hole fraction of the globe's scene against the globe mesh.
fn globe_holes(c: &Conversion) -> anyhow::Result<HoleReport> {
    hole_fraction(&c.scene, &c.mesh, &HoleOptions::default())
        .map_err(|e| InternalFailure(format!("measuring holes failed: {e}")).into())
}

/// Writes the report when asked, prints it with `--json`, and prints the summary.
fn report_and_print(args: &EarthArgs, source_name: &str, done: Finished) -> anyhow::Result<()> {
    let Measured {
        conversion,
        error,
        mut times,
    } = done.measured;
    let mut details = ConversionDetails::of(&conversion.report);
    details.globe = Some(done.globe);
    if let Some((holes, seconds)) = done.holes {
        times.measured.push("holes", seconds);
        details.holes = Some(Holes::Scene(holes));
    }
    let seconds = times.seconds;
    let report = report_json(
        "earth",
        source_name,
        &args.output,
        &conversion,
        error.as_ref(),
        times,
        details,
    );
    if let Some(path) = &args.report {
        write_json_report(path, &report)?;
    }
    if args.json {
        print_json(&report)?;
    }
    let mut text = summary(
        &args.output,
        &conversion,
        error.as_ref(),
        seconds,
        args.report.as_deref(),
    );
    if let Some(Holes::Scene(holes)) = &report.details.holes {
        text.push_str(&globe_holes_line(holes));
    }
    print_summary(
        &format!(
            "{source_name}: {} triangles\n{text}",
            conversion.report.triangles
        ),
        args.json,
    )
}

/// The summary's line on the globe's holes.
fn globe_holes_line(holes: &HoleReport) -> String {
    format!(
        "  holes: {:.4} % of the globe's pixels over {} views ({} of {}; {:.4} % inside the outlines)\n",
        holes.fraction * 100.0,
        holes.views.len(),
        holes.hole_pixels,
        holes.source_pixels,
        holes.interior_fraction * 100.0
    )
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
            .json_on_stdout(self.json)
    }
}
