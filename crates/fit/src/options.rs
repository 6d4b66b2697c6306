//! The fitter's options and the default node spacing derived from a mesh.

use spatch_mesh::TriangleMesh;

use crate::{FitError, TextureBudget};

/// How regions become patches.
///
/// Every field has a documented default; build with `FitOptions::default()` and change the
/// fields you need.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct FitOptions {
    /// Node spacing `|ax|`, `|ay|` in model units, or `None` to derive it from the source with
    /// [`default_spacing`]. Per patch the spacing is shrunk slightly so that a whole number of
    /// cells spans the region's rectangle (nodes then land on the rectangle's edges).
    /// Smaller spacing: lower error, more nodes and bytes, longer fitting (quadratically).
    pub spacing: Option<f32>,
    /// Largest number of nodes per patch side, 2..=257. Default [`FitOptions::DEFAULT_GRID`]
    /// (17 = 2^4 + 1). Regions wider than this are split into several patches on the same
    /// node lattice. A larger grid means fewer patches (less frame overhead) but coarser
    /// culling when rendering.
    pub grid: u32,
    /// Extra rings of nodes, beyond the cells the region touches, filled from the neighbouring
    /// surface so that patches overlap their neighbours. Default
    /// [`FitOptions::DEFAULT_OVERLAP`]. Each ring costs about `4 × side` nodes per patch.
    pub overlap: u32,
    /// Largest displacement reconstruction error (half a step) allowed before a region gets a
    /// finer step and 16-bit codes, as a fraction of the node spacing. Default
    /// [`FitOptions::DEFAULT_STEP_ERROR`]. Smaller: more 16-bit patches (more bytes), lower
    /// error along z.
    pub max_step_error: f32,
    /// Deepest ring of neighbouring faces (by shared edges) searched for surface under the
    /// overlap nodes. Default [`FitOptions::DEFAULT_NEIGHBOURHOOD_RINGS`]. The search also
    /// stops at faces whose footprint covers no node the patch needs, so a large value costs
    /// little.
    pub neighbourhood_rings: u32,
    /// Steepest tilt in degrees, from a patch's axis, of a face outside the region that may
    /// fill the patch's outer nodes, in (0, 90]. Default
    /// [`FitOptions::DEFAULT_MAX_NEIGHBOUR_TILT_DEG`] (90: every face that faces the axis
    /// at all). Lower (75 on coarse meshes): no cell bridges a steep wall with a chord that
    /// stands out of the surface as a fin, but patches stop exactly at sharp creases, where
    /// the renderer's outline reach then shows more dark specks (docs/algorithms/fitter.md,
    /// "Steep neighbours").
    pub max_neighbour_tilt_deg: f32,
    /// Whether to sample colour when the source has any. Default `true`. A source without
    /// colour never gets a colour channel.
    pub colour: bool,
    /// Largest number of lattice nodes one region may need before fitting refuses (a guard
    /// against a spacing far too fine for the model). Default
    /// [`FitOptions::DEFAULT_MAX_REGION_NODES`].
    pub max_region_nodes: usize,
    /// Node spacing of textured regions in texels of their texture (the texel size in model
    /// space from each triangle's UV Jacobian), so colour keeps the texture's detail; the
    /// mesh's spacing still applies where it is finer. `0` turns it off (textures are sampled
    /// at the mesh's spacing, as untextured colour is). Default
    /// [`FitOptions::DEFAULT_TEXELS_PER_NODE`]. Smaller: sharper texture, more nodes (about
    /// `1 / texels_per_node²` of them), within [`FitOptions::texture_budget`].
    pub texels_per_node: f32,
    /// How many nodes [`FitOptions::texels_per_node`] may add; default
    /// [`TextureBudget::DEFAULT_SCALE`] × the texture-blind fit. The finest textures give up
    /// detail first when it binds.
    pub texture_budget: TextureBudget,
    /// Texels of the texture per colour-grid sample: a textured patch whose node spacing is
    /// coarser than this gets a colour grid (`spatch_format::ColourGrid`) with
    /// `round(spacing / (colour_grid_texels × texel))` colour cells per node cell (2..=64).
    /// `0` turns colour grids off. Default [`FitOptions::DEFAULT_COLOUR_GRID_TEXELS`] (1).
    /// Smaller: sharper texture, more samples (about `1 / colour_grid_texels²` per texel² of
    /// surface) and bytes; `spatch convert --colour-budget` caps the bytes afterwards.
    pub colour_grid_texels: f32,
}

