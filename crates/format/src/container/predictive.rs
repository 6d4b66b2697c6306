//! Codec 1 ("predictive"): lossless prediction over the grid followed by the
//! adaptive range coder.
//!
//! Displacements: each stored code `v` at node `(i, j)` is predicted from its
//! already coded neighbours (left `a`, up `b`, up-left `c`) by the
//! parallelogram rule `a + b − c` (just `a` on the first row, `b` on the
//! first column, 0 at the first node), all modulo `2^bits`, and the residual
//! `(v − prediction) mod 2^bits` is range coded: 8-bit patches in one byte
//! context, 16-bit patches as a low byte and a high byte in two more.
//!
//! Colours: each channel of each stored colour is predicted by the same
//! channel of the previous stored colour in the section (0 at the start),
//! and the residual byte is coded in that channel's context.
//!
//! Cost: one pass, O(nodes), a few hundred bytes of model state. Smooth
//! surfaces give residuals of 0 or ±1 almost everywhere, about 1–2 bits per
//! node instead of 8.

use super::range_coder::{ByteModel, Decoder, Encoder, StreamEnded};

/// What the displacement codec needs to know about one patch.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DisplacementLayout {
    pub(crate) cols: usize,
    pub(crate) rows: usize,
    /// 1 or 2.
    pub(crate) bytes_per_code: usize,
}

impl DisplacementLayout {
    pub(crate) fn raw_len(&self) -> usize {
        self.cols * self.rows * self.bytes_per_code
    }
}

fn predict(values: &[u32], cols: usize, k: usize, modulus_mask: u32) -> u32 {
    let (i, j) = (k % cols, k / cols);
    match (i, j) {
        (0, 0) => 0,
        (_, 0) => values[k - 1],
        (0, _) => values[k - cols],
        _ => {
            (values[k - 1]
                .wrapping_add(values[k - cols])
                .wrapping_sub(values[k - cols - 1]))
                & modulus_mask
        }
    }
}

fn read_code(raw: &[u8], at: usize, bytes: usize) -> u32 {
    if bytes == 1 {
        u32::from(raw[at])
    } else {
        u32::from(u16::from_le_bytes([raw[at], raw[at + 1]]))
    }
}

/// Codes a raw DISP payload (the layouts must describe it exactly).
pub(crate) fn encode_displacements(raw: &[u8], layouts: &[DisplacementLayout]) -> Vec<u8> {
    let mut encoder = DisplacementEncoder::new();
    let mut at = 0;
    for layout in layouts {
        let next = at + layout.raw_len();
        encoder.push_patch(&raw[at..next], layout);
        at = next;
    }
    encoder.finish()
}

/// Codes a DISP section patch by patch, handing out the coded bytes as they come, so a
/// section larger than memory can be coded (the merge writer).
pub(crate) struct DisplacementEncoder {
    encoder: Encoder,
    model8: ByteModel,
    model_low: ByteModel,
    model_high: ByteModel,
    values: Vec<u32>,
}

impl DisplacementEncoder {
    pub(crate) fn new() -> Self {
        Self {
            encoder: Encoder::new(),
            model8: ByteModel::new(),
            model_low: ByteModel::new(),
            model_high: ByteModel::new(),
            values: Vec::new(),
        }
    }

    /// Codes one patch's raw codes (`layout.raw_len()` bytes).
    pub(crate) fn push_patch(&mut self, raw: &[u8], layout: &DisplacementLayout) {
        let mask = if layout.bytes_per_code == 1 {
            0xFF
        } else {
            0xFFFF
        };
        self.values.clear();
        for k in 0..layout.cols * layout.rows {
            let v = read_code(raw, k * layout.bytes_per_code, layout.bytes_per_code);
            self.values.push(v);
            let residual = v.wrapping_sub(predict(&self.values, layout.cols, k, mask)) & mask;
            if layout.bytes_per_code == 1 {
                self.encoder.encode_byte(&mut self.model8, residual as u8);
            } else {
                self.encoder
                    .encode_byte(&mut self.model_low, (residual & 0xFF) as u8);
                self.encoder
                    .encode_byte(&mut self.model_high, (residual >> 8) as u8);
            }
        }
    }

