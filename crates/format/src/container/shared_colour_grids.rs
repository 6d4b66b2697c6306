//! The CGRX section (container 1.3): colour grids that may reuse another patch's grid.
//!
//! CGRX supersedes CGRD (which 1.3 readers still read): per patch, either no grid, its own
//! samples, or a **reference** to an earlier patch's own grid in one of the 8 orientations of
//! a square ([`ColourGrid::oriented`]). A textured box whose six faces show the same logo
//! stores it once.
//!
//! Raw layout (docs/format.md §6.7): one kind byte per patch (0 = no grid, 2..=64 = own grid
//! of that factor, 128 + o = a reference in orientation `o < 8`); then one u32 (LE) source
//! patch per reference, in patch order; then the own grids' samples as in CGRD.
//!
//! Codec 1 (§7.6): the kind bytes and the sources' bytes in one byte context each; then
//! the samples, predicted by LOCO-I's median edge detector as in CGRD, with the local
//! gradient (left, up-left, up, up-right) choosing among four activity classes: the class
//! and the left and up decisions pick the "every channel predicted" decision's context, and
//! the class picks each channel's residual context; green's residual is coded first and red
//! and blue code their difference from it (a change of colour moves the three together).
//!
//! Cost: one pass, O(samples); 8 hashes per own grid to find references; model state
//! about 9 KB.

use std::collections::HashMap;

use super::bounded::vec_for_count;
use super::colour_grids::{
    expansion_limit, grid_from, predict, raw_grid, read_grid_section, GridCodecs,
};
use super::layout::{CODEC_PREDICTIVE, CODEC_RAW};
use super::range_coder::{ByteModel, Decoder, Encoder, StreamEnded, PROBABILITY_ONE};
use super::sections::RawSection;
use crate::{ColourGrid, Corruption, FormatError, GridSize};

/// Kind byte of a reference in orientation 0; `REFERENCE + o` for orientation `o`.
const REFERENCE: u8 = 128;
/// Bytes of one reference's source in the raw layout.
const SOURCE_LEN: usize = 4;
/// Activity classes of the sample model (module docs).
const CLASSES: usize = 4;

/// What CGRX stores for one patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum GridEntry<'g> {
    /// No colour grid.
    None,
    /// The patch's own samples.
    Own(&'g ColourGrid),
    /// The grid of patch `source` (earlier, with an own grid) turned by `orientation`.
    Reference { source: u32, orientation: u8 },
}

impl GridEntry<'_> {
    fn kind(&self) -> u8 {
        match self {
            GridEntry::None => 0,
            GridEntry::Own(g) => g.factor(),
            GridEntry::Reference { orientation, .. } => REFERENCE + orientation,
        }
    }
}

/// A key that all 8 orientations of a grid share: its factor, its sides in either order
/// and its per-channel sample sums. Why not a hash of each turned copy: turning and hashing
/// every grid 8 times was most of a textured scene's encode (Spot: 3.5 G instructions).
fn orientation_key(grid: &ColourGrid) -> (u8, usize, usize, [u64; 4]) {
    let mut sums = [0u64; 4];
    for sample in grid.samples() {
        for (sum, &v) in sums.iter_mut().zip(sample) {
            *sum += u64::from(v);
        }
    }
    let (a, b) = (grid.cols(), grid.rows());
    (grid.factor(), a.min(b), a.max(b), sums)
}

