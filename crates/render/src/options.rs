//! Typed render options with documented defaults.

use crate::error::RenderError;

/// What is rasterized.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum RenderMode {
    /// Patches: nodes projected, cells drawn by subdivision (the real thing).
    #[default]
    Patches,
    /// Each drawable cell as two triangles through the scan-line rasterizer
    /// (the baseline and the reference for image error).
    Triangles,
}

/// How patch nodes are projected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Projection {
    /// Trilinear interpolation of the 8 projected corners of the patch's
    /// bounding box (no division per node; not perspective-correct).
    #[default]
    Trilinear,
    /// Each node projected exactly (one division per node).
    Exact,
}

/// How magnified cells are filled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum CellScheme {
    /// Bilinear subdivision in integer fixed point (cheap).
    #[default]
    Bilinear,
    /// Catmull-Rom (C1) subdivision over the 4×4 neighbouring nodes, in f32.
    Smooth,
}

/// Shading model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Shading {
    /// One colour per cell (or triangle).
    Flat,
    /// Colours computed at nodes and interpolated.
    Gouraud,
    /// Normals interpolated and shaded once per pixel (deferred).
    #[default]
    Phong,
}

/// Back-face culling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Culling {
    /// Cull where it is safe, as the scene says
    /// ([`spatch_format::Patch::sides`]): a front-only patch whose normal
    /// cone faces away is dropped; a patch of an open surface only when
    /// none of the scene's openings lies between the eye and it (else it
    /// is drawn from both sides, lit two-sided); a patch seen from both
    /// sides (point clouds) never. A mesh is culled when it is closed
    /// (every edge shared by two triangles wound oppositely) and wound
    /// outward (positive signed volume), else drawn from both sides. Files
    /// without sides (container 1.0) cull every patch, as before.
    #[default]
    Auto,
    /// Drop every patch whose normal cone faces away from the eye (and, for
    /// meshes, triangles facing away), marks or not. Right for closed surfaces.
    Back,
    /// Draw everything (open surfaces, camera inside a closed one).
    None,
}

/// A directional light with Blinn-Phong terms. The viewer is at infinity
/// (as OpenGL's default light model), so the half vector is constant.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct Lighting {
    /// Direction towards the light in eye space (x right, y up, z towards
    /// the viewer). Default [`Lighting::DEFAULT_DIRECTION`] (upper left front).
    pub direction: [f32; 3],
    /// Ambient term, 0..=1. Default 0.15.
    pub ambient: f32,
    /// Diffuse term, 0..=1. Default 0.8.
    pub diffuse: f32,
    /// Specular term, 0..=1. Default 0.25.
    pub specular: f32,
    /// Specular exponent, 1..=256. Default 32.
    pub shininess: u32,
    /// Albedo of scenes without colour (RGB). Default light grey.
    pub base_colour: [u8; 3],
}

impl Lighting {
    /// Default light direction (eye space, not normalized).
    pub const DEFAULT_DIRECTION: [f32; 3] = [-0.4, 0.5, 0.75];
}

impl Default for Lighting {
    fn default() -> Self {
        Self {
            direction: Self::DEFAULT_DIRECTION,
            ambient: 0.15,
            diffuse: 0.8,
            specular: 0.25,
            shininess: 32,
            base_colour: [220, 220, 220],
        }
    }
}

