//! One patch prepared once per scene and reused for every frame: its
//! model-space frame in f64, its normal cone and bounding sphere (at once:
//! every frame's culling reads them), and its mip pyramid, every level of
//! it built the first time a frame draws it (level 0 included: a view
//! culls about a quarter of a closed model's patches as facing away).
//!
//! Each level also keeps its nodes' unit patch-space normals (and albedos)
//! in the form the Phong resolve pass interpolates ([`LevelShading`]):
//! they do not depend on the view, so a frame reads them instead of copying
//! them into its projected nodes. They are built the first time a Phong
//! frame draws the level ([`PreparedPatch::shading`]), and kept.
//!
//! Cost: O(nodes) time; about 1.4× the patch's node memory, plus 16 bytes
//! per node of every level drawn so far for the normals (32 with colours).

use std::sync::{Mutex, MutexGuard, OnceLock, PoisonError};

use glam::{DMat3, DVec3};
use spatch_format::{ColourGrid, Patch, Sides, EMPTY};

use crate::grid::drawn_cells;
use crate::isa::Isa;
use crate::prepare::coarse_fit::{coarse_gap, coarse_gaps, Gaps};
use crate::prepare::cone::{compute_normal_cone, NormalCone};
use crate::prepare::corner_fill::FinerLevel;
use crate::prepare::level_shading::{level_slot_set, LevelShading};
use crate::prepare::mip::{
    coarse_level_count, halve, halve_level, halve_quartered, level_zero, MipLevel, MAX_MIP_LEVELS,
};
use crate::prepare::normal_buffer::SlotSet;

/// One patch ready to draw.
#[derive(Debug, Clone)]
pub(crate) struct PreparedPatch {
    /// Model-space origin (scene offset included).
    pub(crate) origin: DVec3,
    /// Level-0 axes `ax, ay, az` in model space.
    pub(crate) axes: [DVec3; 3],
    /// Unit axes as columns.
    pub(crate) rotation: DMat3,
    /// `(|az| / |ax|, |az| / |ay|)` at level 0.
    pub(crate) ratios: (f32, f32),
    pub(crate) cone: NormalCone,
    pub(crate) centre: DVec3,
    pub(crate) radius: f64,
    /// Which sides the scene says may be seen (automatic culling).
    pub(crate) sides: Sides,
    /// Level 0's grid size `[cols, rows]`.
    pub(crate) grid: [usize; 2],
    /// Level 0's used displacement range, found with the normal cone
    /// ([`crate::prepare::cone::ConeScan::d_range`]), so building level 0
    /// need not find it again.
    d_range: (u16, u16),
    /// True when every node of level 0 is filled (so every cell is drawn).
    full_grid: bool,
    /// True when the patch has per-node colours.
    node_colours: bool,
    /// Level 0's displacements and colours, which [`Self::level`] takes to
    /// build level 0.
    nodes: BaseNodes,
    /// The patch's colour grid (albedo finer than its nodes), read by the
    /// resolve pass at each pixel's position ([`crate::shade::colour_grid`]).
    pub(crate) colour_grid: Option<ColourGrid>,
    /// Per level of the mip pyramid ([`crate::prepare::mip`]), what is
    /// built the first time a frame asks for it. Why one vector: four (one
    /// per kind) were four allocations per patch, 1.4 M instructions of a
    /// one-frame bunny render (callgrind).
    levels: Vec<LazyLevel>,
    /// Level 1 with its outline cells drawn by quarters
    /// ([`QUARTERED_ONE`]), built the first time a frame asks for it.
    quartered_one: LazyLevel,
    /// How far level 0 strays from [`QUARTERED_ONE`], summed up
    /// ([`PreparedPatch::quartered_gaps`]).
    quartered_gaps: OnceLock<Gaps>,
    /// The instruction set the preparation kernels run with, here and on
    /// first use ([`Self::level`], [`Self::shading`]).
    isa: Isa,
}