impl FitOptions {
    /// Default [`FitOptions::grid`]: 17 nodes per side.
    pub const DEFAULT_GRID: u32 = 17;
    /// Default [`FitOptions::overlap`]: no ring beyond the cells the region touches (those
    /// cells already reach into the neighbours by up to one cell).
    pub const DEFAULT_OVERLAP: u32 = 0;
    /// Default [`FitOptions::max_step_error`]: a tenth of the node spacing.
    pub const DEFAULT_STEP_ERROR: f32 = 0.1;
    /// Default [`FitOptions::neighbourhood_rings`].
    pub const DEFAULT_NEIGHBOURHOOD_RINGS: u32 = 64;
    /// Default [`FitOptions::max_neighbour_tilt_deg`]: no limit but facing the axis.
    pub const DEFAULT_MAX_NEIGHBOUR_TILT_DEG: f32 = 90.0;
    /// Default [`FitOptions::max_region_nodes`]: 16 Mi nodes.
    pub const DEFAULT_MAX_REGION_NODES: usize = 1 << 24;
    /// Default [`FitOptions::texels_per_node`]: one node per texel.
    pub const DEFAULT_TEXELS_PER_NODE: f32 = 1.0;
    /// Default [`FitOptions::colour_grid_texels`]: one sample per texel, so a textured
    /// patch whose nodes lie 1.5 texels apart or more (factor 2 and up) gets a grid, within
    /// the convert pipeline's colour budget. Why on: without the texture between its nodes
    /// fuze's albedo stays below 30 dB even with exact outlines (28.8 dB, unlit, 14 views;
    /// 30.7 with grids at 1.83 × the bytes); Duck and Spot pay 5 % and 14 % more bytes
    /// (docs/algorithms/fitter.md, "Colour grids").
    pub const DEFAULT_COLOUR_GRID_TEXELS: f32 = 1.0;

    /// Checks the ranges documented on each field.
    pub fn validate(&self) -> Result<(), FitError> {
        if let Some(s) = self.spacing {
            if !(s.is_finite() && s > 0.0) {
                return Err(FitError::InvalidOptions {
                    reason: "spacing must be a positive finite number",
                });
            }
        }
        if !(2..=257).contains(&self.grid) {
            return Err(FitError::InvalidOptions {
                reason: "grid must be in 2..=257 nodes per side",
            });
        }
        if !(self.max_step_error.is_finite() && self.max_step_error > 0.0) {
            return Err(FitError::InvalidOptions {
                reason: "max_step_error must be a positive finite fraction of the spacing",
            });
        }
        if !(self.texels_per_node.is_finite() && self.texels_per_node >= 0.0) {
            return Err(FitError::InvalidOptions {
                reason: "texels_per_node must be a finite number >= 0 (0 = off)",
            });
        }
        let budget_ok = match self.texture_budget {
            TextureBudget::Scale(k) => k.is_finite() && k >= 1.0,
            TextureBudget::Nodes(_) => true,
        };
        if !budget_ok {
            return Err(FitError::InvalidOptions {
                reason: "the texture budget's scale must be a finite number >= 1",
            });
        }
        if !(self.colour_grid_texels.is_finite() && self.colour_grid_texels >= 0.0) {
            return Err(FitError::InvalidOptions {
                reason: "colour_grid_texels must be a finite number >= 0 (0 = off)",
            });
        }
        let tilt = self.max_neighbour_tilt_deg;
        if !(tilt.is_finite() && tilt > 0.0 && tilt <= 90.0) {
            return Err(FitError::InvalidOptions {
                reason: "max_neighbour_tilt_deg must be in (0, 90] degrees",
            });
        }
        if self.overlap > 64 {
            return Err(FitError::InvalidOptions {
                reason: "overlap must be at most 64 node rings",
            });
        }
        Ok(())
    }
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            spacing: None,
            grid: Self::DEFAULT_GRID,
            overlap: Self::DEFAULT_OVERLAP,
            max_step_error: Self::DEFAULT_STEP_ERROR,
            neighbourhood_rings: Self::DEFAULT_NEIGHBOURHOOD_RINGS,
            max_neighbour_tilt_deg: Self::DEFAULT_MAX_NEIGHBOUR_TILT_DEG,
            colour: true,
            max_region_nodes: Self::DEFAULT_MAX_REGION_NODES,
            texels_per_node: Self::DEFAULT_TEXELS_PER_NODE,
            texture_budget: TextureBudget::default(),
            colour_grid_texels: Self::DEFAULT_COLOUR_GRID_TEXELS,
        }
    }
}

/// Ratio of the default node spacing to the source's mean triangle size
/// (`sqrt(area / faces)`).
///
/// Calibrated on the Stanford bunny (`bun_zipper.ply`, 69,451 triangles) so that it lands just
/// under the original work's 441,014 nodes at 17 × 17 (see `docs/algorithms/fitter.md`).
pub const SPACING_PER_TRIANGLE_SIZE: f32 = 0.5;

/// The default node spacing of `mesh`: [`SPACING_PER_TRIANGLE_SIZE`] × `sqrt(area / faces)`,
/// counting only faces of non-zero area.
///
/// Following the source's own resolution keeps the node density near the triangle density,
/// whatever the model's units. Returns `None` when the mesh has no surface.
pub fn default_spacing(mesh: &TriangleMesh) -> Option<f32> {
    let (mut area, mut faces) = (0.0f64, 0usize);
    for face in mesh.faces() {
        let a = f64::from(mesh.face_area(face));
        if a > 0.0 && a.is_finite() {
            area += a;
            faces += 1;
        }
    }
    if faces == 0 {
        return None;
    }
    let s = (f64::from(SPACING_PER_TRIANGLE_SIZE) * (area / faces as f64).sqrt()) as f32;
    (s.is_finite() && s > 0.0).then_some(s)
}
