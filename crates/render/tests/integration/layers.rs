//! The crate's house: its modules form one layered order with no import
//! circle (issue 21, item 5; the layers are listed at the top of
//! `src/lib.rs` and in docs/architecture.md).
//!
//! Every `crate::` path in the production code of every source file (test
//! modules and test-only files left out, comments stripped) is resolved to
//! the module it names. A module may use a module of a lower layer, or of
//! its own layer, and the uses within each layer must not form a circle.
//! The layers, bottom up: the vocabulary files at the crate root, then the
//! folders `prepare`, `raster`, `plan`, `shade`, `frame`, then `lib.rs`.
//! Paths must name a leaf module (a file), not a folder's `mod.rs` or the
//! crate root, so that no re-export hides an edge.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The folders in layer order, after the root files (layer 0).
const FOLDERS: [&str; 5] = ["prepare", "raster", "plan", "shade", "frame"];

/// A module path: its segments below the crate root (empty for `lib.rs`).
type ModPath = Vec<String>;

/// The layer of a module: 0 for a root file, 1.. for the folders in
/// order, and one past the last folder for `lib.rs`.
fn layer(path: &ModPath) -> usize {
    match path.first() {
        None => FOLDERS.len() + 1,
        Some(top) => FOLDERS.iter().position(|f| f == top).map_or(0, |k| k + 1),
    }
}

/// Every `.rs` file under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src is readable") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The module path of a source file (`lib.rs` → `[]`, `a/mod.rs` → `[a]`,
/// `a/b.rs` → `[a, b]`) and whether it is a folder's `mod.rs`.
fn module_of(src: &Path, file: &Path) -> (ModPath, bool) {
    let rel = file.strip_prefix(src).expect("under src");
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    let last = parts.pop().expect("a file name");
    match last.as_str() {
        "lib" if parts.is_empty() => (parts, true),
        "mod" => (parts, true),
        _ => {
            parts.push(last);
            (parts, false)
        }
    }
}

/// The modules a file declares under `#[cfg(test)]` (`mod x;` after the
/// attribute), which only tests compile.
fn test_only_children(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().map(str::trim).collect();
    lines
        .windows(2)
        .filter(|w| w[0] == "#[cfg(test)]")
        .filter_map(|w| {
            let decl = w[1].trim_start_matches("pub(crate) ");
            decl.strip_prefix("mod ")
                .and_then(|rest| rest.strip_suffix(';'))
                .map(str::to_string)
        })
        .collect()
}

/// The production code of a file: up to its `#[cfg(test)]` test module,
/// each line without its comment.
fn production_code(text: &str) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let end = lines
        .windows(2)
        .position(|w| {
            w[0].trim() == "#[cfg(test)]"
                && w[1].trim_start_matches("pub(crate) ").trim() == "mod tests {"
        })
        .unwrap_or(lines.len());
    lines[..end]
        .iter()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// The paths after every `crate::` and `super::` in `code` (segments of
/// identifiers joined by `::`), and the problems of forms the check cannot
/// read (grouped `crate::{…}` imports, `super::` paths).
fn crate_paths(code: &str) -> (Vec<Vec<String>>, Vec<String>) {
    let (mut paths, mut problems) = (Vec::new(), Vec::new());
    for (marker, relative) in [("crate::", false), ("super::", true)] {
        for (at, _) in code.match_indices(marker) {
            let before = code[..at].chars().next_back();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let rest = &code[at + marker.len()..];
            if relative {
                problems.push(format!("`super::{}`: use a `crate::` path", head(rest)));
                continue;
            }
            if rest.starts_with('{') {
                problems.push(format!("`crate::{}`: one path per `use`", head(rest)));
                continue;
            }
            let mut segments = Vec::new();
            let mut tail = rest;
            loop {
                let len = tail
                    .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .unwrap_or(tail.len());
                if len == 0 {
                    break;
                }
                segments.push(tail[..len].to_string());
                match tail[len..].strip_prefix("::") {
                    Some(next) => tail = next,
                    None => break,
                }
            }
            paths.push(segments);
        }
    }
    (paths, problems)
}

/// The first few characters of `s`, for messages.
fn head(s: &str) -> String {
    s.chars().take(30).collect()
}

