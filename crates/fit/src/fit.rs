//! Region → patches: the fitter's driver.
//!
//! Per region (in parallel, results collected in region order so the output never depends on
//! the thread count):
//! 1. frame: ẑ = the cone axis, x̂/ŷ along the minimum-area rectangle of the projected region
//!    (`frame_fit`);
//! 2. lattice: the rectangle cut into whole cells of about the target spacing, widened by the
//!    overlap rings (`lattice`);
//! 3. needed nodes and the neighbourhood that may fill them (`overlap`);
//! 4. node heights by rays along −z onto region and neighbourhood (`node_cast`);
//! 5. one quantizer for the region (`quantize`);
//! 6. the filled part of the lattice cut into windows of at most `grid` nodes per side
//!    sharing their boundary nodes, each cropped to its filled nodes and kept when it has a
//!    drawable cell; colours sampled at the nodes' hits (`colour`).
//!
//! Windows of one region share the lattice and the quantizer, so their shared boundary nodes
//! are the same points: splitting a region opens no crack.
//!
//! Cost per region: O(lattice nodes + Σ face footprints); memory O(lattice nodes).

use glam::{DVec2, Vec3};
use rayon::prelude::*;
use spatch_format::{ColourChannel, Frame, GridSize, Patch, EMPTY};
use spatch_mesh::{FaceAdjacency, FaceId, TriangleMesh};

use crate::boundary_reach::reach_past_boundaries;
use crate::colour::{choose_channel, node_colour, Footprint};
use crate::colour_grid::{grid_factor, sample_colour_grid, SampleFaces};
use crate::frame_fit::{basis_from_axis, min_area_rect, PlaneRect};
use crate::lattice::Lattice;
use crate::node_cast::{cast_nodes, Hit};
use crate::overlap::{needed_nodes, neighbourhood};
use crate::quantize::{choose_quantizer, quantize_height};
use crate::texture_spacing::{region_texel_size, texture_spacings};
use crate::{default_spacing, FitError, FitOptions, TextureDetail};

/// One region to fit: its faces and the axis of its normal cone.
#[derive(Debug, Clone, Copy)]
pub struct FitRegion<'a> {
    /// The region's faces, sorted by id, without duplicates.
    pub faces: &'a [FaceId],
    /// Axis of the region's normal cone (any non-zero length; normalized here). It becomes the
    /// patches' z axis: the direction the region is seen from.
    pub axis: Vec3,
}

/// Counts gathered while fitting.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FitStats {
    /// Regions given.
    pub regions: usize,
    /// Regions that gave no patch (no face visible along their axis).
    pub empty_regions: usize,
    /// Regions split into more than one patch because they exceed the grid.
    pub split_regions: usize,
    /// Regions too thin for the target spacing that were fitted at a finer one (see
    /// [`MAX_REFINEMENTS`]).
    pub refined_regions: usize,
    /// Patches made.
    pub patches: usize,
    /// Patches that need 16-bit displacements.
    pub wide_patches: usize,
    /// Grid nodes of all patches, filled or not.
    pub nodes: usize,
    /// Filled nodes of all patches.
    pub filled_nodes: usize,
    /// Patches with a colour grid ([`FitOptions::colour_grid_texels`]).
    pub colour_grids: usize,
    /// Colour samples of those grids.
    pub colour_samples: usize,
}

/// What [`fit_regions`] returns.
#[derive(Debug, Clone)]
pub struct FitOutput {
    /// The patches, region by region in input order.
    pub patches: Vec<Patch>,
    /// The colour channel the patches use (their colours match it).
    pub channel: ColourChannel,
    /// The node spacing used (the target; each patch may be slightly finer).
    pub spacing: f32,
    /// Counts.
    pub stats: FitStats,
    /// How much texture detail the fit kept, or `None` when no region is textured (or
    /// [`FitOptions::texels_per_node`] is 0).
    pub texture: Option<TextureDetail>,
}

