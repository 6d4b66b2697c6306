//! Wavefront OBJ reader with MTL materials and diffuse textures.
//!
//! Reads `v` (with optional `r g b` vertex colours), `vt`, `vn`, `f` (any of `v`, `v/vt`,
//! `v//vn`, `v/vt/vn`; negative indices count back from the latest element), `usemtl` and
//! `mtllib`; other statements (`o`, `g`, `s`, `l`, `p`, ...) are skipped. Lines ending in `\`
//! continue on the next line. Positions are parsed as f64.
//!
//! Materials: `Kd` becomes the base colour; `map_Kd` loads a texture (PNG/JPEG/TIFF) and, when
//! it loads, the base colour becomes white (the texture replaces `Kd`, as Blender and most
//! viewers show it). Texture options `-s` and `-o` are applied to the UVs of that material's
//! faces; other options are ignored with a [`LoadWarning::TextureOptionIgnored`].
//! Transparency (`d`, `Tr`) is ignored: spatch stores opaque colour, and MeshLab writes
//! `Tr 1.0` meaning opaque while the MTL specification reads it as invisible.
//!
//! Fallbacks, each with a warning: a missing MTL file or texture leaves the faces uncoloured;
//! an undefined material is white; an OBJ with UVs but no `mtllib` whose folder holds exactly
//! one image named like the OBJ (`<stem>.png`, `<stem>.jpg`, ...) or `*_texture.*` takes that
//! image as its texture (Keenan Crane's `spot` ships that way).
//!
//! Per-corner data: UVs stay per face corner ([`TriangleMesh::face_uvs`](crate::TriangleMesh::face_uvs)); normals, given per
//! corner in OBJ, become per-vertex normals by averaging a vertex's corner normals (only when
//! every corner has one).
//!
//! Cost: one pass over the text, O(file size) time and memory.
//!
//! Based on: the OBJ and MTL format notes (Wavefront Technologies, *Advanced Visualizer*
//! manual, appendices B1 and B2).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};

use super::local_reference::resolve_name;
use super::texture::load_texture_file;
use super::{parent_dir, read_file, unit_to_byte, LoadedMesh, MeshBuilder};
use crate::error::{Element, ElementKind, OutsideReason, SyntaxProblem};
use crate::{LoadWarning, Material, MaterialId, MeshError, Texture};

/// One face corner: indices into the file's position, UV and normal lists.
#[derive(Clone, Copy)]
struct Corner {
    v: u32,
    vt: Option<u32>,
    vn: Option<u32>,
}

/// A material as the MTL file defines it, before its texture is loaded.
#[derive(Clone, Default)]
struct MtlDef {
    diffuse: Option<[f32; 3]>,
    texture: Option<PathBuf>,
    uv_scale: [f32; 2],
    uv_offset: [f32; 2],
    transparent: bool,
}

