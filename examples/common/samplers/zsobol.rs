//! `zsobol`: Owen-scrambled Sobol' in Morton order across pixels, after
//! Ahmed and Wonka 2020 ("Screen-space blue-noise diffusion of Monte Carlo
//! sampling error via hierarchical ordering of pixels") as pbrt-v4's
//! `ZSobolSampler` uses it. Written from the paper's and the book's
//! description; no code or tables taken from either.

use super::{Cursor, MAX_SPP, TAG_1D, TAG_2D, TAG_FILM, hash, mix};
use bridson::{Error, PixelSampler};

/// One Owen-scrambled (0,2)-sequence shared by the whole image: sample `i`
/// of pixel `(x, y)` takes Sobol' index `morton(x, y) · 2^m + i`
/// (`2^m >= spp` the next power of two), so every pixel owns an aligned
/// block of `2^m` indices and neighbouring pixels (in Morton order) own
/// neighbouring blocks, which together form larger nets. That spreads the
/// error across pixels as blue noise (Ahmed and Wonka).
///
/// Before the Sobol' point is taken, the index's base-4 digits are
/// permuted, each by one of the 24 permutations of `0..4` chosen by a hash
/// of (seed, dimension, the digits above it); with `m` odd the last, single
/// bit is flipped by such a hash. This is a random hierarchical reordering
/// of the pixels (and of the samples inside each pixel) that keeps every
/// aligned block whole, so each pixel's set stays a (0,m,2)-net.
///
/// Every draw (the film pair, time, lens, each further 1-D or 2-D draw) is
/// Sobol' dimensions 0 and 1 (or 0 alone), Owen-scrambled with a seed of
/// its own hashed from (seed, kind, dimension) but not from the pixel:
/// padding across dimensions, one sequence across pixels.
///
/// The index is computed in 64 bits and the Sobol' point in 64-bit fixed
/// point, so no index bit is lost; pixel coordinates at or above 2¹⁶ are
/// folded into the scramble seeds (their pixels still get nets, but no
/// longer Morton neighbours). Owen scrambling is a hash in the style of
/// Laine and Karras (every output digit flipped by a function of the
/// digits above it), with multipliers drawn from the seed.
///
/// For `spp = 2^m` each 2-D set of a pixel is a (0,m,2)-net and each 1-D
/// set has one value per `1/spp` stratum; other counts take the first
/// `spp` indices of the `2^m` block (pbrt-v4 rounds the count up instead).
/// Values lie on the 2⁻⁵³ grid of `[0, 1)`.
#[derive(Clone, Debug)]
pub(crate) struct ZSobolSampler {
    cursor: Cursor,
    /// `m`: the block of a pixel has `2^m >= spp` indices.
    log2_spp: u32,
}

/// Interleaves the low 16 bits of `x` and `y` (`x` in the even bits).
pub(crate) fn morton(x: u32, y: u32) -> u64 {
    fn spread(v: u32) -> u64 {
        let mut v = u64::from(v & 0xffff);
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    }
    spread(x) | (spread(y) << 1)
}

/// The permutation of `0..4` numbered `h % 24` (a Fisher–Yates shuffle
/// driven by the mixed-radix digits of `h`), applied to `digit`.
fn permute4(digit: u64, mut h: u64) -> u64 {
    let mut p = [0_u64, 1, 2, 3];
    for k in (1..4_u64).rev() {
        #[expect(clippy::cast_possible_truncation, reason = "j <= k < 4")]
        let j = (h % (k + 1)) as usize;
        h /= k + 1;
        #[expect(clippy::cast_possible_truncation, reason = "k < 4")]
        p.swap(k as usize, j);
    }
    #[expect(clippy::cast_possible_truncation, reason = "a base-4 digit")]
    p[digit as usize & 3]
}

/// The Morton index `code` with its base-4 digits permuted under `key`:
/// digits at bit pairs `(s, s + 1)` for `s = m mod 2, m mod 2 + 2, ..`
/// up to bit `31 + m` (the Morton code's 32 bits above the sample's `m`),
/// each by a permutation chosen from the original digits
/// above it; with `m` odd, bit 0 is flipped by a hash of the bits above.
pub(crate) fn shuffle_index(code: u64, log2_spp: u32, key: u64) -> u64 {
    let low = log2_spp & 1;
    let mut out = 0_u64;
    let mut shift = low;
    while shift < 32 + log2_spp {
        let digit = (code >> shift) & 3;
        let above = code.checked_shr(shift + 2).unwrap_or(0);
        // One mix per digit of the key, the digit's place and the digits
        // above it, folded so that no two (place, above) pairs collide
        // (`shift < 64` takes 6 bits; `above < 2^(30 + m - shift)` fits in
        // the other 58 for every `m <= 16`).
        let h = mix(key ^ (above << 6 | u64::from(shift)));
        out |= permute4(digit, h >> 16) << shift;
        shift += 2;
    }
    if low == 1 {
        out |= (code & 1) ^ (hash(&[key, 0x0062_6974, code >> 1]) & 1);
    }
    out
}

