//! Building the shared JSON report (`spatch_eval::Report`, docs/report-schema.md) from what
//! each command measured.

use serde::Serialize;
use serde_json::{Map, Value};
use spatch_convert::{ConvertReport, EdgeStats, OrientCounts, PrepareCounts, SideCounts};
use spatch_earth::GlobeSummary;
use spatch_eval::{HoleReport, Report, Stages};

use crate::failure::InternalFailure;

/// `spatch <version>`, the report's `tool`.
pub(crate) fn tool() -> String {
    format!("spatch {}", env!("CARGO_PKG_VERSION"))
}

/// A new report of `command` on `input` whose details are filled in later.
pub(crate) fn new_report(command: &str, input: &str) -> Report<Value> {
    Report::new(&tool(), command, input, Value::Object(Map::new()))
}

/// The stages of a library report (a list of `{name, seconds}`) as [`Stages`].
pub(crate) fn stages_from<'a>(list: impl IntoIterator<Item = (&'a str, f64)>) -> Stages {
    let mut stages = Stages::default();
    for (name, seconds) in list {
        stages.push(name, seconds);
    }
    stages
}

/// Keys of the pipelines' own reports (`ConvertReport`, `CloudReport`) that the shared part
/// of the JSON report already holds.
const SHARED_KEYS: [&str; 10] = [
    "patches",
    "nodes",
    "filled_nodes",
    "bytes",
    "seconds",
    "stages",
    "threads",
    "diagonal",
    "warnings",
    "error",
];

/// A library report serialized, without the keys the shared part already holds
/// ([`SHARED_KEYS`]): what is left is the command's `details`.
pub(crate) fn details_from(
    library_report: &impl serde::Serialize,
) -> anyhow::Result<Map<String, Value>> {
    let value = serde_json::to_value(library_report)
        .map_err(|e| InternalFailure(format!("cannot format the report: {e}")))?;
    let Value::Object(mut map) = value else {
        return Err(
            InternalFailure("the report is not a JSON object (this is a bug)".to_owned()).into(),
        );
    };
    for key in SHARED_KEYS {
        map.remove(key);
    }
    Ok(map)
}

/// Inserts `value` (any serializable figure) under `key` in the report's details.
pub(crate) fn set_detail(
    report: &mut Report<Value>,
    key: &str,
    value: &impl serde::Serialize,
) -> anyhow::Result<()> {
    let value = serde_json::to_value(value)
        .map_err(|e| InternalFailure(format!("cannot format the report's {key}: {e}")))?;
    if let Value::Object(map) = &mut report.details {
        map.insert(key.to_owned(), value);
    }
    Ok(())
}

/// The `details` of a mesh conversion's report (`convert`, `earth`, `demo`): the
/// pipeline's own figures, the hole fraction with `--holes`, and the globe for `earth`
/// (docs/report-schema.md).
#[derive(Debug, Clone, Serialize)]
pub(crate) struct ConversionDetails {
    /// Source triangles after preparation.
    pub(crate) triangles: usize,
    /// Regions found by the segmenter.
    pub(crate) regions: usize,
    /// Regions split into several patches.
    pub(crate) split_regions: usize,
    /// Patches with 16-bit displacements.
    pub(crate) wide_patches: usize,
    /// Node spacing used (model units).
    pub(crate) spacing: f32,
    /// Colour channel of the scene.
    pub(crate) colour: &'static str,
    /// What welding and cleaning changed.
    pub(crate) prepare: PrepareCounts,
    /// What winding the pieces outward changed (`null` with `--keep-winding` or for a tile).
    pub(crate) orient: Option<OrientCounts>,
    /// How much texture detail the fit kept (`null` when no region is textured).
    pub(crate) texture: Option<spatch_fit::TextureDetail>,
    /// What the colour grids kept (`null` when no patch has one).
    pub(crate) colour_grids: Option<spatch_convert::ColourGridReport>,
    /// What the sharp-edge stage found and made (`null` when it was off).
    pub(crate) edges: Option<EdgeStats>,
    /// Bytes the edge patches add to the file.
    pub(crate) edge_bytes: usize,
    /// Boundary edges, openings, two-sided patches.
    pub(crate) sides: SideCounts,
    /// The hole fraction, with `--holes`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) holes: Option<Holes>,
    /// What the globe was made of (`earth` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) globe: Option<GlobeSummary>,
}

impl ConversionDetails {
    /// The pipeline's figures of `r`; no holes, no globe.
    pub(crate) fn of(r: &ConvertReport) -> Self {
        Self {
            triangles: r.triangles,
            regions: r.regions,
            split_regions: r.split_regions,
            wide_patches: r.wide_patches,
            spacing: r.spacing,
            colour: r.colour,
            prepare: r.prepare,
            orient: r.orient,
            texture: r.texture,
            colour_grids: r.colour_grids,
            edges: r.edges,
            edge_bytes: r.edge_bytes,
            sides: r.sides,
            holes: None,
            globe: None,
        }
    }
}

/// The hole fraction of a conversion.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub(crate) enum Holes {
    /// `convert --holes`: with the edge patches, and without them when there are any.
    WithAndWithoutEdges {
        /// The whole scene.
        with_edges: HoleReport,
        /// The scene without its edge patches (`null` when it has none).
        without_edges: Option<HoleReport>,
    },
    /// `earth --holes`: the scene against the globe mesh.
    Scene(HoleReport),
}

/// The diagonal of `scene`'s bounding box (the report's `diagonal` for commands that read
/// or build a scene without a source); `None` for a scene without filled nodes.
pub(crate) fn scene_diagonal(scene: &spatch_format::Scene) -> Option<f64> {
    scene.bounds().map(|(lo, hi)| (hi - lo).length())
}
