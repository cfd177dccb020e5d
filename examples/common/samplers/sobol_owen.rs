//! `sobol-owen`: Owen-scrambled Sobol' points, padded per dimension pair
//! (pbrt-v4's `PaddedSobolSampler` with Owen scrambling).

use super::{Cursor, MAX_SPP, TAG_1D, TAG_2D, TAG_FILM, cursor_position, halves};
use bridson::{Error, PixelSampler};

/// Owen-scrambled Sobol' points through the `sobol_burley` crate (Burley
/// 2020, hash-based Owen scrambling), padded as pbrt-v4's
/// `PaddedSobolSampler` is.
///
/// Each draw of a pixel (the film pair, time, lens, every further 1-D or
/// 2-D draw) takes Sobol' dimensions 0 and 1 (a (0,2)-sequence), or 0
/// alone for a 1-D draw, under its own 32-bit seed hashed from (seed,
/// pixel, dimension, kind). `sobol_burley` turns the seed into an
/// Owen-scrambled shuffle of the index and an Owen scramble of each
/// coordinate, so sample `i` of a pixel is point `i` of a freshly
/// scrambled and shuffled sequence, and different dimensions are only
/// randomly associated: padding.
///
/// For `spp = 2^m` the shuffle maps `0..spp` onto an aligned block of
/// `2^m` indices, so each 2-D set is a (0,m,2)-net in base 2 and each 1-D
/// set has one value per `1/spp` stratum. Other counts take the first
/// `spp` points of the shuffled sequence. At most 2¹⁶ samples per pixel,
/// `sobol_burley`'s limit.
///
/// Values are `f32` converted exactly to `f64`, in `[0, 1)`.
#[derive(Clone, Debug)]
pub(crate) struct SobolOwenSampler {
    cursor: Cursor,
}

impl SobolOwenSampler {
    /// A sampler of `spp` samples per pixel for `seed`.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if `spp` is 0 or above
    /// [`MAX_SPP`] (2¹⁶).
    pub(crate) fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        Ok(Self {
            cursor: Cursor::new(spp, seed, MAX_SPP)?,
        })
    }

    /// The `sobol_burley` seed of the set of kind `tag` at `dimension`.
    fn seed(&self, tag: u64, dimension: u32) -> u32 {
        halves(self.cursor.set_key(tag, dimension))[0]
    }

    fn pair(&self, tag: u64, dimension: u32) -> [f64; 2] {
        let seed = self.seed(tag, dimension);
        let i = self.cursor.index;
        [
            f64::from(sobol_burley::sample(i, 0, seed)),
            f64::from(sobol_burley::sample(i, 1, seed)),
        ]
    }
}

impl PixelSampler for SobolOwenSampler {
    cursor_position!();

    fn get_1d(&mut self) -> f64 {
        let d = self.cursor.take(1);
        let seed = self.seed(TAG_1D, d);
        f64::from(sobol_burley::sample(self.cursor.index, 0, seed))
    }

    fn get_2d(&mut self) -> [f64; 2] {
        let d = self.cursor.take(2);
        self.pair(TAG_2D, d)
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        self.pair(TAG_FILM, 0)
    }
}