/// Fits every region of `mesh` with patches (see the module docs).
///
/// `adjacency` must be the face adjacency of `mesh`; regions must name faces of `mesh`.
/// Regions need not cover the mesh, and may overlap. The result is deterministic: the same
/// inputs give the same patches whatever the number of threads.
pub fn fit_regions(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    regions: &[FitRegion<'_>],
    options: &FitOptions,
) -> Result<FitOutput, FitError> {
    fit_regions_counted(mesh, adjacency, regions, options, &|_, _| {})
}

/// [`fit_regions`], calling `on_region(done, total)` from the worker threads as each
/// region is fitted (for a progress display; `done` counts up to `total` = the number of
/// regions, in no particular order of regions). Costs one atomic add per region.
pub fn fit_regions_counted(
    mesh: &TriangleMesh,
    adjacency: &FaceAdjacency,
    regions: &[FitRegion<'_>],
    options: &FitOptions,
    on_region: &(dyn Fn(usize, usize) + Sync),
) -> Result<FitOutput, FitError> {
    options.validate()?;
    let spacing = match options.spacing {
        Some(s) => s,
        None => default_spacing(mesh).ok_or(FitError::NoSurface)?,
    };
    let with_colour = options.colour && mesh.has_colour();
    let textured = with_colour
        .then(|| texture_spacings(mesh, regions, spacing, options))
        .flatten();
    let (region_spacings, texture) = match textured {
        Some((s, detail)) => (Some(s), Some(detail)),
        None => (None, None),
    };
    let shared = SharedFit {
        mesh,
        adjacency,
        options,
        spacing,
        region_spacings: region_spacings.as_deref(),
        with_colour,
    };
    let fitted = fit_each_region(&shared, regions, on_region)?;
    let (patches, stats) = gather_patches(fitted);
    let channel = choose_channel(&patches);
    Ok(FitOutput {
        patches,
        channel,
        spacing,
        stats,
        texture,
    })
}

/// What the fit of every region of one call shares, before the region's own spacing.
struct SharedFit<'a> {
    mesh: &'a TriangleMesh,
    adjacency: &'a FaceAdjacency,
    options: &'a FitOptions,
    /// The target spacing.
    spacing: f32,
    /// Per region, the spacing its texture asks for (finer than the target where the
    /// texture has detail; `None` without a texture or texels per node).
    region_spacings: Option<&'a [f32]>,
    with_colour: bool,
}

impl SharedFit<'_> {
    /// The job of region `index`.
    fn job(&self, index: usize, region: &FitRegion<'_>) -> RegionJob<'_> {
        let (mesh, options, spacing) = (self.mesh, self.options, self.spacing);
        let spacings = self.region_spacings;
        RegionJob {
            mesh,
            adjacency: self.adjacency,
            options,
            spacing: spacings.map_or(spacing, |s| s[index]),
            step_scale: spacings.map_or(1.0, |s| spacing / s[index]),
            with_colour: self.with_colour,
            footprint_colour: options.texels_per_node > 0.0,
            texel: (self.with_colour && options.colour_grid_texels > 0.0)
                .then(|| region_texel_size(mesh, region))
                .flatten(),
        }
    }
}

/// Fits every region on the worker threads, in the order of `regions`, counting each
/// finished one to `on_region`.
fn fit_each_region(
    shared: &SharedFit<'_>,
    regions: &[FitRegion<'_>],
    on_region: &(dyn Fn(usize, usize) + Sync),
) -> Result<Vec<RegionPatches>, FitError> {
    let finished = std::sync::atomic::AtomicUsize::new(0);
    regions
        .par_iter()
        .enumerate()
        .map(|(index, region)| {
            let patches = fit_region(&shared.job(index, region), index, region);
            let done = finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            on_region(done, regions.len());
            patches
        })
        .collect()
}

/// The regions' patches in order, and the counts of [`FitStats`].
fn gather_patches(fitted: Vec<RegionPatches>) -> (Vec<Patch>, FitStats) {
    let mut stats = FitStats {
        regions: fitted.len(),
        ..FitStats::default()
    };
    let mut patches = Vec::new();
    for region in fitted {
        match region.patches.len() {
            0 => stats.empty_regions += 1,
            1 => {}
            _ => stats.split_regions += 1,
        }
        stats.refined_regions += usize::from(region.refined);
        patches.extend(region.patches);
    }
    stats.patches = patches.len();
    for p in &patches {
        stats.nodes += p.grid().node_count();
        stats.filled_nodes += p.filled_count();
        if p.displacement_width() == spatch_format::DisplacementWidth::Bits16 {
            stats.wide_patches += 1;
        }
        if let Some(g) = p.colour_grid() {
            stats.colour_grids += 1;
            stats.colour_samples += g.samples().len();
        }
    }
    (patches, stats)
}

/// What every region's fit shares.
struct RegionJob<'a> {
    mesh: &'a TriangleMesh,
    adjacency: &'a FaceAdjacency,
    options: &'a FitOptions,
    spacing: f32,
    /// The mesh's spacing over this region's spacing (1 unless the texture made it finer):
    /// displacement steps follow the geometry's spacing, not the texture's.
    step_scale: f32,
    with_colour: bool,
    /// Textured nodes take their footprint's mean (on with [`FitOptions::texels_per_node`]).
    footprint_colour: bool,
    /// The region's texel size when it is textured and colour grids are on.
    texel: Option<f64>,
}

/// Fits one region (steps 1-6 of the module docs), refining the spacing up to
/// [`MAX_REFINEMENTS`] times while the region gives no patch (a thin region, narrower than a
/// cell at the target spacing).
fn fit_region(
    job: &RegionJob<'_>,
    index: usize,
    region: &FitRegion<'_>,
) -> Result<RegionPatches, FitError> {
    let axis = region.axis.normalize_or_zero();
    if !axis.is_finite() || axis == Vec3::ZERO {
        return Err(FitError::InvalidAxis { region: index });
    }
    let faces = faces_with_area(job.mesh, index, region)?;
    if faces.is_empty() {
        return Ok(RegionPatches::default());
    }
    // 1. Frame.
    let rect = region_rect(job.mesh, axis, &faces);
    // 2.-6. at the target spacing, then finer while the region gives no patch.
    fit_refining(job, index, &faces, &rect)
}

/// The faces of `region` (number `index`) with a positive area; an error when one is not
/// a face of `mesh`.
fn faces_with_area(
    mesh: &TriangleMesh,
    index: usize,
    region: &FitRegion<'_>,
) -> Result<Vec<FaceId>, FitError> {
    if let Some(&bad) = region.faces.iter().find(|f| f.index() >= mesh.face_count()) {
        return Err(FitError::FaceOutOfRange {
            region: index,
            face: bad.0,
            face_count: mesh.face_count(),
        });
    }
    // Faces edge-on or facing away from the axis cannot be seen by the patch.
    Ok(region
        .faces
        .iter()
        .copied()
        .filter(|&f| mesh.face_area(f) > 0.0)
        .collect())
}

/// The smallest rectangle holding the corners of `faces` projected along the unit `axis`
/// (step 1: the region's frame).
fn region_rect(mesh: &TriangleMesh, axis: Vec3, faces: &[FaceId]) -> PlaneRect {
    let basis = basis_from_axis(axis);
    let mut projected: Vec<DVec2> = Vec::with_capacity(faces.len() * 3);
    for &f in faces {
        for p in mesh.face_positions(f) {
            projected.push(DVec2::new(
                f64::from(p.dot(basis.x)),
                f64::from(p.dot(basis.y)),
            ));
        }
    }
    min_area_rect(basis, &mut projected)
}

/// Steps 2-6 over `rect` at the job's spacing, then at finer spacings while the region
/// (number `index`) gives no patch; empty when it never does.
fn fit_refining(
    job: &RegionJob<'_>,
    index: usize,
    faces: &[FaceId],
    rect: &PlaneRect,
) -> Result<RegionPatches, FitError> {
    let mut spacing = job.spacing;
    for refinement in 0..=MAX_REFINEMENTS {
        let (lattice, count) = Lattice::over_rect(rect, spacing, job.options.overlap);
        if count > job.options.max_region_nodes as u64 {
            if refinement > 0 {
                // Finer would cost more nodes than allowed: the region stays empty.
                break;
            }
            return Err(FitError::TooManyNodes {
                region: index,
                nodes: count,
                spacing,
                limit: job.options.max_region_nodes,
            });
        }
        let patches = fit_lattice(job, faces, &lattice, spacing)?;
        if !patches.is_empty() {
            return Ok(RegionPatches {
                patches,
                refined: refinement > 0,
            });
        }
        match finer_spacing(spacing, rect) {
            Some(finer) => spacing = finer,
            None => break,
        }
    }
    Ok(RegionPatches::default())
}

/// How many times the fitter refines the spacing of a thin region that gives no patch at
/// the target spacing. The first refinement brings the spacing to a quarter of the region's
/// narrow side at most; each further one halves it, while the region is narrower than
/// [`THIN_REGION_CELLS`] cells.
pub const MAX_REFINEMENTS: u32 = 6;

/// A region narrower than this many cells (of its rectangle's narrow side) that gives no
/// patch is fitted again at a finer spacing; a wider one is empty for another reason (its
/// faces are hidden along its axis) and is left empty.
pub const THIN_REGION_CELLS: f32 = 8.0;

/// The next spacing to try for a region over `rect` that gave no patch at `spacing`: half of
/// it, and at most a quarter of the rectangle's narrow side (a region narrower than a cell
/// cannot hold one with four filled corners); `None` when the region is not thin.
fn finer_spacing(spacing: f32, rect: &PlaneRect) -> Option<f32> {
    let size = rect.max - rect.min;
    let narrow = size.x.min(size.y) as f32;
    if !(narrow > 0.0 && narrow < THIN_REGION_CELLS * spacing) {
        return None;
    }
    let finer = (0.5 * spacing).min(0.25 * narrow);
    (finer.is_finite() && finer > 0.0).then_some(finer)
}

/// The patches of one region, and whether they needed a finer spacing than the target.
#[derive(Default)]
struct RegionPatches {
    patches: Vec<Patch>,
    refined: bool,
}

/// Steps 3-6 of the module docs on one lattice of the region's faces.
fn fit_lattice(
    job: &RegionJob<'_>,
    faces: &[FaceId],
    lattice: &Lattice,
    spacing: f32,
) -> Result<Vec<Patch>, FitError> {
    let (needed, around, mut hits) = cast_lattice(job, faces, lattice);
    // 5. Quantizer, on the heights the mesh gave.
    let Some((h_min, h_max)) = hit_height_range(&hits) else {
        return Ok(Vec::new());
    };
    let (mesh, adjacency) = (job.mesh, job.adjacency);
    let range = h_min..=h_max;
    reach_past_boundaries(mesh, adjacency, faces, lattice, &needed, range, &mut hits);
    let step_spacing = spacing * job.step_scale;
    let quantizer = choose_quantizer(
        h_max - h_min,
        step_spacing,
        job.options.max_step_error * step_spacing,
    )?;
    let codes = height_codes(&hits, &quantizer, h_min);
    // 6. Windows.
    let nodes = LatticeNodes {
        lattice,
        hits: &hits,
        codes: &codes,
        quantized: (&quantizer, h_min),
    };
    let faces = SampleFaces {
        region: faces,
        around: &around,
    };
    window_patches(job, &nodes, faces)
}

/// Steps 3 and 4 of the module docs: which nodes the region needs, the faces around it, and
/// the hits of rays cast at the needed nodes, first against the region's own faces, then
/// (for nodes those missed) against the faces around it.
fn cast_lattice(
    job: &RegionJob<'_>,
    faces: &[FaceId],
    lattice: &Lattice,
) -> (Vec<bool>, Vec<FaceId>, Vec<Hit>) {
    let mesh = job.mesh;
    let needed = needed_nodes(mesh, faces, lattice, job.options.overlap);
    let mut hits = vec![Hit::NONE; lattice.cols * lattice.rows];
    cast_nodes(mesh, faces, lattice, &needed, None, &mut hits);
    let options = job.options;
    let around = neighbourhood(
        mesh,
        job.adjacency,
        faces,
        (lattice, &needed),
        (options.neighbourhood_rings, options.max_neighbour_tilt_deg),
    );
    let locked: Vec<bool> = hits.iter().map(Hit::is_hit).collect();
    cast_nodes(mesh, &around, lattice, &needed, Some(&locked), &mut hits);
    (needed, around, hits)
}

/// The lowest and highest height among the nodes that hit the mesh; `None` when none did.
fn hit_height_range(hits: &[Hit]) -> Option<(f32, f32)> {
    let (mut h_min, mut h_max) = (f32::INFINITY, f32::NEG_INFINITY);
    for h in hits.iter().filter(|h| h.is_hit()) {
        h_min = h_min.min(h.height);
        h_max = h_max.max(h.height);
    }
    (h_min <= h_max).then_some((h_min, h_max))
}

/// Every node's displacement code under `quantizer` (heights from `h_min`), [`EMPTY`] where
/// its ray missed.
fn height_codes(hits: &[Hit], quantizer: &spatch_format::Quantizer, h_min: f32) -> Vec<u16> {
    hits.iter()
        .map(|h| {
            if h.is_hit() {
                quantize_height(quantizer, h_min, h.height)
            } else {
                EMPTY
            }
        })
        .collect()
}

/// A region's lattice after its rays and quantization: what its windows are cut from.
struct LatticeNodes<'a> {
    lattice: &'a Lattice,
    hits: &'a [Hit],
    codes: &'a [u16],
    /// The quantizer and the height its code 0 stands for.
    quantized: (&'a spatch_format::Quantizer, f32),
}

/// Step 6 of the module docs: the filled nodes cut into windows of at most the grid's cells
/// per side, one patch (with its colour grid when asked) per window that holds a patch.
fn window_patches(
    job: &RegionJob<'_>,
    nodes: &LatticeNodes<'_>,
    faces: SampleFaces<'_>,
) -> Result<Vec<Patch>, FitError> {
    let (lattice, codes) = (nodes.lattice, nodes.codes);
    let whole = ((0, lattice.cols - 1), (0, lattice.rows - 1));
    let Some(filled) = filled_bounds(codes, lattice, whole.0, whole.1) else {
        return Ok(Vec::new());
    };
    let max_cells = job.options.grid as usize - 1;
    let mut patches = Vec::new();
    for (ia, ib) in split_span(filled.0, max_cells) {
        for (ja, jb) in split_span(filled.1, max_cells) {
            let Some(window) = filled_bounds(codes, lattice, (ia, ib), (ja, jb)) else {
                continue;
            };
            let made = make_patch(job, lattice, nodes.hits, codes, window, nodes.quantized)?;
            if let Some(patch) = made {
                patches.push(with_colour_grid(job, faces, lattice, window, patch)?);
            }
        }
    }
    Ok(patches)
}

/// The inclusive node bounds `((i0, i1), (j0, j1))` of the filled nodes inside the window
/// `is × js`, or `None` when it holds none.
fn filled_bounds(
    codes: &[u16],
    lattice: &Lattice,
    is: (usize, usize),
    js: (usize, usize),
) -> Option<((usize, usize), (usize, usize))> {
    let (mut i0, mut i1, mut j0, mut j1) = (usize::MAX, 0, usize::MAX, 0);
    for j in js.0..=js.1 {
        for i in is.0..=is.1 {
            if codes[lattice.index(i, j)] != EMPTY {
                i0 = i0.min(i);
                i1 = i1.max(i);
                j0 = j0.min(j);
                j1 = j1.max(j);
            }
        }
    }
    (i0 <= i1).then_some(((i0, i1), (j0, j1)))
}

/// Splits the inclusive node span `[a, b]` into as few windows of at most `max_cells` cells as
/// possible, of nearly equal size, each sharing its last node with the next window's first.
fn split_span((a, b): (usize, usize), max_cells: usize) -> Vec<(usize, usize)> {
    let cells = b - a;
    let windows = cells.div_ceil(max_cells).max(1);
    (0..windows)
        .map(|k| (a + k * cells / windows, a + (k + 1) * cells / windows))
        .collect()
}

/// `patch` (over the node window starting at `(i0, j0)`) with a colour grid when its region is
/// textured finer than its spacing (`colour_grid`).
fn with_colour_grid(
    job: &RegionJob<'_>,
    faces: SampleFaces<'_>,
    lattice: &Lattice,
    ((i0, _), (j0, _)): ((usize, usize), (usize, usize)),
    patch: Patch,
) -> Result<Patch, FitError> {
    let spacing = lattice.spacing[0].max(lattice.spacing[1]);
    let factor = job
        .texel
        .and_then(|t| grid_factor(spacing, t, job.options.colour_grid_texels));
    let (Some(factor), Some(texel), true) = (factor, job.texel, job.with_colour) else {
        return Ok(patch);
    };
    let texels = f64::from(spacing) / f64::from(factor) / texel;
    let window = ((i0, j0), patch.grid());
    match sample_colour_grid(job.mesh, faces, lattice, window, factor, texels) {
        Some(grid) => Ok(patch.with_colour_grid(grid)?),
        None => Ok(patch),
    }
}

/// The patch over the node window `((i0, i1), (j0, j1))`, or `None` when it has no drawable
/// cell (a single row or column, or no cell with four filled corners).
fn make_patch(
    job: &RegionJob<'_>,
    lattice: &Lattice,
    hits: &[Hit],
    codes: &[u16],
    ((i0, i1), (j0, j1)): ((usize, usize), (usize, usize)),
    (quantizer, h_min): (&spatch_format::Quantizer, f32),
) -> Result<Option<Patch>, FitError> {
    if i1 == i0 || j1 == j0 {
        return Ok(None);
    }
    let window = NodeWindow {
        lattice,
        corner: (i0, j0),
        cols: i1 - i0 + 1,
        rows: j1 - j0 + 1,
    };
    if !window.has_drawable_cell(codes) {
        return Ok(None);
    }
    let base = window.lowest_code(codes);
    let (displacements, colours) = window.node_values(job, hits, codes, base);
    let frame = window.frame(quantizer, h_min, base)?;
    let grid = GridSize::new(window.cols as u32, window.rows as u32)?;
    Ok(Some(Patch::new(frame, grid, displacements, colours)?))
}

/// The nodes of one patch: `cols × rows` nodes of the lattice from node `corner`.
struct NodeWindow<'a> {
    lattice: &'a Lattice,
    /// The lattice node `(i0, j0)` of the patch's node `(0, 0)`.
    corner: (usize, usize),
    cols: usize,
    rows: usize,
}

