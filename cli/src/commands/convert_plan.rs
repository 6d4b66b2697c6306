//! Meshes at scale: `spatch plan MESH --tile SIZE` (tiles by face) and `spatch convert MESH
//! --plan plan.json --tile K` (one tile at the plan's spacing, segmenting the faces and
//! covering the creases and corners it owns). See docs/scale.md, "Meshes".

use std::io::Read;
use std::path::Path;
use std::time::Instant;

use spatch_convert::{convert_part, ConvertError, ConvertInput};
use spatch_format::encode_scene;
use spatch_mesh::{load_mesh, prepare_mesh, FileFormat, PrepareOptions};
use spatch_tiling::{
    can_stream_mesh, census_mesh, census_mesh_file, mesh_tile, read_mesh_tile, Plan, TileOwner,
    WorldBox,
};

use super::pipeline_args::PipelineArgs;
use crate::failure::InternalFailure;
use crate::output::{print_summary, write_output};

/// Whether `path` is a mesh to tile by face rather than a cloud to stream: an OBJ, glTF,
/// OFF or STL file, or a PLY whose header declares faces.
pub(crate) fn is_mesh(path: &Path) -> bool {
    match FileFormat::from_path(path) {
        Some(FileFormat::Obj | FileFormat::Gltf | FileFormat::Off | FileFormat::Stl) => true,
        Some(FileFormat::Ply) => ply_declares_faces(path),
        _ => false,
    }
}

/// Whether a PLY header (its first 4 KiB) declares `element face N` with N > 0.
fn ply_declares_faces(path: &Path) -> bool {
    let mut head = Vec::new();
    let read = std::fs::File::open(path).and_then(|f| f.take(4096).read_to_end(&mut head));
    if read.is_err() {
        return false;
    }
    let text = String::from_utf8_lossy(&head);
    let header = text.split("end_header").next().unwrap_or("");
    header.lines().any(|line| {
        let words: Vec<&str> = line.split_whitespace().collect();
        matches!(words.as_slice(), ["element", "face", n] if n.parse::<u64>().is_ok_and(|n| n > 0))
    })
}

/// The mesh at `path`, loaded and prepared as `spatch convert` prepares it.
fn load_prepared(path: &Path) -> anyhow::Result<spatch_mesh::TriangleMesh> {
    let loaded = load_mesh(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(prepare_mesh(&loaded.mesh, &PrepareOptions::default()).0)
}

/// A mesh plan's default buffer in node spacings: the context a tile's border patches
/// reach into (one cell past their region, and the faces under it), with room to spare.
const MESH_BUFFER_SPACINGS: f64 = 4.0;

/// `spatch plan MESH`: the plan of a mesh's tiles (the spacing given, or the one `spatch
/// convert` would derive for the whole mesh; the buffer given, or
/// [`MESH_BUFFER_SPACINGS`] spacings, at most a quarter tile). A PLY or plain OBJ is
/// streamed (one position per vertex and the tile counts held), other formats loaded.
pub(crate) fn plan_mesh(
    input: &Path,
    tile: f64,
    buffer: Option<f64>,
    spacing: Option<f32>,
) -> anyhow::Result<Plan> {
    let census = if can_stream_mesh(input).map_err(anyhow::Error::msg)? {
        census_mesh_file(input, tile).map_err(anyhow::Error::msg)?
    } else {
        census_mesh(&load_prepared(input)?, tile).map_err(anyhow::Error::msg)?
    };
    let derived = census
        .mean_face_area()
        .map(|a| (f64::from(spatch_fit::SPACING_PER_TRIANGLE_SIZE) * a.sqrt()) as f32)
        .filter(|s| s.is_finite() && *s > 0.0);
    let spacing = spacing
        .or(derived)
        .ok_or_else(|| anyhow::anyhow!("{}: the mesh has no surface", input.display()))?;
    let buffer =
        buffer.unwrap_or_else(|| (MESH_BUFFER_SPACINGS * f64::from(spacing)).min(0.25 * tile));
    census
        .plan(input, buffer, spacing)
        .map_err(anyhow::Error::msg)
}

/// The faces of the mesh at `input` whose box touches `area`: streamed from a PLY or a
/// plain OBJ (memory follows the tile), else cut from the whole mesh, loaded and prepared.
fn read_part(
    input: &Path,
    plan: &Plan,
    area: &WorldBox,
) -> anyhow::Result<spatch_mesh::TriangleMesh> {
    if can_stream_mesh(input).map_err(anyhow::Error::msg)? {
        let anchor = glam::DVec3::from_array(plan.grid.anchor);
        return read_mesh_tile(input, anchor, area).map_err(anyhow::Error::msg);
    }
    Ok(mesh_tile(&load_prepared(input)?, area))
}

/// `spatch convert MESH --plan P --tile K -o FILE`: tile K's faces (with its buffer's)
/// converted at the plan's spacing, segmenting only the faces whose centroid lies in K's
/// own box and making the edge patches of the creases whose midpoint (and the corners)
/// lie there (a tile with no patch is written as a scene with no patch).
pub(crate) fn run_tile(
    input: &Path,
    plan_path: &Path,
    tile: usize,
    output: &Path,
    pipeline: &PipelineArgs,
) -> anyhow::Result<()> {
    let started = Instant::now();
    let plan = Plan::read(plan_path).map_err(anyhow::Error::msg)?;
    let entry = plan
        .tile(tile)
        .map_err(|e| anyhow::anyhow!("{}: {e}", plan_path.display()))?;
    let mut options = pipeline.options();
    options.fit.spacing = Some(plan.spacing);
    let part = read_part(input, &plan, &entry.buffered)?;
    let faces = part.triangles.len();
    let label = || format!("{} (tile {tile})", input.display());
    let owner = TileOwner {
        bounds: &entry.bounds,
    };
    let kept = match convert_part(ConvertInput::Mesh(part), &owner, &options) {
        Ok(conversion) => conversion.scene,
        Err(ConvertError::NoSurface { .. } | ConvertError::NoPatches { .. }) => {
            let offset = glam::DVec3::from_array(entry.bounds.min);
            spatch_format::Scene::new(offset, spatch_format::ColourChannel::None, Vec::new())?
        }
        Err(e) => return Err(anyhow::anyhow!("{}: {e}", label())),
    };
    let bytes = encode_scene(&kept, &options.write)
        .map_err(|e| InternalFailure(format!("{}: encoding: {e}", label())))?;
    write_output(output, &bytes)?;
    print_summary(
        &format!(
            "{}: tile {tile} of {}: {} patches from {faces} faces read, {} bytes, {:.2} s\n",
            output.display(),
            plan.tiles.len(),
            kept.patches().len(),
            bytes.len(),
            started.elapsed().as_secs_f64()
        ),
        false,
    )
}
