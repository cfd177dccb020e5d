//! `stratified`: jittered strata in every dimension, padded.

use super::{
    Cursor, MAX_SPP, TAG_1D, TAG_2D, TAG_FILM, cursor_position, halves, hash, jitter, permute,
};
use bridson::{Error, PixelSampler};

/// Jittered stratified sampling, padded (pbrt's `StratifiedSampler` with
/// jitter, for any `spp`).
///
/// - A 1-D dimension splits `[0, 1)` into `spp` equal strata and puts one
///   jittered value in each.
/// - A 2-D dimension (film, lens, every `get_2d`) splits `[0, 1)²` into an
///   `nx × ny = spp` grid, `nx` the largest divisor of `spp` not above
///   `√spp` (so a prime `spp` gives a `1 × spp` grid of slabs), and puts one
///   jittered point in each cell.
///
/// Sample index `i` of a pixel gets stratum (or cell) `π(i)`, with `π` a
/// hashed permutation of `0..spp` per (pixel, dimension): the padding that
/// keeps one dimension's strata uncorrelated with another's.
#[derive(Clone, Debug)]
pub(crate) struct StratifiedSampler {
    cursor: Cursor,
    grid: [u32; 2],
}

/// The `[nx, ny]` grid of `spp` cells: `nx` the largest divisor of `spp`
/// with `nx² <= spp`.
pub(crate) fn grid_of(spp: u32) -> [u32; 2] {
    let nx = (1..=spp)
        .take_while(|d| u64::from(*d) * u64::from(*d) <= u64::from(spp))
        .filter(|d| spp.is_multiple_of(*d))
        .last()
        .unwrap_or(1);
    [nx, spp / nx]
}

/// Sample `index` of the padded, jittered 1-D strata of `n` values keyed by
/// `key`.
pub(crate) fn stratum_1d(key: u64, index: u32, n: u32) -> f64 {
    let stratum = permute(index, n, key);
    let [bits, _] = halves(hash(&[key, u64::from(index)]));
    (f64::from(stratum) + jitter(bits)) / f64::from(n)
}

/// Sample `index` of the padded, jittered `[nx, ny]` grid keyed by `key`.
pub(crate) fn cell_2d(key: u64, index: u32, [nx, ny]: [u32; 2]) -> [f64; 2] {
    let cell = permute(index, nx * ny, key);
    let [jx, jy] = halves(hash(&[key, u64::from(index)]));
    [
        (f64::from(cell % nx) + jitter(jx)) / f64::from(nx),
        (f64::from(cell / nx) + jitter(jy)) / f64::from(ny),
    ]
}

impl StratifiedSampler {
    /// A sampler of `spp` samples per pixel for `seed`.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if `spp` is 0 or above
    /// [`MAX_SPP`].
    pub(crate) fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        Ok(Self {
            cursor: Cursor::new(spp, seed, MAX_SPP)?,
            grid: grid_of(spp),
        })
    }

    /// The grid each 2-D dimension is stratified on, `[nx, ny]`.
    pub(crate) fn grid(&self) -> [u32; 2] {
        self.grid
    }
}

impl PixelSampler for StratifiedSampler {
    cursor_position!();

    fn get_1d(&mut self) -> f64 {
        let d = self.cursor.take(1);
        stratum_1d(
            self.cursor.set_key(TAG_1D, d),
            self.cursor.index,
            self.cursor.spp,
        )
    }

    fn get_2d(&mut self) -> [f64; 2] {
        let d = self.cursor.take(2);
        cell_2d(self.cursor.set_key(TAG_2D, d), self.cursor.index, self.grid)
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        cell_2d(
            self.cursor.set_key(TAG_FILM, 0),
            self.cursor.index,
            self.grid,
        )
    }
}
