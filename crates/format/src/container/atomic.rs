//! Atomic file output: write a temporary file beside the target, flush it to
//! disk, then rename it over the target, so an interrupted run never leaves a
//! truncated file under the output name.

use std::io::Write;
use std::path::Path;

use crate::FormatError;

/// Writes `bytes` to `path` atomically (temporary file in the same folder,
/// `fsync`, rename). On failure the temporary file is removed and `path` is
/// untouched.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<(), FormatError> {
    let io_error = |source| FormatError::Io {
        path: path.to_path_buf(),
        source,
    };
    let folder = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".to_owned());
    let temporary = folder.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| {
        let mut file = std::fs::File::create(&temporary)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temporary, path)
    })();
    if let Err(source) = result {
        let _ = std::fs::remove_file(&temporary);
        return Err(io_error(source));
    }
    Ok(())
}
