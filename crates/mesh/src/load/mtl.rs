//! Wavefront MTL material libraries, as OBJ files name them with `mtllib`.
//!
//! Reads `newmtl`, `Kd` (the base colour), `map_Kd` (the diffuse texture, with its options:
//! `-s` and `-o` are kept as a UV scale and offset, others are reported as ignored), `d` and
//! `Tr` (only to warn that transparency is dropped). The first definition of a name wins.
//! Library and texture names resolve inside the model's folder only.
//!
//! Cost: one pass over each library's text.
//!
//! Based on: the MTL format notes (Wavefront Technologies, *Advanced Visualizer* manual,
//! appendix B2).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::local_reference::resolve_name;
use super::parent_dir;
use crate::error::OutsideReason;
use crate::LoadWarning;

/// A material as the MTL file defines it, before its texture is loaded.
#[derive(Clone, Default)]
pub(super) struct MtlDef {
    /// `Kd`, clamped to `0..=1`.
    pub(super) diffuse: Option<[f32; 3]>,
    /// The `map_Kd` file, resolved inside the library's folder.
    pub(super) texture: Option<PathBuf>,
    /// `map_Kd -s u v`.
    pub(super) uv_scale: [f32; 2],
    /// `map_Kd -o u v`.
    pub(super) uv_offset: [f32; 2],
    /// `d < 1` or `0 < Tr < 1`.
    pub(super) transparent: bool,
}

/// The materials of every library an OBJ named, in definition order.
#[derive(Default)]
pub(super) struct MtlLibrary {
    /// Definitions by name.
    pub(super) defs: HashMap<String, MtlDef>,
    /// Names in the order they were first defined.
    pub(super) order: Vec<String>,
}

impl MtlLibrary {
    /// Reads the libraries an `mtllib` statement names (`rest`: the text after the keyword),
    /// relative to `dir`; unreadable ones become warnings.
    pub(super) fn read_statement(
        &mut self,
        dir: &Path,
        rest: &str,
        warnings: &mut Vec<LoadWarning>,
    ) {
        for lib in library_candidates(dir, rest) {
            let lib = match lib {
                Ok(lib) => lib,
                Err((name, reason)) => {
                    warnings.push(LoadWarning::MissingMaterialLibrary {
                        path: PathBuf::from(name),
                        reason: format!("not read: {reason}"),
                    });
                    continue;
                }
            };
            match std::fs::read(&lib) {
                Ok(text) => parse_mtl(
                    &String::from_utf8_lossy(&text),
                    &parent_dir(&lib),
                    self,
                    warnings,
                ),
                Err(e) => warnings.push(LoadWarning::MissingMaterialLibrary {
                    path: lib,
                    reason: e.to_string(),
                }),
            }
        }
    }
}

/// A library or texture name resolved inside the model's folder, or the name and why it was
/// refused.
type Resolved = Result<PathBuf, (String, OutsideReason)>;

/// The files an `mtllib` statement names: the whole rest of the line if that file exists
/// (names may hold spaces), else each whitespace-separated name; each only inside `dir`.
fn library_candidates(dir: &Path, rest: &str) -> Vec<Resolved> {
    let resolve = |name: &str| resolve_name(dir, name).map_err(|r| (name.to_owned(), r));
    let whole = resolve(rest);
    if whole.as_ref().is_ok_and(|p| p.is_file()) || !rest.contains(char::is_whitespace) {
        return vec![whole];
    }
    rest.split_ascii_whitespace().map(resolve).collect()
}

/// Parses MTL text into `library` (the first definition of a name wins).
fn parse_mtl(text: &str, dir: &Path, library: &mut MtlLibrary, warnings: &mut Vec<LoadWarning>) {
    let mut current: Option<(String, MtlDef)> = None;
    for raw in text.lines() {
        let content = raw.split('#').next().unwrap_or("").trim();
        let mut tokens = content.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        if keyword == "newmtl" {
            library.finish(current.take());
            let name = content["newmtl".len()..].trim().to_owned();
            current = Some((name, MtlDef::new()));
            continue;
        }
        let Some((name, def)) = current.as_mut() else {
            continue;
        };
        let statement = Statement {
            material: name,
            dir,
            warnings,
        };
        statement.apply(keyword, tokens, def);
    }
    library.finish(current.take());
}

impl MtlLibrary {
    /// Adds a definition that `newmtl` (or the end of the text) closed, unless its name is
    /// already defined.
    fn finish(&mut self, current: Option<(String, MtlDef)>) {
        if let Some((name, def)) = current {
            if let std::collections::hash_map::Entry::Vacant(slot) = self.defs.entry(name) {
                self.order.push(slot.key().clone());
                slot.insert(def);
            }
        }
    }
}

impl MtlDef {
    /// A definition as `newmtl` opens it: no colour, no texture, UV scale 1.
    fn new() -> MtlDef {
        MtlDef {
            uv_scale: [1.0; 2],
            ..MtlDef::default()
        }
    }
}

/// Where a statement inside a material definition is read.
struct Statement<'a> {
    /// The name of the material being defined.
    material: &'a str,
    /// The library's folder, which texture names resolve in.
    dir: &'a Path,
    /// Where ignored options and refused textures are reported.
    warnings: &'a mut Vec<LoadWarning>,
}

