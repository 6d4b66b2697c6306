//! The value types of `spatch render`'s flags, which `spatch eval`, `merge` and `export`
//! share: what to rasterize, the projection, the cells, the shading and the culling (each
//! with the library option it stands for), and the parsers of points and colours.

use clap::ValueEnum;
use glam::DVec3;
use spatch_render::{CellScheme, Culling, Projection, RenderMode, RenderOptions, Shading};

/// What to rasterize.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ModeArg {
    /// Patches: nodes projected, cells subdivided.
    Patches,
    /// Each cell as two triangles (scan-line baseline).
    Triangles,
}

/// How nodes are projected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ProjectionArg {
    /// Trilinear interpolation of the projected bounding-box corners (fast).
    Trilinear,
    /// Every node projected exactly.
    Exact,
}

/// How magnified cells are filled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum CellsArg {
    /// Bilinear subdivision in fixed point.
    Bilinear,
    /// C1 Catmull-Rom subdivision.
    Smooth,
}

/// The shading model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ShadingArg {
    /// One colour per cell.
    Flat,
    /// Colours at nodes, interpolated.
    Gouraud,
    /// Normals interpolated, shaded per pixel.
    Phong,
    /// The albedo alone (no light: ambient 1, diffuse 0, specular 0), colours at nodes
    /// interpolated: what the colour channel holds, to compare with a texture.
    Unlit,
}

impl ShadingArg {
    /// The library's shading model and lighting for this choice.
    pub(crate) fn apply(self, o: &mut RenderOptions) {
        o.shading = match self {
            ShadingArg::Flat => Shading::Flat,
            ShadingArg::Gouraud | ShadingArg::Unlit => Shading::Gouraud,
            ShadingArg::Phong => Shading::Phong,
        };
        if self == ShadingArg::Unlit {
            o.lighting.ambient = 1.0;
            o.lighting.diffuse = 0.0;
            o.lighting.specular = 0.0;
        }
    }
}

/// Back-face culling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum CullArg {
    /// Cull patches facing away unless the scene marks them two-sided (an
    /// opening shows their back, or the source was wound inward and the eye
    /// is inside its box): those are drawn from both sides.
    Auto,
    /// Drop every patch facing away, marked or not (closed surfaces).
    Back,
    /// Draw everything (open surfaces, camera inside).
    None,
}

impl From<ModeArg> for RenderMode {
    fn from(mode: ModeArg) -> Self {
        match mode {
            ModeArg::Patches => RenderMode::Patches,
            ModeArg::Triangles => RenderMode::Triangles,
        }
    }
}

impl From<ProjectionArg> for Projection {
    fn from(projection: ProjectionArg) -> Self {
        match projection {
            ProjectionArg::Trilinear => Projection::Trilinear,
            ProjectionArg::Exact => Projection::Exact,
        }
    }
}

impl From<CellsArg> for CellScheme {
    fn from(cells: CellsArg) -> Self {
        match cells {
            CellsArg::Bilinear => CellScheme::Bilinear,
            CellsArg::Smooth => CellScheme::Smooth,
        }
    }
}

impl From<CullArg> for Culling {
    fn from(cull: CullArg) -> Self {
        match cull {
            CullArg::Auto => Culling::Auto,
            CullArg::Back => Culling::Back,
            CullArg::None => Culling::None,
        }
    }
}

/// A point or vector `x,y,z` of three finite numbers.
pub(crate) fn parse_vec3(s: &str) -> Result<DVec3, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("expected three numbers x,y,z, found {s:?}"));
    }
    let mut v = [0.0; 3];
    for (dst, part) in v.iter_mut().zip(&parts) {
        *dst = part
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("{part:?} is not a finite number"))?;
    }
    Ok(DVec3::from_array(v))
}

/// A colour `r,g,b` or `r,g,b,a` of bytes (alpha 255 when left out).
pub(crate) fn parse_colour(s: &str) -> Result<[u8; 4], String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if !(3..=4).contains(&parts.len()) {
        return Err(format!("expected r,g,b or r,g,b,a, found {s:?}"));
    }
    let mut c = [255u8; 4];
    for (dst, part) in c.iter_mut().zip(&parts) {
        *dst = part
            .parse::<u8>()
            .map_err(|_| format!("{part:?} is not in 0..=255"))?;
    }
    Ok(c)
}
