//! Safe file output: a regular file is replaced atomically (a temporary file
//! beside it, `fsync`, rename), so an interrupted run never leaves a truncated
//! file under the output name; anything else is written in place or refused,
//! never replaced.
//!
//! - A symbolic link is written through: the file it names (following every
//!   link in the chain, also a dangling one) is replaced, the link stays.
//! - A FIFO or a character device (`/dev/null`, a terminal, `/dev/stdout`) is
//!   opened and written in place; a block device, a socket or a folder is
//!   refused.
//! - An existing file keeps its permissions (and, where the process may, its
//!   owner and group).
//! - The temporary name is short (`.spatch.PID.N.tmp`), so any valid output
//!   name works; it is removed when the write fails, and
//!   [`abandon_pending_writes`] removes the ones in progress when the process
//!   is about to exit (a signal, a panic). Temporaries left by a process that
//!   no longer runs (killed with `SIGKILL`) are removed by the next write into
//!   the same folder.

use std::fs::{File, Metadata, OpenOptions};
use std::io::{self, ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::FormatError;

/// Temporary files being written by this process, removed by
/// [`abandon_pending_writes`].
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());
/// Makes temporary names unique within the process.
static NEXT_TEMPORARY: AtomicU64 = AtomicU64::new(0);
/// Symbolic links followed before an output is refused as a loop.
const MAX_LINKS: usize = 40;

/// Writes `bytes` to `path` safely (see the module docs): a regular or new
/// file is replaced atomically; a FIFO or character device is written in
/// place. On failure nothing under `path` has changed and the temporary file
/// is gone.
pub fn write_file_atomically(path: &Path, bytes: &[u8]) -> Result<(), FormatError> {
    write_file_atomically_with(path, |out| out.write_all(bytes))
}

/// Like [`write_file_atomically`], with the bytes written by `fill` as it makes them,
/// so a file larger than memory can be written safely.
pub fn write_file_atomically_with(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<(), FormatError> {
    let io_error = |source| FormatError::Io {
        path: path.to_path_buf(),
        source,
    };
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_dir() => Err(io_error(io::Error::from(ErrorKind::IsADirectory))),
        Ok(meta) if meta.is_file() => {
            replace_regular(&resolve_links(path).map_err(io_error)?, fill, Some(&meta))
                .map_err(io_error)
        }
        Ok(meta) => write_special(path, &meta, fill).map_err(io_error),
        Err(e) if e.kind() == ErrorKind::NotFound => {
            replace_regular(&resolve_links(path).map_err(io_error)?, fill, None).map_err(io_error)
        }
        Err(e) => Err(io_error(e)),
    }
}

/// A scratch file of this process in `folder` (named like the atomic writes'
/// temporaries, so [`abandon_pending_writes`] and a later write remove it if the process
/// dies), open for reading and writing. Remove it with [`remove_temporary`].
pub(crate) fn create_temporary(folder: &Path) -> io::Result<(PathBuf, File)> {
    let path = temporary_name(folder);
    let mut pending = lock_pending();
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create_new(true)
        .open(&path)?;
    pending.push(path.clone());
    Ok((path, file))
}

/// Removes a scratch file made by [`create_temporary`].
pub(crate) fn remove_temporary(path: &Path) {
    let _ = std::fs::remove_file(path);
    lock_pending().retain(|p| p != path);
}

fn temporary_name(folder: &Path) -> PathBuf {
    folder.join(format!(
        ".spatch.{}.{}.tmp",
        std::process::id(),
        NEXT_TEMPORARY.fetch_add(1, Ordering::Relaxed)
    ))
}

/// Removes every temporary file this process is writing and blocks any
/// further atomic write, for a process about to exit (on a signal or a
/// panic). Writes already renamed into place are kept.
pub fn abandon_pending_writes() {
    let guard = lock_pending();
    for path in guard.iter() {
        let _ = std::fs::remove_file(path);
    }
    // Keep the lock until the process exits, so no writer creates or renames
    // a temporary file after this point.
    std::mem::forget(guard);
}

fn lock_pending() -> MutexGuard<'static, Vec<PathBuf>> {
    PENDING.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The file a chain of symbolic links ends at (the path itself when it is not
/// a link). The end need not exist.
fn resolve_links(path: &Path) -> io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let target = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(folder) if target.is_relative() => folder.join(target),
                    _ => target,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(io::Error::new(
        ErrorKind::InvalidInput,
        format!("more than {MAX_LINKS} symbolic links in a chain"),
    ))
}

/// Writes into an existing FIFO or character device; refuses other special
/// files.
fn write_special(
    path: &Path,
    meta: &Metadata,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    use std::os::unix::fs::FileTypeExt;
    let kind = meta.file_type();
    if !(kind.is_fifo() || kind.is_char_device()) {
        let what = if kind.is_block_device() {
            "a block device"
        } else if kind.is_socket() {
            "a socket"
        } else {
            "a special file"
        };
        return Err(io::Error::new(
            ErrorKind::InvalidInput,
            format!("is {what}; spatch writes regular files, FIFOs and character devices only"),
        ));
    }
    let mut file = io::BufWriter::new(OpenOptions::new().write(true).open(path)?);
    fill(&mut file)?;
    file.flush()
}

/// Replaces (or creates) the regular file `target` through a temporary file
/// in its folder, giving it the permissions of `existing`.
fn replace_regular(
    target: &Path,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    existing: Option<&Metadata>,
) -> io::Result<()> {
    let folder = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    remove_stale_temporaries(&folder, target);
    let temporary = temporary_name(&folder);
    let result = fill_and_rename(&temporary, target, fill, existing);
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
        lock_pending().retain(|p| p != &temporary);
    }
    result
}

