//! One scene against its source: every measure of DESIGN §6, timed.
//!
//! [`load_source`] reads the source: a mesh (welded and cleaned as the converter does, so the
//! figures match `spatch convert`'s) or, for `.xyz`/`.txt`/`.pts` files and PLY files without
//! faces, a point cloud. [`evaluate`] then measures:
//!
//! - **mesh source**: `node_to_surface` and `surface_to_patch` (see [`crate::geometric`]) with
//!   their histograms, the per-patch errors and the quantization-only bound
//!   ([`crate::per_patch`]), and the image error over the views ([`mod@crate::image_error`]);
//! - **cloud source**: `cloud_to_patch` and `node_to_cloud` as `spatch-cloud` measures them
//!   (two triangles per cell), their histograms and per-patch figures (nodes to the nearest
//!   point, exact; points to the nearest bilinear cell, which differs from the two-triangle
//!   surface by at most a quarter of a cell's twist). No image error: a cloud has no surface
//!   to render ([`CLOUD_IMAGE_NOTE`]).
//!
//! First, the source and the scene must overlap ([`crate::overlap`]): a source elsewhere is
//! refused with [`EvalError::NoOverlap`] before anything is measured.
//!
//! Every measurement is timed as a stage. Results do not depend on the thread count (except
//! the times).

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;
use spatch_cloud::CloudErrorReport;
use spatch_format::Scene;
use spatch_mesh::{
    load_mesh, load_point_cloud, prepare_mesh, Bvh, FileFormat, MeshError, PointCloud,
    PrepareOptions, TriangleMesh,
};
use spatch_render::PreparedScene;

use crate::geometric::{
    cloud_error_entries, node_to_surface_distances, sample_count, sampled_surface_to_patch,
};
use crate::histogram::ErrorHistogram;
use crate::image_error::{image_error, ImageError, ImageOptions};
use crate::overlap::{box_text, source_overlap};
use crate::per_patch::{per_patch_errors, quantization_bound, PatchError, QuantizationBound};
use crate::{ErrorStats, EvalError};

/// Why a cloud source has no image error.
pub const CLOUD_IMAGE_NOTE: &str =
    "the source is a point cloud, which has no surface to render: image error skipped";

/// A source to measure against.
#[derive(Debug, Clone)]
pub enum Source {
    /// A triangle mesh (prepared: welded, degenerate faces dropped).
    Mesh(TriangleMesh),
    /// A point cloud.
    Cloud(PointCloud),
}

impl Source {
    /// `mesh` or `cloud`.
    pub fn kind(&self) -> &'static str {
        match self {
            Source::Mesh(_) => "mesh",
            Source::Cloud(_) => "cloud",
        }
    }

    /// The bounding-box diagonal (model units).
    pub fn diagonal(&self) -> f64 {
        match self {
            Source::Mesh(m) => f64::from(m.diagonal()),
            Source::Cloud(c) => f64::from(c.bounds().diagonal()),
        }
    }
}

/// A loaded source and what the reader worked around.
#[derive(Debug, Clone)]
pub struct LoadedSource {
    /// The source.
    pub source: Source,
    /// Reader warnings and dropped points, as sentences.
    pub warnings: Vec<String>,
}

/// Reads `path` as a mesh, or as a point cloud when it is an `.xyz`/`.txt`/`.pts` file or a
/// PLY file without faces.
pub fn load_source(path: &Path) -> Result<LoadedSource, EvalError> {
    let cloud = |path: &Path| -> Result<LoadedSource, EvalError> {
        let loaded = load_point_cloud(path)?;
        let mut warnings: Vec<String> = loaded.warnings.iter().map(ToString::to_string).collect();
        if loaded.dropped_non_finite > 0 {
            warnings.push(format!(
                "dropped {} points with a non-finite coordinate or normal",
                loaded.dropped_non_finite
            ));
        }
        Ok(LoadedSource {
            source: Source::Cloud(loaded.cloud),
            warnings,
        })
    };
    match FileFormat::from_path(path) {
        Some(FileFormat::Xyz | FileFormat::Pts) => return cloud(path),
        Some(FileFormat::Ply) => match load_mesh(path) {
            Err(MeshError::NoFaces { .. }) => return cloud(path),
            Err(e) => return Err(e.into()),
            Ok(loaded) => return prepared(path, loaded),
        },
        _ => {}
    }
    prepared(path, load_mesh(path)?)
}

