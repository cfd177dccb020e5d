//! `poisson-exact`: the library's streaming exact scheme (`Tiled::exact`
//! through `CameraPixels`), one pixel at a time, behind `PixelSampler`.

use super::{hash, mix};
use bridson::{CameraPixel, CameraPixels, Error, PixelSampler, Tiled};

/// The film offsets of each pixel are the one pixel of its own `1 × 1`
/// exact-scheme stream ([`CameraPixels`] over `Tiled::builder(1, 1)
/// .exact(spp)`), seeded by a hash of the seed and the pixel; time, lens
/// and further dimensions are the stream's exact-count Poisson sets. Each
/// pixel is therefore an independent set, as the convergence study's trials
/// need (in a renderer the stream runs over the whole image instead).
/// Past the stream's dimensions (time, lens and [`EXTRA`] values) values
/// are hashed, independent.
#[derive(Clone, Debug)]
pub(crate) struct PoissonExactSampler {
    tiled: Tiled,
    spp: u32,
    seed: u64,
    /// The pixel last streamed, and its samples.
    cached: Option<([u32; 2], CameraPixel)>,
    pixel: [u32; 2],
    index: u32,
    dimension: u32,
}

/// Further 1-D values the stream makes per sample after time and lens.
const EXTRA: u32 = 8;

impl PoissonExactSampler {
    /// A sampler of exactly `spp` samples per pixel for `seed`.
    ///
    /// # Errors
    /// The errors of `TiledBuilder::build` for `exact(spp)`.
    pub(crate) fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        Ok(Self {
            tiled: Tiled::builder(1, 1).exact(spp).build()?,
            spp,
            seed,
            cached: None,
            pixel: [0, 0],
            index: 0,
            dimension: 0,
        })
    }

    /// The current pixel's samples, streamed on first use.
    fn samples(&mut self) -> Option<&CameraPixel> {
        if self.cached.as_ref().is_none_or(|(p, _)| *p != self.pixel) {
            let seed = hash(&[
                self.seed,
                u64::from(self.pixel[0]),
                u64::from(self.pixel[1]),
            ]);
            let pixel = CameraPixels::new(&self.tiled, seed, EXTRA).ok()?.next()?;
            self.cached = Some((self.pixel, pixel));
        }
        self.cached.as_ref().map(|(_, p)| p)
    }

    /// A hashed value for dimensions past the stream's.
    fn hashed(&self, dimension: u32) -> f64 {
        let h = mix(hash(&[
            self.seed,
            u64::from(self.pixel[0]),
            u64::from(self.pixel[1]),
            u64::from(self.index),
            u64::from(dimension),
        ]));
        super::to_unit(h)
    }

    /// Value `d` of the current sample: 0 time, 1–2 lens, then the extras.
    fn value(&mut self, d: u32) -> f64 {
        let index = self.index as usize;
        let from_stream = self.samples().and_then(|p| {
            let s = p.samples.get(index)?;
            match d {
                0 => Some(s.time),
                1 | 2 => s.lens.get(d as usize - 1).copied(),
                _ => p
                    .extra
                    .get(index * EXTRA as usize + (d - 3) as usize)
                    .copied(),
            }
        });
        from_stream.unwrap_or_else(|| self.hashed(d))
    }
}

impl PixelSampler for PoissonExactSampler {
    fn samples_per_pixel(&self) -> u32 {
        // `exact(spp)` gives exactly spp in every pixel.
        self.spp
    }

    fn start_pixel_sample(
        &mut self,
        pixel: [u32; 2],
        index: u32,
        dimension: u32,
    ) -> Result<(), Error> {
        let spp = self.samples_per_pixel();
        if index >= spp {
            return Err(Error::SampleIndexOutOfRange { index, spp });
        }
        (self.pixel, self.index, self.dimension) = (pixel, index, dimension);
        Ok(())
    }

    fn get_1d(&mut self) -> f64 {
        let d = self.dimension;
        self.dimension = d.wrapping_add(1);
        self.value(d)
    }

    fn get_2d(&mut self) -> [f64; 2] {
        let d = self.dimension;
        self.dimension = d.wrapping_add(2);
        [self.value(d), self.value(d.wrapping_add(1))]
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        let index = self.index as usize;
        self.samples()
            .and_then(|p| p.samples.get(index))
            .map_or([0.0; 2], |s| s.film)
    }
}
