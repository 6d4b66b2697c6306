//! Stanford PLY reader (ASCII, binary little and big endian) for meshes and point clouds.
//!
//! One reader serves both: the `vertex` element gives positions (`x y z`, any numeric type,
//! read as f64), optional normals (`nx ny nz`) and optional colours (`red green blue [alpha]`,
//! `r g b [a]` or `diffuse_red ...`); the `face` element gives polygons through a
//! `vertex_indices` or `vertex_index` list of any integer type, split into triangles, or,
//! when there is no `face` element, a `tristrips` element's `vertex_indices` lists (strips
//! with `-1` restarts, see `tristrips`), or else a raw scan's `range_grid` (its samples
//! joined as the scanner's grid, see `range_grid`). Other
//! vertex properties (confidence, intensity, ...) and other elements (`edge`, `material`,
//! ...) before or after are skipped; reading stops once the needed elements are read.
//!
//! Colour scale follows the property type: `uchar`/`char` are bytes, `ushort`/`short` are
//! 16-bit (divided by 257), `float`/`double` are `0..=1`, wider integers are clamped to
//! `0..=255`.
//!
//! Cost: one streaming pass; memory O(vertices + faces). Counts in the header never size an
//! allocation beyond 65,536 elements before data backs them (ply-rs-bw caps pre-allocation).
//!
//! Based on: Greg Turk, *The PLY Polygon File Format* (1994).

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use glam::{DVec3, Vec3};
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Header, Property, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};

use super::range_grid::{grid_size, range_grid_triangles};
use super::tristrips::strips_to_triangles;
use super::{build_point_cloud, LoadedMesh, LoadedPointCloud, MeshBuilder};
use crate::error::{Element, PlyProblem};
use crate::triangulate::PolygonTriangulator;
use crate::MeshError;

/// Loads a PLY file as a triangle mesh.
pub fn load_ply_mesh(path: &Path) -> Result<LoadedMesh, MeshError> {
    let data = read_ply(path, true)?;
    let vertex_count = data.vertices.len();
    for (i, v) in data.vertices.iter().enumerate() {
        if !v.position().is_finite() {
            return Err(MeshError::NonFinite {
                path: path.to_path_buf(),
                element: Element::Vertex(i as u64),
            });
        }
        if data.layout.normals && !v.normal().is_finite() {
            return Err(MeshError::NonFinite {
                path: path.to_path_buf(),
                element: Element::Normal(i as u64),
            });
        }
    }
    let mut warnings = Vec::new();
    let mut builder = MeshBuilder {
        positions: data.vertices.iter().map(PlyVertex::position).collect(),
        ..MeshBuilder::default()
    };
    match data.face_layout {
        FaceLayout::Polygons => {
            let mut triangulator = PolygonTriangulator::default();
            split_faces(path, &data.faces, &mut builder, &mut triangulator)?;
            warnings.extend(triangulator.warnings());
        }
        FaceLayout::Strips => {
            builder.triangles =
                strips_to_triangles(data.faces.iter().map(|f| &f.indices), vertex_count).map_err(
                    |problem| MeshError::PlyStructure {
                        path: path.to_path_buf(),
                        problem,
                    },
                )?;
        }
        FaceLayout::RangeGrid(size) => {
            let lists = data.faces.iter().map(|f| &f.indices);
            builder.triangles =
                range_grid_triangles(lists, size, &builder.positions).map_err(|problem| {
                    MeshError::PlyStructure {
                        path: path.to_path_buf(),
                        problem,
                    }
                })?;
        }
    }
    if data.layout.normals {
        builder.vertex_normals = Some(data.vertices.iter().map(PlyVertex::normal).collect());
    }
    if let Some(scale) = data.layout.colours {
        builder.vertex_colours = Some(data.vertices.iter().map(|v| v.colour(scale)).collect());
    }
    let mesh = builder.finish(path)?;
    Ok(LoadedMesh { mesh, warnings })
}