/// Options of [`crate::render`] and [`crate::rasterize_triangles`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[non_exhaustive]
pub struct RenderOptions {
    /// Patches or triangles. Default patches.
    pub mode: RenderMode,
    /// Node projection. Default trilinear (faster; see `--stats` for its error).
    pub projection: Projection,
    /// Cell filling of magnified patches. Default bilinear.
    pub cells: CellScheme,
    /// Shading model. Default Phong.
    pub shading: Shading,
    /// Back-face culling. Default auto (cull unless the patch is marked
    /// two-sided).
    pub culling: Culling,
    /// Worker threads; 0 means all cores. Default 0. The image does not
    /// depend on it.
    pub threads: usize,
    /// Supersampling factor per axis, 1..=4 (K² samples per pixel, box
    /// filter). Default 1. Costs about K² in time.
    pub ssaa: u32,
    /// Minify far patches through their mip pyramid. Default true: far views
    /// place 4× fewer nodes per level, at the cost of detail below a pixel.
    pub mip: bool,
    /// With `mip`, a whole patch takes the coarsest level whose estimated
    /// projected cell extent stays below this many pixels, 0.1..=16.
    /// Default 3: a coarser level where its cells stay within about three
    /// pixels, subdivided as magnified cells are. Why not below a pixel
    /// (0.9, the default before 2026-12-04): pixel-sized cells cost two to
    /// four sub-nodes each, and the coarser level's normals, from height
    /// differences over twice the span, are as close to the source's render
    /// on a scan (bunny 500²: 74.5 → 47.3 M instructions per frame, PSNR
    /// against the source 24.75 → 24.74 dB, holes 0.0019 → 0.0174 %; see
    /// docs/algorithms/render.md, "Mip levels of any grid"). Larger values
    /// trade more detail for speed; 0.9 takes a coarser level only where
    /// its cells stay under a pixel.
    pub mip_limit: f32,
    /// With `mip`, how far (pixels on screen) a coarser level may move the
    /// surface of a patch whose levels keep its outline exactly (a full
    /// grid whose sides halve evenly: no filled or padded node) for it to
    /// take that level although its cells exceed `mip_limit` (patches the
    /// limit keeps at level 0, without colours), up to
    /// [`Self::EXACT_LEVEL_CAP`] × `mip_limit`; 0..=2, 0 turns it off.
    /// Default 0.25. The move is the largest distance of the finer level's
    /// nodes from the coarser level's cells, projected at the patch's box.
    /// Why only such patches: a coarse level of a grid with empty nodes
    /// fills or drops cells along its outline, which opened holes and cost
    /// the bunny 0.6 dB at this tolerance (docs/algorithms/render-log.md,
    /// "Where a scan's samples come from"); a full grid's coarse level
    /// covers exactly what level 0 does (the perfect sphere at 500²: 74.0 →
    /// 55.5 M instructions per frame). Patches with colours keep the limit's
    /// level: a coarser level's colours are averages the tolerance does not
    /// measure.
    pub mip_tolerance: f32,
    /// With `mip`, the largest cell (pixels, estimated as for `mip_limit`)
    /// that level 1 may draw where `mip_limit` keeps a patch at level 0;
    /// 0 (the default, off) or 0.1..=16. Such a patch takes a level 1 of
    /// its own, whose cells along the outline are drawn by the level-0
    /// cells they hold (so the outline is level 0's), while that level
    /// moves its surface by at most 0.25 px (root mean square over level
    /// 0's nodes) and all but the farthest 2 % of level 0's nodes by at
    /// most 0.5 px; patches with node colours lift only under Phong, which
    /// shades them from level 0, the others carry level 0's normals at the
    /// nodes the two levels share. The frame projects a quarter of the
    /// nodes: with 6, the bunny at 1000² in 0.75–0.91 of the default's time
    /// (27.45 → 27.59 dB against the source), the mannequin at 500² in 0.86
    /// (26.55 → 26.38 dB), fandisk at 500² 0.4 dB lower. Off by default:
    /// the lowered surface lets dark specks through (surfaces just behind
    /// it, the outline's reach across creases: the bunny at 1000², the
    /// mannequin at 700², the demo's Spot along its muzzle's crease;
    /// docs/algorithms/render.md, "Level 1 past the limit").
    /// Patches with a colour grid keep the limit's level.
    pub level_one_limit: f32,
    /// Largest footprint half-width (pixels) of the splatting path for
    /// pixel-sized cells, 0 or 0.5..=3; 0 (the default) disables it. A
    /// piece of bilinear cells whose nodes can cover its cells with
    /// rectangles of at most this half-width is drawn by splatting its
    /// nodes (one set-up per node, footprints up to 3 × 3 pixels at 1.5)
    /// instead of subdividing its cells; with mip on, a whole patch then
    /// takes the coarsest level whose estimated cell extent stays below
    /// twice this reach. Trades shading detail (each pixel takes its
    /// nearest node's normal: bunny 500², PSNR against the source 24.7 →
    /// 23.1 dB at 1.5) and up to `limit - 1/2` px of silhouette for fewer
    /// samples (bunny 500²: 82.0 → 64.2 M instructions per frame).
    pub splat_limit: f32,
    /// With `mip` and Phong shading, a whole patch's positions may come
    /// from the level above its shading level (cells twice as long, a
    /// quarter of the nodes) when that level's estimated cell extent stays
    /// below this many pixels; 0 (the default) disables it, else 1..=16.
    /// The resolve pass still interpolates the shading level's normals and
    /// albedos at each pixel's point of the patch, so normals keep their
    /// detail; what changes is the surface, bilinear between every other
    /// node. Trades image quality on rough scans for speed (bunny 500² at
    /// 3.6: 83.7 → 53.0 M instructions per frame, PSNR against the source
    /// 24.91 → 23.22 dB, specks along thin rims; the smooth sphere at 200²:
    /// 54.9 dB against the default image; see docs/algorithms/render.md,
    /// "Coarse geometry"). Bilinear cells only, not with `splat_limit`.
    pub geometry_limit: f32,
    /// With `geometry_limit`, a patch takes coarse geometry only when every
    /// filled node of its shading level lies within this many of that
    /// level's node spacings of the coarser level's bilinear surface
    /// (measured once per scene and patch); 0 (the default) takes every
    /// whole patch, else 0.001..=16. Keeps the rough parts of a scan, where
    /// the coarse surface would move samples, at their own level (see
    /// docs/algorithms/render.md, "Coarse geometry").
    pub geometry_tolerance: f32,
    /// Guard band beyond each side of the viewport, as a fraction of its
    /// size, 0..=1. Default 0.1. Patches inside it are drawn without
    /// splitting (pixels outside the image are discarded); wider bands split
    /// less but project and discard more.
    pub guard_band: f32,
    /// Rows per framebuffer tile (the unit of parallel work), 4..=256, or
    /// 0 (the default): automatic, [`Self::band_rows`]. Taller bands walk
    /// fewer rows of cells twice (500² sphere: 89.7 → 86.0 M instructions
    /// per frame at 64 against 32, 74.1 M at 128); shorter ones give more
    /// threads a band each.
    pub tile_rows: u32,
    /// Colour of pixels with no surface (RGBA). Default transparent black.
    pub background: [u8; 4],
    /// The light and material.
    pub lighting: Lighting,
    /// Run the frame's hot kernels with AVX2 and FMA when the CPU has them
    /// (detected at run time; the portable build stays baseline x86-64).
    /// Default true. The image is the same bit for bit either way; false
    /// keeps the portable instructions (for comparisons).
    pub simd: bool,
    /// Draw the cells of coloured patches by pixel-centre coverage (as a
    /// triangle rasterizer does) instead of sub-nodes that reach about half
    /// a pixel past the outline. Default false: sharper coloured outlines
    /// (fuze, unlit, 14 views: 27.9 → 30.7 dB against its source) at several
    /// times the frame's cost on coloured scenes (Spot 5.8×, mannequin
    /// 1.4× and more); see docs/algorithms/render.md.
    pub exact_outlines: bool,
    /// Draw the cells of patches that carry a colour grid by pixel-centre
    /// coverage: each pixel whose centre a cell's two triangles hold
    /// (outline sides pushed out 0.15 px, folded cells by sub-quads)
    /// records its own place in the cell, where the resolve reads the
    /// grid. Default true: a colour grid is texture detail, and the
    /// sub-nodes' half-pixel reach drew fuze at 27.9 dB against its source
    /// (unlit, 14 views) where this draws 30.3 dB. Pieces cut 4 and more
    /// per side. Scenes without colour grids (every untextured one) draw
    /// the same image either way. Cost per frame: Spot 500² 59.6 M
    /// instructions against 51.4 M with sub-nodes (false) and 142.5 M for
    /// the sub-quads this replaced at stop 49; 1000² 169 M against 157 M
    /// and 555 M (docs/algorithms/render.md).
    pub exact_grid_outlines: bool,
    /// Skip a piece when every 8 × 8 tile its screen box touches is
    /// already drawn nearer than the piece's nearest depth
    /// (`frame/occlusion_skip.rs`). Default false. The image is the
    /// same bit for bit either way; per 500² frame it saves 1-3 % of the
    /// bunny's instructions and costs about 1 % on the mannequin and the
    /// sphere, which hide little (docs/algorithms/render.md).
    pub occlusion_skip: bool,
    /// Patches: cut magnified cells so that their sub-nodes land up to
    /// about 1.5 px apart (sub-cells under 1.5 px instead of 0.95) and
    /// close the gaps this leaves, and the pixels where a farther surface
    /// shows through them, by one screen-space pass per band
    /// (`raster/gap_fill.rs`). Default false: 5-12 % fewer instructions
    /// per frame on the scans and the sphere at about the same PSNR, and
    /// the sphere's hole-free tests pass with it, but a pixel on an outline
    /// that its surface covers by a fraction of a pixel can stay open (a
    /// turned cube drawn without culling: 38 pixels over 14 views; see
    /// docs/algorithms/render.md, "Gap fill"). Triangles (`mode`
    /// triangles, meshes) are drawn exactly either way.
    pub gap_fill: bool,
    /// Cell size (pixels) up to which bilinear cells are drawn by
    /// pixel-centre coverage instead of sub-nodes, 0 (off) or 0.5..=4; with
    /// `mip`, a whole patch then takes the coarsest level whose estimated
    /// cell extent stays below this (or `mip_limit`, the larger). Each such
    /// cell writes exactly the pixel centres its two triangles hold and the
    /// resolve interpolates its corners there, so pixel-sized cells need no
    /// sub-nodes (see docs/algorithms/render.md, "Pixel-centre cells").
    /// Bilinear cells only, not with `splat_limit`.
    pub centre_limit: f32,
    /// Count a Phong frame's normal-buffer lookups for
    /// [`crate::RenderStats::normals_needed`] and the two
    /// `normals_computed_*` percentages. Default true. The image is the
    /// same bit for bit either way; false leaves those three statistics at
    /// 0 and skips their bookkeeping (the slot set of each level drawn, found
    /// on first use, and the per-frame counting): 4 M of the bunny's
    /// one-frame command (docs/algorithms/render.md). Flat and Gouraud
    /// frames compute their normals through the buffer and count them
    /// either way.
    pub normal_counts: bool,
    /// Time the planning's stages per chunk (cull, split, traverse,
    /// normals, triangle set-up: [`crate::RenderStats`]'s `times_ms`).
    /// Default true. The image is the same either way; false leaves those
    /// five times at 0 and reads no clock while planning: three clock
    /// reads per drawn patch were about 1.5 % of a 500² bunny frame. The
    /// walls of the frame's phases and the bands' own times are measured
    /// either way.
    pub stage_times: bool,
}