/// The module a path names: its longest prefix that is a module.
fn resolve(path: &[String], modules: &BTreeMap<ModPath, bool>) -> ModPath {
    (0..=path.len())
        .rev()
        .map(|n| path[..n].to_vec())
        .find(|prefix| modules.contains_key(prefix))
        .unwrap_or_default()
}

/// A circle in `edges` (module → modules it uses), if any, as the modules
/// along it.
fn find_circle(edges: &BTreeMap<ModPath, BTreeSet<ModPath>>) -> Option<Vec<ModPath>> {
    // 0: unvisited, 1: on the current path, 2: done.
    fn visit(
        m: &ModPath,
        edges: &BTreeMap<ModPath, BTreeSet<ModPath>>,
        state: &mut BTreeMap<ModPath, u8>,
        stack: &mut Vec<ModPath>,
    ) -> Option<Vec<ModPath>> {
        state.insert(m.clone(), 1);
        stack.push(m.clone());
        for next in edges.get(m).into_iter().flatten() {
            match state.get(next).copied().unwrap_or(0) {
                1 => {
                    let from = stack.iter().position(|s| s == next).expect("on the path");
                    let mut circle = stack[from..].to_vec();
                    circle.push(next.clone());
                    return Some(circle);
                }
                0 => {
                    if let Some(c) = visit(next, edges, state, stack) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        stack.pop();
        state.insert(m.clone(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for m in edges.keys() {
        if state.get(m).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(m, edges, &mut state, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

fn name(m: &ModPath) -> String {
    if m.is_empty() {
        "lib".to_string()
    } else {
        m.join("::")
    }
}

#[test]
fn the_circle_finder_finds_a_circle_and_only_a_circle() {
    let m = |s: &str| vec![s.to_string()];
    let mut edges: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
    edges.entry(m("a")).or_default().insert(m("b"));
    edges.entry(m("b")).or_default().insert(m("c"));
    edges.entry(m("a")).or_default().insert(m("c"));
    assert_eq!(find_circle(&edges), None);
    edges.entry(m("c")).or_default().insert(m("a"));
    let circle = find_circle(&edges).expect("a → b → c → a");
    assert_eq!(circle.first(), circle.last());
    assert_eq!(circle.len(), 4);
}

#[test]
fn modules_form_one_layered_order_without_circles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let texts: Vec<(ModPath, bool, String)> = files
        .iter()
        .map(|f| {
            let (path, folder) = module_of(&src, f);
            (path, folder, std::fs::read_to_string(f).expect("readable"))
        })
        .collect();
    // Modules only tests compile.
    let mut test_only: BTreeSet<ModPath> = BTreeSet::new();
    for (path, _, text) in &texts {
        for child in test_only_children(text) {
            let mut p = path.clone();
            p.push(child);
            test_only.insert(p);
        }
    }
    let modules: BTreeMap<ModPath, bool> = texts
        .iter()
        .map(|(p, folder, _)| (p.clone(), *folder))
        .collect();
    let mut problems = Vec::new();
    let mut same_layer: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
    let mut uses = 0;
    for (path, _, text) in &texts {
        if test_only.contains(path) {
            continue;
        }
        let (paths, unreadable) = crate_paths(&production_code(text));
        problems.extend(
            unreadable
                .into_iter()
                .map(|p| format!("{}: {p}", name(path))),
        );
        for used in paths {
            let target = resolve(&used, &modules);
            if target == *path {
                continue;
            }
            uses += 1;
            let shown = format!("{}: crate::{}", name(path), used.join("::"));
            if modules[&target] {
                problems.push(format!(
                    "{shown} names a folder or the crate root, not a file"
                ));
            } else if test_only.contains(&target) {
                problems.push(format!("{shown} names a test-only module"));
            } else if layer(&target) > layer(path) {
                problems.push(format!("{shown} uses a higher layer"));
            } else if layer(&target) == layer(path) {
                same_layer.entry(path.clone()).or_default().insert(target);
            }
        }
    }
    if let Some(circle) = find_circle(&same_layer) {
        let names: Vec<String> = circle.iter().map(name).collect();
        problems.push(format!("import circle: {}", names.join(" → ")));
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // The check read the crate: dozens of modules, hundreds of uses.
    assert!(
        modules.len() > 30 && uses > 150,
        "{} modules, {uses} uses",
        modules.len()
    );
}