/// Splits polygon faces into `builder.triangles` (positions already in place).
fn split_faces(
    path: &Path,
    faces: &[PlyFace],
    builder: &mut MeshBuilder,
    triangulator: &mut PolygonTriangulator,
) -> Result<(), MeshError> {
    let vertex_count = builder.positions.len();
    let mut polygon = Vec::new();
    for (f, face) in faces.iter().enumerate() {
        if face.indices.len() < 3 {
            return Err(MeshError::PlyStructure {
                path: path.to_path_buf(),
                problem: PlyProblem::FaceTooSmall {
                    face: f as u64,
                    len: face.indices.len(),
                },
            });
        }
        if let Some(&bad) = face
            .indices
            .iter()
            .find(|&&i| i < 0 || i as u64 >= vertex_count as u64)
        {
            return Err(MeshError::IndexOutOfRange {
                path: path.to_path_buf(),
                face: f as u64,
                index: bad,
                vertex_count: vertex_count as u64,
            });
        }
        polygon.clear();
        polygon.extend(face.indices.iter().map(|&i| i as u32));
        triangulator.push(&builder.positions, &polygon, &mut builder.triangles);
    }
    Ok(())
}

/// Loads the vertices of any PLY file (faces, if any, are not read) as a point cloud.
pub fn load_ply_points(path: &Path) -> Result<LoadedPointCloud, MeshError> {
    let data = read_ply(path, false)?;
    let positions = data.vertices.iter().map(PlyVertex::position).collect();
    let normals = data
        .layout
        .normals
        .then(|| data.vertices.iter().map(PlyVertex::normal).collect());
    let colours = data
        .layout
        .colours
        .map(|scale| data.vertices.iter().map(|v| v.colour(scale)).collect());
    build_point_cloud(path, positions, colours, normals, Vec::new())
}

/// How a vertex colour channel's value maps to a byte.
#[derive(Clone, Copy, Debug, PartialEq)]
enum ColourScale {
    /// Already `0..=255`.
    Byte,
    /// `0..=65535`.
    Short,
    /// `0..=1`.
    Unit,
}

#[derive(Clone, Copy, Default)]
struct VertexLayout {
    normals: bool,
    colours: Option<ColourScale>,
}

/// How the face element lists its triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
enum FaceLayout {
    /// A `face` element: one polygon per entry.
    Polygons,
    /// A `tristrips` element: strips with `-1` restarts.
    Strips,
    /// A raw scan's `range_grid` element of `[cols, rows]` samples, each listing zero or
    /// one vertex.
    RangeGrid([usize; 2]),
}

struct PlyData {
    vertices: Vec<PlyVertex>,
    faces: Vec<PlyFace>,
    face_layout: FaceLayout,
    layout: VertexLayout,
}

fn read_ply(path: &Path, want_faces: bool) -> Result<PlyData, MeshError> {
    let file = File::open(path).map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if file.metadata().map(|m| m.len() == 0).unwrap_or(false) {
        return Err(MeshError::EmptyFile {
            path: path.to_path_buf(),
        });
    }
    let mut file = BufReader::with_capacity(1 << 16, file);
    let start = file.fill_buf().map_err(|source| MeshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    if has_cr_only_header(start) {
        let mut bytes = Vec::new();
        file.read_to_end(&mut bytes)
            .map_err(|source| MeshError::Io {
                path: path.to_path_buf(),
                source,
            })?;
        normalise_cr_line_ends(&mut bytes);
        return read_ply_from(path, Reader::new(std::io::Cursor::new(bytes)), want_faces);
    }
    read_ply_from(path, Reader::new(file), want_faces)
}

/// Whether the header's lines end in a lone CR (classic Mac OS files): ply-rs-bw reads lines up
/// to LF, so such a header would be one long line.
fn has_cr_only_header(start: &[u8]) -> bool {
    start.starts_with(b"ply\r") && start.get(4) != Some(&b'\n')
}

/// Turns the lone CRs of a CR-only file into LFs: in the header always, and in the body too
/// when it is ASCII (a binary body is left as it is).
fn normalise_cr_line_ends(bytes: &mut [u8]) {
    let header_end = bytes
        .windows(11)
        .position(|w| w == b"end_header\r")
        .map_or(bytes.len(), |at| at + 11);
    let ascii = bytes[..header_end]
        .windows(12)
        .any(|w| w == b"format ascii");
    let end = if ascii { bytes.len() } else { header_end };
    for b in &mut bytes[..end] {
        if *b == b'\r' {
            *b = b'\n';
        }
    }
}

/// Reads a PLY file's header and then its vertices (and faces, if `want_faces`) from
/// `reader`; `path` names the file in errors.
fn read_ply_from<R: BufRead>(
    path: &Path,
    mut reader: Reader<R>,
    want_faces: bool,
) -> Result<PlyData, MeshError> {
    let ply_err = |source: ParseError| MeshError::Ply {
        path: path.to_path_buf(),
        reason: one_line_reason(&source),
    };
    let header: Header = Parser::<Skip>::new()
        .read_header(&mut reader)
        .map_err(ply_err)?;
    let plan = ElementPlan::of(&header, want_faces).map_err(|problem| MeshError::PlyStructure {
        path: path.to_path_buf(),
        problem,
    })?;
    let (vertices, faces) = read_elements(&mut reader, &header, &plan).map_err(ply_err)?;
    if vertices.is_empty() {
        return Err(if want_faces {
            MeshError::NoFaces {
                path: path.to_path_buf(),
            }
        } else {
            MeshError::NoPoints {
                path: path.to_path_buf(),
            }
        });
    }
    Ok(PlyData {
        vertices,
        faces,
        face_layout: plan.face_layout,
        layout: plan.layout,
    })
}

/// What a header says to read: the vertex layout and the element that lists the faces.
struct ElementPlan<'h> {
    /// The properties of the vertex element that are read.
    layout: VertexLayout,
    /// The element listing the faces, when faces are wanted and the file has one.
    faces: Option<&'h ElementDef>,
    /// How that element lists its triangles.
    face_layout: FaceLayout,
}

