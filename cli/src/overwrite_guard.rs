//! Refusing, before any work, an output that would destroy an input or
//! another output of the same run, or that cannot be written at all.
//!
//! Files are compared by device and inode after following links, so a hard
//! link, a symbolic link or a different spelling of the input's path is
//! caught. Only regular inputs are compared: a terminal or `/dev/null` named
//! both as input and output is not destroyed by writing.

use std::collections::HashSet;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

use crate::output::is_dash;

/// The files a run reads and the files it writes, as named on the command
/// line (`-` is standard input or output and is never checked).
#[derive(Debug, Default)]
pub(crate) struct Files<'a> {
    /// Files read.
    pub(crate) inputs: Vec<&'a Path>,
    /// Files written (the main output, reports, statistics, extra images).
    pub(crate) outputs: Vec<&'a Path>,
    /// The format of each output whose extension is checked.
    formats: Vec<(&'a Path, Written)>,
    /// `--json` was given: the report goes to standard output, so no output may.
    json_on_stdout: bool,
}

/// The format a command writes to an output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Written {
    /// A `.spatch` container.
    Spatch,
    /// A PNG image.
    Png,
    /// A PLY file.
    Ply,
    /// A Wavefront OBJ file.
    Obj,
    /// A glTF JSON file.
    Gltf,
    /// A binary glTF file.
    Glb,
    /// A TIFF image.
    Tiff,
    /// An OpenEXR image.
    Exr,
    /// A JSON report.
    Json,
    /// CSV rows.
    Csv,
}

impl Written {
    fn name(self) -> &'static str {
        match self {
            Written::Spatch => "a .spatch scene",
            Written::Png => "a PNG image",
            Written::Ply => "a PLY file",
            Written::Obj => "an OBJ file",
            Written::Gltf => "a glTF file",
            Written::Glb => "a binary glTF file",
            Written::Tiff => "a TIFF image",
            Written::Exr => "an OpenEXR image",
            Written::Json => "JSON",
            Written::Csv => "CSV",
        }
    }

    fn extensions(self) -> &'static [&'static str] {
        match self {
            Written::Spatch => &["spatch"],
            Written::Png => &["png"],
            Written::Ply => &["ply"],
            Written::Obj => &["obj"],
            Written::Gltf => &["gltf"],
            Written::Glb => &["glb"],
            Written::Tiff => &["tiff", "tif"],
            Written::Exr => &["exr"],
            Written::Json => &["json"],
            Written::Csv => &["csv"],
        }
    }
}

/// Extensions of formats spatch knows: an output named with one of them
/// must be in that format. Other extensions (and none) are the user's choice.
const KNOWN_EXTENSIONS: [&str; 21] = [
    "spatch", "png", "jpg", "jpeg", "tif", "tiff", "bmp", "gif", "webp", "exr", "ply", "obj",
    "gltf", "glb", "off", "stl", "json", "csv", "svg", "xyz", "pts",
];

/// Refuses an output whose extension names a known format other than the one
/// written (`-o t.jpg` for a PNG).
fn check_extension(path: &Path, format: Written) -> anyhow::Result<()> {
    let Some(ext) = path.extension().and_then(|e| e.to_str()) else {
        return Ok(());
    };
    let ext = ext.to_ascii_lowercase();
    if KNOWN_EXTENSIONS.contains(&ext.as_str()) && !format.extensions().contains(&ext.as_str()) {
        anyhow::bail!(
            "{}: this output is written as {}, but .{ext} names another format; name it .{}",
            path.display(),
            format.name(),
            format.extensions()[0]
        );
    }
    Ok(())
}

impl<'a> Files<'a> {
    /// Adds an input if it is given.
    pub(crate) fn input(mut self, path: Option<&'a Path>) -> Self {
        self.inputs.extend(path);
        self
    }

    /// Adds an output if it is given.
    pub(crate) fn output(mut self, path: Option<&'a Path>) -> Self {
        self.outputs.extend(path);
        self
    }

    /// Adds an output written in `format`, if it is given: its extension
    /// must not name another format.
    pub(crate) fn output_as(mut self, path: Option<&'a Path>, format: Written) -> Self {
        if let Some(path) = path {
            self.outputs.push(path);
            self.formats.push((path, format));
        }
        self
    }

    /// Notes that the run prints its report on standard output (`--json`).
    pub(crate) fn json_on_stdout(mut self, json: bool) -> Self {
        self.json_on_stdout = json;
        self
    }

    /// Refuses the run when an output is a folder, sits in a folder that does
    /// not exist, is the same file as an input, is named twice, has the
    /// extension of another format than the one written, or is standard
    /// output while `--json` prints there.
    pub(crate) fn check(&self) -> anyhow::Result<()> {
        if self.json_on_stdout {
            if let Some(path) = self.outputs.iter().find(|p| crate::output::is_stdout(p)) {
                anyhow::bail!(
                    "{}: --json prints the report on standard output, where this output would go too; \
                     write the output to a file, or leave out --json",
                    path.display()
                );
            }
        }
        let inputs: Vec<(&Path, (u64, u64))> = self
            .inputs
            .iter()
            .filter(|p| !is_dash(p))
            .filter_map(|p| {
                let meta = std::fs::metadata(p).ok().filter(|m| m.is_file())?;
                Some((*p, (meta.dev(), meta.ino())))
            })
            .collect();
        let mut seen = HashSet::new();
        for output in &self.outputs {
            crate::output::claim_stdout_if_named(output);
        }
        for output in self.outputs.iter().filter(|p| !is_dash(p)) {
            let key = output_key(output)?;
            if let OutputKey::Existing(id) = key {
                if let Some((input, _)) = inputs.iter().find(|(_, i)| *i == id) {
                    anyhow::bail!(
                        "{}: is the same file as the input {}; refusing to overwrite it",
                        output.display(),
                        input.display()
                    );
                }
            }
            if !seen.insert(key) {
                anyhow::bail!("{}: named as two outputs of the same run", output.display());
            }
        }
        for (path, format) in &self.formats {
            check_extension(path, *format)?;
        }
        Ok(())
    }
}

/// What identifies an output: an existing file's device and inode, or the
/// canonical folder and name of a file still to be made.
#[derive(Debug, PartialEq, Eq, Hash)]
enum OutputKey {
    Existing((u64, u64)),
    New(PathBuf),
}

fn output_key(output: &Path) -> anyhow::Result<OutputKey> {
    if let Ok(meta) = std::fs::metadata(output) {
        if meta.is_dir() {
            anyhow::bail!("{}: cannot write output: is a directory", output.display());
        }
        return Ok(OutputKey::Existing((meta.dev(), meta.ino())));
    }
    let folder = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let Ok(canonical) = std::fs::canonicalize(folder) else {
        anyhow::bail!(
            "{}: cannot write output: the folder {} does not exist",
            output.display(),
            folder.display()
        );
    };
    let name = output.file_name().unwrap_or(output.as_os_str());
    Ok(OutputKey::New(canonical.join(name)))
}