/// Loads an OBJ file and the materials and textures it names.
pub fn load_obj(path: &Path) -> Result<LoadedMesh, MeshError> {
    let bytes = read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let text = super::strip_bom(&text);
    let dir = parent_dir(path);
    let err = |line: usize, problem| MeshError::Syntax {
        path: path.to_path_buf(),
        line,
        problem,
    };

    let mut warnings = Vec::new();
    let mut positions: Vec<DVec3> = Vec::new();
    let mut colours: Vec<[u8; 4]> = Vec::new();
    let mut texcoords: Vec<Vec2> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut corners: Vec<[Corner; 3]> = Vec::new();
    let mut face_material: Vec<Option<u32>> = Vec::new();
    let mut used_materials: Vec<String> = Vec::new();
    let mut used_index: HashMap<String, u32> = HashMap::new();
    let mut library: HashMap<String, MtlDef> = HashMap::new();
    let mut library_order: Vec<String> = Vec::new();
    let mut saw_mtllib = false;
    let mut current_material: Option<u32> = None;
    let mut face_count: u64 = 0;
    let mut fanned: u64 = 0;
    let mut coloured: usize = 0;
    let mut polygon: Vec<Corner> = Vec::new();

    let mut logical = String::new();
    for (line_index, raw) in text.lines().enumerate() {
        let line_no = line_index + 1;
        if let Some(stripped) = raw.strip_suffix('\\') {
            logical.push_str(stripped);
            logical.push(' ');
            continue;
        }
        logical.push_str(raw);
        let line = std::mem::take(&mut logical);
        let content = line.split('#').next().unwrap_or("");
        let mut tokens = content.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        match keyword {
            "v" => {
                let values = parse_numbers(tokens, line_no, path)?;
                if values.len() < 3 {
                    return Err(err(
                        line_no,
                        SyntaxProblem::TooFewValues {
                            expected: 3,
                            found: values.len(),
                        },
                    ));
                }
                let p = DVec3::new(values[0], values[1], values[2]);
                if !p.is_finite() {
                    return Err(MeshError::NonFinite {
                        path: path.to_path_buf(),
                        element: Element::Vertex(positions.len() as u64),
                    });
                }
                // `v x y z r g b` (6 or 7 values) carries a vertex colour in 0..1.
                if values.len() >= 6 {
                    coloured += 1;
                    colours.resize(positions.len(), [255; 4]);
                    colours.push([
                        unit_to_byte(values[3]),
                        unit_to_byte(values[4]),
                        unit_to_byte(values[5]),
                        255,
                    ]);
                }
                positions.push(p);
            }
            "vt" => {
                let values = parse_numbers(tokens, line_no, path)?;
                let uv = match values.as_slice() {
                    [u] => Vec2::new(*u as f32, 0.0),
                    [u, v, ..] => Vec2::new(*u as f32, *v as f32),
                    [] => {
                        return Err(err(
                            line_no,
                            SyntaxProblem::TooFewValues {
                                expected: 2,
                                found: 0,
                            },
                        ))
                    }
                };
                if !uv.is_finite() {
                    return Err(MeshError::NonFinite {
                        path: path.to_path_buf(),
                        element: Element::TexCoord(texcoords.len() as u64),
                    });
                }
                texcoords.push(uv);
            }
            "vn" => {
                let values = parse_numbers(tokens, line_no, path)?;
                if values.len() < 3 {
                    return Err(err(
                        line_no,
                        SyntaxProblem::TooFewValues {
                            expected: 3,
                            found: values.len(),
                        },
                    ));
                }
                let n = Vec3::new(values[0] as f32, values[1] as f32, values[2] as f32);
                if !n.is_finite() {
                    return Err(MeshError::NonFinite {
                        path: path.to_path_buf(),
                        element: Element::Normal(normals.len() as u64),
                    });
                }
                normals.push(n);
            }
            "f" | "fo" => {
                polygon.clear();
                for (column, token) in tokens.enumerate() {
                    let mut parts = token.split('/');
                    let v = parts.next().unwrap_or("");
                    let vt = parts.next().filter(|s| !s.is_empty());
                    let vn = parts.next().filter(|s| !s.is_empty());
                    let v = resolve_index(v, positions.len(), line_no, column + 1, path)?;
                    let Some(v) = v.filter(|&v| (v as usize) < positions.len()) else {
                        return Err(MeshError::IndexOutOfRange {
                            path: path.to_path_buf(),
                            face: face_count,
                            index: raw_index(token),
                            vertex_count: positions.len() as u64,
                        });
                    };
                    let vt = attribute_index(vt, texcoords.len(), line_no, column + 1, path)?;
                    let vn = attribute_index(vn, normals.len(), line_no, column + 1, path)?;
                    polygon.push(Corner { v, vt, vn });
                }
                if polygon.len() < 3 {
                    return Err(err(
                        line_no,
                        SyntaxProblem::FaceTooSmall { len: polygon.len() },
                    ));
                }
                if polygon.len() > 3 {
                    fanned += 1;
                }
                for k in 1..polygon.len() - 1 {
                    corners.push([polygon[0], polygon[k], polygon[k + 1]]);
                    face_material.push(current_material);
                }
                face_count += 1;
            }
            "usemtl" => {
                let name = content.trim_start()["usemtl".len()..].trim().to_owned();
                let next = used_materials.len() as u32;
                let id = *used_index.entry(name.clone()).or_insert_with(|| {
                    used_materials.push(name);
                    next
                });
                current_material = Some(id);
            }
            "mtllib" => {
                saw_mtllib = true;
                let rest = content.trim_start()["mtllib".len()..].trim();
                for lib in library_candidates(&dir, rest) {
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
                        Ok(mtl) => parse_mtl(
                            &String::from_utf8_lossy(&mtl),
                            &parent_dir(&lib),
                            &mut library,
                            &mut library_order,
                            &mut warnings,
                        ),
                        Err(e) => warnings.push(LoadWarning::MissingMaterialLibrary {
                            path: lib,
                            reason: e.to_string(),
                        }),
                    }
                }
            }
            _ => {}
        }
    }

    if corners.len() >= u32::MAX as usize {
        return Err(MeshError::TooManyElements {
            path: path.to_path_buf(),
            kind: ElementKind::Triangles,
            count: corners.len() as u64,
        });
    }
    if fanned > 0 {
        warnings.push(LoadWarning::PolygonsFanned { count: fanned });
    }

    let mut builder = MeshBuilder {
        triangles: corners.iter().map(|c| c.map(|k| k.v)).collect(),
        ..MeshBuilder::default()
    };

    // Texture coordinates per corner.
    let with_uv = corners
        .iter()
        .filter(|c| c.iter().all(|k| k.vt.is_some()))
        .count();
    if corners.iter().any(|c| c.iter().any(|k| k.vt.is_some())) {
        if with_uv < corners.len() {
            warnings.push(LoadWarning::PartialTexCoords {
                faces_without: (corners.len() - with_uv) as u64,
            });
        }
        builder.face_uvs = Some(
            corners
                .iter()
                .map(|c| c.map(|k| k.vt.map_or(Vec2::ZERO, |i| texcoords[i as usize])))
                .collect(),
        );
    }

    // Normals: average the corner normals of each vertex, when every corner has one.
    let corners_with_normal = corners.iter().flatten().filter(|k| k.vn.is_some()).count();
    if corners_with_normal == corners.len() * 3 && !corners.is_empty() {
        let mut sum = vec![Vec3::ZERO; positions.len()];
        for k in corners.iter().flatten() {
            if let Some(n) = k.vn {
                sum[k.v as usize] += normals[n as usize];
            }
        }
        builder.vertex_normals = Some(sum.into_iter().map(Vec3::normalize_or_zero).collect());
    } else if corners_with_normal > 0 {
        warnings.push(LoadWarning::NormalsDropped);
    }

    // Vertex colours: only when every vertex has one.
    if !colours.is_empty() {
        if coloured == positions.len() {
            builder.vertex_colours = Some(colours);
        } else {
            warnings.push(LoadWarning::ColoursDropped);
        }
    }

    // Materials.
    if used_materials.is_empty() && library_order.len() == 1 {
        // A library with one material and no `usemtl`: it can only mean that material.
        used_materials.push(library_order[0].clone());
        face_material.iter_mut().for_each(|m| *m = Some(0));
    }
    if !used_materials.is_empty() {
        let mut texture_cache: HashMap<PathBuf, Option<Texture>> = HashMap::new();
        let mut uv_transforms = Vec::new();
        for name in &used_materials {
            let mut material = Material::white(name.clone());
            let mut transform = ([1.0f32; 2], [0.0f32; 2]);
            match library.get(name) {
                Some(def) => {
                    if let Some(kd) = def.diffuse {
                        material.base_colour = [kd[0], kd[1], kd[2], 1.0];
                    }
                    if def.transparent {
                        warnings.push(LoadWarning::TransparencyIgnored {
                            material: name.clone(),
                        });
                    }
                    if let Some(tex_path) = &def.texture {
                        let texture = texture_cache
                            .entry(tex_path.clone())
                            .or_insert_with(|| match load_texture_file(tex_path) {
                                Ok(t) => Some(t),
                                Err(w) => {
                                    warnings.push(w);
                                    None
                                }
                            })
                            .clone();
                        if texture.is_some() {
                            material.base_colour = [1.0; 4];
                            transform = (def.uv_scale, def.uv_offset);
                        }
                        material.texture = texture;
                    }
                }
                None if saw_mtllib => {
                    warnings.push(LoadWarning::UnknownMaterial { name: name.clone() })
                }
                None => {}
            }
            builder.materials.push(material);
            uv_transforms.push(transform);
        }
        let default_id = builder.materials.len() as u32;
        if face_material.iter().any(Option::is_none) {
            builder.materials.push(Material::white("default"));
            uv_transforms.push(([1.0; 2], [0.0; 2]));
        }
        builder.face_materials = face_material
            .iter()
            .map(|m| MaterialId(m.unwrap_or(default_id)))
            .collect();
        if let Some(uvs) = builder.face_uvs.as_mut() {
            for (uv, m) in uvs.iter_mut().zip(&builder.face_materials) {
                let (scale, offset) = uv_transforms[m.index()];
                if scale != [1.0; 2] || offset != [0.0; 2] {
                    for c in uv.iter_mut() {
                        *c = Vec2::new(c.x * scale[0] + offset[0], c.y * scale[1] + offset[1]);
                    }
                }
            }
        }
    } else if !saw_mtllib && builder.face_uvs.is_some() {
        if let Some(image) = guess_texture(path) {
            match load_texture_file(&image) {
                Ok(texture) => {
                    warnings.push(LoadWarning::TextureGuessed { path: image });
                    builder.materials.push(Material {
                        name: "texture".to_owned(),
                        base_colour: [1.0; 4],
                        texture: Some(texture),
                    });
                    builder.face_materials = vec![MaterialId(0); builder.triangles.len()];
                }
                Err(w) => warnings.push(w),
            }
        }
    }

    builder.positions = positions;
    let mesh = builder.finish(path)?;
    Ok(LoadedMesh { mesh, warnings })
}