    /// The coded bytes final so far (see [`Encoder::take_output`]).
    pub(crate) fn take_output(&mut self) -> Vec<u8> {
        self.encoder.take_output()
    }

    /// Flushes the coder: the rest of the coded bytes.
    pub(crate) fn finish(self) -> Vec<u8> {
        self.encoder.finish()
    }
}

/// Decodes a DISP payload back to its raw bytes.
/// `raw` must be empty; the caller sized it from a checked raw length.
pub(crate) fn decode_displacements(
    coded: &[u8],
    layouts: &[DisplacementLayout],
    mut raw: Vec<u8>,
) -> Result<Vec<u8>, StreamEnded> {
    let mut decoder = Decoder::new(coded)?;
    let (mut model8, mut model_low, mut model_high) =
        (ByteModel::new(), ByteModel::new(), ByteModel::new());
    let mut values = Vec::new();
    for layout in layouts {
        let mask = if layout.bytes_per_code == 1 {
            0xFF
        } else {
            0xFFFF
        };
        values.clear();
        for k in 0..layout.cols * layout.rows {
            // Reserve slot k (filled below) so `predict` indexes exactly as the encoder does.
            values.push(0);
            let prediction = predict(&values, layout.cols, k, mask);
            let residual = if layout.bytes_per_code == 1 {
                u32::from(decoder.decode_byte(&mut model8)?)
            } else {
                let low = u32::from(decoder.decode_byte(&mut model_low)?);
                low | u32::from(decoder.decode_byte(&mut model_high)?) << 8
            };
            let v = prediction.wrapping_add(residual) & mask;
            values[k] = v;
            if layout.bytes_per_code == 1 {
                raw.push(v as u8);
            } else {
                raw.extend_from_slice(&(v as u16).to_le_bytes());
            }
        }
    }
    Ok(raw)
}

/// Codes a raw COLR payload of `bytes_per_node`-byte colours.
pub(crate) fn encode_colours(raw: &[u8], bytes_per_node: usize) -> Vec<u8> {
    let mut encoder = ColourEncoder::new(bytes_per_node);
    encoder.push(raw);
    encoder.finish()
}

/// Codes a COLR section in pieces, handing out the coded bytes as they come.
pub(crate) struct ColourEncoder {
    encoder: Encoder,
    models: Vec<ByteModel>,
    previous: [u8; 4],
}

impl ColourEncoder {
    pub(crate) fn new(bytes_per_node: usize) -> Self {
        Self {
            encoder: Encoder::new(),
            models: vec![ByteModel::new(); bytes_per_node],
            previous: [0; 4],
        }
    }

    /// Codes whole colours (`raw.len()` a multiple of the bytes per node).
    pub(crate) fn push(&mut self, raw: &[u8]) {
        for colour in raw.chunks_exact(self.models.len()) {
            for (ch, &value) in colour.iter().enumerate() {
                let residual = value.wrapping_sub(self.previous[ch]);
                self.encoder.encode_byte(&mut self.models[ch], residual);
                self.previous[ch] = value;
            }
        }
    }

    /// The coded bytes final so far (see [`Encoder::take_output`]).
    pub(crate) fn take_output(&mut self) -> Vec<u8> {
        self.encoder.take_output()
    }

    /// Flushes the coder: the rest of the coded bytes.
    pub(crate) fn finish(self) -> Vec<u8> {
        self.encoder.finish()
    }
}

/// Decodes a COLR payload back to `raw_len` raw bytes.
/// `raw` must be empty with capacity for the whole payload, whose length
/// (`raw.capacity()` is not trusted for it) is `raw_len`.
pub(crate) fn decode_colours(
    coded: &[u8],
    bytes_per_node: usize,
    raw_len: usize,
    mut raw: Vec<u8>,
) -> Result<Vec<u8>, StreamEnded> {
    let mut decoder = Decoder::new(coded)?;
    let mut models = vec![ByteModel::new(); bytes_per_node];
    let mut previous = [0u8; 4];
    for _ in 0..raw_len / bytes_per_node {
        for (ch, model) in models.iter_mut().enumerate() {
            let value = previous[ch].wrapping_add(decoder.decode_byte(model)?);
            raw.push(value);
            previous[ch] = value;
        }
    }
    Ok(raw)
}
