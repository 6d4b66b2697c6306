//! Building the perfect sphere.
//!
//! Inputs: radius, patch count, grid side, node spacing `|ax| = |ay|`,
//! displacement step `|az|`. Output: a colourless [`Scene`] centred on the
//! origin. Each node lies on the line through its grid position along the
//! patch normal, at the sphere's height quantized to the step, so every
//! filled node is within `step / 2` (plus f32 rounding) of the radius.
//! Nodes whose grid position lies outside the sphere's silhouette (only for
//! patches wider than the sphere) are left empty.
//!
//! Cost: O(patches × nodes), about 400k nodes by default (a few ms); the
//! patches are built in parallel on the current rayon pool.

use glam::DVec3;
use rayon::prelude::*;
use spatch_format::{ColourChannel, FormatError, Frame, GridSize, Patch, Scene, EMPTY};

use crate::centres::neighbours_within;
use crate::distribute_on_sphere;
use crate::orient::orient_patch;

/// A built sphere and how well its patches cover it.
#[derive(Debug, Clone)]
pub struct Sphere {
    /// The patches.
    pub scene: Scene,
    /// The smallest room (model units, in a patch plane) between a patch's
    /// Voronoi cell and the edge of its square, over all patches. Non-negative
    /// means the patches cover the sphere with no gap; negative means some
    /// cell sticks out of its patch by that much (too few patches or too
    /// small a grid for the radius).
    pub coverage_margin: f64,
}

/// Options of [`build_sphere`]. The defaults are the original work's sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct SphereOptions {
    /// Sphere radius in model units. Default 128.
    pub radius: f64,
    /// Number of patches (centres spread almost evenly). Default 1362.
    /// More patches: more overlap and bytes, no change in error.
    pub patches: usize,
    /// Nodes per patch side, 2..=257. Default 17.
    pub grid: u32,
    /// Node spacing `|ax| = |ay|`. Default 1. With the default grid, the
    /// patch side is 16 spacings; patches must overlap to cover the sphere.
    pub spacing: f64,
    /// Displacement step `|az|`. Default 0.01: the radial error is at most
    /// half of it. A finer step needs wider codes once the height range
    /// exceeds 254 steps (then 16-bit codes are used automatically).
    pub step: f64,
}

impl SphereOptions {
    /// Default radius.
    pub const DEFAULT_RADIUS: f64 = 128.0;
    /// Default patch count.
    pub const DEFAULT_PATCHES: usize = 1362;
    /// Default nodes per side.
    pub const DEFAULT_GRID: u32 = 17;
    /// Default node spacing.
    pub const DEFAULT_SPACING: f64 = 1.0;
    /// Default displacement step.
    pub const DEFAULT_STEP: f64 = 0.01;
}

impl Default for SphereOptions {
    fn default() -> Self {
        Self {
            radius: Self::DEFAULT_RADIUS,
            patches: Self::DEFAULT_PATCHES,
            grid: Self::DEFAULT_GRID,
            spacing: Self::DEFAULT_SPACING,
            step: Self::DEFAULT_STEP,
        }
    }
}

/// Why a sphere could not be built.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SphereError {
    /// An option is out of its range.
    #[error("invalid --{name}: {reason}")]
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// Its valid range.
        reason: &'static str,
    },
    /// The height range of a patch needs more than 65,535 steps.
    #[error(
        "step {step} is too fine: a patch spans {range} units of height, more than 65,534 steps"
    )]
    StepTooFine {
        /// The requested step.
        step: f64,
        /// The height range of the widest patch.
        range: f64,
    },
    /// The format crate refused a frame or patch (a bug or an extreme option).
    #[error(transparent)]
    Format(#[from] FormatError),
}

/// `Ok` if `ok`, else the invalid-option error for `name`.
fn check(ok: bool, name: &'static str, reason: &'static str) -> Result<(), SphereError> {
    if ok {
        Ok(())
    } else {
        Err(SphereError::InvalidOption { name, reason })
    }
}

/// The node layout and displacement codes shared by every patch (all
/// patches have the same size).
struct PatchShape {
    /// Nodes per side.
    grid: GridSize,
    /// Node spacing `|ax| = |ay|`.
    spacing: f64,
    /// Displacement step `|az|`.
    step: f64,
    /// Half the patch side, in model units.
    half: f64,
    /// The lowest filled height above the patch plane through the centre.
    lowest: f64,
    /// The quantized displacement of each node (or [`EMPTY`]).
    displacements: Vec<u16>,
}

