//! glTF 2.0 reader: `.gltf` (external or data-URI buffers) and `.glb`.
//!
//! Every triangle primitive (`TRIANGLES`, and `TRIANGLE_STRIP` / `TRIANGLE_FAN` converted to
//! triangles) of every mesh instance reachable from the default scene (or from every scene,
//! or every root node when there are no scenes) is merged into one [`TriangleMesh`](crate::TriangleMesh). Node
//! transforms are composed in f64 and applied to positions (normals by the inverse transpose;
//! mirroring transforms flip the winding back to counter-clockwise). Point and line primitives
//! are skipped with a warning. Each primitive is read by `gltf_primitive`.
//!
//! Colour: each glTF material becomes a [`Material`] with `baseColorFactor` as the base colour
//! and `baseColorTexture` as the texture (its `TEXCOORD_n` set, with `KHR_texture_transform`
//! applied to the UVs); `COLOR_0` (any component type) becomes sRGB vertex colours. UVs are
//! flipped to `v` up (`v' = 1 - v`), the convention of every mesh here.
//!
//! Compression and quantization: `KHR_mesh_quantization` (integer and normalized-integer
//! attributes, dequantized by `gltf_accessor`) and
//! `EXT_meshopt_compression` (views decoded by `gltf_buffers`) are
//! read. Refused with [`MeshError::GltfExtensionRequired`]: files that *require* any other
//! extension not known to affect only shading (`KHR_draco_mesh_compression` among them: no
//! maintained pure-Rust Draco decoder was found fit to rely on). Accessors are checked (type,
//! component type, count and byte range) before they are read, and every primitive's accessor
//! indices before the gltf crate's validation (which indexes them unchecked), so a malformed
//! file gives an error, not a panic.
//!
//! External files (buffers, images) are read only from the model's folder or below
//! (`local_reference`).
//!
//! Cost: O(vertices + indices) after the JSON parse; buffers are held in memory.
//!
//! Based on: the Khronos glTF 2.0 specification (2021), sections 3.6 (buffers, accessors),
//! 3.7 (meshes), 3.9 (materials) and 3.5 (node hierarchy).

use std::path::Path;

use glam::{DMat4, Vec2};

use super::gltf_buffers::{load_buffers, read_uri, resolve_views, Views};
use super::gltf_primitive::{read_primitive, Piece, PrimitiveAt, UvTransform};
use super::texture::load_texture_bytes;
use super::{parent_dir, read_file, LoadedMesh, MeshBuilder};
use crate::error::{Element, GltfAttribute, GltfProblem};
use crate::{LoadWarning, Material, MaterialId, MeshError, Texture};

/// Required extensions that change only shading or metadata, which this reader may ignore.
const IGNORABLE_REQUIRED_EXTENSIONS: &[&str] = &[
    "KHR_texture_transform",
    "KHR_materials_unlit",
    "KHR_materials_emissive_strength",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_clearcoat",
    "KHR_materials_sheen",
    "KHR_materials_variants",
    "KHR_lights_punctual",
];

/// Required extensions that this reader decodes itself (the gltf crate's validation refuses
/// them, so they are taken off the required list before it runs).
const DECODED_REQUIRED_EXTENSIONS: &[&str] = &["KHR_mesh_quantization", "EXT_meshopt_compression"];

/// Refuses a GLB whose header declares a total length shorter than the header itself (the
/// glTF crate subtracts the header size from it unchecked: an overflow panic in builds with
/// overflow checks, found by the `gltf_load` fuzz target).
fn check_glb_length(bytes: &[u8]) -> Result<(), gltf::Error> {
    const GLB_HEADER_LEN: u32 = 12;
    if let [b'g', b'l', b'T', b'F', _, _, _, _, l0, l1, l2, l3, ..] = *bytes {
        let length = u32::from_le_bytes([l0, l1, l2, l3]);
        if length < GLB_HEADER_LEN {
            return Err(gltf::Error::Binary(gltf::binary::Error::Length {
                length,
                length_read: bytes.len(),
            }));
        }
    }
    Ok(())
}

