//! Node spacing of textured regions from the texture's own resolution, within a node budget.
//!
//! A node carries one colour, so a patch can only keep texture detail down to its node
//! spacing. For a region whose faces carry a texture, the spacing that follows the texture is
//! `texels_per_node × t`, where `t` is the region's texel size in model space: the square
//! root of its textured faces' model-space area over their area in texels (the UV Jacobian
//! of each triangle, area-weighted over the region). A region's spacing is the smaller of
//! that and the mesh's spacing; untextured regions keep the mesh's spacing exactly.
//!
//! The budget caps the nodes this may add. A region of projected area `A` at spacing `s`
//! needs about `(√A / s + 1)²` nodes (a square of that area, with its boundary row and
//! column); the budget is a number of nodes, by default
//! [`TextureBudget::DEFAULT_SCALE`] × the nodes of the texture-blind fit (so the file grows
//! by about as much). When the wanted spacings would exceed it, every textured region's
//! spacing is raised to at least one floor `s_min`, the smallest for which the estimate fits
//! (found by bisection): the finest textures give up detail first, none is made coarser than
//! the texture-blind spacing.
//!
//! Cost: O(faces) once per fit, before any region is fitted.

use spatch_mesh::{FaceId, TriangleMesh};

use crate::colour_grid::grid_factor;
use crate::fit::FitRegion;
use crate::FitOptions;

/// How many nodes the texture may add over the texture-blind fit.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum TextureBudget {
    /// At most this many times the (estimated) nodes of the texture-blind fit, `>= 1`; `1`
    /// leaves every region at the mesh's spacing.
    Scale(f32),
    /// At most this many nodes over all regions (estimated); never fewer than the
    /// texture-blind fit needs.
    Nodes(u64),
}

impl TextureBudget {
    /// Default scale: 3 × the texture-blind node count (the estimate counts surface nodes
    /// only; with the edge patches a finer surface may add, BoxTextured.glb then stays within
    /// 4 × its texture-blind bytes: docs/algorithms/fitter.md).
    pub const DEFAULT_SCALE: f32 = 3.0;
}

impl Default for TextureBudget {
    fn default() -> Self {
        TextureBudget::Scale(Self::DEFAULT_SCALE)
    }
}

/// How much texture detail a fit kept.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct TextureDetail {
    /// Regions with textured faces.
    pub textured_regions: usize,
    /// Texels per node spacing asked for ([`crate::FitOptions::texels_per_node`]).
    pub texels_per_node_wanted: f32,
    /// Texels per node spacing reached, over the textured regions (weighted by their
    /// texels): the texture's own resolution when it equals the wanted figure, coarser when
    /// the budget or the mesh's spacing stopped it.
    pub texels_per_node: f32,
    /// Texels the textured regions cover (area in texels, summed over their faces).
    pub texels: f64,
    /// Estimated nodes of the texture-blind fit, all regions.
    pub blind_nodes: f64,
    /// Estimated nodes with the texture spacings, all regions.
    pub nodes: f64,
    /// The node budget the estimate was held to.
    pub budget_nodes: f64,
    /// True when the budget raised some region's spacing above its wanted one.
    pub budget_limited: bool,
    /// The finest spacing given to a textured region (model units; the mesh's spacing when
    /// none got finer).
    pub finest_spacing: f32,
}

/// Per region: projected area, textured model area, texels and depth along its axis.
#[derive(Debug, Clone, Copy, Default)]
struct RegionTexels {
    area: f64,
    textured_area: f64,
    texels: f64,
    /// Extent of the region's corners along its axis (0 for a plane across the axis).
    depth: f64,
}