impl RenderOptions {
    /// Rows per band of an image `height` rows tall drawn by `threads`
    /// threads: [`Self::tile_rows`], or when it is 0, about half of
    /// `height / threads` (two bands per thread, so the heaviest-first
    /// order can even them out) in whole multiples of 16, within 64..=128.
    /// Why: with 2 threads at 500², bands of 128 rows walk fewer rows of
    /// cells twice than 64 (callgrind per thread, the critical path of
    /// serial part and busiest worker: sphere 39.48 → 37.49 M, bunny
    /// 24.96 → 24.14 M, mannequin 23.19 → 22.67 M); more threads keep 64.
    pub fn band_rows(&self, height: u32, threads: usize) -> u32 {
        if self.tile_rows != 0 {
            return self.tile_rows;
        }
        let share = height.div_ceil(2 * threads.max(1) as u32);
        share.next_multiple_of(16).clamp(64, 128)
    }

    /// Whether patch frames are drawn with the gap fill
    /// ([`Self::gap_fill`] in patch mode).
    pub fn fills_gaps(&self) -> bool {
        self.gap_fill && self.mode == RenderMode::Patches
    }

    /// Default guard band.
    pub const DEFAULT_GUARD_BAND: f32 = 0.1;
    /// Default tile height: 0, automatic ([`Self::band_rows`]).
    pub const DEFAULT_TILE_ROWS: u32 = 0;
    /// Default mip limit (pixels of estimated cell extent).
    pub const DEFAULT_MIP_LIMIT: f32 = 3.0;
    /// Default mip tolerance (pixels a coarser level may move a full
    /// grid's surface).
    pub const DEFAULT_MIP_TOLERANCE: f32 = 0.25;
    /// How many times `mip_limit` the cells of a level taken under
    /// [`Self::mip_tolerance`] may reach, as estimated from the patch's
    /// projected box: 4, 12 px at the default limit, below the 15 px where
    /// cells go to the triangle path. The estimate is an average and a near
    /// patch's largest cells exceed it; a piece whose lifted cells would
    /// need triangles is planned again at the limit's level (the perfect
    /// sphere seen from 350 at 600²: 26 pieces). At 500² the sphere draws
    /// 530 of its 567 pieces at levels 1-2: 74.0 → 55.5 M instructions per
    /// frame (62.8 M with a cap of 2).
    pub const EXACT_LEVEL_CAP: f32 = 4.0;
    /// Default splat limit: off (cells subdivided down to sub-pixel size).
    pub const DEFAULT_SPLAT_LIMIT: f32 = 0.0;
    /// Default geometry limit: off (positions from the shading level).
    pub const DEFAULT_GEOMETRY_LIMIT: f32 = 0.0;
    /// Default geometry tolerance: none (every whole patch may coarsen).
    pub const DEFAULT_GEOMETRY_TOLERANCE: f32 = 0.0;
    /// Default centre limit (pixels of cell extent; 0: off).
    pub const DEFAULT_CENTRE_LIMIT: f32 = 0.0;
    /// Largest supersampling factor.
    pub const MAX_SSAA: u32 = 4;

    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), RenderError> {
        self.validate_sampling()?;
        self.validate_limits()?;
        self.validate_work()?;
        self.validate_lighting()
    }

    /// Checks the supersampling factor, the guard band and the mip limit
    /// and tolerance.
    fn validate_sampling(&self) -> Result<(), RenderError> {
        if !(1..=Self::MAX_SSAA).contains(&self.ssaa) {
            return bad("ssaa", "must be in 1..=4");
        }
        if !(self.guard_band.is_finite() && (0.0..=1.0).contains(&self.guard_band)) {
            return bad("guard_band", "must be in 0..=1");
        }
        if !(self.mip_limit.is_finite() && (0.1..=16.0).contains(&self.mip_limit)) {
            return bad("mip_limit", "must be in 0.1..=16 pixels");
        }
        let tol = self.mip_tolerance;
        if !(tol.is_finite() && (0.0..=2.0).contains(&tol)) {
            return bad("mip_tolerance", "must be in 0..=2 pixels");
        }
        Ok(())
    }

    /// Checks the level-one, splat, geometry and centre limits and the
    /// geometry tolerance (each 0 or in its range).
    fn validate_limits(&self) -> Result<(), RenderError> {
        let l1 = self.level_one_limit;
        if !(l1.is_finite() && (l1 == 0.0 || (0.1..=16.0).contains(&l1))) {
            return bad("level_one_limit", "must be 0 (off) or in 0.1..=16 pixels");
        }
        let splat = self.splat_limit;
        if !(splat.is_finite() && (splat == 0.0 || (0.5..=3.0).contains(&splat))) {
            return bad("splat_limit", "must be 0 (off) or in 0.5..=3 pixels");
        }
        let g = self.geometry_limit;
        if !(g.is_finite() && (g == 0.0 || (1.0..=16.0).contains(&g))) {
            return bad("geometry_limit", "must be 0 (off) or in 1..=16 pixels");
        }
        let t = self.geometry_tolerance;
        if !(t.is_finite() && (t == 0.0 || (0.001..=16.0).contains(&t))) {
            return bad(
                "geometry_tolerance",
                "must be 0 (none) or in 0.001..=16 node spacings",
            );
        }
        let c = self.centre_limit;
        if !(c.is_finite() && (c == 0.0 || (0.5..=4.0).contains(&c))) {
            return bad("centre_limit", "must be 0 (off) or in 0.5..=4 pixels");
        }
        Ok(())
    }

    /// Checks the band height and the thread count.
    fn validate_work(&self) -> Result<(), RenderError> {
        if !(self.tile_rows == 0 || (4..=256).contains(&self.tile_rows)) {
            return bad("tile_rows", "must be 0 (automatic) or in 4..=256");
        }
        if self.threads > 1024 {
            return bad("threads", "must be in 0..=1024 (0 = all cores)");
        }
        Ok(())
    }

    /// Checks the lighting: factors in 0..=1, shininess in 1..=256 and a
    /// finite, non-zero direction.
    fn validate_lighting(&self) -> Result<(), RenderError> {
        let l = &self.lighting;
        let unit = |v: f32| v.is_finite() && (0.0..=1.0).contains(&v);
        if !(unit(l.ambient) && unit(l.diffuse) && unit(l.specular)) {
            return bad("lighting", "ambient, diffuse and specular must be in 0..=1");
        }
        if !(1..=256).contains(&l.shininess) {
            return bad("lighting", "shininess must be in 1..=256");
        }
        let d = l.direction;
        if !d.iter().all(|v| v.is_finite()) || d.iter().all(|v| *v == 0.0) {
            return bad(
                "lighting",
                "the light direction must be finite and non-zero",
            );
        }
        Ok(())
    }
}

