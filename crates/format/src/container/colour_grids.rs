//! The CGRD section (container 1.2): every patch's colour grid, raw or codec 1.
//!
//! Raw layout: one factor byte per patch (0 = no grid), then, for each patch with a grid in
//! patch order, its samples row-major, 3 bytes (RGB) or 4 (RGBA) each as the scene's channel.
//!
//! Codec 1: the factor bytes in one byte context; then per patch, per sample, each channel is
//! predicted from the samples left (`a`), up (`b`) and up-left (`c`) by the median edge
//! detector of LOCO-I (`min(a, b)` when `c >= max(a, b)`, `max(a, b)` when `c <= min(a, b)`,
//! else `a + b − c`; `a` on the first row, `b` on the first column, 0 at the first sample). One
//! binary decision says whether every channel equals its prediction, in one of four contexts
//! chosen by the same decision of the left and up samples (1 where there is none); when not,
//! each channel's residual `(v − p) mod 256` is coded in that channel's byte context. Flat
//! colours (a logo, a label) then cost about 0.02 bits per sample.
//!
//! Cost: one pass, O(samples); model state a few KB.

use super::bounded::vec_for_count;
use super::layout::{CODEC_PREDICTIVE, CODEC_RAW};
#[cfg(test)]
use super::range_coder::Encoder;
use super::range_coder::{ByteModel, Decoder, StreamEnded, PROBABILITY_ONE};
use super::sections::{require_raw_length, RawSection};
use crate::{ColourGrid, Corruption, FormatError, GridSize, Patch};

/// A codec-1 CGRD section never expands by more than this factor (plus
/// [`GRID_EXPANSION_SLACK`]): one decision of at least 0.022 bits may stand for a whole
/// sample of 4 bytes (about 1,450 raw bytes per coded byte).
pub(crate) const GRID_EXPANSION: usize = 2048;
/// See [`GRID_EXPANSION`].
pub(crate) const GRID_EXPANSION_SLACK: usize = 4096;

/// Each patch's colour grid, in patch order.
pub(crate) fn grids_of(patches: &[Patch]) -> Vec<Option<&ColourGrid>> {
    patches.iter().map(Patch::colour_grid).collect()
}

#[cfg(test)] // 1.3 writers write CGRX; kept to test the 1.2 reader
/// The raw CGRD payload of the patches' `grids` with `bytes` per sample (3 or 4).
pub(crate) fn colour_grids_raw(grids: &[Option<&ColourGrid>], bytes: usize) -> Vec<u8> {
    let mut out: Vec<u8> = grids
        .iter()
        .map(|g| g.map_or(0, ColourGrid::factor))
        .collect();
    for grid in grids.iter().flatten() {
        for sample in grid.samples() {
            out.extend_from_slice(&sample[..bytes]);
        }
    }
    out
}

/// The contexts of codec 1 (module docs).
struct Models {
    factors: ByteModel,
    same: [u16; 4],
    channels: [ByteModel; 4],
}

impl Models {
    fn new() -> Self {
        Self {
            factors: ByteModel::new(),
            same: [PROBABILITY_ONE / 2; 4],
            channels: std::array::from_fn(|_| ByteModel::new()),
        }
    }
}

/// The median edge detector of one channel (module docs; CGRX predicts the same way).
#[inline]
pub(super) fn predict(a: u8, b: u8, c: u8) -> u8 {
    if c >= a.max(b) {
        a.min(b)
    } else if c <= a.min(b) {
        a.max(b)
    } else {
        a.wrapping_add(b).wrapping_sub(c)
    }
}

/// The prediction of sample `k` of a grid `cols` wide from the samples before it, and the
/// context of its decision from the decisions `same` before it.
#[inline]
fn prediction(values: &[[u8; 4]], same: &[bool], cols: usize, k: usize) -> ([u8; 4], usize) {
    let (s, t) = (k % cols, k / cols);
    let left = s > 0;
    let up = t > 0;
    let p = match (left, up) {
        (false, false) => [0; 4],
        (true, false) => values[k - 1],
        (false, true) => values[k - cols],
        (true, true) => {
            let (a, b, c) = (values[k - 1], values[k - cols], values[k - cols - 1]);
            std::array::from_fn(|ch| predict(a[ch], b[ch], c[ch]))
        }
    };
    let context = usize::from(!left || same[k - 1]) + 2 * usize::from(!up || same[k - cols]);
    (p, context)
}