impl<'h> ElementPlan<'h> {
    /// The plan of `header`, reading faces if `want_faces`; or why the header cannot serve.
    fn of(header: &'h Header, want_faces: bool) -> Result<ElementPlan<'h>, PlyProblem> {
        let vertex_def = header
            .elements
            .values()
            .find(|e| is_vertex_element(&e.name))
            .ok_or(PlyProblem::NoVertexElement)?;
        let layout = vertex_layout(vertex_def)?;
        let face_def = header
            .elements
            .values()
            .find(|e| is_face_element(&e.name))
            .or_else(|| header.elements.values().find(|e| is_strip_element(&e.name)))
            .or_else(|| header.elements.values().find(|e| is_range_grid(&e.name)));
        let face_layout = face_layout(face_def, header, want_faces)?;
        let faces = face_def.filter(|_| want_faces);
        if let Some(face_def) = faces {
            let ok = face_def
                .properties
                .values()
                .any(|p| is_index_list(&p.name) && matches!(p.data_type, PropertyType::List(_, _)));
            if !ok {
                return Err(PlyProblem::NoFaceIndexList);
            }
        }
        Ok(ElementPlan {
            layout,
            faces,
            face_layout,
        })
    }
}

/// How `face_def` (the header's face, strip or range-grid element, if any) lists its
/// triangles; a range grid needs its size from the header's `obj_info` lines.
fn face_layout(
    face_def: Option<&ElementDef>,
    header: &Header,
    want_faces: bool,
) -> Result<FaceLayout, PlyProblem> {
    Ok(match face_def {
        Some(def) if is_strip_element(&def.name) => FaceLayout::Strips,
        // (Only a mesh needs the grid's size: a point cloud reads the vertices alone.)
        Some(def) if is_range_grid(&def.name) && want_faces => {
            let size = grid_size(header.obj_infos.iter().map(String::as_str));
            FaceLayout::RangeGrid(size.ok_or(PlyProblem::RangeGridWithoutSize)?)
        }
        _ => FaceLayout::Polygons,
    })
}

/// Reads the body element by element up to the vertices and the `plan`'s faces (the first
/// element of each name), skipping the others before them.
fn read_elements<R: BufRead>(
    reader: &mut Reader<R>,
    header: &Header,
    plan: &ElementPlan,
) -> Result<(Vec<PlyVertex>, Vec<PlyFace>), ParseError> {
    let mut vertices = Vec::new();
    let mut faces = Vec::new();
    let (mut have_vertices, mut have_faces) = (false, plan.faces.is_none());
    for def in header.elements.values() {
        if have_vertices && have_faces {
            break;
        }
        if is_vertex_element(&def.name) && !have_vertices {
            vertices = Parser::<PlyVertex>::new().read_payload_for_element(reader, def, header)?;
            have_vertices = true;
        } else if plan.faces.is_some_and(|f| f.name == def.name) && !have_faces {
            faces = Parser::<PlyFace>::new().read_payload_for_element(reader, def, header)?;
            have_faces = true;
        } else {
            Parser::<Skip>::new().read_payload_for_element(reader, def, header)?;
        }
    }
    Ok((vertices, faces))
}

fn is_vertex_element(name: &str) -> bool {
    matches!(name, "vertex" | "vertices")
}

fn is_face_element(name: &str) -> bool {
    matches!(name, "face" | "faces")
}

fn is_strip_element(name: &str) -> bool {
    matches!(name, "tristrips" | "tristrip")
}

fn is_range_grid(name: &str) -> bool {
    name == "range_grid"
}

fn is_index_list(name: &str) -> bool {
    matches!(name, "vertex_indices" | "vertex_index")
}

/// Channel of a colour property name: 0..=3 for r, g, b, a.
fn colour_channel(name: &str) -> Option<usize> {
    Some(match name {
        "red" | "r" | "diffuse_red" => 0,
        "green" | "g" | "diffuse_green" => 1,
        "blue" | "b" | "diffuse_blue" => 2,
        "alpha" | "a" | "diffuse_alpha" => 3,
        _ => return None,
    })
}

fn vertex_layout(def: &ElementDef) -> Result<VertexLayout, PlyProblem> {
    let scalar = |name: &str| -> Result<Option<ScalarType>, PlyProblem> {
        match def.properties.get(name).map(|p| &p.data_type) {
            None => Ok(None),
            Some(PropertyType::Scalar(t)) => Ok(Some(t.clone())),
            Some(PropertyType::List(_, _)) => Err(PlyProblem::WrongPropertyShape {
                element: def.name.clone(),
                property: name.to_owned(),
            }),
        }
    };
    for axis in ['x', 'y', 'z'] {
        if scalar(&axis.to_string())?.is_none() {
            return Err(PlyProblem::MissingCoordinate { axis });
        }
    }
    let normals = scalar("nx")?.is_some() && scalar("ny")?.is_some() && scalar("nz")?.is_some();
    let mut colour_types = [None, None, None];
    for p in def.properties.values() {
        if let (Some(c @ 0..=2), PropertyType::Scalar(t)) = (colour_channel(&p.name), &p.data_type)
        {
            colour_types[c] = Some(t.clone());
        }
    }
    let colours = match &colour_types {
        [Some(t), Some(_), Some(_)] => Some(match t {
            ScalarType::Float | ScalarType::Double => ColourScale::Unit,
            ScalarType::Short | ScalarType::UShort => ColourScale::Short,
            _ => ColourScale::Byte,
        }),
        _ => None,
    };
    Ok(VertexLayout { normals, colours })
}

/// One vertex as read: every property of interest, raw.
#[derive(Clone, Copy)]
struct PlyVertex {
    p: [f64; 3],
    n: [f32; 3],
    c: [f64; 4],
    alpha_set: bool,
}

impl PlyVertex {
    fn position(&self) -> DVec3 {
        DVec3::from_array(self.p)
    }

