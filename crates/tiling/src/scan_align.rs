//! The scan alignment of a tiled scan set: each scan's translation computed once over every
//! tile, so that the tiles move each scan alike and agree at their seams.
//!
//! Input: a [`Spill`] of a scan set (each tile's records in runs of its scans,
//! [`SpilledTile::scan_points`](crate::SpilledTile::scan_points)), the scanner of every scan
//! of the set (`spatch_scan::scan_viewpoints`, posed) and the options and spacing every tile
//! converts with. Output: one translation per scan.
//!
//! Method: each tile's points (own and buffer) give the block planes
//! (`spatch_cloud::scan_shift_sums`), and only its own points add their point-to-plane
//! equations, so every point of the set counts once, against planes fitted to its whole
//! neighbourhood (the buffer, 16 pixels, is far wider than a block, 6 spacings). The sums
//! of every tile are added and solved once ([`ScanShiftSums::shifts`]): the equations the
//! untiled pipeline solves, up to the voxel grid's anchor (each tile's blocks start at its
//! own points' lowest corner).
//!
//! Cost: one read of every spill file and one plane fit per tile, one tile in memory at a
//! time; the solve is O(scans).

use glam::DVec3;
use spatch_cloud::{scan_shift_sums, CloudOptions, ScanShiftSums, Scanner, Scanners};

use crate::{read_spilled_tile, Spill, TilingError};

/// The scanners of a tile's points: `scanners[k]` with the tile's `scan_points[k]` points
/// (none for a scan the tile did not receive).
pub fn tile_scanners(scanners: &[Scanner], scan_points: &[u64]) -> Scanners {
    let runs = scanners
        .iter()
        .enumerate()
        .map(|(k, &s)| (s, scan_points.get(k).copied().unwrap_or(0) as usize))
        .collect();
    Scanners { runs }
}

/// Each scan's translation over every tile of `spill` (see the module documentation).
///
/// Errors: [`TilingError::Io`] reading a spill file; [`TilingError::InvalidOption`] when a
/// tile's points name a scan past `scanners` or the spacing is not positive.
pub fn spilled_scan_shifts(
    spill: &Spill,
    scanners: &[Scanner],
    options: &CloudOptions,
    spacing: f32,
) -> Result<Vec<DVec3>, TilingError> {
    let mut sums = ScanShiftSums::default();
    for (i, tile) in spill.tiles.iter().enumerate() {
        if tile.own == 0 {
            continue;
        }
        if tile.scan_points.len() > scanners.len() {
            return Err(TilingError::InvalidOption {
                option: "scanners",
                reason: format!(
                    "tile {i} holds points of scan {} of {}",
                    tile.scan_points.len() - 1,
                    scanners.len()
                ),
            });
        }
        let (cloud, _) = read_spilled_tile(spill, i)?;
        let runs = tile_scanners(scanners, &tile.scan_points);
        let key = tile.key;
        let own = |w: DVec3| spill.grid.key_of(w) == key;
        let tile_sums = scan_shift_sums(&cloud, &runs, options, spacing, &own).map_err(|e| {
            TilingError::InvalidOption {
                option: "scan alignment",
                reason: e.to_string(),
            }
        })?;
        sums.add(&tile_sums);
    }
    Ok(sums.shifts(spacing))
}
