//! The `spacing`, `normals` and `consensus` stages of the cloud pipeline (`pipeline.rs`):
//! the point spacing, the scans aligned, the normals from the file or from voxel blocks'
//! planes (turned toward the scanners when known), and the points moved onto those planes.

use glam::{DVec3, Vec3};
use rayon::prelude::*;
use spatch_mesh::PointCloud;

use crate::consensus::{project_to_consensus, ConsensusLimits};
use crate::normals::{estimate_planes, VoxelPlanes};
use crate::progress::Stage;
use crate::scan_shifts::{align_scans, shift_scans, Sights};
use crate::scanners::PointScans;
use crate::spacing::estimate_spacing;
use crate::stage_laps::StageLaps;
use crate::{CloudError, CloudOptions, Scanners};

/// What the `spacing`, `normals` and `consensus` stages found (the normals themselves go
/// to the tiles on their own).
pub(crate) struct ShapedSurface {
    /// The point spacing (given or estimated).
    pub(crate) spacing: f32,
    /// The mean nearest-neighbour distance (0 when the spacing was given).
    pub(crate) mean_nearest: f32,
    /// Where the normals came from (`file`, `pca` or [`SIGHT_SOURCE`]).
    pub(crate) source: &'static str,
    /// The translation of each scan (empty when the scans were not aligned).
    pub(crate) scan_shifts: Vec<DVec3>,
    /// Points the consensus moved.
    pub(crate) consensus_points: usize,
}

/// The `spacing`, `normals` and `consensus` stages over the sorted `cloud` (its positions
/// moved by the scan alignment and the consensus); gives the findings and the normals.
/// `scans` (the points' scans) are dropped once the normals are known.
pub(crate) fn shape_surface(
    cloud: &mut PointCloud,
    scans: Option<PointScans>,
    options: &CloudOptions,
    clock: &mut StageLaps<'_>,
) -> Result<(ShapedSurface, Vec<Vec3>), CloudError> {
    let (spacing, mean_nearest) = measure_spacing(&cloud.positions, options)?;
    clock.lap(Stage::Spacing);

    let sights = scans.as_ref().zip(options.scanners.as_ref());
    let scan_shifts = match sights.filter(|_| options.consensus && options.align_scans) {
        Some(sights) => move_scans(
            (&mut cloud.positions, cloud.origin),
            sights,
            options,
            spacing,
        )?,
        None => Vec::new(),
    };
    let surface = estimate_surface(cloud, options, spacing, sights)?;
    drop(scans);
    clock.lap(Stage::Normals);

    let consensus_points = apply_consensus(&mut cloud.positions, surface.planes, options, spacing);
    clock.lap(Stage::Consensus);
    let shaped = ShapedSurface {
        spacing,
        mean_nearest,
        source: surface.source,
        scan_shifts,
        consensus_points,
    };
    Ok((shaped, surface.normals))
}

/// The spacing (given or estimated) and the mean nearest-neighbour distance (0 when given).
fn measure_spacing(positions: &[Vec3], options: &CloudOptions) -> Result<(f32, f32), CloudError> {
    Ok(match options.spacing {
        Some(s) => (s, 0.0),
        None => {
            let estimate = estimate_spacing(positions)?;
            (estimate.spacing, estimate.mean_nearest)
        }
    })
}

/// The scan alignment: each scan moved by its translation, given
/// ([`CloudOptions::scan_shifts`]) or computed (`scan_shifts.rs`); gives the translations.
fn move_scans(
    (positions, origin): (&mut [Vec3], DVec3),
    (scans, scanners): (&PointScans, &Scanners),
    options: &CloudOptions,
    spacing: f32,
) -> Result<Vec<DVec3>, CloudError> {
    let count = scanners.runs.len();
    match &options.scan_shifts {
        Some(given) if given.len() != count => Err(CloudError::InvalidOption {
            option: "scan_shifts",
            reason: "must hold one translation per scan",
        }),
        Some(given) => {
            shift_scans(positions, scans, given);
            Ok(given.clone())
        }
        None => Ok(align_scans(
            positions,
            &Sights {
                origin,
                scans,
                scanners,
            },
            options.normal_voxel * spacing,
            ConsensusLimits::at_spacing(spacing),
        )),
    }
}

/// The report's name for normals turned toward the points' scanners.
pub(crate) const SIGHT_SOURCE: &str = "pca+sight";

/// Normals per point and, when the consensus needs them or the file has no normals, the
/// voxel blocks' planes.
struct Surface {
    /// Unit normals (zero where unknown).
    normals: Vec<Vec3>,
    /// `file` or `pca`.
    source: &'static str,
    /// The blocks' planes, when computed.
    planes: Option<VoxelPlanes>,
}

/// The `normals` stage: the file's normals (normalised) or the PCA normals of voxel blocks,
/// turned toward each point's scanner when `sights` gives the points' scans and the scanners
/// (only for a cloud without normals).
fn estimate_surface(
    cloud: &PointCloud,
    options: &CloudOptions,
    spacing: f32,
    sights: Option<(&PointScans, &Scanners)>,
) -> Result<Surface, CloudError> {
    let planes = (options.consensus || cloud.normals.is_none()).then(|| {
        estimate_planes(&cloud.positions, options.normal_voxel * spacing).without_layout()
    });
    let (normals, source) = match (&cloud.normals, &planes, sights) {
        (None, Some(planes), Some(sights)) => (turn_to_sight(planes, cloud, sights), SIGHT_SOURCE),
        (Some(given), _, _) => (
            given.iter().map(|n| n.normalize_or_zero()).collect(),
            "file",
        ),
        (None, Some(planes), None) => (
            planes
                .point_voxel
                .par_iter()
                .map(|&v| planes.planes[v as usize].normal)
                .collect(),
            "pca",
        ),
        (None, None, _) => {
            return Err(CloudError::Internal {
                what: "normals without planes",
            })
        }
    };
    Ok(Surface {
        normals,
        source,
        planes,
    })
}

/// Each point's block-plane normal turned to its scanner's side (the point's sight line,
/// from its scan's scanner in `sights`); zero (unknown, drawn by every view) where the block
/// has no plane.
fn turn_to_sight(
    planes: &VoxelPlanes,
    cloud: &PointCloud,
    (scans, scanners): (&PointScans, &Scanners),
) -> Vec<Vec3> {
    planes
        .point_voxel
        .par_iter()
        .zip(&cloud.positions)
        .enumerate()
        .map(|(i, (&v, &p))| {
            let toward = scanners.runs[scans.scan(i)].0.sight_line(cloud.origin, p);
            let normal = planes.planes[v as usize].normal;
            if normal.dot(toward) < 0.0 {
                -normal
            } else {
                normal
            }
        })
        .collect()
}

/// The `consensus` stage: moves the (sorted) positions onto their block planes when it is on,
/// and gives how many moved.
fn apply_consensus(
    positions: &mut [Vec3],
    planes: Option<VoxelPlanes>,
    options: &CloudOptions,
    spacing: f32,
) -> usize {
    match (&planes, options.consensus) {
        (Some(planes), true) => {
            project_to_consensus(positions, planes, ConsensusLimits::at_spacing(spacing))
        }
        _ => 0,
    }
}
