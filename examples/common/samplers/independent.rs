//! `independent`: every value an independent uniform hash.

use super::{Cursor, MAX_SPP, TAG_1D, TAG_2D, TAG_FILM, cursor_position, hash, to_unit};
use bridson::{Error, PixelSampler};

/// Independent uniform values: each is the hash of (seed, pixel, sample
/// index, dimension, kind), mapped to the 2⁻⁵³ grid of `[0, 1)`. The
/// Monte Carlo baseline: its error falls as `N^-1/2`, whatever the
/// integrand.
#[derive(Clone, Debug)]
pub(crate) struct IndependentSampler {
    cursor: Cursor,
}

impl IndependentSampler {
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

    fn value(&self, tag: u64, dimension: u32, coordinate: u64) -> f64 {
        let key = self.cursor.set_key(tag, dimension);
        to_unit(hash(&[key, u64::from(self.cursor.index), coordinate]))
    }
}

impl PixelSampler for IndependentSampler {
    cursor_position!();

    fn get_1d(&mut self) -> f64 {
        let d = self.cursor.take(1);
        self.value(TAG_1D, d, 0)
    }

    fn get_2d(&mut self) -> [f64; 2] {
        let d = self.cursor.take(2);
        [self.value(TAG_2D, d, 0), self.value(TAG_2D, d, 1)]
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        [self.value(TAG_FILM, 0, 0), self.value(TAG_FILM, 0, 1)]
    }
}
