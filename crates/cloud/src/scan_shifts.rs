//! Scans moved onto each other before the consensus: the translation of each scan that best
//! puts its points on the voxel blocks' planes (point-to-plane least squares, translation
//! only).
//!
//! Input: positions, the block planes of `normals.rs` fitted to every scan together, the
//! scan of each point (`scanners.rs`) and the consensus limits. Output: one translation per
//! scan, which the pipeline adds to the scan's points before fitting the planes again for
//! the normals and the consensus.
//!
//! Why: registered scans disagree by a fraction of the spacing, and much of it is a rigid
//! offset of the whole scan (its registration error). The consensus moves each point onto
//! its block's plane, but a block whose scans disagree by about a spacing has a spread over
//! the limit and is left alone, and neighbouring blocks fit different mixtures of the offset
//! layers: rough depth that shades as specks. Removing each scan's offset first leaves the
//! consensus only the noise.
//!
//! Method: each point whose block passes the consensus limits (enough points, a unique
//! plane, spread and distance within the limits) adds `n nᵀ` and `d n` to its scan's normal
//! equations (`d` the signed distance from the plane, `n` the unit normal); the translation
//! `t` solves `(Σ n nᵀ + λ I) t = −Σ d n`, with `λ` a thousandth of the trace so that a
//! direction no plane constrains (the in-plane shift of a flat scan) stays unmoved. A
//! translation longer than `max_move` is scaled to it.
//!
//! Invariants: deterministic for any thread count (sums over fixed chunks, added in order).
//!
//! Cost: one parallel pass over the points; 9 f64 a scan per chunk.
//!
//! Based on: the point-to-plane error of iterative closest point registration (Y. Chen,
//! G. Medioni, "Object modelling by registration of multiple range images", 1992), one
//! linearised step with translations only.

use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;

use spatch_mesh::PointCloud;

use crate::consensus::{ConsensusLimits, CONSENSUS_MIN_POINTS, TWO_SIDED_MIN_POINTS};
use crate::normals::VoxelPlanes;
use crate::scanners::PointScans;
use crate::{CloudError, CloudOptions, Scanners};

/// Points summed by one task (fixed, so the sums do not depend on the thread count).
const POINTS_PER_CHUNK: usize = 1 << 16;

/// Share of the normal matrix's trace added to its diagonal.
const DAMPING: f64 = 1e-3;

/// One scan's normal equations: `Σ n nᵀ` (xx xy xz yy yz zz) and `Σ d n`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Equations {
    matrix: [f64; 6],
    rhs: DVec3,
}

impl Equations {
    /// Adds the equation of one point: unit normal `n`, signed distance `d`.
    fn add_point(&mut self, n: DVec3, d: f64) {
        let products = [
            n.x * n.x,
            n.x * n.y,
            n.x * n.z,
            n.y * n.y,
            n.y * n.z,
            n.z * n.z,
        ];
        for (a, b) in self.matrix.iter_mut().zip(products) {
            *a += b;
        }
        self.rhs += d * n;
    }

    fn add(&mut self, other: &Equations) {
        for (a, b) in self.matrix.iter_mut().zip(other.matrix) {
            *a += b;
        }
        self.rhs += other.rhs;
    }

    /// The damped least-squares translation, at most `max_move` long.
    fn translation(&self, max_move: f64) -> DVec3 {
        let [xx, xy, xz, yy, yz, zz] = self.matrix;
        let damping = DAMPING * (xx + yy + zz);
        if damping.is_nan() || damping <= 0.0 {
            return DVec3::ZERO;
        }
        let m = DMat3::from_cols(
            DVec3::new(xx + damping, xy, xz),
            DVec3::new(xy, yy + damping, yz),
            DVec3::new(xz, yz, zz + damping),
        );
        let t = m.inverse() * -self.rhs;
        if !t.is_finite() {
            return DVec3::ZERO;
        }
        t.clamp_length_max(max_move)
    }
}