/// The bytes of the colour grid section (CGRX since 1.3) `encode_scene` writes for `patches` in a scene of `channel`
/// (payload and its 20-byte header; 0 when no patch has a colour grid).
pub fn colour_grid_section_len(patches: &[Patch], channel: crate::ColourChannel) -> usize {
    let grids = grids_of(patches);
    if grids.iter().all(Option::is_none) {
        return 0;
    }
    let section =
        super::shared_colour_grids::shared_grids_section(&grids, channel.bytes_per_node());
    super::layout::SECTION_HEADER_LEN + section.2.len()
}

#[cfg(test)] // 1.3 writers write CGRX; kept to test the 1.2 reader
/// Codes the CGRD payload of the patches' `grids` (`bytes` per sample).
pub(crate) fn encode_colour_grids(grids: &[Option<&ColourGrid>], bytes: usize) -> Vec<u8> {
    let mut encoder = Encoder::new();
    let mut models = Models::new();
    for g in grids {
        encoder.encode_byte(&mut models.factors, g.map_or(0, ColourGrid::factor));
    }
    let mut same = Vec::new();
    for grid in grids.iter().flatten() {
        let values = grid.samples();
        same.clear();
        for (k, v) in values.iter().enumerate() {
            let (p, context) = prediction(values, &same, grid.cols(), k);
            let equal = v[..bytes] == p[..bytes];
            same.push(equal);
            encoder.encode_bit(&mut models.same[context], u32::from(!equal));
            if !equal {
                for ch in 0..bytes {
                    let residual = v[ch].wrapping_sub(p[ch]);
                    encoder.encode_byte(&mut models.channels[ch], residual);
                }
            }
        }
    }
    encoder.finish()
}

/// Decodes a codec-1 CGRD payload into its factors and samples, for patches of `grids`.
fn decode_colour_grids(
    coded: &[u8],
    grids: &[GridSize],
    bytes: usize,
    raw_limit: usize,
) -> Result<Vec<Option<ColourGrid>>, Corruption> {
    let ended = |_: StreamEnded| Corruption::StreamEndsEarly;
    let mut decoder = Decoder::new(coded).map_err(ended)?;
    let mut models = Models::new();
    // One factor per FRAM record actually present.
    let mut factors = Vec::new();
    for _ in grids {
        factors.push(decoder.decode_byte(&mut models.factors).map_err(ended)?);
    }
    check_raw_length(grids, &factors, bytes, raw_limit)?;
    let mut out = Vec::new();
    let mut same = Vec::new();
    for (&grid, &factor) in grids.iter().zip(&factors) {
        if factor == 0 {
            out.push(None);
            continue;
        }
        let (cols, rows) = checked_size(grid, factor)?;
        // Bounded: the factors' sample counts sum to the checked raw length.
        let mut values: Vec<[u8; 4]> = vec_for_count(cols * rows, bytes, raw_limit, "samples")
            .map_err(|_| Corruption::Expansion {
                raw: raw_limit,
                stored: coded.len(),
            })?;
        same.clear();
        for k in 0..cols * rows {
            let (p, context) = prediction(&values, &same, cols, k);
            let differs = decoder
                .decode_bit(&mut models.same[context])
                .map_err(ended)?;
            let mut v = p;
            if differs == 1 {
                for (ch, value) in v.iter_mut().enumerate().take(bytes) {
                    let residual = decoder
                        .decode_byte(&mut models.channels[ch])
                        .map_err(ended)?;
                    *value = value.wrapping_add(residual);
                }
            }
            same.push(differs == 0);
            values.push(v);
        }
        out.push(Some(grid_from(grid, factor, values, bytes)?));
    }
    Ok(out)
}

/// The sample grid size of `factor` over `grid`, refusing a factor out of range.
fn checked_size(grid: GridSize, factor: u8) -> Result<(usize, usize), Corruption> {
    if factor == 1 || factor > ColourGrid::MAX_FACTOR {
        return Err(Corruption::UnknownCode {
            field: "colour grid factor",
            value: factor,
        });
    }
    Ok(ColourGrid::sample_size(grid, factor))
}