/// Each patch's entry: a grid equal, sample for sample, to an earlier own grid in one of its
/// 8 orientations becomes a reference to it; other grids are stored.
pub(crate) fn find_references<'g>(grids: &[Option<&'g ColourGrid>]) -> Vec<GridEntry<'g>> {
    type Key = (u8, usize, usize, [u64; 4]);
    let mut seen: HashMap<Key, Vec<u32>> = HashMap::new();
    let mut out = Vec::new();
    for (k, grid) in grids.iter().enumerate() {
        let Some(grid) = grid else {
            out.push(GridEntry::None);
            continue;
        };
        let key = orientation_key(grid);
        let found = seen.get(&key).and_then(|candidates| {
            candidates.iter().find_map(|&source| {
                let source_grid = grids[source as usize]?;
                (0..ColourGrid::ORIENTATIONS)
                    .find(|&o| source_grid.oriented(o) == **grid)
                    .map(|o| (source, o))
            })
        });
        if let Some((source, orientation)) = found {
            out.push(GridEntry::Reference {
                source,
                orientation,
            });
            continue;
        }
        seen.entry(key).or_default().push(k as u32);
        out.push(GridEntry::Own(grid));
    }
    out
}

/// The raw CGRX payload of `entries` with `bytes` per sample (3 or 4).
pub(crate) fn shared_grids_raw(entries: &[GridEntry<'_>], bytes: usize) -> Vec<u8> {
    let mut out: Vec<u8> = entries.iter().map(GridEntry::kind).collect();
    for e in entries {
        if let GridEntry::Reference { source, .. } = e {
            out.extend_from_slice(&source.to_le_bytes());
        }
    }
    for e in entries {
        if let GridEntry::Own(grid) = e {
            for sample in grid.samples() {
                out.extend_from_slice(&sample[..bytes]);
            }
        }
    }
    out
}

/// The CGRX section of the patches' `grids` as `(codec, raw length, payload)`: codec 1
/// unless raw is smaller.
pub(crate) fn shared_grids_section(
    grids: &[Option<&ColourGrid>],
    bytes: usize,
) -> (u8, usize, Vec<u8>) {
    let entries = find_references(grids);
    let raw = shared_grids_raw(&entries, bytes);
    let coded = encode_shared_grids(&entries, bytes);
    if coded.len() < raw.len() {
        (CODEC_PREDICTIVE, raw.len(), coded)
    } else {
        (CODEC_RAW, raw.len(), raw)
    }
}

/// The adaptive contexts of codec 1 (module docs).
struct Models {
    kinds: ByteModel,
    sources: ByteModel,
    same: [u16; 4 * CLASSES],
    channels: [[ByteModel; CLASSES]; 4],
}

impl Models {
    fn new() -> Self {
        Self {
            kinds: ByteModel::new(),
            sources: ByteModel::new(),
            same: [PROBABILITY_ONE / 2; 4 * CLASSES],
            channels: std::array::from_fn(|_| std::array::from_fn(|_| ByteModel::new())),
        }
    }
}

/// The activity class of a gradient sum `g` over RGB (module docs).
#[inline]
fn class_of(g: u32) -> usize {
    match g {
        0 => 0,
        1..=16 => 1,
        17..=64 => 2,
        _ => 3,
    }
}

/// The prediction of sample `k` of a grid `cols` wide, the context of its decision (from
/// the decisions `same` before it) and its activity class.
#[inline]
fn prediction(values: &[[u8; 4]], same: &[bool], cols: usize, k: usize) -> ([u8; 4], usize, usize) {
    let (s, t) = (k % cols, k / cols);
    let (left, up) = (s > 0, t > 0);
    let (p, class) = match (left, up) {
        (false, false) => ([0; 4], 0),
        (true, false) => (values[k - 1], 0),
        (false, true) => (values[k - cols], 0),
        (true, true) => {
            let (a, b, c) = (values[k - 1], values[k - cols], values[k - cols - 1]);
            let d = if s + 1 < cols {
                values[k - cols + 1]
            } else {
                b
            };
            let g: u32 = (0..3)
                .map(|ch| {
                    u32::from(a[ch].abs_diff(c[ch]))
                        + u32::from(c[ch].abs_diff(b[ch]))
                        + u32::from(b[ch].abs_diff(d[ch]))
                })
                .sum();
            let p = std::array::from_fn(|ch| predict(a[ch], b[ch], c[ch]));
            (p, class_of(g))
        }
    };
    let n = usize::from(!left || same[k - 1]) + 2 * usize::from(!up || same[k - cols]);
    (p, n + 4 * class, class)
}

/// The residuals of a sample as coded: green's, then red's and blue's minus green's, then
/// alpha's (module docs). `r` holds `(v − p) mod 256` per channel.
#[inline]
fn decorrelate(r: [u8; 4]) -> [u8; 4] {
    [r[1], r[0].wrapping_sub(r[1]), r[2].wrapping_sub(r[1]), r[3]]
}

/// The inverse of [`decorrelate`].
#[inline]
fn correlate(c: [u8; 4]) -> [u8; 4] {
    [c[1].wrapping_add(c[0]), c[0], c[2].wrapping_add(c[0]), c[3]]
}

/// Codes the CGRX payload of `entries` (`bytes` per sample).
pub(crate) fn encode_shared_grids(entries: &[GridEntry<'_>], bytes: usize) -> Vec<u8> {
    let mut encoder = Encoder::new();
    let mut models = Models::new();
    for e in entries {
        encoder.encode_byte(&mut models.kinds, e.kind());
    }
    for e in entries {
        if let GridEntry::Reference { source, .. } = e {
            for byte in source.to_le_bytes() {
                encoder.encode_byte(&mut models.sources, byte);
            }
        }
    }
    let mut same = Vec::new();
    for e in entries {
        let GridEntry::Own(grid) = e else { continue };
        let values = grid.samples();
        same.clear();
        for (k, v) in values.iter().enumerate() {
            let (p, context, class) = prediction(values, &same, grid.cols(), k);
            let equal = v[..bytes] == p[..bytes];
            same.push(equal);
            encoder.encode_bit(&mut models.same[context], u32::from(!equal));
            if !equal {
                let coded = decorrelate(std::array::from_fn(|ch| v[ch].wrapping_sub(p[ch])));
                for (ch, &byte) in coded.iter().enumerate().take(bytes) {
                    encoder.encode_byte(&mut models.channels[ch][class], byte);
                }
            }
        }
    }
    encoder.finish()
}

/// A decoded kind byte: `Ok(None)` no grid, `Ok(Some(Ok(factor)))` own grid,
/// `Ok(Some(Err(orientation)))` a reference.
fn parse_kind(kind: u8) -> Result<Option<Result<u8, u8>>, Corruption> {
    match kind {
        0 => Ok(None),
        2..=ColourGrid::MAX_FACTOR => Ok(Some(Ok(kind))),
        k if (REFERENCE..REFERENCE + ColourGrid::ORIENTATIONS).contains(&k) => {
            Ok(Some(Err(k - REFERENCE)))
        }
        value => Err(Corruption::UnknownCode {
            field: "colour grid kind",
            value,
        }),
    }
}

/// The raw length the kinds imply for patches of `grids`.
fn implied_raw_length(grids: &[GridSize], kinds: &[u8], bytes: usize) -> Result<usize, Corruption> {
    let mut expected = grids.len();
    for (&grid, &kind) in grids.iter().zip(kinds) {
        match parse_kind(kind)? {
            None => {}
            Some(Ok(factor)) => {
                let (cols, rows) = ColourGrid::sample_size(grid, factor);
                expected = expected.saturating_add(cols * rows * bytes);
            }
            Some(Err(_)) => expected = expected.saturating_add(SOURCE_LEN),
        }
    }
    Ok(expected)
}

/// Replaces each reference of `kinds` (with `sources`, in patch order) by its source's grid
/// turned, checking that the source is an earlier patch with an own grid and that the turned
/// grid fits the patch.
///
/// `limit` bounds the bytes of samples the grids hold once resolved (a reference costs a few
/// bits and copies a whole grid, so it counts against the expansion bound like a stored one).
fn resolve_references(
    grids: &[GridSize],
    kinds: &[u8],
    sources: &[u32],
    own: Vec<Option<ColourGrid>>,
    (bytes, limit): (usize, usize),
) -> Result<Vec<Option<ColourGrid>>, Corruption> {
    let mut out = own;
    let mut next = sources.iter();
    let mut total: usize = out
        .iter()
        .flatten()
        .map(|g| g.samples().len() * bytes)
        .sum();
    for (k, &kind) in kinds.iter().enumerate() {
        let Some(Err(orientation)) = parse_kind(kind)? else {
            continue;
        };
        let source = *next.next().ok_or(Corruption::StreamEndsEarly)?;
        let bad = |reason| Corruption::GridReference {
            patch: k,
            source_patch: source,
            reason,
        };
        let s = source as usize;
        if s >= k {
            return Err(bad("the source is not an earlier patch"));
        }
        let source_grid = out[s]
            .as_ref()
            .filter(|_| matches!(parse_kind(kinds[s]), Ok(Some(Ok(_)))));
        let Some(source_grid) = source_grid else {
            return Err(bad("the source has no grid of its own"));
        };
        total = total.saturating_add(source_grid.samples().len() * bytes);
        if total > limit {
            return Err(bad("the references expand past the section's bound"));
        }
        let turned = source_grid.oriented(orientation);
        let expected = ColourGrid::sample_size(grids[k], turned.factor());
        if (turned.cols(), turned.rows()) != expected {
            return Err(bad("the turned grid does not fit the patch"));
        }
        out[k] = Some(turned);
    }
    Ok(out)
}

/// Decodes a codec-1 CGRX payload for patches of `grids`.
fn decode_shared_grids(
    coded: &[u8],
    grids: &[GridSize],
    bytes: usize,
    raw_len: usize,
) -> Result<Vec<Option<ColourGrid>>, Corruption> {
    let ended = |_: StreamEnded| Corruption::StreamEndsEarly;
    let mut decoder = Decoder::new(coded).map_err(ended)?;
    let mut models = Models::new();
    let mut kinds = Vec::new();
    for _ in grids {
        kinds.push(decoder.decode_byte(&mut models.kinds).map_err(ended)?);
    }
    check_raw_length(grids, &kinds, bytes, raw_len)?;
    let sources = decode_sources(&mut decoder, &mut models, &kinds)?;
    let mut own = Vec::new();
    let mut same = Vec::new();
    for (&grid, &kind) in grids.iter().zip(&kinds) {
        let Some(Ok(factor)) = parse_kind(kind)? else {
            own.push(None);
            continue;
        };
        let (cols, rows) = ColourGrid::sample_size(grid, factor);
        // Bounded: the kinds' sample counts sum to the checked raw length.
        let mut values: Vec<[u8; 4]> = vec_for_count(cols * rows, bytes, raw_len, "samples")
            .map_err(|_| Corruption::Expansion {
                raw: raw_len,
                stored: coded.len(),
            })?;
        let mut samples = SampleDecoder {
            decoder: &mut decoder,
            models: &mut models,
            bytes,
        };
        samples
            .decode(&mut values, &mut same, cols, cols * rows)
            .map_err(ended)?;
        own.push(Some(grid_from(grid, factor, values, bytes)?));
    }
    let limit = expansion_limit(coded.len());
    resolve_references(grids, &kinds, &sources, own, (bytes, limit))
}

/// The source patch of each reference among `kinds`, in patch order.
fn decode_sources(
    decoder: &mut Decoder<'_>,
    models: &mut Models,
    kinds: &[u8],
) -> Result<Vec<u32>, Corruption> {
    let ended = |_: StreamEnded| Corruption::StreamEndsEarly;
    let mut sources = Vec::new();
    for &kind in kinds {
        if let Some(Err(_)) = parse_kind(kind)? {
            let mut le = [0u8; SOURCE_LEN];
            for byte in &mut le {
                *byte = decoder.decode_byte(&mut models.sources).map_err(ended)?;
            }
            sources.push(u32::from_le_bytes(le));
        }
    }
    Ok(sources)
}

/// Decodes the samples of own grids: the payload's decoder, the codec's models and the
/// bytes per sample.
struct SampleDecoder<'d, 'a> {
    decoder: &'d mut Decoder<'a>,
    models: &'d mut Models,
    bytes: usize,
}

impl SampleDecoder<'_, '_> {
    /// Decodes the `count` samples of a grid `cols` wide onto the empty `values`, with
    /// `same` (cleared first) holding each sample's "every channel predicted" decision.
    fn decode(
        &mut self,
        values: &mut Vec<[u8; 4]>,
        same: &mut Vec<bool>,
        cols: usize,
        count: usize,
    ) -> Result<(), StreamEnded> {
        same.clear();
        for k in 0..count {
            let (p, context, class) = prediction(values, same, cols, k);
            let differs = self.decoder.decode_bit(&mut self.models.same[context])?;
            let mut v = p;
            if differs == 1 {
                let r = self.residuals(class)?;
                for (ch, value) in v.iter_mut().enumerate().take(self.bytes) {
                    *value = p[ch].wrapping_add(r[ch]);
                }
            }
            same.push(differs == 0);
            values.push(v);
        }
        Ok(())
    }

    /// The residuals `(v − p) mod 256` of a sample in activity class `class`, decoded from
    /// their coded form (module docs).
    #[inline]
    fn residuals(&mut self, class: usize) -> Result<[u8; 4], StreamEnded> {
        let mut coded = [0u8; 4];
        for (ch, byte) in coded.iter_mut().enumerate().take(self.bytes) {
            *byte = self
                .decoder
                .decode_byte(&mut self.models.channels[ch][class])?;
        }
        Ok(correlate(coded))
    }
}

/// The raw length the kinds imply must be the section's `raw_len`.
fn check_raw_length(
    grids: &[GridSize],
    kinds: &[u8],
    bytes: usize,
    raw_len: usize,
) -> Result<(), Corruption> {
    let expected = implied_raw_length(grids, kinds, bytes)?;
    if expected != raw_len {
        return Err(Corruption::RawLength {
            found: raw_len,
            expected,
        });
    }
    Ok(())
}

/// The grids of a raw CGRX payload.
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
    let (kinds, mut rest) = payload.split_at(grids.len());
    check_raw_length(grids, kinds, bytes, payload.len())?;
    let mut sources = Vec::new();
    for &kind in kinds {
        if let Some(Err(_)) = parse_kind(kind)? {
            let (le, tail) = rest.split_at(SOURCE_LEN);
            sources.push(u32::from_le_bytes([le[0], le[1], le[2], le[3]]));
            rest = tail;
        }
    }
    let mut own = Vec::new();
    for (&grid, &kind) in grids.iter().zip(kinds) {
        let Some(Ok(factor)) = parse_kind(kind)? else {
            own.push(None);
            continue;
        };
        let (grid, tail) = raw_grid(rest, grid, factor, bytes)?;
        rest = tail;
        own.push(Some(grid));
    }
    let limit = expansion_limit(payload.len());
    resolve_references(grids, kinds, &sources, own, (bytes, limit))
}

/// Reads CGRX: each patch's colour grid (`None` for a patch without one), references
/// resolved. `grids` are the patches' grid sizes, `bytes` the scene's bytes per colour (0: a
/// scene without colour may not hold CGRX).
pub(super) fn read_shared_colour_grids(
    section: &RawSection<'_>,
    grids: &[GridSize],
    bytes: usize,
) -> Result<Vec<Option<ColourGrid>>, FormatError> {
    let codecs = GridCodecs {
        raw: read_raw,
        predictive: decode_shared_grids,
        what: "colour grid kinds",
    };
    read_grid_section(section, grids, bytes, codecs)
}