/// The normal equations of each of `scan_count` scans over the points `include` accepts
/// (by index; see the module documentation).
fn scan_equations(
    positions: &[Vec3],
    planes: &VoxelPlanes,
    scans: &PointScans,
    scan_count: usize,
    limits: ConsensusLimits,
    two_sided: &[bool],
    include: &(dyn Fn(usize) -> bool + Sync),
) -> Vec<Equations> {
    let chunks: Vec<Vec<Equations>> = positions
        .par_chunks(POINTS_PER_CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut sums = vec![Equations::default(); scan_count];
            for (k, p) in chunk.iter().enumerate() {
                let i = c * POINTS_PER_CHUNK + k;
                let plane = planes.of_point(i);
                if plane.count < CONSENSUS_MIN_POINTS
                    || plane.normal == Vec3::ZERO
                    || plane.spread > limits.max_spread
                    || two_sided[planes.point_voxel[i] as usize]
                    || !include(i)
                {
                    continue;
                }
                let n = plane.normal.as_dvec3();
                let d = (p.as_dvec3() - planes.origin - plane.centre).dot(n);
                if d.abs() > f64::from(limits.max_move) {
                    continue;
                }
                sums[scans.scan(i)].add_point(n, d);
            }
            sums
        })
        .collect();
    let mut total = vec![Equations::default(); scan_count];
    for chunk in &chunks {
        for (t, c) in total.iter_mut().zip(chunk) {
            t.add(c);
        }
    }
    total
}

/// Each scan's point-to-plane normal equations summed over some of the points of a scan
/// set: a tile's own points ([`scan_shift_sums`]). The sums of every tile of a set, added
/// ([`ScanShiftSums::add`]), give the equations of the whole set, solved once
/// ([`ScanShiftSums::shifts`]) so that every tile moves each scan alike.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ScanShiftSums {
    equations: Vec<Equations>,
}

impl ScanShiftSums {
    /// Adds `other`'s sums (scan by scan; the shorter list is extended).
    pub fn add(&mut self, other: &ScanShiftSums) {
        if self.equations.len() < other.equations.len() {
            self.equations
                .resize(other.equations.len(), Equations::default());
        }
        for (a, b) in self.equations.iter_mut().zip(&other.equations) {
            a.add(b);
        }
    }

    /// Scans summed.
    pub fn scans(&self) -> usize {
        self.equations.len()
    }

    /// The translation of each scan for points of spacing `spacing` (at most
    /// [`CloudOptions::CONSENSUS_MAX_MOVE`] spacings long), as the untiled pipeline solves it.
    pub fn shifts(&self, spacing: f32) -> Vec<DVec3> {
        let max_move = f64::from(CloudOptions::CONSENSUS_MAX_MOVE * spacing);
        self.equations
            .iter()
            .map(|e| e.translation(max_move))
            .collect()
    }
}

/// The scan alignment's normal equations (see the module documentation) of the points of
/// `cloud` that `own` accepts (by world position: a tile's own points; the others only
/// shape the planes), with `scanners` giving each point's scan and `spacing` the point
/// spacing every tile shares; the block planes use `options.normal_voxel`.
///
/// Errors: [`CloudError::MismatchedAttribute`] when the scanners' runs do not add up to
/// the cloud, [`CloudError::InvalidOption`] for more than [`crate::MAX_SCANS`] scans or a
/// spacing that is not positive.
pub fn scan_shift_sums(
    cloud: &PointCloud,
    scanners: &Scanners,
    options: &CloudOptions,
    spacing: f32,
    own: &(dyn Fn(DVec3) -> bool + Sync),
) -> Result<ScanShiftSums, CloudError> {
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(CloudError::InvalidOption {
            option: "spacing",
            reason: "must be a positive number",
        });
    }
    let scans = PointScans::of(scanners, cloud.len())?;
    let planes = crate::normals::estimate_planes(&cloud.positions, options.normal_voxel * spacing);
    let limits = ConsensusLimits::at_spacing(spacing);
    let sights = Sights {
        origin: cloud.origin,
        scans: &scans,
        scanners,
    };
    let two_sided = sights.two_sided_blocks(&planes, &cloud.positions);
    let include = |i: usize| own(cloud.world_position(i));
    let equations = scan_equations(
        &cloud.positions,
        &planes,
        &scans,
        scanners.runs.len(),
        limits,
        &two_sided,
        &include,
    );
    Ok(ScanShiftSums { equations })
}

