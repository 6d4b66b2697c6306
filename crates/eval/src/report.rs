//! The JSON report every producing or measuring command writes (`convert`, `from-cloud`,
//! `earth`, `eval`), in one shape (docs/report-schema.md).
//!
//! The shared part says what was read and written, how big the result is, where the time
//! went and how far the result is from its source; the command's own figures go under
//! [`Report::details`]. A reader that knows only this module can compare any two reports:
//! `counts`, `seconds`, `stages`, `threads`, `diagonal` and `error` mean the same everywhere.
//!
//! Stage maps keep the order the stages ran in (a JSON object written in that order); the
//! error map is sorted by name.

use std::collections::BTreeMap;

use serde::de::{Deserializer, MapAccess, Visitor};
use serde::ser::{SerializeMap, Serializer};
use serde::{Deserialize, Serialize};

pub use spatch_report::Counts;

use crate::geometric::ErrorStats;

/// The version of the report shape, written as `schema`. Raised when a shared key changes
/// meaning or goes away (adding keys does not raise it).
pub const REPORT_SCHEMA: u32 = 1;

/// One command's report: the shared keys and the command's `details`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Report<D> {
    /// [`REPORT_SCHEMA`].
    pub schema: u32,
    /// The program and its version, e.g. `spatch 0.1.0`.
    pub tool: String,
    /// The subcommand: `convert`, `from-cloud`, `earth` or `eval`.
    pub command: String,
    /// What was read: a file path, or a description of a generated input.
    pub input: String,
    /// The main file written, or `None` when the command wrote none.
    pub output: Option<String>,
    /// Sizes of the scene.
    pub counts: Counts,
    /// Wall time of the work in `stages` (seconds), measurement excluded.
    pub seconds: f64,
    /// Each stage of the work, in the order it ran.
    pub stages: Stages,
    /// Wall time spent measuring error (seconds); 0 when nothing was measured.
    pub measure_seconds: f64,
    /// Each measurement, in the order it ran.
    pub measure_stages: Stages,
    /// Worker threads available to the parallel stages.
    pub threads: usize,
    /// The source's bounding-box diagonal (model units): the scale of every `*_rel` figure;
    /// `None` when no source was measured.
    pub diagonal: Option<f64>,
    /// Named one-way errors (`node_to_surface`, `surface_to_patch`, `cloud_to_patch`,
    /// `node_to_cloud`); empty when the error was not measured.
    pub error: BTreeMap<String, ErrorStats>,
    /// What the readers and the pipeline worked around, as sentences.
    pub warnings: Vec<String>,
    /// The command's own figures.
    pub details: D,
}

impl<D> Report<D> {
    /// A report of `command` on `input` with every figure empty, to be filled in.
    pub fn new(tool: &str, command: &str, input: &str, details: D) -> Self {
        Self {
            schema: REPORT_SCHEMA,
            tool: tool.to_owned(),
            command: command.to_owned(),
            input: input.to_owned(),
            output: None,
            counts: Counts::default(),
            seconds: 0.0,
            stages: Stages::default(),
            measure_seconds: 0.0,
            measure_stages: Stages::default(),
            threads: 0,
            diagonal: None,
            error: BTreeMap::new(),
            warnings: Vec::new(),
            details,
        }
    }
}

/// Stage names and their wall times in seconds, in the order they ran; serialized as a JSON
/// object whose keys keep that order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stages(pub Vec<(String, f64)>);

impl Stages {
    /// Appends a stage.
    pub fn push(&mut self, name: &str, seconds: f64) {
        self.0.push((name.to_owned(), seconds));
    }

    /// The seconds of the stage called `name`, if it ran.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, s)| *s)
    }

    /// The sum of all stages.
    pub fn total(&self) -> f64 {
        self.0.iter().map(|(_, s)| s).sum()
    }

    /// Stage names in order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.0.iter().map(|(n, _)| n.as_str())
    }
}

impl Serialize for Stages {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, seconds) in &self.0 {
            map.serialize_entry(name, seconds)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for Stages {
    fn deserialize<De: Deserializer<'de>>(deserializer: De) -> Result<Self, De::Error> {
        struct StagesVisitor;
        impl<'de> Visitor<'de> for StagesVisitor {
            type Value = Stages;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an object of stage names to seconds")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut access: A) -> Result<Stages, A::Error> {
                let mut stages = Vec::new();
                while let Some((name, seconds)) = access.next_entry::<String, f64>()? {
                    stages.push((name, seconds));
                }
                Ok(Stages(stages))
            }
        }
        deserializer.deserialize_map(StagesVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stages_keep_their_order_through_json() {
        let mut stages = Stages::default();
        stages.push("load", 0.5);
        stages.push("fit", 0.25);
        stages.push("encode", 0.125);
        let text = serde_json::to_string(&stages).unwrap();
        assert_eq!(text, r#"{"load":0.5,"fit":0.25,"encode":0.125}"#);
        let back: Stages = serde_json::from_str(&text).unwrap();
        assert_eq!(back, stages);
        assert_eq!(back.total(), 0.875);
        assert_eq!(back.get("fit"), Some(0.25));
        assert_eq!(back.get("edges"), None);
    }

    #[test]
    fn a_report_round_trips_with_an_infinite_error() {
        let mut report = Report::new("spatch 0", "eval", "a.spatch", serde_json::json!({"k": 1}));
        report.error.insert(
            "surface_to_patch".to_owned(),
            ErrorStats::from_distances(&mut [f32::INFINITY, 1.0], 2.0),
        );
        let text = serde_json::to_string(&report).unwrap();
        let back: Report<serde_json::Value> = serde_json::from_str(&text).unwrap();
        assert!(back.error["surface_to_patch"].max.is_infinite());
        assert_eq!(back.details["k"], 1);
        assert_eq!(back.schema, REPORT_SCHEMA);
    }
}