/// The error of option `name`, out of range: `reason`.
fn bad(name: &'static str, reason: &'static str) -> Result<(), RenderError> {
    Err(RenderError::InvalidOption { name, reason })
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            mode: RenderMode::default(),
            projection: Projection::default(),
            cells: CellScheme::default(),
            shading: Shading::default(),
            culling: Culling::default(),
            threads: 0,
            ssaa: 1,
            mip: true,
            mip_limit: Self::DEFAULT_MIP_LIMIT,
            mip_tolerance: Self::DEFAULT_MIP_TOLERANCE,
            level_one_limit: 0.0,
            splat_limit: Self::DEFAULT_SPLAT_LIMIT,
            geometry_limit: Self::DEFAULT_GEOMETRY_LIMIT,
            geometry_tolerance: Self::DEFAULT_GEOMETRY_TOLERANCE,
            guard_band: Self::DEFAULT_GUARD_BAND,
            tile_rows: Self::DEFAULT_TILE_ROWS,
            background: [0, 0, 0, 0],
            lighting: Lighting::default(),
            simd: true,
            exact_outlines: false,
            exact_grid_outlines: true,
            occlusion_skip: false,
            gap_fill: false,
            centre_limit: Self::DEFAULT_CENTRE_LIMIT,
            normal_counts: true,
            stage_times: true,
        }
    }
}