fn prepared(path: &Path, loaded: spatch_mesh::LoadedMesh) -> Result<LoadedSource, EvalError> {
    let (mesh, _) = prepare_mesh(&loaded.mesh, &PrepareOptions::default());
    if mesh.face_count() == 0 || mesh.diagonal() <= 0.0 {
        return Err(EvalError::NoSurface {
            path: path.to_path_buf(),
        });
    }
    Ok(LoadedSource {
        source: Source::Mesh(mesh),
        warnings: loaded.warnings.iter().map(ToString::to_string).collect(),
    })
}

/// What [`evaluate`] measures.
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct EvalOptions {
    /// Seed of the source samples. Default 1 (as `spatch convert`).
    pub seed: u64,
    /// The image error's views and render options, or `None` to skip it. Default: the 14
    /// standard views at 500 × 500 with the default render options.
    pub image: Option<ImageOptions>,
}

impl Default for EvalOptions {
    fn default() -> Self {
        Self {
            seed: 1,
            image: Some(ImageOptions::default()),
        }
    }
}

/// Figures only a cloud source has.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CloudFigures {
    /// The cloud's estimated point spacing (model units).
    pub spacing: f64,
    /// Share of the points (0..=1) farther than twice the spacing from every patch.
    pub share_beyond_2x_spacing: f64,
}