/// The raw length `factors` imply must be `raw_limit` (the section's raw length).
fn check_raw_length(
    grids: &[GridSize],
    factors: &[u8],
    bytes: usize,
    raw_len: usize,
) -> Result<(), Corruption> {
    let mut expected = grids.len();
    for (&grid, &factor) in grids.iter().zip(factors) {
        if factor != 0 {
            let (cols, rows) = checked_size(grid, factor)?;
            expected = expected.saturating_add(cols * rows * bytes);
        }
    }
    if expected != raw_len {
        return Err(Corruption::RawLength {
            found: raw_len,
            expected,
        });
    }
    Ok(())
}

/// A grid of `grid`'s size cut `factor` times from decoded samples (alpha 255 when the
/// scene stores 3 bytes per colour).
pub(super) fn grid_from(
    grid: GridSize,
    factor: u8,
    mut values: Vec<[u8; 4]>,
    bytes: usize,
) -> Result<ColourGrid, Corruption> {
    if bytes == 3 {
        values.iter_mut().for_each(|v| v[3] = 255);
    }
    ColourGrid::new(grid, factor, values).map_err(|e| Corruption::Scene(Box::new(e)))
}

/// The grid of `grid`'s size cut `factor` times whose raw samples (`bytes` each) start
/// `raw`, and the bytes after them.
pub(super) fn raw_grid(
    raw: &[u8],
    grid: GridSize,
    factor: u8,
    bytes: usize,
) -> Result<(ColourGrid, &[u8]), Corruption> {
    let (cols, rows) = ColourGrid::sample_size(grid, factor);
    let (mine, rest) = raw.split_at(cols * rows * bytes);
    let values = mine
        .chunks_exact(bytes)
        .map(|c| [c[0], c[1], c[2], if bytes == 4 { c[3] } else { 255 }])
        .collect();
    Ok((grid_from(grid, factor, values, bytes)?, rest))
}

/// Reads CGRD: each patch's colour grid (`None` for a patch without one). `grids` are the
/// patches' grid sizes, `bytes` the scene's bytes per colour (0: a scene without colour may
/// not hold CGRD).
pub(super) fn read_colour_grids(
    section: &RawSection<'_>,
    grids: &[GridSize],
    bytes: usize,
) -> Result<Vec<Option<ColourGrid>>, FormatError> {
    let codecs = GridCodecs {
        raw: read_raw,
        predictive: decode_colour_grids,
        what: "colour grid factors",
    };
    read_grid_section(section, grids, bytes, codecs)
}

/// Decoded colour grids, or what is wrong with a payload.
type GridsOrCorruption = Result<Vec<Option<ColourGrid>>, Corruption>;

/// How a colour grid section (CGRD or CGRX) reads each codec: `raw(payload, grids, bytes)`,
/// `predictive(payload, grids, bytes, raw_len)`; `what` names its per-patch bytes.
pub(super) struct GridCodecs {
    pub(super) raw: fn(&[u8], &[GridSize], usize) -> GridsOrCorruption,
    pub(super) predictive: fn(&[u8], &[GridSize], usize, usize) -> GridsOrCorruption,
    pub(super) what: &'static str,
}

/// The most raw bytes `stored` payload bytes may stand for (docs/format.md §7.5).
pub(super) fn expansion_limit(stored: usize) -> usize {
    stored
        .saturating_mul(GRID_EXPANSION)
        .saturating_add(GRID_EXPANSION_SLACK)
}