/// The first Sobol' dimension (van der Corput) of `index`, as a 64-bit
/// fraction: the index's bits reversed.
fn sobol_0(index: u64) -> u64 {
    index.reverse_bits()
}

/// The second Sobol' dimension of `index`, as a 64-bit fraction: the XOR
/// of the generator's columns picked by the index's bits; column 0 is the
/// top bit and each next column the last XORed with itself shifted right
/// by one (Pascal's triangle mod 2).
fn sobol_1(mut index: u64) -> u64 {
    let mut column = 1_u64 << 63;
    let mut x = 0;
    while index != 0 {
        if index & 1 == 1 {
            x ^= column;
        }
        index >>= 1;
        column ^= column >> 1;
    }
    x
}

/// Owen scrambling of a 64-bit fraction under `key`, hash-based: with the
/// bits reversed (the fraction's first digit in bit 0), each step (add a
/// constant; multiply by an odd number; XOR with the product by an even
/// number) changes bit `j` by a function of bits `< j` only, i.e. flips
/// each digit by a function of the digits above it.
pub(crate) fn owen(value: u64, key: u64) -> u64 {
    let mut x = value.reverse_bits();
    let mut k = key;
    for _ in 0..3 {
        k = mix(k ^ 0x243f_6a88_85a3_08d3);
        x = x.wrapping_add(k);
        x = x.wrapping_mul(mix(k) | 1);
        x ^= x.wrapping_mul(mix(k ^ 0x1319_8a2e_0370_7344) & !1);
    }
    x.reverse_bits()
}

/// A 64-bit fraction to the 2⁻⁵³ grid of `[0, 1)`.
fn unit(x: u64) -> f64 {
    #[expect(clippy::cast_precision_loss, reason = "53 bits, exact")]
    let v = (x >> 11) as f64;
    v / 9_007_199_254_740_992.0 // 2⁵³
}

impl ZSobolSampler {
    /// A sampler of `spp` samples per pixel for `seed`.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if `spp` is 0 or above
    /// [`MAX_SPP`].
    pub(crate) fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        let cursor = Cursor::new(spp, seed, MAX_SPP)?;
        Ok(Self {
            cursor,
            log2_spp: spp.next_power_of_two().trailing_zeros(),
        })
    }

    /// The key of the draw of kind `tag` at `dimension`: the same in every
    /// pixel (apart from pixels beyond 2¹⁶, folded in).
    fn key(&self, tag: u64, dimension: u32) -> u64 {
        let [x, y] = self.cursor.pixel;
        hash(&[
            self.cursor.seed_hash,
            tag,
            u64::from(dimension),
            u64::from(x >> 16) << 32 | u64::from(y >> 16),
        ])
    }

    /// The shuffled Sobol' index of the current sample under `key`.
    fn index(&self, key: u64) -> u64 {
        let [x, y] = self.cursor.pixel;
        let code = (morton(x, y) << self.log2_spp) | u64::from(self.cursor.index);
        shuffle_index(code, self.log2_spp, key)
    }

    fn pair(&self, tag: u64, dimension: u32) -> [f64; 2] {
        let key = self.key(tag, dimension);
        let i = self.index(key);
        [
            unit(owen(sobol_0(i), mix(key ^ 0x78))),
            unit(owen(sobol_1(i), mix(key ^ 0x79))),
        ]
    }
}

impl PixelSampler for ZSobolSampler {
    fn samples_per_pixel(&self) -> u32 {
        self.cursor.spp
    }

    fn start_pixel_sample(
        &mut self,
        pixel: [u32; 2],
        index: u32,
        dimension: u32,
    ) -> Result<(), Error> {
        self.cursor.start(pixel, index, dimension)
    }

    fn get_1d(&mut self) -> f64 {
        let d = self.cursor.take(1);
        let key = self.key(TAG_1D, d);
        unit(owen(sobol_0(self.index(key)), mix(key ^ 0x78)))
    }

    fn get_2d(&mut self) -> [f64; 2] {
        let d = self.cursor.take(2);
        self.pair(TAG_2D, d)
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        self.pair(TAG_FILM, 0)
    }
}