/// Loads a `.gltf` or `.glb` file.
pub fn load_gltf(path: &Path) -> Result<LoadedMesh, MeshError> {
    let bytes = read_file(path)?;
    let (document, blob) = read_document(path, &bytes)?;
    let dir = parent_dir(path);
    let base = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir.as_path()
    };
    let buffers = load_buffers(path, base, &document, blob)?;
    let views = resolve_views(&document, &buffers);
    let mut warnings = Vec::new();
    let materials = read_materials(&document, (path, base), &views, &mut warnings);
    let (pieces, skipped) = read_nodes(&document, path, &views, &materials)?;
    if skipped > 0 {
        warnings.push(LoadWarning::NonTrianglePrimitivesSkipped { count: skipped });
    }
    let builder = merge_pieces(pieces, materials.materials, &mut warnings);
    let mesh = builder.finish(path)?;
    Ok(LoadedMesh { mesh, warnings })
}

/// The file's document, checked for what the loader cannot decode (its
/// extensions decoded here taken out of the required ones), and the GLB
/// binary chunk.
fn read_document(
    path: &Path,
    bytes: &[u8],
) -> Result<(gltf::Document, Option<Vec<u8>>), MeshError> {
    let gltf_err = |source| MeshError::Gltf {
        path: path.to_path_buf(),
        source,
    };
    check_glb_length(bytes).map_err(gltf_err)?;
    let unvalidated = gltf::Gltf::from_slice_without_validation(bytes).map_err(gltf_err)?;
    let blob = unvalidated.blob;
    let mut json = unvalidated.document.into_json();
    check_required_extensions(path, &json)?;
    check_primitive_indices(path, &json)?;
    json.extensions_required
        .retain(|e| !DECODED_REQUIRED_EXTENSIONS.contains(&e.as_str()));
    let document = gltf::Document::from_json(json).map_err(gltf_err)?;
    Ok((document, blob))
}

/// The materials of a glTF file, and per material the texture
/// coordinate set and transform of its base colour texture.
struct GltfMaterials {
    materials: Vec<Material>,
    uv_sets: Vec<u32>,
    uv_transforms: Vec<UvTransform>,
}

/// Reads the materials and decodes their textures (each image once; one
/// that cannot be read is a warning and no texture), images relative to
/// `base`, the folder of `path`.
fn read_materials(
    document: &gltf::Document,
    (path, base): (&Path, &Path),
    views: &Views,
    warnings: &mut Vec<LoadWarning>,
) -> GltfMaterials {
    let mut out = GltfMaterials {
        materials: Vec::new(),
        uv_sets: Vec::new(),
        uv_transforms: Vec::new(),
    };
    let mut texture_cache: Vec<Option<Option<Texture>>> = vec![None; document.images().len()];
    for (i, m) in document.materials().enumerate() {
        let pbr = m.pbr_metallic_roughness();
        let mut material = Material {
            name: m
                .name()
                .map_or_else(|| format!("material_{i}"), str::to_owned),
            base_colour: sanitise_factor(pbr.base_color_factor()),
            texture: None,
        };
        let mut set = 0;
        let mut transform = UvTransform::IDENTITY;
        if let Some(info) = pbr.base_color_texture() {
            set = info.tex_coord();
            if let Some(t) = info.texture_transform() {
                set = t.tex_coord().unwrap_or(set);
                transform = UvTransform {
                    offset: t.offset(),
                    rotation: t.rotation(),
                    scale: t.scale(),
                };
            }
            let image = info.texture().source();
            let slot = &mut texture_cache[image.index()];
            if slot.is_none() {
                *slot = Some(match decode_image(&image, base, views, path) {
                    Ok(t) => Some(t),
                    Err(w) => {
                        warnings.push(w);
                        None
                    }
                });
            }
            material.texture = slot.clone().flatten();
        }
        out.materials.push(material);
        out.uv_sets.push(set);
        out.uv_transforms.push(transform);
    }
    out
}

/// The nodes the hierarchy starts from: the default scene's, else every
/// scene's, else every node that is no other's child.
fn root_nodes(document: &gltf::Document) -> Vec<gltf::Node<'_>> {
    match document.default_scene() {
        Some(scene) => scene.nodes().collect(),
        None if document.scenes().len() > 0 => document.scenes().flat_map(|s| s.nodes()).collect(),
        None => {
            let mut is_child = vec![false; document.nodes().len()];
            for n in document.nodes() {
                for c in n.children() {
                    is_child[c.index()] = true;
                }
            }
            document.nodes().filter(|n| !is_child[n.index()]).collect()
        }
    }
}

