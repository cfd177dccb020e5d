//! `poisson-exact`: the library's streaming exact scheme (`Tiled::exact`,
//! as `CameraPixels` uses it), one pixel at a time, behind `PixelSampler`.

use super::hash;
use bridson::{Error, PixelSampler, PoissonPixelSampler, Tiled};

/// The film offsets of each pixel are the one pixel of its own `1 × 1`
/// exact-scheme stream (`Tiled::builder(1, 1).exact(spp)`), seeded by a
/// hash of the seed and the pixel, so each pixel is an independent set, as
/// the convergence study's trials need (in a renderer `CameraPixels` runs
/// one stream over the whole image instead). Time, lens and further
/// dimensions are exact-count Poisson sets from a [`PoissonPixelSampler`]
/// of the same count, as in `CameraPixels`.
#[derive(Clone, Debug)]
pub(crate) struct PoissonExactSampler {
    tiled: Tiled,
    seed: u64,
    rest: PoissonPixelSampler,
    /// The pixel last streamed, and its film points (raster coordinates in
    /// the `1 × 1` raster: offsets in the pixel).
    film: Option<([u32; 2], Vec<[f64; 2]>)>,
}

impl PoissonExactSampler {
    /// A sampler of exactly `spp` samples per pixel for `seed`.
    ///
    /// # Errors
    /// The errors of `TiledBuilder::build` for `exact(spp)`, and of
    /// [`PoissonPixelSampler::new`].
    pub(crate) fn new(spp: u32, seed: u64) -> Result<Self, Error> {
        Ok(Self {
            tiled: Tiled::builder(1, 1).exact(spp).build()?,
            seed,
            rest: PoissonPixelSampler::new(spp, seed)?,
            film: None,
        })
    }
}

impl PixelSampler for PoissonExactSampler {
    fn samples_per_pixel(&self) -> u32 {
        self.rest.samples_per_pixel()
    }

    fn start_pixel_sample(
        &mut self,
        pixel: [u32; 2],
        index: u32,
        dimension: u32,
    ) -> Result<(), Error> {
        self.rest.start_pixel_sample(pixel, index, dimension)
    }

    fn get_1d(&mut self) -> f64 {
        self.rest.get_1d()
    }

    fn get_2d(&mut self) -> [f64; 2] {
        self.rest.get_2d()
    }

    fn get_pixel_2d(&mut self) -> [f64; 2] {
        let pixel = self.rest.pixel();
        if self.film.as_ref().is_none_or(|(p, _)| *p != pixel) {
            let seed = hash(&[self.seed, u64::from(pixel[0]), u64::from(pixel[1])]);
            let points = self
                .tiled
                .pixels_seeded(seed)
                .next()
                .map(|p| p.points)
                .unwrap_or_default();
            self.film = Some((pixel, points));
        }
        let index = self.rest.sample_index() as usize;
        self.film
            .as_ref()
            .and_then(|(_, points)| points.get(index))
            .copied()
            .unwrap_or([0.0; 2])
    }
}
