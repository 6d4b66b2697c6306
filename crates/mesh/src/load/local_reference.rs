//! Resolving a file reference written inside a model (a glTF buffer or image URI, an OBJ
//! `mtllib` or texture name) to a path inside the model's folder.
//!
//! Model files are untrusted: a reference may only name a file at or below the folder that
//! holds the model. Absolute paths (`/etc/passwd`, `C:\x`, `\\server\share`, `file:` URIs)
//! and any `..` component are refused ([`OutsideReason`]), whatever the file system would
//! make of them; so are URI schemes other than `data:` (`http:`, ...), which no reader here
//! fetches. glTF URIs are percent-decoded first (`%20` is a space), as the specification
//! requires; OBJ names are taken as written. Backslashes count as separators (Windows
//! exporters write them).
//!
//! Cost: O(length of the reference).
//!
//! Based on: RFC 3986 (URI syntax, percent-encoding); glTF 2.0 specification section 3.6.1.

use std::path::{Path, PathBuf};

use crate::error::OutsideReason;

/// Resolves a glTF URI (not a `data:` one) against `base`, the model's folder.
pub(crate) fn resolve_uri(base: &Path, uri: &str) -> Result<PathBuf, OutsideReason> {
    if has_scheme(uri) {
        return Err(
            if uri
                .get(..5)
                .is_some_and(|s| s.eq_ignore_ascii_case("file:"))
            {
                OutsideReason::Absolute
            } else {
                OutsideReason::UnsupportedScheme
            },
        );
    }
    let decoded = percent_decode(uri).ok_or(OutsideReason::BadEncoding)?;
    resolve_name(base, &decoded)
}

/// Resolves a plain relative file name (an OBJ `mtllib` or `map_Kd`) against `base`.
pub(crate) fn resolve_name(base: &Path, name: &str) -> Result<PathBuf, OutsideReason> {
    if name.is_empty() {
        return Err(OutsideReason::Empty);
    }
    let bytes = name.as_bytes();
    let drive = bytes.len() >= 2 && bytes[0].is_ascii_alphabetic() && bytes[1] == b':';
    if name.starts_with('/') || name.starts_with('\\') || drive {
        return Err(OutsideReason::Absolute);
    }
    let mut out = base.to_path_buf();
    for part in name.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => return Err(OutsideReason::ParentComponent),
            _ => out.push(part),
        }
    }
    Ok(out)
}

/// Whether `uri` starts with a URI scheme (`letters:`), beyond a one-letter Windows drive.
fn has_scheme(uri: &str) -> bool {
    match uri.find(':') {
        Some(colon) if colon >= 2 => {
            let scheme = &uri[..colon];
            scheme.starts_with(|c: char| c.is_ascii_alphabetic())
                && scheme
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
        }
        _ => false,
    }
}

/// Decodes `%XX` escapes; `None` when one is malformed or the result is not UTF-8.
fn percent_decode(text: &str) -> Option<String> {
    let bytes = text.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes.get(i + 1..i + 3)?;
            let hex = std::str::from_utf8(hex).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_names_resolve_inside_the_folder() {
        let base = Path::new("/models/car");
        assert_eq!(
            resolve_uri(base, "textures/paint%20red.png"),
            Ok(PathBuf::from("/models/car/textures/paint red.png"))
        );
        assert_eq!(
            resolve_name(base, "./maps\\wood.jpg"),
            Ok(PathBuf::from("/models/car/maps/wood.jpg"))
        );
    }

    #[test]
    fn escapes_are_refused() {
        let base = Path::new("m");
        let cases = [
            ("/etc/passwd", OutsideReason::Absolute),
            ("file:///etc/passwd", OutsideReason::Absolute),
            ("C:\\Windows\\x.bin", OutsideReason::Absolute),
            ("\\\\server\\share\\x.bin", OutsideReason::Absolute),
            ("../secret.bin", OutsideReason::ParentComponent),
            ("a/../../b.bin", OutsideReason::ParentComponent),
            ("%2e%2e/b.bin", OutsideReason::ParentComponent),
            ("%2Fetc/passwd", OutsideReason::Absolute),
            (
                "https://example.com/a.bin",
                OutsideReason::UnsupportedScheme,
            ),
            ("a%zz.bin", OutsideReason::BadEncoding),
            ("a%ff.bin", OutsideReason::BadEncoding),
            ("", OutsideReason::Empty),
        ];
        for (uri, reason) in cases {
            assert_eq!(resolve_uri(base, uri), Err(reason), "{uri}");
        }
    }
}
