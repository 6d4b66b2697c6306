//! Reading inputs and writing outputs with errors that name the file.
//! `-` is standard input (for a scene) or standard output (for any output).

use std::io::{Read, Write};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;
use spatch_format::{
    inspect, read_container_bytes, write_file_atomically, ContainerInfo, FormatError, Scene,
};

use crate::failure::InternalFailure;

/// The most bytes read from a scene that is not a regular file (a pipe, a
/// device, `-`): 1 GiB.
pub(crate) const STREAM_LIMIT: u64 = 1 << 30;

/// Reads and decodes a `.spatch` file (`-`: standard input); the error
/// names the file. A regular file is read whole; a pipe or a device only as
/// far as its headers announce, at most [`STREAM_LIMIT`] bytes.
pub(crate) fn read_spatch(path: &Path) -> anyhow::Result<(Scene, ContainerInfo)> {
    let name = || path.display().to_string();
    let bytes = if is_dash(path) {
        read_container_bytes(&mut std::io::stdin().lock(), STREAM_LIMIT).with_context(name)?
    } else {
        let mut file =
            std::fs::File::open(path).with_context(|| format!("{}: cannot read", name()))?;
        let meta = file
            .metadata()
            .with_context(|| format!("{}: cannot read", name()))?;
        if meta.is_dir() {
            anyhow::bail!("{}: cannot read: is a directory", name());
        }
        if meta.is_file() {
            let mut bytes = Vec::new();
            file.read_to_end(&mut bytes)
                .with_context(|| format!("{}: cannot read", name()))?;
            bytes
        } else {
            read_container_bytes(&mut file, STREAM_LIMIT).with_context(name)?
        }
    };
    inspect(&bytes).with_context(name)
}

/// Writes `bytes` to `path` (`-`: standard output) safely (see
/// `spatch_format::write_file_atomically`). What the user can fix (a
/// missing folder, a refused permission, a folder or a device named as the
/// output) exits 2; anything else, such as a full disk, is the system's
/// (exit 1).
pub(crate) fn write_output(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    match standard_stream(path) {
        Some(StandardStream::Out) => return write_stdout(bytes),
        Some(StandardStream::Err) => {
            let mut err = std::io::stderr().lock();
            err.write_all(bytes)?;
            return Ok(err.flush()?);
        }
        None => {}
    }
    write_file_atomically(path, bytes).map_err(write_error)
}

/// The error of a failed output write: what the user can fix (a missing folder, a
/// refused permission, a folder or a device named as the output) exits 2; anything
/// else, such as a full disk, is the system's (exit 1).
pub(crate) fn write_error(e: FormatError) -> anyhow::Error {
    use std::io::ErrorKind as K;
    let user_fixable = matches!(
        &e,
        FormatError::Io { source, .. }
            if matches!(
                source.kind(),
                K::NotFound
                    | K::PermissionDenied
                    | K::IsADirectory
                    | K::NotADirectory
                    | K::InvalidInput
                    | K::ReadOnlyFilesystem
                    | K::InvalidFilename
            )
    );
    if user_fixable {
        anyhow::anyhow!("cannot write output {e}")
    } else {
        anyhow::Error::new(InternalFailure(format!("cannot write output {e}")))
    }
}

/// Set when an output file is standard output: the human summary then goes
/// to standard error, so it does not mix with the output's bytes.
static STDOUT_IS_AN_OUTPUT: AtomicBool = AtomicBool::new(false);

/// Notes that `path`, an output of this run, is standard output if it is.
pub(crate) fn claim_stdout_if_named(path: &Path) {
    if matches!(standard_stream(path), Some(StandardStream::Out)) {
        STDOUT_IS_AN_OUTPUT.store(true, Ordering::Relaxed);
    }
}

/// Whether `path` is `-` (standard input or output).
pub(crate) fn is_dash(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Whether `path` names this process's standard output (`-`, `/dev/stdout`, …).
pub(crate) fn is_stdout(path: &Path) -> bool {
    matches!(standard_stream(path), Some(StandardStream::Out))
}

/// Standard output or standard error named as an output path.
enum StandardStream {
    Out,
    Err,
}

/// Whether `path` names this process's standard output (`-`, `/dev/stdout`,
/// `/dev/fd/1`, `/proc/self/fd/1`) or standard error. They are written
/// through the process's own streams, so a shell redirection (`> file`,
/// `>> file`) keeps its file and its position instead of seeing the file
/// replaced under it.
fn standard_stream(path: &Path) -> Option<StandardStream> {
    let name = path.to_str()?;
    match name {
        "-" | "/dev/stdout" | "/dev/fd/1" | "/proc/self/fd/1" => Some(StandardStream::Out),
        "/dev/stderr" | "/dev/fd/2" | "/proc/self/fd/2" => Some(StandardStream::Err),
        _ => None,
    }
}

/// Writes raw bytes to standard output; a closed pipe surfaces as an
/// `io::Error` of kind `BrokenPipe`, which exits quietly.
pub(crate) fn write_stdout(bytes: &[u8]) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)?;
    out.flush()?;
    Ok(())
}

/// Prints `text` to standard output (see [`write_stdout`]), or to standard
/// error when an output file of this run is standard output.
pub(crate) fn print_stdout(text: &str) -> anyhow::Result<()> {
    if STDOUT_IS_AN_OUTPUT.load(Ordering::Relaxed) {
        let mut err = std::io::stderr().lock();
        err.write_all(text.as_bytes())?;
        return Ok(err.flush()?);
    }
    write_stdout(text.as_bytes())
}

/// Prints the human summary of a run (see [`print_stdout`]), unless the run
/// is quiet (`-q`) or prints its report as JSON instead (`--json`).
pub(crate) fn print_summary(text: &str, json: bool) -> anyhow::Result<()> {
    if json || crate::progress::is_quiet() {
        return Ok(());
    }
    print_stdout(text)
}

/// Prints a report as one pretty-printed JSON object on standard output
/// (`--json`).
pub(crate) fn print_json(report: &impl serde::Serialize) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(report)
        .map_err(|e| InternalFailure(format!("cannot format the report: {e}")))?;
    text.push('\n');
    write_stdout(text.as_bytes())
}

/// Writes a JSON report, pretty-printed with a final newline, atomically.
pub(crate) fn write_json_report(path: &Path, report: &impl serde::Serialize) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(report)
        .map_err(|e| InternalFailure(format!("cannot format the report: {e}")))?;
    text.push('\n');
    write_output(path, text.as_bytes())
}

/// A scene written by [`encode_and_write`]: its size and the time of each step.
pub(crate) struct SceneWritten {
    /// Bytes of the container.
    pub(crate) bytes: usize,
    /// Seconds spent encoding.
    pub(crate) encode_seconds: f64,
    /// Seconds spent writing.
    pub(crate) write_seconds: f64,
}

/// Encodes `scene` with `options` and writes it to `path` (`-`: standard
/// output), as the progress steps "encode" and "write".
pub(crate) fn encode_and_write(
    progress: &crate::progress::Progress,
    scene: &Scene,
    options: &spatch_format::WriteOptions,
    path: &Path,
) -> anyhow::Result<SceneWritten> {
    progress.step("encode");
    let started = std::time::Instant::now();
    let bytes = spatch_format::encode_scene(scene, options)?;
    let encode_seconds = started.elapsed().as_secs_f64();
    progress.step("write");
    let started = std::time::Instant::now();
    write_output(path, &bytes)?;
    Ok(SceneWritten {
        bytes: bytes.len(),
        encode_seconds,
        write_seconds: started.elapsed().as_secs_f64(),
    })
}