/// A patch's level-0 nodes until level 0 is built: the build takes them
/// (empty after). Why taken, not copied: a copy of every drawn patch's
/// nodes (an allocation, a copy and a free each) was 0.5 M instructions of
/// a one-frame bunny render (callgrind, `spatch render bunny.spatch -o
/// out.png --threads 1`).
#[derive(Debug, Default)]
struct BaseNodes(Mutex<Nodes>);

/// A level's displacements and colours, as [`level_zero`] takes them.
type Nodes = (Vec<u16>, Option<Vec<[u8; 4]>>);

impl BaseNodes {
    /// Holds `nodes` until level 0 takes them.
    fn new(nodes: Nodes) -> Self {
        Self(Mutex::new(nodes))
    }

    /// The nodes, locked (a panic elsewhere leaves them as they were).
    fn lock(&self) -> MutexGuard<'_, Nodes> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The nodes, leaving none.
    fn take(&self) -> Nodes {
        std::mem::take(&mut *self.lock())
    }
}

impl Clone for BaseNodes {
    fn clone(&self) -> Self {
        Self::new(self.lock().clone())
    }
}

/// What a prepared patch builds of one mip level on first use, each part
/// boxed. Why boxed: a level's parts inline took 432 bytes, written when
/// the patch was prepared (every part's empty state) whether a frame ever
/// built them or not; for the bunny's 2,532 patches of five levels that
/// was 5.5 MB, where boxes take 72 bytes a level (88 since flat shading's
/// inputs have their own) and allocate only what is built (with the
/// prepared patches ordered in place, 480 fewer page faults of a one-image
/// bunny render; `perf stat`, 2 threads).
#[derive(Debug, Clone, Default)]
struct LazyLevel {
    /// The level ([`PreparedPatch::level`]): level 0 from the patch's
    /// nodes, the others from the level below.
    level: OnceLock<Box<MipLevel>>,
    /// The nodes' shading inputs ([`PreparedPatch::shading`]).
    shading: OnceLock<Box<LevelShading>>,
    /// The nodes' flat-shading inputs ([`PreparedPatch::flat_shading`]).
    flat_shading: OnceLock<Box<LevelShading>>,
    /// Above level 0: the shading inputs of the level below on this
    /// level's grid ([`PreparedPatch::fine_shading`]).
    fine_shading: OnceLock<Box<LevelShading>>,
    /// Above level 0: how far the level below strays from this level's
    /// surface at most, in codes ([`PreparedPatch::coarse_gap`]).
    coarse_gap: OnceLock<f32>,
    /// The normal-buffer slots of the level's used nodes
    /// ([`PreparedPatch::slot_set`]).
    slots: OnceLock<Box<SlotSet>>,
}

/// The corners of the box spanning a grid of `size` nodes and the
/// displacement codes `d_range`, in model space.
fn box_corners(
    origin: DVec3,
    axes: [DVec3; 3],
    size: [usize; 2],
    d_range: (u16, u16),
) -> [DVec3; 8] {
    let (d0, d1) = d_range;
    let (ci, cj) = ((size[0] - 1) as f64, (size[1] - 1) as f64);
    std::array::from_fn(|k| {
        origin
            + axes[0] * if k & 1 == 0 { 0.0 } else { ci }
            + axes[1] * if k & 2 == 0 { 0.0 } else { cj }
            + axes[2] * if k & 4 == 0 { d0 as f64 } else { d1 as f64 }
    })
}

impl PreparedPatch {
    /// `patch` ready to draw (its shading inputs are built on first use,
    /// [`Self::shading`]), with a copy of its nodes; `None` when it has no
    /// drawable cell.
    pub(crate) fn new(patch: &Patch, offset: DVec3, isa: Isa) -> Option<Self> {
        let mut prepared = Self::without_nodes(patch, offset, isa)?;
        prepared.nodes = BaseNodes::new((
            patch.displacements().to_vec(),
            patch.colours().map(<[_]>::to_vec),
        ));
        Some(prepared)
    }