/// Parses every remaining token as a number.
fn parse_numbers<'a>(
    tokens: impl Iterator<Item = &'a str>,
    line: usize,
    path: &Path,
) -> Result<Vec<f64>, MeshError> {
    tokens
        .enumerate()
        .map(|(column, t)| {
            t.parse::<f64>().map_err(|_| MeshError::Syntax {
                path: path.to_path_buf(),
                line,
                problem: SyntaxProblem::NotANumber { column: column + 1 },
            })
        })
        .collect()
}

/// The index as written, for error messages (0 when it is not a number).
fn raw_index(token: &str) -> i64 {
    token
        .split('/')
        .next()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0)
}

/// Resolves an OBJ index (1-based, or negative counting back from `count`) to 0-based.
/// `Ok(None)` means it points before the first element.
fn resolve_index(
    token: &str,
    count: usize,
    line: usize,
    column: usize,
    path: &Path,
) -> Result<Option<u32>, MeshError> {
    let value: i64 = token.parse().map_err(|_| MeshError::Syntax {
        path: path.to_path_buf(),
        line,
        problem: SyntaxProblem::NotANumber { column },
    })?;
    let resolved = match value {
        0 => {
            return Err(MeshError::Syntax {
                path: path.to_path_buf(),
                line,
                problem: SyntaxProblem::ZeroIndex,
            })
        }
        v if v > 0 => v - 1,
        v => (count as i64).saturating_add(v),
    };
    Ok(u32::try_from(resolved).ok())
}

