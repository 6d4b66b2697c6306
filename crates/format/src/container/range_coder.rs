//! An adaptive binary range coder with bit-tree byte models.
//!
//! The coder is the classic carry-less-cache design used by LZMA: 32-bit
//! range, 11-bit probabilities adapted with a shift of 5. A byte is coded as
//! 8 binary decisions walking a 255-node bit tree, most significant bit
//! first. `docs/format.md` specifies it exactly, so that an independent
//! decoder can be written from the text.
//!
//! Cost: O(8) multiply-and-compare steps per byte; memory: 255 × u16 per
//! context. Based on: G. N. N. Martin, "Range encoding" (1979); the LZMA
//! specification (I. Pavlov).

const PROBABILITY_BITS: u32 = 11;
pub(crate) const PROBABILITY_ONE: u16 = 1 << PROBABILITY_BITS;
const ADAPT_SHIFT: u32 = 5;
const TOP: u32 = 1 << 24;

/// Adaptive probabilities for one byte-valued context (a 255-node bit tree;
/// slot 0 is unused so that node `m` lives at index `m`).
#[derive(Clone)]
pub(crate) struct ByteModel {
    probabilities: [u16; 256],
}

impl ByteModel {
    pub(crate) fn new() -> Self {
        Self {
            probabilities: [PROBABILITY_ONE / 2; 256],
        }
    }
}

/// Range encoder writing into a byte vector.
pub(crate) struct Encoder {
    low: u64,
    range: u32,
    cache: u8,
    cache_size: u64,
    out: Vec<u8>,
}

impl Encoder {
    pub(crate) fn new() -> Self {
        Self {
            low: 0,
            range: u32::MAX,
            cache: 0,
            cache_size: 1,
            out: Vec::new(),
        }
    }

    /// Codes one binary decision with the adaptive probability `probability` (of a 0).
    pub(crate) fn encode_bit(&mut self, probability: &mut u16, bit: u32) {
        let bound = (self.range >> PROBABILITY_BITS) * u32::from(*probability);
        if bit == 0 {
            self.range = bound;
            *probability += (PROBABILITY_ONE - *probability) >> ADAPT_SHIFT;
        } else {
            self.low += u64::from(bound);
            self.range -= bound;
            *probability -= *probability >> ADAPT_SHIFT;
        }
        while self.range < TOP {
            self.range <<= 8;
            self.shift_low();
        }
    }

    fn shift_low(&mut self) {
        if (self.low as u32) < 0xFF00_0000 || (self.low >> 32) != 0 {
            let carry = (self.low >> 32) as u8;
            let mut pending = self.cache;
            loop {
                self.out.push(pending.wrapping_add(carry));
                pending = 0xFF;
                self.cache_size -= 1;
                if self.cache_size == 0 {
                    break;
                }
            }
            self.cache = ((self.low >> 24) & 0xFF) as u8;
        }
        self.cache_size += 1;
        self.low = (self.low & 0x00FF_FFFF) << 8;
    }

    /// Codes one byte in the given context.
    pub(crate) fn encode_byte(&mut self, model: &mut ByteModel, byte: u8) {
        let mut node = 1usize;
        for shift in (0..8).rev() {
            let bit = u32::from(byte >> shift) & 1;
            self.encode_bit(&mut model.probabilities[node], bit);
            node = (node << 1) | bit as usize;
        }
    }

    /// Hands out the bytes written so far and forgets them: they are final (a carry
    /// only ever reaches the byte held back in `cache` and the pending `0xFF`s).
    pub(crate) fn take_output(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.out)
    }

    /// Flushes the coder and returns the coded bytes.
    pub(crate) fn finish(mut self) -> Vec<u8> {
        for _ in 0..5 {
            self.shift_low();
        }
        self.out
    }
}

/// The coded stream ended before the decoder had all the bytes it needs.
#[derive(Debug)]
pub(crate) struct StreamEnded;

/// Range decoder reading from a byte slice.
pub(crate) struct Decoder<'a> {
    input: &'a [u8],
    position: usize,
    range: u32,
    code: u32,
}

impl<'a> Decoder<'a> {
    pub(crate) fn new(input: &'a [u8]) -> Result<Self, StreamEnded> {
        let mut decoder = Self {
            input,
            position: 0,
            range: u32::MAX,
            code: 0,
        };
        // The first byte is always 0 (the encoder's initial cache).
        for _ in 0..5 {
            decoder.code = (decoder.code << 8) | u32::from(decoder.next_byte()?);
        }
        Ok(decoder)
    }

    fn next_byte(&mut self) -> Result<u8, StreamEnded> {
        let byte = *self.input.get(self.position).ok_or(StreamEnded)?;
        self.position += 1;
        Ok(byte)
    }

    /// Decodes one binary decision coded by [`Encoder::encode_bit`].
    pub(crate) fn decode_bit(&mut self, probability: &mut u16) -> Result<u32, StreamEnded> {
        let bound = (self.range >> PROBABILITY_BITS) * u32::from(*probability);
        let bit = if self.code < bound {
            self.range = bound;
            *probability += (PROBABILITY_ONE - *probability) >> ADAPT_SHIFT;
            0
        } else {
            self.code -= bound;
            self.range -= bound;
            *probability -= *probability >> ADAPT_SHIFT;
            1
        };
        while self.range < TOP {
            self.range <<= 8;
            self.code = (self.code << 8) | u32::from(self.next_byte()?);
        }
        Ok(bit)
    }

    /// Decodes one byte in the given context.
    pub(crate) fn decode_byte(&mut self, model: &mut ByteModel) -> Result<u8, StreamEnded> {
        let mut node = 1usize;
        for _ in 0..8 {
            let bit = self.decode_bit(&mut model.probabilities[node])?;
            node = (node << 1) | bit as usize;
        }
        Ok((node & 0xFF) as u8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(data: &[u8]) -> usize {
        let mut model = ByteModel::new();
        let mut enc = Encoder::new();
        for &b in data {
            enc.encode_byte(&mut model, b);
        }
        let coded = enc.finish();
        let mut model = ByteModel::new();
        let mut dec = Decoder::new(&coded).unwrap();
        for &b in data {
            assert_eq!(dec.decode_byte(&mut model).unwrap(), b);
        }
        coded.len()
    }

    #[test]
    fn round_trips_skewed_and_random_data() {
        let zeros = vec![0u8; 100_000];
        let coded = round_trip(&zeros);
        // Each coded byte carries at most ~45 input bytes at the clamped probability.
        assert!(coded * 64 + 64 >= zeros.len(), "{coded}");
        assert!(coded < 3000, "{coded}");
        let mut state = 12345u32;
        let noise: Vec<u8> = (0..50_000)
            .map(|_| {
                state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (state >> 24) as u8
            })
            .collect();
        let coded = round_trip(&noise);
        assert!(coded < 50_000 * 102 / 100, "{coded}");
        round_trip(&[0xFF; 5000]);
        round_trip(&[]);
    }

    #[test]
    fn a_short_stream_is_an_error_not_a_panic() {
        let mut model = ByteModel::new();
        let mut dec = Decoder::new(&[0, 1, 2, 3, 4]).unwrap();
        let mut ended = false;
        for _ in 0..100 {
            if dec.decode_byte(&mut model).is_err() {
                ended = true;
                break;
            }
        }
        assert!(ended);
        assert!(Decoder::new(&[0, 1]).is_err());
    }
}