/// Adds each point's scan translation to it.
pub(crate) fn shift_scans(positions: &mut [Vec3], scans: &PointScans, shifts: &[DVec3]) {
    positions.par_iter_mut().enumerate().for_each(|(i, p)| {
        *p = (p.as_dvec3() + shifts[scans.scan(i)]).as_vec3();
    });
}

/// Moves every scan by its translation onto the planes of all scans (voxels of `voxel`),
/// fitted once; gives the translations. One round: two and three
/// (the planes fitted again to the moved scans each time) cost a plane fit each and gave the
/// same specks within 0.01 % on the scan sets measured, and two rounds fewer filled nodes a
/// patch on the ten bunny scans (148.6 against 151.1; docs/algorithms/cloud.md).
pub(crate) fn align_scans(
    positions: &mut [Vec3],
    sights: &Sights<'_>,
    voxel: f32,
    limits: ConsensusLimits,
) -> Vec<DVec3> {
    let planes = crate::normals::estimate_planes(positions, voxel);
    let two_sided = sights.two_sided_blocks(&planes, positions);
    let count = sights.scanners.runs.len();
    let all = |_| true;
    let sums = scan_equations(
        positions,
        &planes,
        sights.scans,
        count,
        limits,
        &two_sided,
        &all,
    );
    drop(planes);
    let max_move = f64::from(limits.max_move);
    let shifts: Vec<DVec3> = sums.iter().map(|e| e.translation(max_move)).collect();
    shift_scans(positions, sights.scans, &shifts);
    shifts
}

/// Smallest |cosine| between a point's sight line and its block's plane normal for the point
/// to tell the plane's side (60°): grazing samples tip to either side with the plane's
/// noise (counting every sample put half the mannequin's covering scan set in blocks "of
/// both sides"); a thin part seen from both sides is seen nearly head-on by each side's
/// scans (docs/algorithms/cloud.md, "Two-sided blocks").
pub(crate) const SIDE_MIN_COSINE: f32 = 0.5;

/// Where each point of a cloud was seen from: its scan and the scans' scanners.
pub(crate) struct Sights<'a> {
    /// The cloud's origin (positions are relative to it).
    pub(crate) origin: DVec3,
    /// The scan of every point.
    pub(crate) scans: &'a PointScans,
    /// Every scan's scanner.
    pub(crate) scanners: &'a Scanners,
}

impl Sights<'_> {
    /// Per point, which side of its block's plane it was seen from: `Some(true)` when the
    /// plane's normal faces its scanner, `Some(false)` when it faces away, `None` when the
    /// sight line is within [`SIDE_MIN_COSINE`] of the plane (a grazing sample, or no plane):
    /// grazing samples of one side tip either way with the plane's noise and do not vote.
    pub(crate) fn sides(&self, planes: &VoxelPlanes, positions: &[Vec3]) -> Vec<Option<bool>> {
        positions
            .par_iter()
            .enumerate()
            .map(|(i, &p)| {
                let scanner = self.scanners.runs[self.scans.scan(i)].0;
                let cosine = planes
                    .of_point(i)
                    .normal
                    .dot(scanner.sight_line(self.origin, p));
                (cosine.abs() >= SIDE_MIN_COSINE).then_some(cosine > 0.0)
            })
            .collect()
    }

    /// The blocks of `planes` that hold both sides of a thin part
    /// ([`TWO_SIDED_MIN_POINTS`] points or more seen from each side of the block's plane):
    /// the alignment leaves their points out, so that the two sides do not pull their scans
    /// into each other (one plane fitted across both sides would).
    pub(crate) fn two_sided_blocks(&self, planes: &VoxelPlanes, positions: &[Vec3]) -> Vec<bool> {
        let sides = self.sides(planes, positions);
        planes.two_sided_blocks(&sides, TWO_SIDED_MIN_POINTS)
    }
}