/// Walks the node hierarchy with an explicit stack (no recursion on file
/// data): every triangle primitive as a [`Piece`] in world space, and the
/// count of primitives skipped (points, lines).
fn read_nodes(
    document: &gltf::Document,
    path: &Path,
    views: &Views,
    materials: &GltfMaterials,
) -> Result<(Vec<Piece>, u64), MeshError> {
    let node_limit = document.nodes().len().max(1) * 64;
    let mut stack: Vec<(gltf::Node, DMat4, usize)> = root_nodes(document)
        .into_iter()
        .map(|n| (n, DMat4::IDENTITY, 0))
        .collect();
    let mut pieces = Vec::new();
    let mut skipped = 0u64;
    let mut visited = 0usize;
    let uv = (&materials.uv_sets[..], &materials.uv_transforms[..]);
    while let Some((node, parent, depth)) = stack.pop() {
        visited += 1;
        // A cyclic or absurdly shared hierarchy would never end; the limit stops it.
        if visited > node_limit || depth > document.nodes().len() {
            break;
        }
        let local = DMat4::from_cols_array_2d(&node.transform().matrix().map(|c| c.map(f64::from)));
        let world = parent * local;
        if !world.is_finite() {
            return Err(MeshError::NonFinite {
                path: path.to_path_buf(),
                element: Element::Node(node.index() as u64),
            });
        }
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                let at = PrimitiveAt {
                    path,
                    mesh: mesh.index(),
                    primitive: primitive.index(),
                    views,
                    world: &world,
                };
                match read_primitive(&at, &primitive, uv)? {
                    Some(piece) => pieces.push(piece),
                    None => skipped += 1,
                }
            }
        }
        for child in node.children() {
            stack.push((child, world, depth + 1));
        }
    }
    Ok((pieces, skipped))
}

fn sanitise_factor(f: [f32; 4]) -> [f32; 4] {
    f.map(|c| {
        if c.is_finite() {
            c.clamp(0.0, 1.0)
        } else {
            1.0
        }
    })
}

/// Refuses a file that requires an extension this reader neither decodes nor may ignore.
fn check_required_extensions(path: &Path, json: &gltf::json::Root) -> Result<(), MeshError> {
    match json.extensions_required.iter().find(|e| {
        !IGNORABLE_REQUIRED_EXTENSIONS.contains(&e.as_str())
            && !DECODED_REQUIRED_EXTENSIONS.contains(&e.as_str())
    }) {
        Some(ext) => Err(MeshError::GltfExtensionRequired {
            path: path.to_path_buf(),
            extension: ext.clone(),
        }),
        None => Ok(()),
    }
}

/// Checks that every primitive's attribute and index accessors exist (the gltf crate's
/// validation indexes the `POSITION` accessor before checking it, and panics on a bad one).
fn check_primitive_indices(path: &Path, json: &gltf::json::Root) -> Result<(), MeshError> {
    let count = json.accessors.len();
    for (m, mesh) in json.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let attributes = primitive.attributes.iter().map(|(semantic, index)| {
                let attribute = match semantic {
                    gltf::json::validation::Checked::Valid(gltf::Semantic::Positions) => {
                        GltfAttribute::Position
                    }
                    gltf::json::validation::Checked::Valid(gltf::Semantic::Normals) => {
                        GltfAttribute::Normal
                    }
                    gltf::json::validation::Checked::Valid(gltf::Semantic::Colors(_)) => {
                        GltfAttribute::Colour
                    }
                    _ => GltfAttribute::TexCoord,
                };
                (attribute, index.value())
            });
            let indices = primitive
                .indices
                .map(|i| (GltfAttribute::Indices, i.value()));
            if let Some((attribute, index)) = attributes.chain(indices).find(|&(_, i)| i >= count) {
                return Err(MeshError::GltfPrimitive {
                    path: path.to_path_buf(),
                    mesh: m,
                    primitive: p,
                    problem: GltfProblem::MissingAccessor {
                        attribute,
                        index,
                        accessor_count: count,
                    },
                });
            }
        }
    }
    Ok(())
}

/// Joins the primitive instances into one mesh: optional attributes are kept when at least
/// one piece has them (normals only when all do), missing ones filled neutrally.
fn merge_pieces(
    pieces: Vec<Piece>,
    mut materials: Vec<Material>,
    warnings: &mut Vec<LoadWarning>,
) -> MeshBuilder {
    let mut b = builder_for(&pieces, warnings);
    let any_material = pieces.iter().any(|p| p.material.is_some());
    let default_material = materials.len() as u32;
    if any_material && pieces.iter().any(|p| p.material.is_none()) {
        materials.push(Material::white("default"));
    }
    let mut faces_without_uv = 0u64;
    for piece in pieces {
        faces_without_uv += append_piece(&mut b, piece, any_material.then_some(default_material));
    }
    if faces_without_uv > 0 {
        warnings.push(LoadWarning::PartialTexCoords {
            faces_without: faces_without_uv,
        });
    }
    if any_material {
        b.materials = materials;
    }
    b
}