impl Statement<'_> {
    /// Applies the statement `keyword tokens...` to `def`; unknown keywords are skipped.
    fn apply<'t>(self, keyword: &str, mut tokens: impl Iterator<Item = &'t str>, def: &mut MtlDef) {
        match keyword {
            "Kd" => def.diffuse = diffuse_colour(tokens),
            "d" => {
                if let Some(d) = tokens.next().and_then(|t| t.parse::<f32>().ok()) {
                    def.transparent |= d < 1.0;
                }
            }
            "Tr" => {
                // Tr is 1 - d by the specification, but MeshLab writes `Tr 1` for opaque.
                if let Some(tr) = tokens.next().and_then(|t| t.parse::<f32>().ok()) {
                    def.transparent |= tr > 0.0 && tr < 1.0;
                }
            }
            "map_Kd" => self.diffuse_map(&tokens.collect::<Vec<&str>>(), def),
            _ => {}
        }
    }

    /// Reads `map_Kd` arguments into `def`: the `-s` and `-o` options, then the texture
    /// file; other options are reported as ignored, and a file outside the folder as
    /// unreadable.
    fn diffuse_map(self, args: &[&str], def: &mut MtlDef) {
        let (file, options) = split_texture_options(args);
        for option in options {
            match option.as_slice() {
                [flag, rest @ ..] if *flag == "-s" || *flag == "-o" => {
                    let target = if *flag == "-s" {
                        &mut def.uv_scale
                    } else {
                        &mut def.uv_offset
                    };
                    set_uv_pair(target, rest);
                }
                _ => self.warnings.push(LoadWarning::TextureOptionIgnored {
                    material: self.material.to_owned(),
                    option: option.join(" "),
                }),
            }
        }
        if !file.is_empty() {
            match resolve_name(self.dir, &file) {
                Ok(texture) => def.texture = Some(texture),
                Err(reason) => self.warnings.push(LoadWarning::TextureUnreadable {
                    path: PathBuf::from(&file),
                    reason: format!("not read: {reason}"),
                }),
            }
        }
    }
}

/// The colour of a `Kd` statement's values, clamped to `0..=1`: `Kd r g b`, or one value
/// for grey; anything else (or a value that is not finite) gives none.
fn diffuse_colour<'t>(tokens: impl Iterator<Item = &'t str>) -> Option<[f32; 3]> {
    let v: Vec<f32> = tokens.filter_map(|t| t.parse().ok()).collect();
    let kd = match v.as_slice() {
        [g] => Some([*g; 3]),
        [r, g, b, ..] => Some([*r, *g, *b]),
        _ => None,
    };
    kd.filter(|c| c.iter().all(|x| x.is_finite()))
        .map(|c| c.map(|x| x.clamp(0.0, 1.0)))
}

/// Sets `target` (a UV scale or offset) from the first two numbers of an option's
/// arguments, skipping those that are not finite.
fn set_uv_pair(target: &mut [f32; 2], args: &[String]) {
    let values: Vec<f32> = args.iter().filter_map(|t| t.parse().ok()).collect();
    for (k, v) in values.iter().take(2).enumerate() {
        if v.is_finite() {
            target[k] = *v;
        }
    }
}

/// Splits `map_Kd` arguments into the file name (the tokens after the options, rejoined with
/// spaces) and the options, each as its flag followed by its arguments.
fn split_texture_options(args: &[&str]) -> (String, Vec<Vec<String>>) {
    let mut options = Vec::new();
    let mut i = 0;
    while i < args.len() && args[i].starts_with('-') && args[i].len() > 1 {
        let flag = args[i];
        // Argument counts from the MTL specification; -o, -s and -t take 1 to 3 numbers.
        let (min, max) = match flag {
            "-o" | "-s" | "-t" => (1, 3),
            "-mm" => (2, 2),
            "-blendu" | "-blendv" | "-cc" | "-clamp" | "-bm" | "-boost" | "-texres"
            | "-imfchan" | "-type" => (1, 1),
            _ => (0, 0),
        };
        let mut option = vec![flag.to_owned()];
        i += 1;
        let mut taken = 0;
        while taken < max && i < args.len() {
            let numeric = args[i].parse::<f64>().is_ok();
            // Past the required count, only numbers belong to the option.
            if taken >= min && !numeric {
                break;
            }
            option.push(args[i].to_owned());
            i += 1;
            taken += 1;
        }
        options.push(option);
    }
    (args[i.min(args.len())..].join(" "), options)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_options_are_split_from_the_file_name() {
        let (file, options) =
            split_texture_options(&["-s", "2", "2", "1", "-clamp", "on", "a", "b.png"]);
        assert_eq!(file, "a b.png");
        assert_eq!(
            options,
            vec![vec!["-s", "2", "2", "1"], vec!["-clamp", "on"]]
        );
        let (file, options) = split_texture_options(&["-o", "0.5", "tex.png"]);
        assert_eq!(file, "tex.png");
        assert_eq!(options, vec![vec!["-o", "0.5"]]);
        let (file, options) = split_texture_options(&["plain.png"]);
        assert_eq!(file, "plain.png");
        assert!(options.is_empty());
    }
}