/// Reads a colour grid section by its codec, after the checks both sections share: colour
/// in the scene, the raw length (raw) or the expansion bound (codec 1).
pub(super) fn read_grid_section(
    section: &RawSection<'_>,
    grids: &[GridSize],
    bytes: usize,
    codecs: GridCodecs,
) -> Result<Vec<Option<ColourGrid>>, FormatError> {
    if bytes == 0 {
        return Err(section.corrupt(Corruption::UnexpectedColours));
    }
    let info = &section.info;
    match info.codec {
        CODEC_RAW => {
            require_raw_length(section)?;
            (codecs.raw)(section.payload, grids, bytes).map_err(|k| section.corrupt(k))
        }
        CODEC_PREDICTIVE => {
            if info.raw_len > expansion_limit(info.stored_len) {
                return Err(section.corrupt(Corruption::Expansion {
                    raw: info.raw_len,
                    stored: info.stored_len,
                }));
            }
            // The samples are allocated per patch as they decode, each bounded by the checked
            // raw length; the per-patch bytes by the patches FRAM holds.
            vec_for_count::<u8>(grids.len(), 1, info.raw_len, codecs.what)?;
            (codecs.predictive)(section.payload, grids, bytes, info.raw_len)
                .map_err(|k| section.corrupt(k))
        }
        other => Err(section.corrupt(Corruption::UnknownCodec(other))),
    }
}

/// The grids of a raw CGRD payload.
fn read_raw(
    payload: &[u8],
    grids: &[GridSize],
    bytes: usize,
) -> Result<Vec<Option<ColourGrid>>, Corruption> {
    if payload.len() < grids.len() {
        return Err(Corruption::RawLength {
            found: payload.len(),
            expected: grids.len(),
        });
    }
    let (factors, mut rest) = payload.split_at(grids.len());
    check_raw_length(grids, factors, bytes, payload.len())?;
    let mut out = Vec::new();
    for (&grid, &factor) in grids.iter().zip(factors) {
        if factor == 0 {
            out.push(None);
            continue;
        }
        let (own, tail) = raw_grid(rest, grid, factor, bytes)?;
        rest = tail;
        out.push(Some(own));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Frame;
    use glam::Vec3;

    fn patch_with_grid(cols: u32, rows: u32, factor: u8, seed: u32) -> Patch {
        let grid = GridSize::new(cols, rows).unwrap();
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let n = grid.node_count();
        let patch = Patch::new(frame, grid, vec![0; n], Some(vec![[9, 9, 9, 255]; n])).unwrap();
        let (sc, sr) = ColourGrid::sample_size(grid, factor);
        // Two flat colours split by a diagonal, and a little noise.
        let samples = (0..sc * sr)
            .map(|k| {
                let (s, t) = (k % sc, k / sc);
                let noise = (k as u32).wrapping_mul(seed) >> 29;
                if s > t {
                    [200, 30, 30, 255]
                } else {
                    [20, 20 + noise as u8, 220, 255]
                }
            })
            .collect();
        let colour_grid = ColourGrid::new(grid, factor, samples).unwrap();
        patch.with_colour_grid(colour_grid).unwrap()
    }

    #[test]
    fn coded_grids_decode_to_the_raw_layout_and_flat_colours_code_small() {
        let frame = Frame::new(Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z).unwrap();
        let plain = Patch::new(frame, GridSize::new(2, 2).unwrap(), vec![0; 4], None).unwrap();
        let patches = vec![
            patch_with_grid(5, 4, 8, 0),
            plain,
            patch_with_grid(3, 3, 16, 2_654_435_761),
        ];
        let grids: Vec<GridSize> = patches.iter().map(Patch::grid).collect();
        assert_eq!(grids_of(&patches).iter().flatten().count(), 2);
        let raw = colour_grids_raw(&grids_of(&patches), 3);
        assert_eq!(raw.len(), 3 + (33 * 25 + 33 * 33) * 3);
        assert_eq!(&raw[..3], &[8, 0, 16]);
        let coded = encode_colour_grids(&grids_of(&patches), 3);
        assert!(
            coded.len() * 10 < raw.len(),
            "{} of {}",
            coded.len(),
            raw.len()
        );
        let decoded = decode_colour_grids(&coded, &grids, 3, raw.len()).unwrap();
        let from_raw = read_raw(&raw, &grids, 3).unwrap();
        for (k, p) in patches.iter().enumerate() {
            assert_eq!(decoded[k].as_ref(), p.colour_grid());
            assert_eq!(from_raw[k].as_ref(), p.colour_grid());
        }
        assert!(decode_colour_grids(&coded, &grids, 3, raw.len() + 1).is_err());
        assert!(decode_colour_grids(&coded[..coded.len() / 2], &grids, 3, raw.len()).is_err());
    }
}
