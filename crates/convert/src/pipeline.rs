//! The pipeline: load → prepare → adjacency → orient → segment → fit → edges → sides →
//! encode, each stage timed.
//!
//! Every stage is a call into the crate that owns it; this file only wires them together and
//! keeps the clock. The sharp-edge patch generator (a later stage) slots in between fit and
//! encode: its patches join the fitter's before the scene is built.

use std::path::Path;

use glam::DVec3;
use spatch_edges::{generate_edge_patches, generate_part_edge_patches, EdgeOptions, EdgeStats};

use crate::owned::{segment_owned, PartOwner};
use crate::sides::{apply_sides, find_mesh_sides, MeshSides, Winding};
use spatch_fit::{
    choose_channel, default_spacing, fit_regions_counted, FitError, FitOptions, FitOutput,
    FitRegion,
};
use spatch_format::{encode_scene, ColourChannel, Patch, Scene};
use spatch_mesh::{
    build_face_adjacency, load_mesh, orient_faces, prepare_mesh, FaceAdjacency, LoadWarning,
    OrientReport, PrepareReport, TriangleMesh,
};
use spatch_report::StageClock;
use spatch_segment::{segment, Region};

use crate::colour_budget::{floor_error_levels, hold_colour_budget};
use crate::{
    ColourGridReport, ConvertError, ConvertOptions, ConvertReport, Counts, OrientCounts,
    PrepareCounts,
};

/// What to convert.
#[derive(Debug, Clone)]
pub enum ConvertInput<'a> {
    /// A mesh file (`.obj`, `.gltf`, `.glb`, `.ply`, `.off`, `.stl`), loaded by `spatch-mesh`.
    Path(&'a Path),
    /// A mesh already in memory (the load stage then takes no time).
    Mesh(TriangleMesh),
}

/// A pipeline stage, announced to the progress callback as it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Stage {
    /// Reading the file.
    Load,
    /// Welding and cleaning.
    Prepare,
    /// Face adjacency.
    Adjacency,
    /// Winding every piece consistently and outward (`spatch_mesh::orient_faces`).
    Orient,
    /// Segmentation into regions.
    Segment,
    /// Fitting patches to regions.
    Fit,
    /// Sharp-edge patches.
    Edges,
    /// Two-sided marks of the patches an opening lets the eye see from behind.
    Sides,
    /// Encoding the container bytes.
    Encode,
}

impl Stage {
    /// The stage's name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Load => "load",
            Stage::Prepare => "prepare",
            Stage::Adjacency => "adjacency",
            Stage::Orient => "orient",
            Stage::Segment => "segment",
            Stage::Fit => "fit",
            Stage::Edges => "edges",
            Stage::Sides => "sides",
            Stage::Encode => "encode",
        }
    }

    /// All stages in pipeline order.
    pub const ALL: [Stage; 9] = [
        Stage::Load,
        Stage::Prepare,
        Stage::Adjacency,
        Stage::Orient,
        Stage::Segment,
        Stage::Fit,
        Stage::Edges,
        Stage::Sides,
        Stage::Encode,
    ];
}

/// The result of a conversion.
#[derive(Debug, Clone)]
pub struct Conversion {
    /// The patches.
    pub scene: Scene,
    /// The scene encoded as a `.spatch` file.
    pub bytes: Vec<u8>,
    /// The prepared source mesh the scene was fitted to (error is measured against it).
    pub mesh: TriangleMesh,
    /// What the loader worked around (typed; the report holds them as sentences).
    pub load_warnings: Vec<LoadWarning>,
    /// Timings and counts.
    pub report: ConvertReport,
}

/// Converts a mesh to patches with `options` (see the crate docs).
pub fn convert(
    input: ConvertInput<'_>,
    options: &ConvertOptions,
) -> Result<Conversion, ConvertError> {
    convert_with_progress(input, options, &|_| {})
}

/// What the pipeline tells a progress display.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ProgressEvent {
    /// A stage starts.
    Stage(Stage),
    /// Inside the current stage, `done` of `total` items are finished (the fit stage
    /// counts regions). Sent from worker threads, in increasing `done` per thread only.
    Count {
        /// Items finished so far.
        done: usize,
        /// Items of the stage.
        total: usize,
    },
}