/// Resolves a `vt` or `vn` index of a corner and checks it against the elements so far.
fn attribute_index(
    token: Option<&str>,
    count: usize,
    line: usize,
    column: usize,
    path: &Path,
) -> Result<Option<u32>, MeshError> {
    let Some(token) = token else {
        return Ok(None);
    };
    match resolve_index(token, count, line, column, path)? {
        Some(i) if (i as usize) < count => Ok(Some(i)),
        other => Err(MeshError::Syntax {
            path: path.to_path_buf(),
            line,
            problem: SyntaxProblem::AttributeIndexOutOfRange {
                index: other.map_or(-1, i64::from),
                count: count as u64,
            },
        }),
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
fn parse_mtl(
    text: &str,
    dir: &Path,
    library: &mut HashMap<String, MtlDef>,
    order: &mut Vec<String>,
    warnings: &mut Vec<LoadWarning>,
) {
    let mut current: Option<(String, MtlDef)> = None;
    let mut finish = |current: &mut Option<(String, MtlDef)>| {
        if let Some((name, def)) = current.take() {
            if let std::collections::hash_map::Entry::Vacant(slot) = library.entry(name) {
                order.push(slot.key().clone());
                slot.insert(def);
            }
        }
    };
    for raw in text.lines() {
        let content = raw.split('#').next().unwrap_or("").trim();
        let mut tokens = content.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            continue;
        };
        if keyword == "newmtl" {
            finish(&mut current);
            let name = content["newmtl".len()..].trim().to_owned();
            current = Some((
                name,
                MtlDef {
                    uv_scale: [1.0; 2],
                    ..MtlDef::default()
                },
            ));
            continue;
        }
        let Some((name, def)) = current.as_mut() else {
            continue;
        };
        match keyword {
            "Kd" => {
                let v: Vec<f32> = tokens.filter_map(|t| t.parse().ok()).collect();
                // `Kd r g b`, or one value for grey; anything else keeps the default.
                let kd = match v.as_slice() {
                    [g] => Some([*g; 3]),
                    [r, g, b, ..] => Some([*r, *g, *b]),
                    _ => None,
                };
                def.diffuse = kd
                    .filter(|c| c.iter().all(|x| x.is_finite()))
                    .map(|c| c.map(|x| x.clamp(0.0, 1.0)));
            }
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
            "map_Kd" => {
                let args: Vec<&str> = tokens.collect();
                let (file, options) = split_texture_options(&args);
                for option in options {
                    match option.as_slice() {
                        [flag, rest @ ..] if *flag == "-s" || *flag == "-o" => {
                            let values: Vec<f32> =
                                rest.iter().filter_map(|t| t.parse().ok()).collect();
                            let target = if *flag == "-s" {
                                &mut def.uv_scale
                            } else {
                                &mut def.uv_offset
                            };
                            for (k, v) in values.iter().take(2).enumerate() {
                                if v.is_finite() {
                                    target[k] = *v;
                                }
                            }
                        }
                        _ => warnings.push(LoadWarning::TextureOptionIgnored {
                            material: name.clone(),
                            option: option.join(" "),
                        }),
                    }
                }
                if !file.is_empty() {
                    match resolve_name(dir, &file) {
                        Ok(texture) => def.texture = Some(texture),
                        Err(reason) => warnings.push(LoadWarning::TextureUnreadable {
                            path: PathBuf::from(&file),
                            reason: format!("not read: {reason}"),
                        }),
                    }
                }
            }
            _ => {}
        }
    }
    finish(&mut current);
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

/// For an OBJ without `mtllib`: the single image in its folder named `<stem>.<ext>` or
/// `*_texture.<ext>`, if there is exactly one.
fn guess_texture(obj: &Path) -> Option<PathBuf> {
    let stem = obj.file_stem()?.to_str()?.to_ascii_lowercase();
    let dir = parent_dir(obj);
    let dir = if dir.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        dir
    };
    let mut found = Vec::new();
    for entry in std::fs::read_dir(&dir).ok()?.flatten() {
        let p = entry.path();
        let Some(ext) = p.extension().and_then(|e| e.to_str()) else {
            continue;
        };
        if !matches!(
            ext.to_ascii_lowercase().as_str(),
            "png" | "jpg" | "jpeg" | "tif" | "tiff"
        ) {
            continue;
        }
        let Some(s) = p.file_stem().and_then(|s| s.to_str()) else {
            continue;
        };
        let s = s.to_ascii_lowercase();
        if s == stem || s.ends_with("_texture") {
            found.push(p);
        }
    }
    if found.len() == 1 {
        found.pop()
    } else {
        None
    }
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

    #[test]
    fn indices_resolve_relative_and_absolute() {
        let p = Path::new("x.obj");
        assert_eq!(resolve_index("1", 5, 1, 1, p).unwrap(), Some(0));
        assert_eq!(resolve_index("-1", 5, 1, 1, p).unwrap(), Some(4));
        assert_eq!(resolve_index("-6", 5, 1, 1, p).unwrap(), None);
        assert!(resolve_index("0", 5, 1, 1, p).is_err());
        assert!(resolve_index("x", 5, 1, 1, p).is_err());
    }
}