impl NodeWindow<'_> {
    /// The lattice index of the patch's node `(i, j)`.
    fn at(&self, i: usize, j: usize) -> usize {
        self.lattice.index(self.corner.0 + i, self.corner.1 + j)
    }

    /// Whether some cell has its four corners filled.
    fn has_drawable_cell(&self, codes: &[u16]) -> bool {
        (0..self.rows - 1).any(|j| {
            (0..self.cols - 1).any(|i| {
                [
                    self.at(i, j),
                    self.at(i + 1, j),
                    self.at(i, j + 1),
                    self.at(i + 1, j + 1),
                ]
                .iter()
                .all(|&k| codes[k] != EMPTY)
            })
        })
    }

    /// The lowest code of the filled nodes (`u16::MAX` when none is filled).
    fn lowest_code(&self, codes: &[u16]) -> u16 {
        let mut base = u16::MAX;
        for j in 0..self.rows {
            for i in 0..self.cols {
                let c = codes[self.at(i, j)];
                if c != EMPTY {
                    base = base.min(c);
                }
            }
        }
        base
    }

    /// Each node's displacement (its code above `base`, or [`EMPTY`]) and, when the job has
    /// colour, its colour, row by row.
    fn node_values(
        &self,
        job: &RegionJob<'_>,
        hits: &[Hit],
        codes: &[u16],
        base: u16,
    ) -> (Vec<u16>, Option<Vec<[u8; 4]>>) {
        let (lattice, cols, rows) = (self.lattice, self.cols, self.rows);
        let b = &lattice.basis;
        let footprint = Footprint {
            ax: b.x * lattice.spacing[0],
            ay: b.y * lattice.spacing[1],
            axis: b.z,
        };
        let job_footprint = job.footprint_colour.then_some(&footprint);
        let mut displacements = Vec::with_capacity(cols * rows);
        let mut colours = job.with_colour.then(|| Vec::with_capacity(cols * rows));
        for j in 0..rows {
            for i in 0..cols {
                let k = self.at(i, j);
                let c = codes[k];
                displacements.push(if c == EMPTY { EMPTY } else { c - base });
                if let Some(colours) = colours.as_mut() {
                    colours.push(if c == EMPTY {
                        [0; 4]
                    } else {
                        node_colour(job.mesh, hits[k].face, hits[k].bary, job_footprint)
                    });
                }
            }
        }
        (displacements, colours)
    }

    /// The patch's frame: origin at the corner node at the height of code `base` (heights
    /// from `h_min`), axes one cell and one `quantizer` step long.
    fn frame(
        &self,
        quantizer: &spatch_format::Quantizer,
        h_min: f32,
        base: u16,
    ) -> Result<Frame, FitError> {
        let (lattice, (i0, j0)) = (self.lattice, self.corner);
        let b = &lattice.basis;
        let step = quantizer.step();
        let origin = lattice.position(i0, j0, f64::from(h_min) + f64::from(base) * f64::from(step));
        Ok(Frame::new(
            origin,
            b.x * lattice.spacing[0],
            b.y * lattice.spacing[1],
            b.z * step,
        )?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_split_evenly_and_share_nodes() {
        assert_eq!(split_span((0, 16), 16), vec![(0, 16)]);
        assert_eq!(split_span((3, 3), 16), vec![(3, 3)]);
        assert_eq!(split_span((0, 20), 16), vec![(0, 10), (10, 20)]);
        let w = split_span((5, 45), 16);
        assert_eq!(w.len(), 3);
        assert!(w.windows(2).all(|p| p[0].1 == p[1].0));
        assert!(w.iter().all(|&(a, b)| b - a <= 16));
    }
}
