//! `spatch stats`: what a .spatch file holds.

use std::path::PathBuf;

use serde_json::{json, Map, Value};
use spatch_format::{ContainerInfo, Scene, SceneSummary};

use crate::output::{print_stdout, read_spatch};

/// Arguments of `spatch stats`.
#[derive(Debug, clap::Args)]
pub(crate) struct StatsArgs {
    /// Input .spatch file (`-`: standard input; a pipe or a device is read only as far as
    /// its headers announce, at most 1 GiB).
    #[arg(value_name = "FILE")]
    input: PathBuf,
    /// Print one JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

fn codec_name(codec: u8) -> &'static str {
    match codec {
        0 => "raw",
        1 => "predictive",
        _ => "unknown",
    }
}

/// Patches per visible sides: front only, through openings, both.
fn side_counts(scene: &Scene) -> [usize; 3] {
    let mut counts = [0; 3];
    for p in scene.patches() {
        counts[usize::from(p.sides().code())] += 1;
    }
    counts
}

/// What says where a scene's backs show: patches per sides, openings and the inside box.
fn visibility_json(scene: &Scene) -> Value {
    let [front, through_openings, both] = side_counts(scene);
    let inside_box = scene
        .inside_box()
        .map(|b| json!({ "min": b.min().to_array(), "max": b.max().to_array() }));
    json!({
        "front": front,
        "through_openings": through_openings,
        "both": both,
        "openings": scene.openings().len(),
        "inside_box": inside_box,
    })
}

/// The table row of [`visibility_json`].
fn visibility_row(scene: &Scene) -> String {
    let [front, through, both] = side_counts(scene);
    let mut text = format!(
        "front {front}, through openings {through}, both {both}; {} openings",
        scene.openings().len()
    );
    if let Some(b) = scene.inside_box() {
        let (lo, hi) = (b.min(), b.max());
        text.push_str(&format!(
            "; both only from inside {:.6} {:.6} {:.6} .. {:.6} {:.6} {:.6} (offset-relative)",
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        ));
    }
    text
}

fn to_json(path: &str, scene: &Scene, info: &ContainerInfo, s: &SceneSummary) -> Value {
    let mut sections = Map::new();
    for section in &info.sections {
        sections.insert(
            section.tag.clone(),
            json!({ "raw": section.raw_len, "stored": section.stored_len, "codec": codec_name(section.codec) }),
        );
    }
    let bits: Map<String, Value> = s
        .displacement_bits
        .iter()
        .map(|(b, n)| (b.to_string(), json!(n)))
        .collect();
    let grids: Map<String, Value> = s
        .grids
        .iter()
        .map(|(g, n)| (g.to_string(), json!(n)))
        .collect();
    let bounds = s
        .bounds
        .map(|(lo, hi)| json!({ "min": lo.to_array(), "max": hi.to_array() }));
    let lengths = s.frame_lengths.map(|[x, y, z]| {
        json!({
            "ax": { "min": x.min, "max": x.max },
            "ay": { "min": y.min, "max": y.max },
            "az": { "min": z.min, "max": z.max },
        })
    });
    json!({
        "file": path,
        "version": format!("{}.{}", info.version_major, info.version_minor),
        "patches": s.patches,
        "nodes": s.nodes,
        "filled_nodes": s.filled_nodes,
        "drawable_cells": s.drawable_cells,
        "bytes": info.file_len,
        "sections": sections,
        "colour": scene.channel().name(),
        "flat_colour": info.flat_colour,
        "displacement_bits": bits,
        "displacement_bits_per_node": s.displacement_bits_per_node,
        "colour_bits_per_node": s.colour_bits_per_node,
        "grid": grids,
        "offset": scene.offset().to_array(),
        "bounds": bounds,
        "frame_lengths": lengths,
        "sides": visibility_json(scene),
    })
}

fn table(path: &str, scene: &Scene, info: &ContainerInfo, s: &SceneSummary) -> String {
    let mut t = format!(
        "{path}  (spatch {}.{})\n",
        info.version_major, info.version_minor
    );
    let mut row = |k: &str, v: String| t.push_str(&format!("  {k:<22} {v}\n"));
    count_rows(&mut row, scene, info, s);
    precision_rows(&mut row, s);
    extent_rows(&mut row, scene, s);
    t.push_str(&section_lines(info));
    t
}

/// The table's rows of counts: patches, nodes, bytes and colour.
fn count_rows(
    row: &mut impl FnMut(&str, String),
    scene: &Scene,
    info: &ContainerInfo,
    s: &SceneSummary,
) {
    row("patches", s.patches.to_string());
    row(
        "nodes",
        format!(
            "{} ({} filled, {} drawable cells)",
            s.nodes, s.filled_nodes, s.drawable_cells
        ),
    );
    row("bytes", info.file_len.to_string());
    row(
        "colour",
        format!(
            "{}{}",
            scene.channel().name(),
            if info.flat_colour {
                " (one flat colour)"
            } else {
                ""
            }
        ),
    );
}

/// The table's rows of precision: displacement widths, grids and bits per node.
fn precision_rows(row: &mut impl FnMut(&str, String), s: &SceneSummary) {
    let bits: Vec<String> = s
        .displacement_bits
        .iter()
        .map(|(b, n)| format!("{b}-bit: {n}"))
        .collect();
    row("displacement widths", bits.join(", "));
    let grids: Vec<String> = s.grids.iter().map(|(g, n)| format!("{g}: {n}")).collect();
    row("grids", grids.join(", "));
    row(
        "bits per node",
        format!(
            "{:.3} displacement, {:.3} colour",
            s.displacement_bits_per_node, s.colour_bits_per_node
        ),
    );
}

/// The table's rows of extent: bounds, frame lengths and the sides that may show.
fn extent_rows(row: &mut impl FnMut(&str, String), scene: &Scene, s: &SceneSummary) {
    if let Some((lo, hi)) = s.bounds {
        row("bounds min", format!("{:.6} {:.6} {:.6}", lo.x, lo.y, lo.z));
        row("bounds max", format!("{:.6} {:.6} {:.6}", hi.x, hi.y, hi.z));
    }
    if let Some(lengths) = s.frame_lengths {
        for (name, r) in ["|ax|", "|ay|", "|az|"].iter().zip(lengths) {
            row(name, format!("{:.6} .. {:.6}", r.min, r.max));
        }
    }
    row("sides", visibility_row(scene));
}

/// The table's sections, one line each: tag, codec, stored and raw bytes.
fn section_lines(info: &ContainerInfo) -> String {
    let mut t = String::from("  sections (tag codec stored raw):\n");
    for section in &info.sections {
        t.push_str(&format!(
            "    {} {:<10} {:>10} {:>10}\n",
            section.tag,
            codec_name(section.codec),
            section.stored_len,
            section.raw_len
        ));
    }
    t
}

/// Reads the file and prints the summary.
pub(crate) fn run(args: &StatsArgs) -> anyhow::Result<()> {
    let (scene, info) = read_spatch(&args.input)?;
    let summary = SceneSummary::new(&scene, &info);
    let text = if args.json {
        let value = to_json(&args.input.display().to_string(), &scene, &info, &summary);
        format!("{}\n", serde_json::to_string_pretty(&value)?)
    } else {
        table(&args.input.display().to_string(), &scene, &info, &summary)
    };
    print_stdout(&text)
}

impl StatsArgs {
    /// The files this run reads and writes, checked before any work.
    pub(crate) fn files(&self) -> crate::overwrite_guard::Files<'_> {
        crate::overwrite_guard::Files::default().input(Some(&self.input))
    }
}
