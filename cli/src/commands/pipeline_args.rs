//! The conversion pipeline's options on the command line, shared by
//! `spatch convert` (whole meshes and plan tiles) and `spatch demo`.

use std::path::PathBuf;

use spatch_convert::{ColourBudget, ConvertOptions, EdgeOptions};
use spatch_fit::{FitOptions, TextureBudget};
use spatch_format::WriteOptions;

use super::ThreadsArg;

/// The pipeline options shared by `spatch convert` and `spatch demo`.
#[derive(Debug, Clone, clap::Args)]
pub(crate) struct PipelineArgs {
    /// Write a JSON report (counts, bytes, stage timings, geometric error; the shape of
    /// docs/report-schema.md) to this file.
    #[arg(long, value_name = "FILE")]
    pub(crate) report: Option<PathBuf>,
    /// Node spacing in model units [default: derived from the source's triangle size]. Thin
    /// parts that give no patch at this spacing are refitted finer; a mesh that still gives
    /// none is refused.
    #[arg(long, value_parser = positive_f32)]
    pub(crate) spacing: Option<f32>,
    /// Largest number of nodes per patch side (2..=257); larger regions are split.
    #[arg(long, default_value_t = FitOptions::DEFAULT_GRID, value_parser = clap::value_parser!(u32).range(2..=257))]
    pub(crate) grid: u32,
    /// Extra rings of nodes each patch reaches into its neighbours.
    #[arg(long, default_value_t = FitOptions::DEFAULT_OVERLAP, value_parser = clap::value_parser!(u32).range(0..=64))]
    pub(crate) overlap: u32,
    /// Steepest tilt in degrees, from a patch's axis, of the faces that may fill its outer
    /// nodes past its region (0-90]. 75 on coarse meshes keeps cells from bridging steep
    /// walls as fins; at sharp creases it leaves the patches ending on the crease, where
    /// patch mode shows more dark specks.
    #[arg(long, value_name = "DEGREES", default_value_t = FitOptions::DEFAULT_MAX_NEIGHBOUR_TILT_DEG, value_parser = up_to_right_angle)]
    pub(crate) max_neighbour_tilt: f32,
    /// Half-angle in degrees of the normal cone of a region (0-89].
    #[arg(long, value_name = "DEGREES", default_value_t = spatch_segment::DEFAULT_CONE_ANGLE_DEG)]
    pub(crate) cone_angle: f32,
    /// Leave colour out even when the source has it.
    #[arg(long, visible_alias = "no-color")]
    pub(crate) no_colour: bool,
    /// Compress node data (grid prediction + range coding).
    #[arg(long)]
    pub(crate) compress: bool,
    /// Skip measuring the geometric error (it can take as long as the conversion).
    #[arg(long)]
    pub(crate) no_error: bool,
    #[command(flatten)]
    pub(crate) threads: ThreadsArg,
    /// Leave out the sharp-edge patches (to compare holes and bytes without them).
    #[arg(long)]
    pub(crate) no_sharp_edges: bool,
    /// Keep the faces' winding as the file has it. By default every connected piece is wound
    /// consistently and facing out (a mesh partly wound inward would show its inside where the
    /// renderer culls back faces), and a file wound mostly inward is drawn from both sides (it
    /// may be an object exported inside out or a room seen from inside)
    #[arg(long)]
    pub(crate) keep_winding: bool,
    /// Angle in degrees between two faces' normals from which their edge is sharp (0-180).
    #[arg(long, value_name = "DEGREES", default_value_t = EdgeOptions::default().crease_angle_deg, value_parser = crease_angle)]
    pub(crate) crease_angle: f32,
    /// Node density of the edge patches relative to the surface patches (1-16).
    #[arg(long, value_name = "FACTOR", default_value_t = EdgeOptions::default().resolution, value_parser = edge_resolution)]
    pub(crate) edge_resolution: f32,
    /// Width of the strip an edge patch covers on each face, in surface node spacings
    /// (0.5-16).
    #[arg(long, value_name = "SPACINGS", default_value_t = EdgeOptions::default().strip_width, value_parser = edge_strip)]
    pub(crate) edge_strip: f32,
    /// How far a crease may stray from an edge patch's straight row of nodes, in edge node
    /// spacings (0-4). Smaller: more, shorter patches on curved creases, whose tips they
    /// follow closely; larger: fewer, longer patches that cut a curved crease's tip by up
    /// to the stray. Patches that see a face more than about 50° obliquely keep a fifth of it.
    #[arg(long, value_name = "SPACINGS", default_value_t = EdgeOptions::default().max_stray, value_parser = edge_max_stray)]
    pub(crate) edge_max_stray: f32,
    /// Largest turn of the two faces' bisector within one edge patch, in degrees (above 0,
    /// at most 90). Smaller: more, shorter patches, each seeing its faces squarely; larger:
    /// fewer patches, but faces seen obliquely may leave holes along steep rims.
    #[arg(long, value_name = "DEGREES", default_value_t = EdgeOptions::default().max_turn_deg, value_parser = up_to_right_angle)]
    pub(crate) edge_max_turn: f32,
    /// Creases under this angle in degrees are soft (0-180, 0 = none): a surface patch that
    /// reaches over one covers it within the corner cut of its cells, so it gets no edge
    /// patch. Lower: more edge patches on coarse tessellations' shallow creases.
    #[arg(long, value_name = "DEGREES", default_value_t = EdgeOptions::default().soft_crease_deg, value_parser = soft_crease)]
    pub(crate) soft_crease: f32,
    /// Put an edge patch on every sharp edge, also where the surface patches already close
    /// the crease (by default only the gaps get one).
    #[arg(long)]
    pub(crate) all_creases: bool,
    /// Keep the edge patch of every piece, also of pieces that the surface patches and the
    /// other edge patches already cover (by default those are dropped, shortest first).
    #[arg(long)]
    pub(crate) keep_covered_pieces: bool,
    /// Give every edge piece a patch of its own (by default pieces that meet at a crease
    /// vertex share one patch where it covers them all: fewer patches, a few more nodes).
    #[arg(long)]
    pub(crate) separate_pieces: bool,
    /// Node spacing of textured regions in texels of their texture (0 = off: textures are
    /// sampled at the mesh's spacing). Smaller keeps finer texture detail for more nodes,
    /// within --texture-budget.
    #[arg(long, value_name = "TEXELS", default_value_t = FitOptions::DEFAULT_TEXELS_PER_NODE, value_parser = non_negative_f32)]
    pub(crate) texels_per_node: f32,
    /// How much textured regions may grow the file: `Nx` (N >= 1) times the nodes of the
    /// texture-blind conversion, or a size in bytes (`2000000`, `500k`, `2M`; estimated at
    /// 4 bytes per node) for all surface nodes. The finest textures give up detail first.
    #[arg(long, value_name = "Nx|BYTES", default_value = "3x", value_parser = texture_budget)]
    pub(crate) texture_budget: TextureBudget,
    /// Texels per sample of the colour grids (0 = none; 1 = one sample per texel, the
    /// default): a textured patch whose nodes are 1.5 samples apart or more gets colour
    /// samples finer than its nodes (2 to 64 per cell side, container 1.2; 1.3 shares them), read by the
    /// renderer at each pixel. Smaller: sharper texture, more bytes, within --colour-budget,
    /// and a slower fit.
    #[arg(long, value_name = "TEXELS", default_value_t = FitOptions::DEFAULT_COLOUR_GRID_TEXELS, value_parser = non_negative_f32)]
    pub(crate) colour_grid: f32,
    /// How many bytes the colour grids may take: `Nx` (N >= 0) times the file without them,
    /// or a size in bytes (`20000`, `500k`, `2M`). Patches that show the same picture share
    /// one grid (stored once, container 1.3). Over the budget, the finest grids are resampled
    /// coarser until the grids fit, down to --colour-floor.
    #[arg(long, value_name = "Nx|BYTES", default_value = "1x", value_parser = colour_budget)]
    pub(crate) colour_budget: ColourBudget,
    /// The least PSNR in dB, against the grids as sampled from the texture (over all their
    /// samples), that --colour-budget may lower the colour grids to; the lowering stops at the
    /// coarsest grids within it, even over the budget (so a small file's texture is not
    /// starved by a ratio). 0: no floor, the budget alone decides. Higher: sharper texture
    /// where the budget binds, more bytes.
    #[arg(long, value_name = "DB", default_value_t = ColourBudget::DEFAULT_FLOOR_DB, value_parser = non_negative_f32)]
    pub(crate) colour_floor: f32,
    /// Measure the hole fraction over 14 views (500 x 500), with and without the edge
    /// patches (28 renders per scene).
    #[arg(long)]
    pub(crate) holes: bool,
}