/// Everything [`evaluate`] measured.
#[derive(Debug, Clone)]
pub struct Evaluation {
    /// Named one-way errors.
    pub error: BTreeMap<String, ErrorStats>,
    /// A histogram per named error.
    pub histograms: BTreeMap<String, ErrorHistogram>,
    /// The source's bounding-box diagonal.
    pub diagonal: f64,
    /// Source samples (mesh) or points (cloud) measured to the patches.
    pub source_samples: usize,
    /// One row per patch.
    pub patches: Vec<PatchError>,
    /// The quantization-only bound beside the node error.
    pub bound: QuantizationBound,
    /// The image error, when measured.
    pub image: Option<ImageError>,
    /// Why there is no image error, when there is none.
    pub image_note: Option<&'static str>,
    /// Cloud-only figures.
    pub cloud: Option<CloudFigures>,
    /// Seconds to prepare the scene for rendering (part of the render cost).
    pub prepare_render_seconds: f64,
    /// Each measurement's wall time in seconds, in order.
    pub stages: Vec<(&'static str, f64)>,
}

fn timed<T>(stages: &mut Vec<(&'static str, f64)>, name: &'static str, f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    stages.push((name, start.elapsed().as_secs_f64()));
    out
}

/// Records the [`ErrorStats`] and the histogram of `distances` under `name`.
fn stats_and_histogram(name: &str, distances: &[f32], e: &mut Evaluation) {
    e.histograms.insert(
        name.to_owned(),
        ErrorHistogram::from_distances(distances, e.diagonal),
    );
    let mut d = distances.to_vec();
    e.error.insert(
        name.to_owned(),
        ErrorStats::from_distances(&mut d, e.diagonal),
    );
}

/// Per-distance results the per-patch rows are built from.
struct Distances {
    /// Filled nodes to the source, in scene order.
    nodes: Vec<f32>,
    /// Source samples (or cloud points) to the patch surface.
    samples: Vec<f32>,
    /// The patch of each sample's nearest point.
    owners: Vec<u32>,
}

/// Measures `scene` against `source` (see the module docs). `source_path` names the source
/// in errors.
pub fn evaluate(
    scene: &Scene,
    source: &Source,
    source_path: &Path,
    options: &EvalOptions,
) -> Result<Evaluation, EvalError> {
    if scene.filled_node_count() == 0 {
        return Err(EvalError::EmptyScene);
    }
    if let Some(o) = source_overlap(scene, source).filter(|o| !o.meets) {
        return Err(EvalError::NoOverlap {
            path: source_path.to_path_buf(),
            source_box: box_text(o.source),
            scene_box: box_text(o.scene),
        });
    }
    let diagonal = source.diagonal();
    let start = Instant::now();
    let prepared = PreparedScene::new(scene);
    let prepare_render_seconds = start.elapsed().as_secs_f64();
    let mut e = Evaluation {
        error: BTreeMap::new(),
        histograms: BTreeMap::new(),
        diagonal,
        source_samples: 0,
        patches: Vec::new(),
        bound: quantization_bound(&[], diagonal, false),
        image: None,
        image_note: None,
        cloud: None,
        prepare_render_seconds,
        stages: Vec::new(),
    };
    let d = match source {
        Source::Mesh(mesh) => measure_mesh(&mut e, scene, &prepared, mesh, options)?,
        Source::Cloud(cloud) => {
            e.image_note = options.image.as_ref().map(|_| CLOUD_IMAGE_NOTE);
            measure_cloud(&mut e, scene, cloud).map_err(|source| EvalError::Cloud {
                path: source_path.to_path_buf(),
                source,
            })?
        }
    };
    e.source_samples = d.samples.len();
    e.patches = per_patch_errors(scene, &d.nodes, &d.samples, &d.owners);
    e.bound = quantization_bound(&e.patches, diagonal, matches!(source, Source::Mesh(_)));
    Ok(e)
}

/// `node_to_surface`, `surface_to_patch` and the image error against a mesh.
fn measure_mesh(
    e: &mut Evaluation,
    scene: &Scene,
    prepared: &PreparedScene,
    mesh: &TriangleMesh,
    options: &EvalOptions,
) -> Result<Distances, EvalError> {
    let nodes = timed(&mut e.stages, "node_to_surface", || {
        node_to_surface_distances(scene, mesh, &Bvh::new(mesh))
    });
    let (distances, owners): (Vec<f32>, Vec<u32>) =
        timed(&mut e.stages, "surface_to_patch", || {
            sampled_surface_to_patch(scene, mesh, sample_count(mesh), options.seed, |d, p| (d, p))
                .into_iter()
                .unzip()
        });
    stats_and_histogram("node_to_surface", &nodes, e);
    stats_and_histogram("surface_to_patch", &distances, e);
    if let Some(image_options) = &options.image {
        // A colourless scene is compared with a grey source: colour would only add error.
        let mut image_options = image_options.clone();
        image_options.colour_source &= scene.channel() != spatch_format::ColourChannel::None;
        let image = timed(&mut e.stages, "image", || {
            image_error(prepared, mesh, &image_options)
        })?;
        e.image = Some(image);
    }
    Ok(Distances {
        nodes,
        samples: distances,
        owners,
    })
}

/// `cloud_to_patch` and `node_to_cloud` as `spatch-cloud` measures them, with histograms
/// and per-patch distances of this crate's own.
fn measure_cloud(
    e: &mut Evaluation,
    scene: &Scene,
    cloud: &PointCloud,
) -> Result<Distances, spatch_cloud::CloudError> {
    let spacing = timed(&mut e.stages, "cloud_spacing", || {
        spatch_cloud::estimate_spacing(&cloud.positions)
    })?
    .spacing;
    let start = Instant::now();
    let distances = spatch_cloud::cloud_error_distances(cloud, scene)?;
    let measured = CloudErrorReport::from_distances(
        &distances,
        spacing,
        f64::from(cloud.bounds().diagonal()),
        start.elapsed().as_secs_f64(),
    );
    e.stages.push(("cloud_error", measured.seconds));
    e.error.extend(cloud_error_entries(&measured));
    let spatch_cloud::CloudErrorDistances {
        to_patch: samples,
        owners,
        to_cloud: nodes,
    } = distances;
    e.histograms.insert(
        "node_to_cloud".to_owned(),
        ErrorHistogram::from_distances(&nodes, e.diagonal),
    );
    e.histograms.insert(
        "cloud_to_patch".to_owned(),
        ErrorHistogram::from_distances(&samples, e.diagonal),
    );
    e.cloud = Some(CloudFigures {
        spacing: f64::from(spacing),
        share_beyond_2x_spacing: measured.cloud_to_patch.share_beyond_2x_spacing,
    });
    Ok(Distances {
        nodes,
        samples,
        owners,
    })
}
