//! Readers of the FRAM section (one record per patch: frame, grid, width) and
//! of the optional ORGR section (one origin residual per patch).
//!
//! Input: the raw sections and the SCNE fields. Output: each patch's frame and
//! grid, and the layout of its displacement codes in DISP. Checked
//! (docs/format.md §10, steps 5 and 8): both raw, their exact lengths (which
//! bound the patch count before anything is allocated), each record's frame,
//! grid and width, each residual. O(patches).

use glam::{Quat, Vec3};

use super::bounded::vec_for_count;
use super::layout::{GridStorage, SceneFields, WidthStorage, RESIDUAL_LEN};
use super::predictive::DisplacementLayout;
use super::sections::{f32_at, require_raw, RawSection};
use crate::{Corruption, FormatError, Frame, GridSize};

/// What the frame records say about each patch.
pub(super) struct FrameRecords {
    /// Each patch's frame and grid, in order.
    pub(super) frames: Vec<(Frame, GridSize)>,
    /// Each patch's codes in DISP, in order.
    pub(super) layouts: Vec<DisplacementLayout>,
}

/// A patch's refused value as a corruption of `section`.
fn patch_error(section: &RawSection<'_>, patch: usize, error: FormatError) -> FormatError {
    section.corrupt(Corruption::Patch {
        patch,
        error: Box::new(error),
    })
}

/// The checked ORGR payload: raw, one 12-byte record per patch.
pub(super) fn read_residuals<'a>(
    section: Option<&RawSection<'a>>,
    patch_count: usize,
) -> Result<Option<&'a [u8]>, FormatError> {
    let Some(section) = section else {
        return Ok(None);
    };
    require_raw(section)?;
    if section.payload.len() != patch_count.saturating_mul(RESIDUAL_LEN) {
        return Err(section.corrupt(Corruption::RecordCount {
            bytes: section.payload.len(),
            count: patch_count,
            record: RESIDUAL_LEN,
        }));
    }
    Ok(Some(section.payload))
}

/// Reads every FRAM record (with its ORGR residual when `residuals` is given).
pub(super) fn read_frames(
    section: &RawSection<'_>,
    fields: &SceneFields,
    residuals: Option<(&RawSection<'_>, &[u8])>,
) -> Result<FrameRecords, FormatError> {
    require_raw(section)?;
    let record_len = fields.frame_record_len();
    let patch_count = fields.patch_count as usize;
    let bytes = section.payload.len();
    if bytes != patch_count.saturating_mul(record_len) {
        return Err(section.corrupt(Corruption::RecordCount {
            bytes,
            count: patch_count,
            record: record_len,
        }));
    }
    let shared_grid = shared_grid(fields)?;
    let mut frames = vec_for_count(patch_count, record_len, bytes, "frames")?;
    let mut layouts = vec_for_count(patch_count, record_len, bytes, "frames")?;
    for (k, record) in section.payload.chunks_exact(record_len).enumerate() {
        let frame = record_frame(section, record, k, residuals)?;
        let (grid, bytes_per_code) = record_grid(section, fields, shared_grid, record, k)?;
        frames.push((frame, grid));
        layouts.push(DisplacementLayout {
            cols: grid.cols().into(),
            rows: grid.rows().into(),
            bytes_per_code,
        });
    }
    Ok(FrameRecords { frames, layouts })
}

/// The grid every patch shares, when SCNE says they share one.
fn shared_grid(fields: &SceneFields) -> Result<Option<GridSize>, FormatError> {
    Ok(match fields.grid_storage {
        GridStorage::Shared => Some(
            GridSize::new(fields.shared_cols.into(), fields.shared_rows.into())
                .map_err(|e| super::sections::corrupt("SCNE", Corruption::Scene(Box::new(e))))?,
        ),
        GridStorage::PerPatch => None,
    })
}

/// The frame of FRAM record `k`, moved by its ORGR residual when `residuals` is given.
fn record_frame(
    section: &RawSection<'_>,
    record: &[u8],
    k: usize,
    residuals: Option<(&RawSection<'_>, &[u8])>,
) -> Result<Frame, FormatError> {
    let mut frame = read_frame(record).map_err(|e| patch_error(section, k, e))?;
    if let Some((orgr, r)) = residuals {
        let at = k * RESIDUAL_LEN;
        let residual = Vec3::new(f32_at(r, at), f32_at(r, at + 4), f32_at(r, at + 8));
        frame = frame
            .with_residual(residual)
            .map_err(|e| patch_error(orgr, k, e))?;
    }
    Ok(frame)
}

/// The grid of FRAM record `k` (the `shared_grid` when there is one) and the bytes of each
/// of its displacement codes.
fn record_grid(
    section: &RawSection<'_>,
    fields: &SceneFields,
    shared_grid: Option<GridSize>,
    record: &[u8],
    k: usize,
) -> Result<(GridSize, usize), FormatError> {
    let mut at = 40;
    let grid = match shared_grid {
        Some(g) => g,
        None => {
            let cols = u16::from_le_bytes([record[at], record[at + 1]]);
            let rows = u16::from_le_bytes([record[at + 2], record[at + 3]]);
            at += 4;
            GridSize::new(cols.into(), rows.into()).map_err(|e| patch_error(section, k, e))?
        }
    };
    let bytes_per_code = match fields.width_storage {
        WidthStorage::All8 => 1,
        WidthStorage::All16 => 2,
        WidthStorage::PerPatch => match record[at] {
            8 => 1,
            16 => 2,
            bits => return Err(section.corrupt(Corruption::Width { patch: k, bits })),
        },
    };
    Ok((grid, bytes_per_code))
}

/// The frame of one record: origin (3 × f32), quaternion (4 × f32), lengths (3 × f32).
fn read_frame(record: &[u8]) -> Result<Frame, FormatError> {
    let origin = Vec3::new(f32_at(record, 0), f32_at(record, 4), f32_at(record, 8));
    let rotation = Quat::from_xyzw(
        f32_at(record, 12),
        f32_at(record, 16),
        f32_at(record, 20),
        f32_at(record, 24),
    );
    let lengths = [f32_at(record, 28), f32_at(record, 32), f32_at(record, 36)];
    Frame::from_parts(origin, rotation, lengths)
}