fn crease_angle(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && v > 0.0 && v < 180.0 {
        Ok(v)
    } else {
        Err("must be between 0 and 180 degrees (exclusive)".to_owned())
    }
}

fn soft_crease(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && (0.0..180.0).contains(&v) {
        Ok(v)
    } else {
        Err("must be at least 0 and below 180 degrees".to_owned())
    }
}

fn edge_resolution(s: &str) -> Result<f32, String> {
    in_range(s, 1.0, 16.0)
}

fn edge_strip(s: &str) -> Result<f32, String> {
    in_range(s, 0.5, 16.0)
}

fn edge_max_stray(s: &str) -> Result<f32, String> {
    in_range(s, 0.0, 4.0)
}

/// An angle above 0 and at most 90 degrees (`--edge-max-turn`, `--max-neighbour-tilt`).
fn up_to_right_angle(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && v > 0.0 && v <= 90.0 {
        Ok(v)
    } else {
        Err("must be above 0 and at most 90 degrees".to_owned())
    }
}

fn in_range(s: &str, low: f32, high: f32) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && (low..=high).contains(&v) {
        Ok(v)
    } else {
        Err(format!("must be between {low} and {high}"))
    }
}

fn non_negative_f32(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err("must be a number >= 0".to_owned())
    }
}

/// Bytes per surface node the byte form of `--texture-budget` assumes: an 8-bit
/// displacement and RGB8 colour.
const BUDGET_BYTES_PER_NODE: u64 = 4;