/// [`convert`], calling `on_progress` as each stage starts and as the fit stage finishes
/// each region (for a progress display; it may be called from worker threads).
pub fn convert_with_progress(
    input: ConvertInput<'_>,
    options: &ConvertOptions,
    on_progress: &(dyn Fn(ProgressEvent) + Sync),
) -> Result<Conversion, ConvertError> {
    run_pipeline(input, options, None, on_progress)
}

/// [`convert`] of the part of a mesh one tile owns (see [`PartOwner`]): only the faces
/// `owner` owns are segmented, every face of `input` is there for the fitter to reach into,
/// and only the creases and corners `owner` owns get sharp-edge patches. A part that owns no face, or
/// whose faces give no patch, is [`ConvertError::NoPatches`].
pub fn convert_part(
    input: ConvertInput<'_>,
    owner: &dyn PartOwner,
    options: &ConvertOptions,
) -> Result<Conversion, ConvertError> {
    run_pipeline(input, options, Some(owner), &|_| {})
}

/// The prepared source every later stage reads: the mesh with its
/// adjacency and the node spacing.
struct Source {
    mesh: TriangleMesh,
    adjacency: FaceAdjacency,
    prepared: PrepareReport,
    /// The winding pass's counts (`None` when it did not run).
    oriented: Option<OrientReport>,
    load_warnings: Vec<LoadWarning>,
    spacing: f32,
}

/// The load, prepare, adjacency and orient stages.
fn prepare_source(
    clock: &mut Clock<'_>,
    input: ConvertInput<'_>,
    options: &ConvertOptions,
    owner: Option<&dyn PartOwner>,
) -> Result<Source, ConvertError> {
    let (raw, load_warnings) = clock.run(Stage::Load, || match input {
        ConvertInput::Path(path) => load_mesh(path).map(|l| (l.mesh, l.warnings)),
        ConvertInput::Mesh(mesh) => Ok((mesh, Vec::new())),
    })?;
    let (mut mesh, prepared) = clock.run(Stage::Prepare, || prepare_mesh(&raw, &options.prepare));
    drop(raw);
    let no_surface = ConvertError::NoSurface {
        faces: prepared.input_faces,
    };
    if mesh.face_count() == 0 {
        return Err(no_surface);
    }
    let spacing = match options.fit.spacing {
        Some(s) => s,
        None => default_spacing(&mesh).ok_or(no_surface)?,
    };
    let mut adjacency = clock.run(Stage::Adjacency, || build_face_adjacency(&mesh));
    // A tile's part keeps the source's winding: turning a cut-out piece over by its own
    // volume could disagree with the tiles beside it.
    let oriented = clock.run(Stage::Orient, || {
        (options.orient && owner.is_none()).then(|| orient_faces(&mut mesh, &mut adjacency))
    });
    Ok(Source {
        mesh,
        adjacency,
        prepared,
        oriented,
        load_warnings,
        spacing,
    })
}

/// The segment stage: the regions of the whole mesh, or of what `owner`
/// owns.
fn segment_regions(
    source: &Source,
    options: &ConvertOptions,
    owner: Option<&dyn PartOwner>,
) -> Result<Vec<Region>, ConvertError> {
    let mut segment_options = options.segment.clone();
    if segment_options.max_extent.is_infinite() {
        segment_options.max_extent = (options.fit.grid.saturating_sub(1)) as f32 * source.spacing;
    }
    let (mesh, adjacency) = (&source.mesh, &source.adjacency);
    Ok(match owner {
        None => segment(mesh, adjacency, &segment_options).map(|(s, _)| s.regions)?,
        Some(owner) => segment_owned(mesh, owner, &segment_options)?,
    })
}

/// The fit stage: a patch (or several) per region, counted through
/// `on_progress`.
fn fit_patches(
    source: &Source,
    regions: &[Region],
    fit_options: &FitOptions,
    on_progress: &(dyn Fn(ProgressEvent) + Sync),
) -> Result<FitOutput, FitError> {
    let regions: Vec<FitRegion<'_>> = regions
        .iter()
        .map(|r| FitRegion {
            faces: &r.faces,
            axis: r.axis,
        })
        .collect();
    let count = |done, total| on_progress(ProgressEvent::Count { done, total });
    fit_regions_counted(
        &source.mesh,
        &source.adjacency,
        &regions,
        fit_options,
        &count,
    )
}

