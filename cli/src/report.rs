//! Building the shared JSON report (`spatch_eval::Report`, docs/report-schema.md) from what
//! each command measured.

use serde_json::{Map, Value};
use spatch_eval::{Report, Stages};

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
