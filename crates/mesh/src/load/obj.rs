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
//! Polygons are split by [`triangulate_polygon`](crate::triangulate_polygon): a fan from the
//! first corner when convex (as always), ear clipping in the polygon's plane otherwise.
//!
//! Structure: [`load_obj`] feeds each logical line to an `ObjReader`, which has one method per
//! keyword and a `finish` that turns the collected lists into a mesh; MTL libraries are read
//! by the `mtl` module.
//!
//! Cost: one pass over the text, O(file size) time and memory (plus the triangulation, near
//! linear in each polygon's corners).
//!
//! Based on: the OBJ and MTL format notes (Wavefront Technologies, *Advanced Visualizer*
//! manual, appendices B1 and B2).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec2, Vec3};

use super::mtl::{MtlDef, MtlLibrary};
use super::texture::load_texture_file;
use super::{parent_dir, read_file, unit_to_byte, LoadedMesh, MeshBuilder};
use crate::error::{Element, ElementKind, SyntaxProblem};
use crate::triangulate::PolygonTriangulator;
use crate::{LoadWarning, Material, MaterialId, MeshError, Texture};

/// One face corner: indices into the file's position, UV and normal lists.
#[derive(Clone, Copy)]
struct Corner {
    v: u32,
    vt: Option<u32>,
    vn: Option<u32>,
}

/// Loads an OBJ file and the materials and textures it names.
pub fn load_obj(path: &Path) -> Result<LoadedMesh, MeshError> {
    let bytes = read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let text = super::strip_bom(&text);
    let mut reader = ObjReader::new(path);
    let mut logical = String::new();
    for (line_index, raw) in text.lines().enumerate() {
        if let Some(stripped) = raw.strip_suffix('\\') {
            logical.push_str(stripped);
            logical.push(' ');
            continue;
        }
        logical.push_str(raw);
        let line = std::mem::take(&mut logical);
        reader.line = line_index + 1;
        reader.read_line(&line)?;
    }
    reader.finish()
}

/// The state of one OBJ file being read: the element lists so far and the material in use.
struct ObjReader<'p> {
    path: &'p Path,
    dir: PathBuf,
    /// The (1-based) line being read, for errors.
    line: usize,
    warnings: Vec<LoadWarning>,
    positions: Vec<DVec3>,
    /// Vertex colours, filled with white up to the last coloured vertex.
    colours: Vec<[u8; 4]>,
    /// How many vertices carried a colour.
    coloured: usize,
    texcoords: Vec<Vec2>,
    normals: Vec<Vec3>,
    /// Triangles as corners, after triangulation.
    corners: Vec<[Corner; 3]>,
    face_material: Vec<Option<u32>>,
    /// Material names in order of first `usemtl`.
    used_materials: Vec<String>,
    used_index: HashMap<String, u32>,
    library: MtlLibrary,
    saw_mtllib: bool,
    current_material: Option<u32>,
    /// Faces (`f` statements) read so far.
    face_count: u64,
    /// Scratch: the corners and vertex indices of the face being read.
    polygon: Vec<Corner>,
    polygon_vertices: Vec<u32>,
    triangulator: PolygonTriangulator,
}