/// Builds the perfect sphere.
pub fn build_sphere(options: &SphereOptions) -> Result<Sphere, SphereError> {
    let grid = check_options(options)?;
    let radius = options.radius;
    let patches = options.patches;
    let shape = patch_shape(options, grid)?;

    let centres = distribute_on_sphere(patches);
    // Voronoi neighbours lie within about two mean spacings; three is safe.
    let reach = 3.0 * (4.0 * std::f64::consts::PI / patches as f64).sqrt();
    let neighbours = neighbours_within(&centres, reach);
    // One patch per centre, in parallel (the orientation search dominates); the order of
    // the patches and the smallest margin do not depend on the thread count.
    let built: Vec<(Patch, f64)> = centres
        .par_iter()
        .zip(&neighbours)
        .map(|(&normal, near)| {
            let near: Vec<DVec3> = near.iter().map(|&k| centres[k]).collect();
            oriented_patch(&shape, radius, normal, &near)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let coverage_margin = built.iter().map(|(_, m)| *m).fold(f64::INFINITY, f64::min);
    let scene_patches: Vec<Patch> = built.into_iter().map(|(p, _)| p).collect();
    Ok(Sphere {
        scene: Scene::new(DVec3::ZERO, ColourChannel::None, scene_patches)?,
        coverage_margin,
    })
}

/// Refuses options out of range (in the order radius, patches, spacing,
/// step, grid); returns the grid size.
fn check_options(options: &SphereOptions) -> Result<GridSize, SphereError> {
    let SphereOptions {
        radius,
        patches,
        grid,
        spacing,
        step,
    } = *options;
    let positive = |v: f64| v.is_finite() && v > 0.0 && v < 1e30;
    check(
        positive(radius),
        "radius",
        "must be a positive finite number",
    )?;
    check(
        (1..=1_000_000).contains(&patches),
        "patches",
        "must be in 1..=1000000",
    )?;
    check(
        positive(spacing),
        "spacing",
        "must be a positive finite number",
    )?;
    check(positive(step), "step", "must be a positive finite number")?;
    GridSize::new(grid, grid).map_err(|_| SphereError::InvalidOption {
        name: "grid",
        reason: "must be in 2..=257",
    })
}

/// Quantizes the sphere's heights over the patch grid into displacement
/// codes, refusing a sphere narrower than a node spacing or a step too fine.
fn patch_shape(options: &SphereOptions, grid: GridSize) -> Result<PatchShape, SphereError> {
    let SphereOptions {
        radius,
        spacing,
        step,
        ..
    } = *options;
    let n = usize::from(grid.cols());
    let half = (n - 1) as f64 * spacing / 2.0;
    let offsets: Vec<f64> = (0..n).map(|k| k as f64 * spacing - half).collect();

    // Heights of the sphere above the patch plane through the centre, shared
    // by every patch (all patches have the same size).
    let heights: Vec<Option<f64>> = (0..n * n)
        .map(|k| {
            let (u, v) = (offsets[k % n], offsets[k / n]);
            let h2 = radius * radius - u * u - v * v;
            (h2 > 0.0).then(|| h2.sqrt())
        })
        .collect();
    let lowest = heights.iter().flatten().fold(f64::MAX, |a, &b| a.min(b));
    if lowest == f64::MAX {
        return Err(SphereError::InvalidOption {
            name: "radius",
            reason: "is smaller than one node spacing",
        });
    }
    let range = radius - lowest;
    if range / step > 65_534.0 {
        return Err(SphereError::StepTooFine { step, range });
    }
    let displacements: Vec<u16> = heights
        .iter()
        .map(|h| match h {
            Some(h) => ((h - lowest) / step).round() as u16,
            None => EMPTY,
        })
        .collect();
    Ok(PatchShape {
        grid,
        spacing,
        step,
        half,
        lowest,
        displacements,
    })
}

/// The patch centred on `normal`, turned to best cover its Voronoi cell
/// among the `near` centres, with its coverage margin.
fn oriented_patch(
    shape: &PatchShape,
    radius: f64,
    normal: DVec3,
    near: &[DVec3],
) -> Result<(Patch, f64), SphereError> {
    let PatchShape {
        grid,
        spacing,
        step,
        half,
        lowest,
        ..
    } = *shape;
    let (x0, y0) = tangent_axes(normal);
    let orientation = orient_patch(normal, x0, y0, near, radius, half);
    let x = orientation.x;
    let y = normal.cross(x);
    let origin = normal * lowest - x * half - y * half;
    let frame = Frame::new(
        origin.as_vec3(),
        (x * spacing).as_vec3(),
        (y * spacing).as_vec3(),
        (normal * step).as_vec3(),
    )?;
    let patch = Patch::new(frame, grid, shape.displacements.clone(), None)?;
    Ok((patch, orientation.margin))
}

/// A right-handed tangent basis `(x, y)` with `x × y = normal`.
fn tangent_axes(normal: DVec3) -> (DVec3, DVec3) {
    let reference = if normal.z.abs() < 0.9 {
        DVec3::Z
    } else {
        DVec3::X
    };
    let x = reference.cross(normal).normalize();
    let y = normal.cross(x);
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_match_the_original_and_nodes_lie_on_the_sphere() {
        let sphere = build_sphere(&SphereOptions::default()).unwrap();
        assert!(sphere.coverage_margin >= 0.0, "{}", sphere.coverage_margin);
        let scene = sphere.scene;
        assert_eq!(scene.patches().len(), 1362);
        for patch in scene.patches() {
            assert_eq!(patch.grid().node_count(), 289);
            let [lx, ly, lz] = patch.frame().lengths();
            assert!((lx - 1.0).abs() < 1e-6 && (ly - 1.0).abs() < 1e-6 && (lz - 0.01).abs() < 1e-8);
            for (_, _, p) in patch.filled_nodes() {
                let r = p.as_dvec3().length();
                assert!((r - 128.0).abs() <= 0.0051, "radius {r}");
            }
        }
    }

    #[test]
    fn refuses_bad_options() {
        let bad = [
            SphereOptions {
                radius: -1.0,
                ..Default::default()
            },
            SphereOptions {
                patches: 0,
                ..Default::default()
            },
            SphereOptions {
                grid: 1,
                ..Default::default()
            },
            SphereOptions {
                spacing: f64::NAN,
                ..Default::default()
            },
            SphereOptions {
                step: 1e-9,
                ..Default::default()
            },
        ];
        for options in bad {
            assert!(build_sphere(&options).is_err(), "{options:?}");
        }
    }
}