/// The spacing of each region and what detail it keeps, or `None` when no region has a
/// textured face (every region then keeps `spacing`, unchanged).
pub(crate) fn texture_spacings(
    mesh: &TriangleMesh,
    regions: &[FitRegion<'_>],
    spacing: f32,
    options: &FitOptions,
) -> Option<(Vec<f32>, TextureDetail)> {
    let (texels_per_node, budget) = (options.texels_per_node, options.texture_budget);
    if texels_per_node <= 0.0 || mesh.face_uvs.is_none() {
        return None;
    }
    let measured: Vec<RegionTexels> = regions.iter().map(|r| region_texels(mesh, r)).collect();
    if measured.iter().all(|m| m.texels <= 0.0) {
        return None;
    }
    let s = f64::from(spacing);
    let flat_depth = 2.0 * f64::from(options.max_step_error) * s;
    let wanted: Vec<f64> = measured
        .iter()
        .map(|m| {
            if grid_carries_texture(m, spacing, flat_depth, options.colour_grid_texels) {
                s
            } else {
                wanted_spacing(m, s, f64::from(texels_per_node))
            }
        })
        .collect();
    let blind: f64 = measured.iter().map(|m| region_nodes(m.area, s)).sum();
    let budget_nodes = match budget {
        TextureBudget::Scale(k) => blind * f64::from(k.max(1.0)),
        TextureBudget::Nodes(n) => (n as f64).max(blind),
    };
    let floor = spacing_floor(&measured, &wanted, s, budget_nodes);
    let spacings: Vec<f64> = wanted.iter().map(|&w| w.max(floor)).collect();
    let mut detail = summarize(
        &measured,
        &spacings,
        &wanted,
        texels_per_node,
        blind,
        budget_nodes,
    );
    let out: Vec<f32> = spacings
        .iter()
        .zip(&wanted)
        .map(|(&sp, &w)| if w < s { sp as f32 } else { spacing })
        .collect();
    detail.finest_spacing = out.iter().copied().fold(spacing, f32::min);
    Some((out, detail))
}

/// The region's texel size in model units (its textured faces' model area over their area
/// in texels, square-rooted), or `None` when it has no textured face.
pub(crate) fn region_texel_size(mesh: &TriangleMesh, region: &FitRegion<'_>) -> Option<f64> {
    let m = region_texels(mesh, region);
    let t = (m.textured_area / m.texels).sqrt();
    (m.texels > 0.0 && t.is_finite() && t > 0.0).then_some(t)
}

/// True when a region keeps the mesh's spacing `s` because a colour grid carries its texture:
/// it is flat (its corners within `flat_depth` along its axis, so its patch is exact at any
/// spacing and finer nodes could add colour only) and its texture is fine enough for a grid
/// at `s` (`colour_grid_texels > 0`, factor 2 or more).
fn grid_carries_texture(
    m: &RegionTexels,
    s: f32,
    flat_depth: f64,
    colour_grid_texels: f32,
) -> bool {
    if m.texels <= 0.0 || m.depth > flat_depth {
        return false;
    }
    let texel = (m.textured_area / m.texels).sqrt();
    grid_factor(s, texel, colour_grid_texels).is_some()
}

/// Projected area, textured area, texels and depth of one region.
fn region_texels(mesh: &TriangleMesh, region: &FitRegion<'_>) -> RegionTexels {
    let axis = region.axis.normalize_or_zero();
    let mut out = RegionTexels::default();
    let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
    for &face in region.faces {
        if face.index() >= mesh.face_count() {
            continue; // the fitter reports it
        }
        for p in mesh.face_positions(face) {
            let h = f64::from(p.dot(axis));
            (low, high) = (low.min(h), high.max(h));
        }
        let area = f64::from(mesh.face_area(face));
        out.area += area * f64::from(mesh.face_normal(face).dot(axis).abs());
        let texels = face_texels(mesh, face);
        if texels > 0.0 && area > 0.0 {
            out.textured_area += area;
            out.texels += texels;
        }
    }
    out.depth = (high - low).max(0.0);
    out
}

/// The face's area in texels of its material's texture (0 without one).
fn face_texels(mesh: &TriangleMesh, face: FaceId) -> f64 {
    let Some((texture, uvs)) = mesh.face_texture(face) else {
        return 0.0;
    };
    let [a, b, c] = uvs.map(|p| p.as_dvec2());
    let uv_area = 0.5 * (b - a).perp_dot(c - a).abs();
    let texels = uv_area * f64::from(texture.width) * f64::from(texture.height);
    if texels.is_finite() {
        texels
    } else {
        0.0
    }
}

/// `texels_per_node` texel sizes of the region, or the mesh's spacing `s` when that is finer
/// or the region has no texture.
fn wanted_spacing(m: &RegionTexels, s: f64, texels_per_node: f64) -> f64 {
    if m.texels <= 0.0 {
        return s;
    }
    let texel = (m.textured_area / m.texels).sqrt();
    let w = texels_per_node * texel;
    if w.is_finite() && w > 0.0 {
        w.min(s)
    } else {
        s
    }
}

/// Estimated nodes of a region of projected area `area` at spacing `s`.
fn region_nodes(area: f64, s: f64) -> f64 {
    let side = area.sqrt() / s + 1.0;
    side * side
}

/// Estimated nodes of all regions when no spacing is finer than `floor`.
fn nodes_at_floor(measured: &[RegionTexels], wanted: &[f64], floor: f64) -> f64 {
    measured
        .iter()
        .zip(wanted)
        .map(|(m, &w)| region_nodes(m.area, w.max(floor)))
        .sum()
}

/// The smallest floor (at most `s`) whose node estimate stays within `budget`.
fn spacing_floor(measured: &[RegionTexels], wanted: &[f64], s: f64, budget: f64) -> f64 {
    if nodes_at_floor(measured, wanted, 0.0) <= budget {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, s);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if nodes_at_floor(measured, wanted, mid) <= budget {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// What detail the spacings keep.
fn summarize(
    measured: &[RegionTexels],
    spacings: &[f64],
    wanted: &[f64],
    texels_per_node: f32,
    blind_nodes: f64,
    budget_nodes: f64,
) -> TextureDetail {
    let mut detail = TextureDetail {
        texels_per_node_wanted: texels_per_node,
        blind_nodes,
        budget_nodes,
        ..TextureDetail::default()
    };
    let mut weighted = 0.0;
    for ((m, &sp), &w) in measured.iter().zip(spacings).zip(wanted) {
        detail.nodes += region_nodes(m.area, sp);
        if m.texels <= 0.0 {
            continue;
        }
        detail.textured_regions += 1;
        detail.texels += m.texels;
        weighted += m.texels * sp / (m.textured_area / m.texels).sqrt();
        detail.budget_limited |= sp > w * (1.0 + 1e-9);
    }
    detail.texels_per_node = (weighted / detail.texels) as f32;
    detail
}

#[cfg(test)]
mod tests {
    use super::*;

    fn region(area: f64, texels: f64) -> RegionTexels {
        RegionTexels {
            area,
            textured_area: area,
            texels,
            depth: 0.0,
        }
    }

    #[test]
    fn the_wanted_spacing_follows_the_texel_size_and_never_exceeds_the_mesh_spacing() {
        // 1 unit² over 100 × 100 texels: texel size 0.01.
        let m = region(1.0, 1e4);
        assert!((wanted_spacing(&m, 1.0, 2.0) - 0.02).abs() < 1e-12);
        assert_eq!(wanted_spacing(&m, 0.005, 2.0), 0.005);
        assert_eq!(wanted_spacing(&region(1.0, 0.0), 0.3, 2.0), 0.3);
    }

    #[test]
    fn a_flat_region_keeps_the_mesh_spacing_where_a_grid_carries_its_texture() {
        // Texel size 0.01 under a spacing of 0.1: a grid of factor 10 at the mesh's spacing.
        let flat = region(1.0, 1e4);
        assert!(grid_carries_texture(&flat, 0.1, 0.02, 1.0));
        let curved = RegionTexels {
            depth: 0.05,
            ..flat
        };
        assert!(!grid_carries_texture(&curved, 0.1, 0.02, 1.0));
        assert!(!grid_carries_texture(&flat, 0.1, 0.02, 0.0), "grids off");
        assert!(!grid_carries_texture(&region(1.0, 0.0), 0.1, 0.02, 1.0));
        // A texture barely finer than the nodes gets no grid, so its nodes follow it.
        assert!(!grid_carries_texture(&region(1.0, 100.0), 0.1, 0.02, 1.0));
    }

    #[test]
    fn the_floor_holds_the_estimate_to_the_budget() {
        let measured = [region(1.0, 1e4), region(1.0, 0.0)];
        let wanted = [0.01, 0.1];
        // Blind: 2 regions at 0.1 → 242 nodes; wanted: 10,201 + 121.
        let floor = spacing_floor(&measured, &wanted, 0.1, 800.0);
        let nodes = nodes_at_floor(&measured, &wanted, floor);
        assert!(nodes <= 800.0 && nodes > 790.0, "{nodes}");
        assert_eq!(spacing_floor(&measured, &wanted, 0.1, 1e6), 0.0);
    }
}