impl<'p> ObjReader<'p> {
    /// An empty reader for the file at `path`.
    fn new(path: &'p Path) -> ObjReader<'p> {
        ObjReader {
            path,
            dir: parent_dir(path),
            line: 0,
            warnings: Vec::new(),
            positions: Vec::new(),
            colours: Vec::new(),
            coloured: 0,
            texcoords: Vec::new(),
            normals: Vec::new(),
            corners: Vec::new(),
            face_material: Vec::new(),
            used_materials: Vec::new(),
            used_index: HashMap::new(),
            library: MtlLibrary::default(),
            saw_mtllib: false,
            current_material: None,
            face_count: 0,
            polygon: Vec::new(),
            polygon_vertices: Vec::new(),
            triangulator: PolygonTriangulator::default(),
        }
    }

    /// A syntax error on the current line.
    fn syntax(&self, problem: SyntaxProblem) -> MeshError {
        MeshError::syntax(self.path, self.line, problem)
    }

    /// Reads one logical line (continuations joined); comments and unknown keywords (`o`,
    /// `g`, `s`, `l`, `p`, ...) are skipped.
    fn read_line(&mut self, line: &str) -> Result<(), MeshError> {
        let content = line.split('#').next().unwrap_or("");
        let mut tokens = content.split_ascii_whitespace();
        let Some(keyword) = tokens.next() else {
            return Ok(());
        };
        let rest = || content.trim_start()[keyword.len()..].trim();
        match keyword {
            "v" => self.read_vertex(tokens),
            "vt" => self.read_texcoord(tokens),
            "vn" => self.read_normal(tokens),
            "f" | "fo" => self.read_face(tokens),
            "usemtl" => {
                self.use_material(rest());
                Ok(())
            }
            "mtllib" => {
                self.saw_mtllib = true;
                self.library
                    .read_statement(&self.dir, rest(), &mut self.warnings);
                Ok(())
            }
            _ => Ok(()),
        }
    }

    /// `v x y z [r g b [a]]`: a position, and a vertex colour in `0..=1` when given.
    fn read_vertex<'a>(&mut self, tokens: impl Iterator<Item = &'a str>) -> Result<(), MeshError> {
        let values = parse_numbers(tokens, self.line, self.path)?;
        if values.len() < 3 {
            return Err(self.syntax(SyntaxProblem::TooFewValues {
                expected: 3,
                found: values.len(),
            }));
        }
        let p = DVec3::new(values[0], values[1], values[2]);
        if !p.is_finite() {
            return Err(MeshError::NonFinite {
                path: self.path.to_path_buf(),
                element: Element::Vertex(self.positions.len() as u64),
            });
        }
        if values.len() >= 6 {
            self.coloured += 1;
            self.colours.resize(self.positions.len(), [255; 4]);
            self.colours.push([
                unit_to_byte(values[3]),
                unit_to_byte(values[4]),
                unit_to_byte(values[5]),
                255,
            ]);
        }
        self.positions.push(p);
        Ok(())
    }

