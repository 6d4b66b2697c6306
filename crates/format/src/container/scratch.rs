//! A scratch file: bytes appended through a buffer, read back from the start, removed
//! when dropped (and by [`super::abandon_pending_writes`] if the process dies first).

use std::fs::File;
use std::io::{self, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

use super::atomic::{create_temporary, remove_temporary};

/// Bytes on disk that this process writes and reads back (one section of a merge).
pub(crate) struct Scratch {
    path: PathBuf,
    writer: BufWriter<File>,
    len: u64,
}

impl Scratch {
    /// An empty scratch file in `folder`.
    pub(crate) fn new(folder: &Path) -> io::Result<Self> {
        let (path, file) = create_temporary(folder)?;
        Ok(Self {
            path,
            writer: BufWriter::with_capacity(1 << 16, file),
            len: 0,
        })
    }

    /// Appends `bytes`.
    pub(crate) fn append(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.writer.write_all(bytes)?;
        self.len += bytes.len() as u64;
        Ok(())
    }

    /// Bytes appended so far.
    pub(crate) fn len(&self) -> u64 {
        self.len
    }

    /// A reader from the first byte (after flushing what is buffered).
    pub(crate) fn reader(&mut self) -> io::Result<BufReader<File>> {
        self.writer.flush()?;
        Ok(BufReader::with_capacity(1 << 16, File::open(&self.path)?))
    }

    /// Copies every byte into `out`.
    pub(crate) fn copy_to(&mut self, out: &mut dyn Write) -> io::Result<()> {
        let copied = io::copy(&mut self.reader()?, out)?;
        if copied != self.len {
            return Err(io::Error::other("a scratch file changed size under spatch"));
        }
        Ok(())
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        remove_temporary(&self.path);
    }
}