/// The edges stage (when `options` asks for sharp edges): the edge patches
/// closing `patches`' creases at `spacing`, and their counts.
fn edge_patches(
    source: &Source,
    patches: &[Patch],
    spacing: f32,
    edge_options: EdgeOptions,
    owner: Option<&dyn PartOwner>,
) -> Result<(Vec<Patch>, EdgeStats), ConvertError> {
    let (mesh, adjacency) = (&source.mesh, &source.adjacency);
    Ok(match owner {
        None => generate_edge_patches(mesh, adjacency, patches, spacing, &edge_options)?,
        Some(owner) => {
            generate_part_edge_patches(mesh, adjacency, patches, spacing, &edge_options, &|w| {
                owner.owns_point(w)
            })?
        }
    })
}

/// The edges stage's inputs besides the patches: the prepared source, the spacing of the
/// edge patches, and the owner of a tile's part.
struct EdgeStage<'a> {
    source: &'a Source,
    spacing: f32,
    owner: Option<&'a dyn PartOwner>,
}

impl EdgeStage<'_> {
    /// The edge patches of `patches` and their counts, timed on `clock`, when `options` asks
    /// for sharp edges (coloured as `fit_options` says); `None` otherwise.
    fn run(
        &self,
        clock: &mut Clock<'_>,
        patches: &[Patch],
        options: &ConvertOptions,
        fit_options: &FitOptions,
    ) -> Result<Option<(Vec<Patch>, EdgeStats)>, ConvertError> {
        let Some(mut edge_options) = options.sharp_edges else {
            return Ok(None);
        };
        edge_options.colour = fit_options.colour;
        let found = clock.run(Stage::Edges, || {
            edge_patches(self.source, patches, self.spacing, edge_options, self.owner)
        })?;
        Ok(Some(found))
    }
}

/// Refuses a conversion that gave neither surface `patches` nor edge patches
/// ([`ConvertError::NoPatches`] at `spacing`).
fn require_patches(
    patches: &[Patch],
    edges: &Option<(Vec<Patch>, EdgeStats)>,
    spacing: f32,
) -> Result<(), ConvertError> {
    if patches.is_empty() && edges.as_ref().is_none_or(|(e, _)| e.is_empty()) {
        return Err(ConvertError::NoPatches {
            spacing,
            refinements: spatch_fit::MAX_REFINEMENTS,
        });
    }
    Ok(())
}

/// How the source is wound, for the sides stage: as the winding pass
/// left it, turned over, or unknown.
fn source_winding(source: &Source) -> Winding {
    let prepared = &source.prepared;
    // A file that gave most faces a twin wound the other way asked for both sides.
    let mostly_mirrored = 2 * prepared.dropped_mirrored >= prepared.output_faces.max(1);
    // Not oriented (`--keep-winding`, a tile's part), the copy kept of each mirrored pair
    // is wound as it came: nothing says where such a file's outside is.
    match &source.oriented {
        Some(o) if o.conflicting_edges > 0 => Winding::Unknown,
        Some(o) if o.wound_inward || mostly_mirrored => Winding::Turned,
        Some(_) => Winding::AsWound,
        None if mostly_mirrored => Winding::Unknown,
        None => Winding::AsWound,
    }
}

/// The sides stage: where the surface is open and which patches are seen
/// from both sides (set on `patches` and the edge patches).
fn find_sides(
    source: &Source,
    patches: &mut [Patch],
    edges: &mut Option<(Vec<Patch>, EdgeStats)>,
) -> MeshSides {
    // Patches reach half a cell past open boundaries; a spacing covers that and the fit.
    let winding = source_winding(source);
    let mut found = find_mesh_sides(&source.mesh, &source.adjacency, winding, source.spacing);
    found.counts.two_sided_patches = apply_sides(patches, found.sides);
    if let Some((edge_patches, _)) = edges {
        found.counts.two_sided_patches += apply_sides(edge_patches, found.sides);
    }
    found
}