    /// `vt u [v [w]]`: a texture coordinate (`v` defaults to 0).
    fn read_texcoord<'a>(
        &mut self,
        tokens: impl Iterator<Item = &'a str>,
    ) -> Result<(), MeshError> {
        let values = parse_numbers(tokens, self.line, self.path)?;
        let uv = match values.as_slice() {
            [u] => Vec2::new(*u as f32, 0.0),
            [u, v, ..] => Vec2::new(*u as f32, *v as f32),
            [] => {
                return Err(self.syntax(SyntaxProblem::TooFewValues {
                    expected: 2,
                    found: 0,
                }))
            }
        };
        if !uv.is_finite() {
            return Err(MeshError::NonFinite {
                path: self.path.to_path_buf(),
                element: Element::TexCoord(self.texcoords.len() as u64),
            });
        }
        self.texcoords.push(uv);
        Ok(())
    }

    /// `vn x y z`: a normal.
    fn read_normal<'a>(&mut self, tokens: impl Iterator<Item = &'a str>) -> Result<(), MeshError> {
        let values = parse_numbers(tokens, self.line, self.path)?;
        if values.len() < 3 {
            return Err(self.syntax(SyntaxProblem::TooFewValues {
                expected: 3,
                found: values.len(),
            }));
        }
        let n = Vec3::new(values[0] as f32, values[1] as f32, values[2] as f32);
        if !n.is_finite() {
            return Err(MeshError::NonFinite {
                path: self.path.to_path_buf(),
                element: Element::Normal(self.normals.len() as u64),
            });
        }
        self.normals.push(n);
        Ok(())
    }

    /// `f v[/vt[/vn]] ...`: a polygon, split into triangles with the current material.
    fn read_face<'a>(&mut self, tokens: impl Iterator<Item = &'a str>) -> Result<(), MeshError> {
        self.polygon.clear();
        for (column, token) in tokens.enumerate() {
            let corner = self.read_corner(token, column + 1)?;
            self.polygon.push(corner);
        }
        if self.polygon.len() < 3 {
            return Err(self.syntax(SyntaxProblem::FaceTooSmall {
                len: self.polygon.len(),
            }));
        }
        self.polygon_vertices.clear();
        self.polygon_vertices
            .extend(self.polygon.iter().map(|c| c.v));
        let triangles = self
            .triangulator
            .split(&self.positions, &self.polygon_vertices);
        for t in triangles {
            self.corners.push(t.map(|k| self.polygon[k as usize]));
            self.face_material.push(self.current_material);
        }
        self.face_count += 1;
        Ok(())
    }

    /// One `v[/vt[/vn]]` corner of a face, its indices checked against the elements so far.
    fn read_corner(&self, token: &str, column: usize) -> Result<Corner, MeshError> {
        let mut parts = token.split('/');
        let v = parts.next().unwrap_or("");
        let vt = parts.next().filter(|s| !s.is_empty());
        let vn = parts.next().filter(|s| !s.is_empty());
        let count = self.positions.len();
        let v = resolve_index(v, count, self.line, column, self.path)?;
        let Some(v) = v.filter(|&v| (v as usize) < count) else {
            return Err(MeshError::IndexOutOfRange {
                path: self.path.to_path_buf(),
                face: self.face_count,
                index: raw_index(token),
                vertex_count: count as u64,
            });
        };
        let vt = attribute_index(vt, self.texcoords.len(), self.line, column, self.path)?;
        let vn = attribute_index(vn, self.normals.len(), self.line, column, self.path)?;
        Ok(Corner { v, vt, vn })
    }

    /// `usemtl name`: the material of the faces that follow.
    fn use_material(&mut self, name: &str) {
        let next = self.used_materials.len() as u32;
        let used_materials = &mut self.used_materials;
        let id = *self.used_index.entry(name.to_owned()).or_insert_with(|| {
            used_materials.push(name.to_owned());
            next
        });
        self.current_material = Some(id);
    }

    /// Turns the collected lists into a validated mesh.
    fn finish(mut self) -> Result<LoadedMesh, MeshError> {
        if self.corners.len() >= u32::MAX as usize {
            return Err(MeshError::TooManyElements {
                path: self.path.to_path_buf(),
                kind: ElementKind::Triangles,
                count: self.corners.len() as u64,
            });
        }
        self.warnings.extend(self.triangulator.warnings());
        let mut builder = MeshBuilder {
            triangles: self.corners.iter().map(|c| c.map(|k| k.v)).collect(),
            ..MeshBuilder::default()
        };
        builder.face_uvs = self.corner_uvs();
        builder.vertex_normals = self.vertex_normals();
        builder.vertex_colours = self.vertex_colours();
        if self.used_materials.is_empty() && self.library.order.len() == 1 {
            // A library with one material and no `usemtl`: it can only mean that material.
            self.used_materials.push(self.library.order[0].clone());
            self.face_material.iter_mut().for_each(|m| *m = Some(0));
        }
        if !self.used_materials.is_empty() {
            self.apply_materials(&mut builder);
        } else if !self.saw_mtllib && builder.face_uvs.is_some() {
            self.apply_guessed_texture(&mut builder);
        }
        builder.positions = std::mem::take(&mut self.positions);
        let mesh = builder.finish(self.path)?;
        Ok(LoadedMesh {
            mesh,
            warnings: self.warnings,
        })
    }

    /// Texture coordinates per triangle corner, when any corner has one (the others get
    /// `(0, 0)`, with a warning).
    fn corner_uvs(&mut self) -> Option<Vec<[Vec2; 3]>> {
        let corners = &self.corners;
        if !corners.iter().any(|c| c.iter().any(|k| k.vt.is_some())) {
            return None;
        }
        let with_uv = corners
            .iter()
            .filter(|c| c.iter().all(|k| k.vt.is_some()))
            .count();
        if with_uv < corners.len() {
            self.warnings.push(LoadWarning::PartialTexCoords {
                faces_without: (corners.len() - with_uv) as u64,
            });
        }
        let texcoords = &self.texcoords;
        Some(
            corners
                .iter()
                .map(|c| c.map(|k| k.vt.map_or(Vec2::ZERO, |i| texcoords[i as usize])))
                .collect(),
        )
    }

    /// Per-vertex normals, the average of each vertex's corner normals, when every corner
    /// has one.
    fn vertex_normals(&mut self) -> Option<Vec<Vec3>> {
        let corners = &self.corners;
        let with_normal = corners.iter().flatten().filter(|k| k.vn.is_some()).count();
        if with_normal == corners.len() * 3 && !corners.is_empty() {
            let mut sum = vec![Vec3::ZERO; self.positions.len()];
            for k in corners.iter().flatten() {
                if let Some(n) = k.vn {
                    sum[k.v as usize] += self.normals[n as usize];
                }
            }
            return Some(sum.into_iter().map(Vec3::normalize_or_zero).collect());
        }
        if with_normal > 0 {
            self.warnings.push(LoadWarning::NormalsDropped);
        }
        None
    }

    /// Vertex colours, only when every vertex has one.
    fn vertex_colours(&mut self) -> Option<Vec<[u8; 4]>> {
        if self.colours.is_empty() {
            return None;
        }
        if self.coloured == self.positions.len() {
            return Some(std::mem::take(&mut self.colours));
        }
        self.warnings.push(LoadWarning::ColoursDropped);
        None
    }

    /// The used materials from the libraries (textures loaded once each), the faces'
    /// material ids, and each material's `-s`/`-o` UV transform applied to its faces.
    fn apply_materials(&mut self, builder: &mut MeshBuilder) {
        let mut texture_cache: HashMap<PathBuf, Option<Texture>> = HashMap::new();
        let mut uv_transforms: Vec<UvTransform> = Vec::new();
        for name in &self.used_materials {
            let (material, transform) = match self.library.defs.get(name) {
                Some(def) => defined_material(name, def, &mut texture_cache, &mut self.warnings),
                None => {
                    if self.saw_mtllib {
                        self.warnings
                            .push(LoadWarning::UnknownMaterial { name: name.clone() });
                    }
                    (Material::white(name.clone()), NO_UV_TRANSFORM)
                }
            };
            builder.materials.push(material);
            uv_transforms.push(transform);
        }
        let default_id = builder.materials.len() as u32;
        if self.face_material.iter().any(Option::is_none) {
            builder.materials.push(Material::white("default"));
            uv_transforms.push(NO_UV_TRANSFORM);
        }
        builder.face_materials = self
            .face_material
            .iter()
            .map(|m| MaterialId(m.unwrap_or(default_id)))
            .collect();
        apply_uv_transforms(builder, &uv_transforms);
    }

    /// For an OBJ with UVs and no material library: the lone image beside it, if any, as
    /// its texture.
    fn apply_guessed_texture(&mut self, builder: &mut MeshBuilder) {
        let Some(image) = guess_texture(self.path) else {
            return;
        };
        match load_texture_file(&image) {
            Ok(texture) => {
                self.warnings
                    .push(LoadWarning::TextureGuessed { path: image });
                builder.materials.push(Material {
                    name: "texture".to_owned(),
                    base_colour: [1.0; 4],
                    texture: Some(texture),
                });
                builder.face_materials = vec![MaterialId(0); builder.triangles.len()];
            }
            Err(w) => self.warnings.push(w),
        }
    }
}