    /// [`Self::new`] taking the patch's nodes instead of copying them.
    /// Why: the copies were 1.5 MB of fresh memory for the bunny's 2,532
    /// patches, 212 page faults of a one-image render.
    pub(crate) fn from_owned(patch: Patch, offset: DVec3, isa: Isa) -> Option<Self> {
        let mut prepared = Self::without_nodes(&patch, offset, isa)?;
        prepared.nodes = BaseNodes::new(patch.into_nodes());
        Some(prepared)
    }

    /// [`Self::new`] with no level-0 nodes yet.
    fn without_nodes(patch: &Patch, offset: DVec3, isa: Isa) -> Option<Self> {
        let size = [patch.grid().cols() as usize, patch.grid().rows() as usize];
        let displacements = patch.displacements();
        let frame = patch.frame();
        // `Frame::axes` is the unit axes times the lengths: found once.
        let (units, lengths) = (frame.unit_axes(), frame.lengths());
        let axes: [DVec3; 3] = std::array::from_fn(|k| (units[k] * lengths[k]).as_dvec3());
        let units = units.map(|a| a.as_dvec3());
        let rotation = DMat3::from_cols(units[0], units[1], units[2]);
        let [lx, ly, lz] = lengths;
        let ratios = (lz / lx, lz / ly);
        let origin = offset + frame.precise_origin();
        let scan = compute_normal_cone(displacements, size[0], ratios, &rotation, isa)?;
        let levels = 1 + coarse_level_count(displacements, size);
        let corners = box_corners(origin, axes, size, scan.d_range);
        let (lo, hi) = corners
            .iter()
            .fold((corners[0], corners[0]), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
        Some(Self {
            origin,
            axes,
            rotation,
            ratios,
            cone: scan.cone,
            centre: (lo + hi) * 0.5,
            radius: (hi - lo).length() * 0.5,
            sides: patch.sides(),
            grid: size,
            d_range: scan.d_range,
            full_grid: !displacements.contains(&EMPTY),
            node_colours: patch.colours().is_some(),
            nodes: BaseNodes::default(),
            colour_grid: patch.colour_grid().cloned(),
            levels: (0..levels).map(|_| LazyLevel::default()).collect(),
            quartered_one: LazyLevel::default(),
            quartered_gaps: OnceLock::new(),
            isa,
        })
    }

    /// The corners of the box of the patch's used nodes in model space.
    /// Why found again rather than kept from [`Self::new`]: the scene's
    /// bounds read them once, and carried beside every prepared patch they
    /// were 0.5 MB more to write (192 bytes a patch) in a one-image bunny
    /// render.
    pub(crate) fn box_corners(&self) -> [DVec3; 8] {
        box_corners(self.origin, self.axes, self.grid, self.d_range)
    }

    /// Mip level `m` (below [`Self::level_count`]), built from level
    /// `m - 1` the first time it is asked for. Why on first use: a view
    /// draws few levels (the 500² sphere: level 0 only), and the levels
    /// above 0 were 31 M of the sphere's 74 M instructions of pyramids
    /// (callgrind, `profile_sphere 500 1 1`).
    /// Level 0 too is built on first use. Why: its cell flags, closing
    /// flags, edge masks, used nodes and weights are read only by frames
    /// that draw it, and the quarter of the bunny's patches that face away
    /// at the automatic view were 8 M instructions of a one-frame render
    /// (callgrind, `spatch render bunny.spatch -o out.png --threads 1`).
    /// [`QUARTERED_ONE`] names level 1 with its outline cells drawn by
    /// quarters.
    pub(crate) fn level(&self, m: usize) -> &MipLevel {
        self.lazy(m).level.get_or_init(|| {
            Box::new(match m {
                0 => (self.isa).run(
                    #[inline(always)]
                    || level_zero(self.grid, self.nodes.take(), Some(self.d_range)),
                ),
                1 => self.level_one(halve),
                QUARTERED_ONE => self.level_one(halve_quartered),
                _ => halve_level(self.level(m - 1)).expect("a counted level halves"),
            })
        })
    }

    /// What is built on first use for level `m` ([`QUARTERED_ONE`]
    /// included).
    fn lazy(&self, m: usize) -> &LazyLevel {
        if m == QUARTERED_ONE {
            &self.quartered_one
        } else {
            &self.levels[m]
        }
    }

    /// Level 1 by `halving` ([`halve`] or [`halve_quartered`]): from the
    /// patch's nodes while level 0 is not built, else from level 0.
    fn level_one(&self, halving: Halving) -> MipLevel {
        self.level_one_from_nodes(halving).unwrap_or_else(|| {
            let base = self.level(0);
            halving(base.as_finer(), base.colours.as_deref()).expect("a counted level halves")
        })
    }

    /// Level 1 halved straight from the patch's nodes, while level 0 is not
    /// built (`None` once it is: it has taken the nodes). The same level
    /// as halving level 0 (tested). Why: where a patch is drawn at level 1
    /// (most of the bunny's at 500²), level 0's used nodes, closing flags
    /// and box were built only to be halved: 1,800 level-0 builds of a
    /// one-image bunny render.
    /// `halving` is [`halve`] or [`halve_quartered`].
    fn level_one_from_nodes(&self, halving: Halving) -> Option<MipLevel> {
        let nodes = self.nodes.lock();
        let (displacements, colours) = &*nodes;
        if displacements.is_empty() {
            return None;
        }
        let [cols, rows] = self.grid;
        let finer = FinerLevel {
            cols,
            rows,
            displacements,
            cell_flags: &drawn_cells(displacements, cols, rows),
            spacing: 1,
        };
        Some(halving(finer, colours.as_deref()).expect("a counted level halves"))
    }

    /// Level 0, built if no frame has asked for it yet, for changes that
    /// apply to every frame ([`crate::prepare::overlap`]).
    pub(crate) fn base_mut(&mut self) -> &mut MipLevel {
        self.level(0);
        self.levels[0]
            .level
            .get_mut()
            .expect("built by the line above")
    }

    /// Levels in the pyramid (level 0 included).
    pub(crate) fn level_count(&self) -> usize {
        self.levels.len()
    }

    /// The shading inputs of level `m`, built the first time a frame asks
    /// for them (on the thread that asks; the inputs depend on the level
    /// alone, so they are the same whoever builds them). Why on first use: a view draws few of a scene's
    /// levels (the 500² sphere: level 0 of 567 of 1,362 patches), so a
    /// one-frame render builds a fraction of them, and flat and Gouraud
    /// frames none (callgrind, `profile_sphere 500 1 1`).
    pub(crate) fn shading(&self, m: usize) -> &LevelShading {
        self.build_shading(m, None)
    }

    /// [`Self::shading`] for a frame that counts its normal lookups: when
    /// this call builds the shading inputs, it also finds the level's slot
    /// set ([`Self::slot_set`]) from the same displacement differences.
    /// Why: found on their own, the slot sets of a counted one-frame bunny
    /// render cost 3 M instructions more (callgrind, `spatch render
    /// bunny.spatch -o out.png --threads 1 --json`).
    pub(crate) fn counted_shading(&self, m: usize) -> &LevelShading {
        self.build_shading(m, Some(&self.lazy(m).slots))
    }

    /// The shading inputs of level `m`, built with `slots` as
    /// [`LevelShading::new`] takes it; for [`QUARTERED_ONE`], with level
    /// 0's normals at the nodes the two levels share
    /// ([`LevelShading::take_finer_normals`]).
    fn build_shading(&self, m: usize, slots: Option<&OnceLock<Box<SlotSet>>>) -> &LevelShading {
        self.lazy(m).shading.get_or_init(|| {
            let level = self.level(m);
            let mut own = LevelShading::with_isa(self.isa, level, self.ratios_at(m), slots);
            if m == QUARTERED_ONE {
                own.take_finer_normals(level, self.level(0), &self.shading(0).normals);
            }
            Box::new(own)
        })
    }

    /// The flat-shading inputs of level `m` ([`LevelShading::flat`]),
    /// built the first time a flat frame asks for them and kept, as
    /// [`Self::shading`] is. Why kept: flat shading's cell normals were
    /// reconstructed for every node of every frame (2.1 ms of a one-thread
    /// 500² bunny frame, where Phong reads its prepared normals).
    pub(crate) fn flat_shading(&self, m: usize) -> &LevelShading {
        (self.lazy(m).flat_shading)
            .get_or_init(|| Box::new(LevelShading::flat(self.level(m), self.ratios_at(m))))
    }

    /// The normal-buffer slots of level `m`'s used nodes, for counting a
    /// frame's lookups when it draws the level whole
    /// ([`crate::prepare::normal_buffer::NormalBuffer::touch_all`]), found
    /// the first time a frame asks for them (on the thread that asks).
    /// Why apart from [`Self::shading`]: only the statistics read them, and
    /// a frame that does not count ([`crate::RenderOptions::normal_counts`])
    /// skips them: 7.0 M instructions of a one-frame bunny render (the
    /// 1,988 levels' first-use builds 29.8 → 22.8 M; callgrind, `spatch
    /// render bunny.spatch -o out.png --threads 1`). A counting frame finds
    /// them with the shading inputs ([`Self::counted_shading`]).
    pub(crate) fn slot_set(&self, m: usize) -> &SlotSet {
        (self.lazy(m).slots).get_or_init(|| Box::new(level_slot_set(self.isa, self.level(m))))
    }

    /// The shading inputs of level `g - 1` (`g` at least 1) for cells of
    /// level `g` (coarse geometry, [`crate::RenderOptions::geometry_limit`]):
    /// a grid of `2 (cols - 1) + 1` by `2 (rows - 1) + 1` nodes of level
    /// `g`'s grid size, whose node `(2i, 2j)` lies at level `g`'s node
    /// `(i, j)`. A node level `g - 1` has (not empty) keeps its inputs;
    /// the others (empty nodes, and the node row or column that level
    /// `g`'s padding adds) take those of the nearest filled node of level
    /// `g`, so a sample anywhere in a drawn cell of level `g` interpolates
    /// filled inputs. Built the first time a frame asks for it, and kept.
    /// For [`QUARTERED_ONE`], level 0's on its grid (a lifted patch with
    /// colours, [`crate::RenderOptions::level_one_limit`]).
    pub(crate) fn fine_shading(&self, g: usize) -> &LevelShading {
        self.lazy(g).fine_shading.get_or_init(|| {
            let below = grid_level(g) - 1;
            let (fine, coarse) = (self.level(below), self.level(g));
            let (sf, sc) = (self.shading(below), self.shading(g));
            let (cols, rows) = (2 * (coarse.cols - 1) + 1, 2 * (coarse.rows - 1) + 1);
            let coloured = !sf.colours.is_empty() && !sc.colours.is_empty();
            let (mut normals, mut colours) = (Vec::with_capacity(cols * rows), Vec::new());
            for j in 0..rows {
                for i in 0..cols {
                    let own = (i < fine.cols && j < fine.rows)
                        .then_some(j * fine.cols + i)
                        .filter(|&k| fine.displacements[k] != EMPTY);
                    let (v, c) = match own {
                        Some(_) => (&sf.normals, &sf.colours),
                        None => (&sc.normals, &sc.colours),
                    };
                    let k = own.unwrap_or_else(|| nearest_filled(coarse, i, j));
                    normals.push(v[k]);
                    if coloured {
                        colours.push(c[k]);
                    }
                }
            }
            Box::new(LevelShading { normals, colours })
        })
    }

    /// The largest distance of a filled node of level `g - 1` (`g` at
    /// least 1) from the bilinear surface of level `g`'s cells
    /// ([`crate::prepare::coarse_fit::coarse_gap`]), in node spacings of
    /// level `g - 1` (the shorter of its two axes). Measured the first time
    /// a frame asks for it, and kept: a property of the scene, not the view.
    pub(crate) fn coarse_error(&self, g: usize) -> f32 {
        let (rx, ry) = self.ratios_at(g - 1);
        self.coarse_gap(g) * rx.max(ry)
    }

    /// The same gap in displacement codes (the patch's height unit), as
    /// [`coarse_gap`] measures it; measured once, kept.
    pub(crate) fn coarse_gap(&self, g: usize) -> f32 {
        *self.levels[g]
            .coarse_gap
            .get_or_init(|| coarse_gap(self.level(g - 1), self.level(g)))
    }

    /// The distances, in codes, of level 0's filled nodes from the cells
    /// of level 1 drawn by quarters ([`QUARTERED_ONE`]), measured the first
    /// time a frame asks. Why on first use: only the pieces
    /// [`crate::RenderOptions::level_one_limit`] would lift ask.
    pub(crate) fn quartered_gaps(&self) -> Gaps {
        *self
            .quartered_gaps
            .get_or_init(|| coarse_gaps(self.level(0), self.level(QUARTERED_ONE)))
    }

    /// True when level `g` keeps level 0's outline exactly: level 0 draws
    /// every cell (no empty node) and its sides have a multiple of `2^g`
    /// cells, so halving pads and fills nothing and each level draws
    /// exactly the area level 0 draws.
    pub(crate) fn exact_level(&self, g: usize) -> bool {
        let step = 1 << g;
        let draws_every_cell = self
            .built_base()
            .map_or(self.full_grid, MipLevel::draws_every_cell);
        draws_every_cell
            && (self.grid[0] - 1).is_multiple_of(step)
            && (self.grid[1] - 1).is_multiple_of(step)
    }

    /// Level 0's used displacement range, read without building level 0
    /// (the cone's range until then; trimming may narrow level 0's).
    /// Why: a frame asks every patch it draws for its box, and building
    /// level 0 for it was most of the level-0 builds of a one-image render
    /// that draws the patch at a coarser level.
    pub(crate) fn base_d_range(&self) -> (u16, u16) {
        self.built_base().map_or(self.d_range, |l0| l0.d_range)
    }

    /// Level 0 if a frame (or trimming) has built it.
    fn built_base(&self) -> Option<&MipLevel> {
        self.levels[0].level.get().map(|l0| &**l0)
    }

    /// True when the patch has per-node colours (every level then has).
    pub(crate) fn has_node_colours(&self) -> bool {
        self.node_colours
    }

    /// Shading ratios at mip level `m` (node spacing doubles per level).
    pub(crate) fn ratios_at(&self, m: usize) -> (f32, f32) {
        let s = (1u32 << grid_level(m)) as f32;
        (self.ratios.0 / s, self.ratios.1 / s)
    }
}

/// A way to halve level 0 into level 1 ([`halve`], [`halve_quartered`]).
type Halving = fn(FinerLevel<'_>, Option<&[[u8; 4]]>) -> Option<MipLevel>;

/// The level index of level 1 with its outline cells drawn by quarters
/// ([`crate::prepare::mip::halve_quartered`]), past the pyramid's
/// ([`MAX_MIP_LEVELS`]): [`PreparedPatch::level`] and the shading inputs
/// take it as any level, and draw items carry it.
pub(crate) const QUARTERED_ONE: usize = MAX_MIP_LEVELS + 1;

/// The pyramid level whose grid level `m` has: 1 for [`QUARTERED_ONE`],
/// else `m`.
pub(crate) fn grid_level(m: usize) -> usize {
    if m == QUARTERED_ONE {
        1
    } else {
        m
    }
}

/// The index of a filled node of `coarse` nearest to the point `(i / 2,
/// j / 2)` (node units of `coarse`): the first filled one of the (up to
/// four) nodes around it, else node 0 of the cell holding it.
fn nearest_filled(coarse: &MipLevel, i: usize, j: usize) -> usize {
    let clamp = |v: usize, n: usize| v.min(n - 1);
    let (i0, i1) = (clamp(i / 2, coarse.cols), clamp(i.div_ceil(2), coarse.cols));
    let (j0, j1) = (clamp(j / 2, coarse.rows), clamp(j.div_ceil(2), coarse.rows));
    let around = [(i0, j0), (i1, j0), (i0, j1), (i1, j1)].map(|(i, j)| j * coarse.cols + i);
    around
        .into_iter()
        .find(|&k| coarse.displacements[k] != EMPTY)
        .unwrap_or(around[0])
}