/// An empty builder holding the optional attributes [`merge_pieces`] keeps of `pieces`; warns
/// when some pieces' normals are dropped (not all pieces have them).
fn builder_for(pieces: &[Piece], warnings: &mut Vec<LoadWarning>) -> MeshBuilder {
    let any_uv = pieces.iter().any(|p| p.uvs.is_some());
    let any_colour = pieces.iter().any(|p| p.colours.is_some());
    let all_normals = pieces.iter().all(|p| p.normals.is_some());
    if !all_normals && pieces.iter().any(|p| p.normals.is_some()) {
        warnings.push(LoadWarning::NormalsDropped);
    }
    MeshBuilder {
        face_uvs: any_uv.then(Vec::new),
        vertex_colours: any_colour.then(Vec::new),
        vertex_normals: all_normals.then(Vec::new),
        ..MeshBuilder::default()
    }
}

/// Appends `piece` to `b`: its vertices, faces and the attributes `b` keeps (missing ones
/// filled neutrally), and, when materials are kept (`default_material` is given), its faces'
/// material (`default_material` for a piece without one). Returns how many of its faces got
/// no texture coordinates of their own where `b` keeps them.
fn append_piece(b: &mut MeshBuilder, piece: Piece, default_material: Option<u32>) -> u64 {
    let offset = b.positions.len() as u32;
    let n = piece.positions.len();
    b.positions.extend_from_slice(&piece.positions);
    for t in &piece.triangles {
        b.triangles.push(t.map(|i| i + offset));
    }
    let mut faces_without_uv = 0u64;
    if let Some(face_uvs) = b.face_uvs.as_mut() {
        match &piece.uvs {
            Some(uvs) => {
                face_uvs.extend(piece.triangles.iter().map(|t| t.map(|i| uvs[i as usize])))
            }
            None => {
                faces_without_uv += piece.triangles.len() as u64;
                face_uvs.extend(std::iter::repeat_n([Vec2::ZERO; 3], piece.triangles.len()));
            }
        }
    }
    if let Some(colours) = b.vertex_colours.as_mut() {
        match &piece.colours {
            Some(c) => colours.extend_from_slice(c),
            None => colours.extend(std::iter::repeat_n([255u8; 4], n)),
        }
    }
    if let (Some(normals), Some(n)) = (b.vertex_normals.as_mut(), &piece.normals) {
        normals.extend_from_slice(n);
    }
    if let Some(default_material) = default_material {
        let id = MaterialId(piece.material.map_or(default_material, |m| m as u32));
        b.face_materials
            .extend(std::iter::repeat_n(id, piece.triangles.len()));
    }
    faces_without_uv
}

/// Decodes a glTF image (buffer view bytes, data URI or external file in the model's folder)
/// to a texture.
fn decode_image(
    image: &gltf::Image,
    base: &Path,
    views: &Views,
    gltf_path: &Path,
) -> Result<Texture, LoadWarning> {
    let label = gltf_path.join(format!("#image{}", image.index()));
    match image.source() {
        gltf::image::Source::View { view, .. } => {
            let bytes = views
                .get(view.index())
                .and_then(|v| v.as_deref())
                .ok_or_else(|| LoadWarning::TextureUnreadable {
                    path: label.clone(),
                    reason: "the image's buffer view is out of range".to_owned(),
                })?;
            load_texture_bytes(bytes, &label)
        }
        gltf::image::Source::Uri { uri, .. } => {
            let label = if uri.starts_with("data:") {
                label
            } else {
                base.join(uri)
            };
            let bytes =
                read_uri(gltf_path, base, uri).map_err(|e| LoadWarning::TextureUnreadable {
                    path: label.clone(),
                    reason: match e {
                        Some(MeshError::Io { source, .. }) => source.to_string(),
                        Some(MeshError::ReferenceOutsideFolder { reason, .. }) => {
                            format!("not read: {reason}")
                        }
                        Some(other) => other.to_string(),
                        None => "its data: URI is not valid base64".to_owned(),
                    },
                })?;
            load_texture_bytes(&bytes, &label)
        }
    }
}