/// A material's UV transform: `(scale, offset)`, as its `-s` and `-o` options give them.
type UvTransform = ([f32; 2], [f32; 2]);

/// The identity UV transform: scale 1, offset 0.
const NO_UV_TRANSFORM: UvTransform = ([1.0; 2], [0.0; 2]);

/// The material `name` as its library entry `def` defines it, with its UV transform (the
/// identity unless its texture loads); textures come from `texture_cache`, and what is
/// ignored or cannot be loaded goes to `warnings`.
fn defined_material(
    name: &str,
    def: &MtlDef,
    texture_cache: &mut HashMap<PathBuf, Option<Texture>>,
    warnings: &mut Vec<LoadWarning>,
) -> (Material, UvTransform) {
    let mut material = Material::white(name.to_owned());
    let mut transform = NO_UV_TRANSFORM;
    if let Some(kd) = def.diffuse {
        material.base_colour = [kd[0], kd[1], kd[2], 1.0];
    }
    if def.transparent {
        warnings.push(LoadWarning::TransparencyIgnored {
            material: name.to_owned(),
        });
    }
    if let Some(tex_path) = &def.texture {
        let texture = cached_texture(texture_cache, tex_path, warnings);
        if texture.is_some() {
            material.base_colour = [1.0; 4];
            transform = (def.uv_scale, def.uv_offset);
        }
        material.texture = texture;
    }
    (material, transform)
}