fn fill_and_rename(
    temporary: &Path,
    target: &Path,
    fill: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    existing: Option<&Metadata>,
) -> io::Result<()> {
    let file = {
        // Created under the lock, so abandon_pending_writes sees every file.
        let mut pending = lock_pending();
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(temporary)?;
        pending.push(temporary.to_path_buf());
        file
    };
    let mut buffered = io::BufWriter::new(file);
    fill(&mut buffered)?;
    let file = buffered
        .into_inner()
        .map_err(io::IntoInnerError::into_error)?;
    if let Some(meta) = existing {
        keep_owner_and_mode(&file, meta)?;
    }
    file.sync_all()?;
    drop(file);
    let mut pending = lock_pending();
    std::fs::rename(temporary, target)?;
    pending.retain(|p| p != temporary);
    Ok(())
}

/// Gives the new file the old one's mode, and its owner and group where the
/// process may (root, or a group it belongs to); a refused change of owner is
/// not an error.
fn keep_owner_and_mode(file: &File, old: &Metadata) -> io::Result<()> {
    use std::os::unix::fs::MetadataExt;
    let new = file.metadata()?;
    if new.uid() != old.uid() || new.gid() != old.gid() {
        let _ = std::os::unix::fs::fchown(file, Some(old.uid()), Some(old.gid()));
    }
    file.set_permissions(old.permissions())
}

/// Removes temporary files in `folder` left by processes that no longer run:
/// ours (`.spatch.PID.N.tmp`) and the older form `.NAME.PID.tmp` for this
/// target's name. Does nothing where process ids cannot be checked (no
/// `/proc`).
fn remove_stale_temporaries(folder: &Path, target: &Path) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(folder) else {
        return;
    };
    let old_prefix = target
        .file_name()
        .map(|n| format!(".{}.", n.to_string_lossy()));
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let pid = temporary_pid(&name, old_prefix.as_deref());
        if let Some(pid) = pid {
            let running = Path::new(&format!("/proc/{pid}")).exists();
            if pid != std::process::id() && !running {
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
}

/// The process id in a temporary file name of ours, if `name` is one.
fn temporary_pid(name: &str, old_prefix: Option<&str>) -> Option<u32> {
    let middle = name.strip_suffix(".tmp")?;
    if let Some(rest) = middle.strip_prefix(".spatch.") {
        let (pid, counter) = rest.split_once('.')?;
        counter.parse::<u64>().ok()?;
        return pid.parse().ok();
    }
    let pid = middle.strip_prefix(old_prefix?)?;
    if pid.bytes().all(|b| b.is_ascii_digit()) {
        return pid.parse().ok();
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    #[test]
    fn temporary_names_are_recognized() {
        assert_eq!(temporary_pid(".spatch.123.0.tmp", None), Some(123));
        assert_eq!(temporary_pid(".spatch.123.tmp", None), None);
        assert_eq!(
            temporary_pid(".a.spatch.77.tmp", Some(".a.spatch.")),
            Some(77)
        );
        assert_eq!(temporary_pid(".a.spatch.x7.tmp", Some(".a.spatch.")), None);
        assert_eq!(temporary_pid(".b.spatch.77.tmp", Some(".a.spatch.")), None);
        assert_eq!(temporary_pid("spatch.1.2.tmp", None), None);
    }

    #[test]
    fn a_symlink_is_written_through_and_kept() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().join("real.bin");
        std::fs::write(&real, b"old").unwrap();
        let link = dir.path().join("link.bin");
        std::os::unix::fs::symlink("real.bin", &link).unwrap();
        write_file_atomically(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
    }

    #[test]
    fn a_dangling_symlink_creates_its_target() {
        let dir = tempfile::tempdir().unwrap();
        let link = dir.path().join("link.bin");
        std::os::unix::fs::symlink("made.bin", &link).unwrap();
        write_file_atomically(&link, b"x").unwrap();
        assert_eq!(std::fs::read(dir.path().join("made.bin")).unwrap(), b"x");
    }

    #[test]
    fn an_existing_file_keeps_its_mode() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("secret.bin");
        std::fs::write(&path, b"old").unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o600)).unwrap();
        write_file_atomically(&path, b"new").unwrap();
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600);
    }

    #[test]
    fn a_character_device_is_written_in_place() {
        write_file_atomically(Path::new("/dev/null"), b"bytes").unwrap();
        let meta = std::fs::metadata("/dev/null").unwrap();
        assert!(!meta.is_file());
    }

    #[test]
    fn a_folder_is_refused_and_long_names_work() {
        let dir = tempfile::tempdir().unwrap();
        let err = write_file_atomically(dir.path(), b"x").unwrap_err();
        assert!(err.to_string().contains("directory"), "{err}");
        let long = dir.path().join("n".repeat(253));
        write_file_atomically(&long, b"x").unwrap();
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let dir = tempfile::tempdir().unwrap();
        // Process ids above the kernel's largest (4194304) never run.
        let stale = [".spatch.4194999.0.tmp", ".out.bin.4194998.tmp"];
        for name in stale {
            std::fs::write(dir.path().join(name), b"x").unwrap();
        }
        let ours = format!(".spatch.{}.999.tmp", std::process::id());
        std::fs::write(dir.path().join(&ours), b"x").unwrap();
        std::fs::write(dir.path().join(".other.bin.4194998.tmp"), b"x").unwrap();
        write_file_atomically(&dir.path().join("out.bin"), b"x").unwrap();
        for name in stale {
            assert!(!dir.path().join(name).exists(), "{name} left");
        }
        assert!(dir.path().join(ours).exists());
        assert!(dir.path().join(".other.bin.4194998.tmp").exists());
    }
}
