//! `low-discrepancy`: pbrt-v2's `LDSampler`, a scrambled (0,2)-sequence
//! per pixel, shuffled across dimensions.

use super::{Cursor, MAX_SPP, TAG_1D, TAG_2D, TAG_FILM, cursor_position, halves, hash, permute};
use bridson::{Error, PixelSampler};

/// pbrt-v2's low-discrepancy sampler (`LDSampler`, with its
/// `LDShuffleScrambled1D/2D`).
///
/// - A 2-D dimension (film, lens, every `get_2d`) of a pixel is the first
///   `spp` points of the (0,2)-sequence in base 2: the van der Corput
///   sequence in x and the second Sobol' generator in y, each with a random
///   digital scramble (an XOR of all 32 bits) per (pixel, dimension).
/// - A 1-D dimension is the first `spp` points of the van der Corput
///   sequence with a random digital scramble per (pixel, dimension).
/// - Sample index `i` gets point number `π(i)`, `π` a hashed permutation of
///   `0..spp` per (pixel, dimension): pbrt-v2's shuffle, which decorrelates
///   one dimension from another.
///
/// For `spp = 2^m` each 2-D set is a (0,m,2)-net in base 2 (every
/// elementary interval of area `1/spp` holds one point) and each 1-D set
/// has one value in each `1/spp` stratum. pbrt-v2 rounds other counts up
/// to a power of two; here a pixel takes the first `spp` points, so that
/// it gets exactly `spp` samples, and the net property holds only for the
/// largest power-of-two prefix.
///
/// Values are multiples of 2⁻³², so in `[0, 1)`.
#[derive(Clone, Debug)]
pub(crate) struct LowDiscrepancySampler {
    cursor: Cursor,
}

/// The scrambled radical inverse in base 2 (van der Corput) of `i`, as a
/// 32-bit fraction.
pub(crate) fn van_der_corput(i: u32, scramble: u32) -> u32 {
    i.reverse_bits() ^ scramble
}

/// The scrambled second coordinate of Sobol's (0,2)-sequence for `i`, as a
/// 32-bit fraction: the XOR of the generator matrix's columns picked by
/// the bits of `i`. Column 0 is the top bit; each next column is the last
/// one XORed with itself shifted right by one (the columns of Pascal's
/// triangle mod 2, bit-reversed).
pub(crate) fn sobol_second(mut i: u32, scramble: u32) -> u32 {
    let mut column = 1_u32 << 31;
    let mut x = scramble;
    while i != 0 {
        if i & 1 == 1 {
            x ^= column;
        }
        i >>= 1;
        column ^= column >> 1;
    }
    x
}

/// A 32-bit fraction as an `f64` in `[0, 1)` (exact).
fn unit(x: u32) -> f64 {
    f64::from(x) / 4_294_967_296.0 // 2³²
}

impl LowDiscrepancySampler {
    /// A sampler of `spp` samples per pixel for `seed`.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if `spp` is 0 or above
    /// [`MAX_SPP`].
    pub(crate) fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        Ok(Self {
            cursor: Cursor::new(spp, seed, MAX_SPP)?,
        })
    }

    /// The point number and the two scrambles of the current sample in
    /// the set of kind `tag` at `dimension`.
    fn locate(&self, tag: u64, dimension: u32) -> (u32, [u32; 2]) {
        let key = self.cursor.set_key(tag, dimension);
        let point = permute(self.cursor.index, self.cursor.spp, key);
        (point, halves(hash(&[key, 0x5c4a_7b1e])))
    }

    fn pair(&self, tag: u64, dimension: u32) -> [f64; 2] {
        let (point, [sx, sy]) = self.locate(tag, dimension);
        [
            unit(van_der_corput(point, sx)),
            unit(sobol_second(point, sy)),
        ]
    }
}

impl PixelSampler for LowDiscrepancySampler {
    cursor_position!();

    fn get_1d(&mut self) -> f64 {
        let d = self.cursor.take(1);
        let (point, [scramble, _]) = self.locate(TAG_1D, d);
        unit(van_der_corput(point, scramble))
    }

    fn get_2d(&mut self) -> [f64; 2] {
        let d = self.cursor.take(2);
        self.pair(TAG_2D, d)
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        self.pair(TAG_FILM, 0)
    }
}