/// What the encode stage gives: the scene, its file, the bytes the edge
/// patches add and the colour grids' report.
struct Encoded {
    scene: Scene,
    bytes: Vec<u8>,
    edge_bytes: usize,
    colour_grids: Option<ColourGridReport>,
}

/// The encode stage: the surface and edge patches as one scene (colour
/// grids held to their budget), its file, and what the edge patches add
/// to it (the same scene encoded without them).
fn encode(
    origin: DVec3,
    (mut patches, mut channel): (Vec<Patch>, ColourChannel),
    edges: Option<&[Patch]>,
    sides: MeshSides,
    options: &ConvertOptions,
) -> Result<Encoded, ConvertError> {
    let surface_patches = patches.len();
    let with_edges = edges.is_some_and(|e| !e.is_empty());
    if let Some(edge_patches) = edges {
        patches.extend_from_slice(edge_patches);
        channel = choose_channel(&patches);
    }
    let colour_grids = hold_grids(&mut patches, channel, options)?;
    // Surface patches come first, so no grid they keep refers to an edge patch's.
    let mut edge_bytes = 0;
    if with_edges {
        let surface_only = &patches[..surface_patches];
        let surface = Scene::new(origin, choose_channel(surface_only), surface_only.to_vec())?
            .with_openings(sides.openings.clone())
            .with_inside_box(sides.inside_box);
        edge_bytes = encode_scene(&surface, &options.write)?.len();
    }
    let scene = Scene::new(origin, channel, patches)?
        .with_openings(sides.openings)
        .with_inside_box(sides.inside_box);
    let bytes = encode_scene(&scene, &options.write)?;
    if edge_bytes > 0 {
        edge_bytes = bytes.len().saturating_sub(edge_bytes);
    }
    Ok(Encoded {
        scene,
        bytes,
        edge_bytes,
        colour_grids,
    })
}

impl From<&PrepareReport> for PrepareCounts {
    fn from(prepared: &PrepareReport) -> Self {
        Self {
            input_vertices: prepared.input_vertices,
            input_faces: prepared.input_faces,
            welded_vertices: prepared.welded_vertices,
            dropped_degenerate: prepared.dropped_degenerate,
            dropped_zero_area: prepared.dropped_zero_area,
            dropped_duplicate: prepared.dropped_duplicate,
            dropped_mirrored: prepared.dropped_mirrored,
            kept_repeats: prepared.kept_repeats,
            output_vertices: prepared.output_vertices,
            output_faces: prepared.output_faces,
        }
    }
}

/// The pipeline, segmenting only what `owner` owns when it is given.
fn run_pipeline(
    input: ConvertInput<'_>,
    options: &ConvertOptions,
    owner: Option<&dyn PartOwner>,
    on_progress: &(dyn Fn(ProgressEvent) + Sync),
) -> Result<Conversion, ConvertError> {
    let mut clock = Clock {
        times: StageClock::new(),
        on_progress,
    };
    let source = prepare_source(&mut clock, input, options, owner)?;
    let spacing = source.spacing;
    let regions = clock.run(Stage::Segment, || segment_regions(&source, options, owner))?;
    let mut fit_options = options.fit;
    fit_options.spacing = Some(spacing);
    let fitted = clock.run(Stage::Fit, || {
        fit_patches(&source, &regions, &fit_options, on_progress)
    })?;
    let (stats, texture) = (fitted.stats, fitted.texture);
    let mut patches = fitted.patches;
    // Textured regions may be finer than `spacing`: the edge patches then follow the finest
    // surface spacing, so that their strips match the patches they close.
    let edge_spacing = texture.map_or(spacing, |t| t.finest_spacing.min(spacing));
    let edge_stage = EdgeStage {
        source: &source,
        spacing: edge_spacing,
        owner,
    };
    let mut edges = edge_stage.run(&mut clock, &patches, options, &fit_options)?;
    require_patches(&patches, &edges, spacing)?;
    let sides = clock.run(Stage::Sides, || {
        find_sides(&source, &mut patches, &mut edges)
    });
    let sides_counts = sides.counts;
    let encoded = clock.run(Stage::Encode, || {
        let edge_list = edges.as_ref().map(|(e, _)| e.as_slice());
        let surface = (patches, fitted.channel);
        encode(source.mesh.origin, surface, edge_list, sides, options)
    })?;
    let outcome = Outcome {
        regions: regions.len(),
        fit: stats,
        texture,
        edges: edges.map(|(_, s)| s),
        sides: sides_counts,
    };
    Ok(conversion_of(clock, source, encoded, outcome))
}

