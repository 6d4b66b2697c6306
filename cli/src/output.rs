//! Reading inputs and writing outputs with errors that name the file.

use std::path::Path;

use anyhow::Context;
use spatch_format::{inspect, write_file_atomically, ContainerInfo, Scene};

use crate::failure::InternalFailure;

/// Reads and decodes a `.spatch` file; the error names the file.
pub(crate) fn read_spatch(path: &Path) -> anyhow::Result<(Scene, ContainerInfo)> {
    let bytes = std::fs::read(path).with_context(|| format!("{}: cannot read", path.display()))?;
    inspect(&bytes).with_context(|| format!("{}", path.display()))
}

/// Writes `bytes` to `path` atomically. A missing folder or a refused
/// permission is the user's to fix (exit 2); anything else, such as a full
/// disk, is the system's (exit 1).
pub(crate) fn write_output(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    write_file_atomically(path, bytes).map_err(|e| {
        let user_fixable = matches!(
            &e,
            spatch_format::FormatError::Io { source, .. }
                if matches!(source.kind(), std::io::ErrorKind::NotFound | std::io::ErrorKind::PermissionDenied)
        );
        if user_fixable {
            anyhow::anyhow!("cannot write output {e}")
        } else {
            anyhow::Error::new(InternalFailure(format!("cannot write output {e}")))
        }
    })
}

/// Prints `text` to standard output; a closed pipe surfaces as an
/// `io::Error` of kind `BrokenPipe`, which exits quietly.
pub(crate) fn print_stdout(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())?;
    out.flush()?;
    Ok(())
}

/// Writes a JSON report, pretty-printed with a final newline, atomically.
pub(crate) fn write_json_report(path: &Path, report: &impl serde::Serialize) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(report)
        .map_err(|e| InternalFailure(format!("cannot format the report: {e}")))?;
    text.push('\n');
    write_output(path, text.as_bytes())
}