    fn normal(&self) -> Vec3 {
        Vec3::from_array(self.n)
    }

    fn colour(&self, scale: ColourScale) -> [u8; 4] {
        let byte = |v: f64| -> u8 {
            let v = match scale {
                ColourScale::Byte => v,
                ColourScale::Short => v / 257.0,
                ColourScale::Unit => v * 255.0,
            };
            if v.is_nan() {
                0
            } else {
                (v.clamp(0.0, 255.0) + 0.5) as u8
            }
        };
        let alpha = if self.alpha_set { byte(self.c[3]) } else { 255 };
        [byte(self.c[0]), byte(self.c[1]), byte(self.c[2]), alpha]
    }

    fn put(&mut self, name: &str, v: f64) -> PropertyAccessResult {
        match name {
            "x" => self.p[0] = v,
            "y" => self.p[1] = v,
            "z" => self.p[2] = v,
            "nx" => self.n[0] = v as f32,
            "ny" => self.n[1] = v as f32,
            "nz" => self.n[2] = v as f32,
            _ => match colour_channel(name) {
                Some(c) => {
                    self.c[c] = v;
                    self.alpha_set |= c == 3;
                }
                None => return PropertyAccessResult::Ignored,
            },
        }
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for PlyVertex {
    fn new() -> Self {
        PlyVertex {
            p: [0.0; 3],
            n: [0.0; 3],
            c: [0.0; 4],
            alpha_set: false,
        }
    }
    fn set_property(&mut self, name: &str, property: Property) -> PropertyAccessResult {
        match property.to_f32_lossy() {
            Some(v) => self.put(name, f64::from(v)),
            None => PropertyAccessResult::Ignored,
        }
    }
    fn set_char(&mut self, name: &str, v: i8) -> PropertyAccessResult {
        self.put(name, f64::from(v))
    }
    fn set_uchar(&mut self, name: &str, v: u8) -> PropertyAccessResult {
        self.put(name, f64::from(v))
    }
    fn set_short(&mut self, name: &str, v: i16) -> PropertyAccessResult {
        self.put(name, f64::from(v))
    }
    fn set_ushort(&mut self, name: &str, v: u16) -> PropertyAccessResult {
        self.put(name, f64::from(v))
    }
    fn set_int(&mut self, name: &str, v: i32) -> PropertyAccessResult {
        self.put(name, f64::from(v))
    }
    fn set_uint(&mut self, name: &str, v: u32) -> PropertyAccessResult {
        self.put(name, f64::from(v))
    }
    fn set_float(&mut self, name: &str, v: f32) -> PropertyAccessResult {
        self.put(name, f64::from(v))
    }
    fn set_double(&mut self, name: &str, v: f64) -> PropertyAccessResult {
        self.put(name, v)
    }
}

/// One face as read: its vertex index list (any integer type, widened).
struct PlyFace {
    indices: Vec<i64>,
}

impl PlyFace {
    fn take<T: Into<i64>>(&mut self, name: &str, values: Vec<T>) -> PropertyAccessResult {
        if is_index_list(name) {
            self.indices = values.into_iter().map(Into::into).collect();
            PropertyAccessResult::Set
        } else {
            PropertyAccessResult::Ignored
        }
    }

    fn refuse_float(name: &str) -> PropertyAccessResult {
        if is_index_list(name) {
            PropertyAccessResult::UnsupportedType
        } else {
            PropertyAccessResult::Ignored
        }
    }
}

impl PropertyAccess for PlyFace {
    fn new() -> Self {
        PlyFace {
            indices: Vec::new(),
        }
    }
    fn set_list_char(&mut self, name: &str, v: Vec<i8>) -> PropertyAccessResult {
        self.take(name, v)
    }
    fn set_list_uchar(&mut self, name: &str, v: Vec<u8>) -> PropertyAccessResult {
        self.take(name, v)
    }
    fn set_list_short(&mut self, name: &str, v: Vec<i16>) -> PropertyAccessResult {
        self.take(name, v)
    }
    fn set_list_ushort(&mut self, name: &str, v: Vec<u16>) -> PropertyAccessResult {
        self.take(name, v)
    }
    fn set_list_int(&mut self, name: &str, v: Vec<i32>) -> PropertyAccessResult {
        self.take(name, v)
    }
    fn set_list_uint(&mut self, name: &str, v: Vec<u32>) -> PropertyAccessResult {
        self.take(name, v)
    }
    fn set_list_float(&mut self, name: &str, _: Vec<f32>) -> PropertyAccessResult {
        Self::refuse_float(name)
    }
    fn set_list_double(&mut self, name: &str, _: Vec<f64>) -> PropertyAccessResult {
        Self::refuse_float(name)
    }
}

/// An element whose contents are not needed (read past and dropped).
struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Skip
    }
}

/// The reader's message on one line: its first line (which names the file line), plus the
/// text it could not read when it quotes one. ply-rs-bw nests its causes over several lines.
fn one_line_reason(error: &ParseError) -> String {
    let text = error.to_string();
    let first = text
        .lines()
        .next()
        .unwrap_or_default()
        .trim()
        .trim_end_matches('.');
    let quoted = text
        .split("String: '")
        .nth(1)
        .and_then(|rest| rest.split('\'').next())
        .map(str::trim)
        .filter(|q| !q.is_empty());
    let first = controls_escaped(first);
    match quoted {
        Some(q) => format!("{first}: cannot read '{}'", controls_escaped(q)),
        None => first,
    }
}

/// `text` with its control characters (a stray CR of the file, ...) escaped, never raw; the
/// rest as it is (`str::escape_debug` also escaped the reader's apostrophes: "Couldn\'t").
fn controls_escaped(text: &str) -> String {
    text.chars()
        .map(|c| match c.is_control() {
            true => c.escape_debug().to_string(),
            false => c.to_string(),
        })
        .collect()
}