fn texture_budget(s: &str) -> Result<TextureBudget, String> {
    let t = s.trim();
    if let Some(k) = t.strip_suffix(['x', 'X']) {
        let k: f32 = k.parse().map_err(|e| format!("{e}"))?;
        return if k.is_finite() && k >= 1.0 {
            Ok(TextureBudget::Scale(k))
        } else {
            Err("the scale Nx must have N >= 1".to_owned())
        };
    }
    let bytes = byte_size(t, true)?;
    if !(bytes.is_finite() && bytes > 0.0) {
        return Err("the byte budget must be positive".to_owned());
    }
    Ok(TextureBudget::Nodes(bytes as u64 / BUDGET_BYTES_PER_NODE))
}

/// A size in bytes as the budgets write it: a number with an optional
/// `k` or `m` (and, with `giga`, `g`) suffix, either case.
fn byte_size(t: &str, giga: bool) -> Result<f64, String> {
    let (digits, unit) = match t.char_indices().last() {
        Some((i, 'k' | 'K')) => (&t[..i], 1_000.0),
        Some((i, 'm' | 'M')) => (&t[..i], 1_000_000.0),
        Some((i, 'g' | 'G')) if giga => (&t[..i], 1_000_000_000.0),
        _ => (t, 1.0),
    };
    let v: f64 = digits
        .parse()
        .map_err(|_| "expected Nx (a scale) or a size in bytes such as 500k or 2M".to_owned())?;
    Ok(v * unit)
}

fn colour_budget(s: &str) -> Result<ColourBudget, String> {
    let t = s.trim();
    if let Some(k) = t.strip_suffix(['x', 'X']) {
        let k: f32 = k.parse().map_err(|e| format!("{e}"))?;
        return if k.is_finite() && k >= 0.0 {
            Ok(ColourBudget::Scale(k))
        } else {
            Err("the scale Nx must have N >= 0".to_owned())
        };
    }
    let bytes = byte_size(t, false)?;
    if !(bytes.is_finite() && bytes >= 0.0) {
        return Err("the byte budget must not be negative".to_owned());
    }
    Ok(ColourBudget::Bytes(bytes as u64))
}

fn positive_f32(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err("must be a positive number".to_owned())
    }
}

impl PipelineArgs {
    /// The library options these arguments ask for.
    pub(crate) fn options(&self) -> ConvertOptions {
        let mut options = ConvertOptions::default();
        options.fit.spacing = self.spacing;
        options.fit.grid = self.grid;
        options.fit.overlap = self.overlap;
        options.fit.max_neighbour_tilt_deg = self.max_neighbour_tilt;
        options.fit.colour = !self.no_colour;
        options.fit.texels_per_node = self.texels_per_node;
        options.fit.texture_budget = self.texture_budget;
        options.fit.colour_grid_texels = self.colour_grid;
        options.colour_budget = self.colour_budget;
        options.colour_floor_db = self.colour_floor;
        options.orient = !self.keep_winding;
        options.segment = options.segment.clone().with_cone_angle_deg(self.cone_angle);
        options.write = WriteOptions::with_compression(super::compression(self.compress));
        options.sharp_edges = (!self.no_sharp_edges).then(|| {
            let mut edges = EdgeOptions::default();
            edges.crease_angle_deg = self.crease_angle;
            edges.resolution = self.edge_resolution;
            edges.strip_width = self.edge_strip;
            edges.max_stray = self.edge_max_stray;
            edges.max_turn_deg = self.edge_max_turn;
            edges.soft_crease_deg = self.soft_crease;
            edges.only_gaps = !self.all_creases;
            edges.drop_covered_pieces = !self.keep_covered_pieces;
            edges.join_pieces = !self.separate_pieces;
            edges
        });
        options
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacing_must_be_positive() {
        assert!(positive_f32("0").is_err());
        assert!(positive_f32("nan").is_err());
        assert_eq!(positive_f32("0.5"), Ok(0.5));
    }

    #[test]
    fn tilts_and_turns_are_above_0_and_at_most_90_degrees() {
        for bad in ["0", "-1", "90.01", "nan", "inf", "x"] {
            assert!(up_to_right_angle(bad).is_err(), "{bad}");
        }
        assert_eq!(up_to_right_angle("75"), Ok(75.0));
        assert_eq!(up_to_right_angle("90"), Ok(90.0));
    }

    #[test]
    fn byte_sizes_take_their_units_and_only_the_texture_budget_takes_g() {
        assert_eq!(byte_size("500k", false), Ok(500_000.0));
        assert_eq!(byte_size("2M", false), Ok(2_000_000.0));
        assert_eq!(byte_size("3", false), Ok(3.0));
        assert_eq!(byte_size("1g", true), Ok(1_000_000_000.0));
        assert!(byte_size("1g", false).is_err());
        assert!(byte_size("k", true).is_err());
        assert_eq!(texture_budget("4k"), Ok(TextureBudget::Nodes(1_000)));
        assert_eq!(colour_budget("2M"), Ok(ColourBudget::Bytes(2_000_000)));
        assert!(colour_budget("1G").is_err());
    }
}