/// The texture at `tex_path`, loaded the first time it is asked for and kept in
/// `texture_cache`; `None` when it cannot be loaded (the warning given once).
fn cached_texture(
    texture_cache: &mut HashMap<PathBuf, Option<Texture>>,
    tex_path: &Path,
    warnings: &mut Vec<LoadWarning>,
) -> Option<Texture> {
    texture_cache
        .entry(tex_path.to_path_buf())
        .or_insert_with(|| match load_texture_file(tex_path) {
            Ok(t) => Some(t),
            Err(w) => {
                warnings.push(w);
                None
            }
        })
        .clone()
}

/// Applies each face's material's UV transform (from `uv_transforms`, by material id) to
/// the face's UVs, when the mesh has UVs.
fn apply_uv_transforms(builder: &mut MeshBuilder, uv_transforms: &[UvTransform]) {
    if let Some(uvs) = builder.face_uvs.as_mut() {
        for (uv, m) in uvs.iter_mut().zip(&builder.face_materials) {
            let (scale, offset) = uv_transforms[m.index()];
            if (scale, offset) != NO_UV_TRANSFORM {
                for c in uv.iter_mut() {
                    *c = Vec2::new(c.x * scale[0] + offset[0], c.y * scale[1] + offset[1]);
                }
            }
        }
    }
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
            t.parse::<f64>().map_err(|_| {
                MeshError::syntax(path, line, SyntaxProblem::NotANumber { column: column + 1 })
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
    let value: i64 = token
        .parse()
        .map_err(|_| MeshError::syntax(path, line, SyntaxProblem::NotANumber { column }))?;
    let resolved = match value {
        0 => return Err(MeshError::syntax(path, line, SyntaxProblem::ZeroIndex)),
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
        other => {
            let problem = SyntaxProblem::AttributeIndexOutOfRange {
                index: other.map_or(-1, i64::from),
                count: count as u64,
            };
            Err(MeshError::syntax(path, line, problem))
        }
    }
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
    fn indices_resolve_relative_and_absolute() {
        let p = Path::new("x.obj");
        assert_eq!(resolve_index("1", 5, 1, 1, p).unwrap(), Some(0));
        assert_eq!(resolve_index("-1", 5, 1, 1, p).unwrap(), Some(4));
        assert_eq!(resolve_index("-6", 5, 1, 1, p).unwrap(), None);
        assert!(resolve_index("0", 5, 1, 1, p).is_err());
        assert!(resolve_index("x", 5, 1, 1, p).is_err());
    }
}