/// The conversion: the encoded scene and its file, the prepared mesh, the load warnings and
/// the report of the stages `clock` timed.
fn conversion_of(
    clock: Clock<'_>,
    source: Source,
    encoded: Encoded,
    outcome: Outcome,
) -> Conversion {
    let report = conversion_report(clock, &source, &encoded, outcome);
    Conversion {
        scene: encoded.scene,
        bytes: encoded.bytes,
        mesh: source.mesh,
        load_warnings: source.load_warnings,
        report,
    }
}

/// What the stages after the source's preparation found, for the report.
struct Outcome {
    /// Regions segmented.
    regions: usize,
    /// The fit's counts.
    fit: spatch_fit::FitStats,
    /// The texture's detail, when textured regions were fitted finer.
    texture: Option<spatch_fit::TextureDetail>,
    /// The sharp-edge stage's counts, when it ran.
    edges: Option<EdgeStats>,
    /// The sides stage's counts.
    sides: crate::SideCounts,
}

/// The report of a conversion whose stages `clock` timed.
fn conversion_report(
    clock: Clock<'_>,
    source: &Source,
    encoded: &Encoded,
    outcome: Outcome,
) -> ConvertReport {
    let scene = &encoded.scene;
    ConvertReport {
        counts: Counts::of(scene, encoded.bytes.len()),
        seconds: clock.times.total(),
        stages: clock.times.into_stages(),
        threads: rayon::current_num_threads(),
        spacing: source.spacing,
        triangles: source.mesh.face_count(),
        regions: outcome.regions,
        split_regions: outcome.fit.split_regions,
        refined_regions: outcome.fit.refined_regions,
        wide_patches: outcome.fit.wide_patches,
        texture: outcome.texture,
        colour_grids: encoded.colour_grids,
        colour: scene.channel().name(),
        diagonal: f64::from(source.mesh.diagonal()),
        prepare: PrepareCounts::from(&source.prepared),
        orient: source.oriented.map(OrientCounts::from),
        warnings: source
            .load_warnings
            .iter()
            .map(ToString::to_string)
            .collect(),
        edges: outcome.edges,
        edge_bytes: encoded.edge_bytes,
        sides: outcome.sides,
    }
}

/// Holds the colour grids of `patches` to the budget of `options` (measured against the
/// file without them), or `None` when no patch has one.
fn hold_grids(
    patches: &mut Vec<spatch_format::Patch>,
    channel: spatch_format::ColourChannel,
    options: &ConvertOptions,
) -> Result<Option<crate::ColourGridReport>, ConvertError> {
    if patches.iter().all(|p| p.colour_grid().is_none()) {
        return Ok(None);
    }
    let bare: Vec<_> = patches
        .iter()
        .map(|p| p.clone().without_colour_grid())
        .collect();
    let base = encode_scene(
        &Scene::new(glam::DVec3::ZERO, channel, bare)?,
        &options.write,
    )?
    .len();
    let budget = options.colour_budget.bytes(base);
    let max_error = floor_error_levels(options.colour_floor_db);
    Ok(hold_colour_budget(patches, channel, budget, max_error))
}

/// Times stages on the shared [`StageClock`] and announces them.
struct Clock<'a> {
    times: StageClock,
    on_progress: &'a (dyn Fn(ProgressEvent) + Sync),
}

impl Clock<'_> {
    fn run<T>(&mut self, stage: Stage, work: impl FnOnce() -> T) -> T {
        (self.on_progress)(ProgressEvent::Stage(stage));
        self.times.time(stage.name(), work)
    }
}
