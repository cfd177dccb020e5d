//! [`CameraPixels`]: camera samples pixel by pixel in scan order, with the
//! film positions of a [`Tiled`] stream (the paper's cross-pixel pattern).

use super::{MAX_SAMPLES_PER_PIXEL, PixelSampler, PoissonPixelSampler};
use crate::{DefaultRng, Error, Pixels, Tiled};

/// Separates the seed of the lens, time and further dimensions from the
/// seed of the film stream, so the two are independent.
const SEED_SALT: u64 = 0x9e37_79b9_7f4a_7c15;

/// The camera samples of one pixel of a [`CameraPixels`] stream.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraPixel {
    /// Column, from 0 at the left.
    pub x: u32,
    /// Row, from 0 at the top.
    pub y: u32,
    /// One sample per film point of the pixel, in the stream's order:
    /// [`film`](super::CameraSample::film) is the point's offset inside the
    /// pixel (`x + film[0]` is its raster coordinate, exactly), `time` and
    /// `lens` come from exact-count Poisson sets of as many points.
    pub samples: Vec<super::CameraSample>,
    /// The further dimensions, `extra_dims` values per sample, sample by
    /// sample: sample `i`'s are `extra[i * extra_dims..(i + 1) * extra_dims]`.
    pub extra: Vec<f64>,
}

/// Camera samples for a renderer that takes its film positions from a
/// [`Tiled`] stream, pixel by pixel in scan order: the paper's scheme, in
/// which the film points form one Poisson disk set across pixel borders.
///
/// Each pixel's film points come from the stream as it makes them; the
/// time, the lens position and any number of further dimensions come from
/// [`PoissonPixelSampler`] sets with exactly as many points as the pixel
/// has film points, so no sample of the pixel is dropped and every
/// dimension of it is a Poisson set (the paper's point: with independent
/// sets of different sizes, samples go missing). Under [`TiledBuilder::exact`](crate::TiledBuilder::exact)
/// every pixel has exactly `n` samples; under the natural sweep the count
/// varies from pixel to pixel, and each [`CameraPixel`] says how many it
/// has.
///
/// Seeded and deterministic: the same [`Tiled`], seed and dimensions give
/// the same stream.
///
/// # Example: four samples in every pixel, with their lens and time
/// ```
/// use bridson::{CameraPixels, Tiled};
/// let tiled = Tiled::builder(8, 6).exact(4).build()?;
/// let mut pixels = CameraPixels::new(&tiled, 7, 2)?;
/// let first = pixels.next().expect("48 pixels");
/// assert_eq!((first.x, first.y), (0, 0));
/// assert_eq!(first.samples.len(), 4);
/// assert_eq!(first.extra.len(), 4 * 2);
/// for s in &first.samples {
///     assert!(s.film.iter().chain(&s.lens).all(|v| (0.0..1.0).contains(v)));
///     assert!((0.0..1.0).contains(&s.time));
/// }
/// assert_eq!(pixels.count(), 47);
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Debug)]
pub struct CameraPixels {
    pixels: Pixels<DefaultRng>,
    seed: u64,
    extra_dims: u32,
    /// A sampler per sample count met so far (index = count), built on
    /// first use and sharing nothing: each bank is a pure function of its
    /// count.
    samplers: Vec<Option<PoissonPixelSampler>>,
    points: Vec<[f64; 2]>,
}

impl CameraPixels {
    /// The stream of `tiled` for `seed`, with `extra_dims` further 1-D
    /// values per sample after the camera's time and lens.
    ///
    /// # Errors
    /// [`Error::InvalidSamplesPerPixel`] if a pixel of `tiled` could hold
    /// more film points than [`PoissonPixelSampler`] supports
    /// ([`MAX_SAMPLES_PER_PIXEL`]): in exact mode, more than that many
    /// points a pixel (`spp` is then the count asked for); with natural
    /// counts, a radius below about `0.022` pixels (`spp` is then the most
    /// points a pixel could hold at that radius).
    pub fn new(tiled: &Tiled, seed: u64, extra_dims: u32) -> Result<Self, Error> {
        // Exact mode: the count itself. Natural counts: points at least r
        // apart in a unit square are at most one per cell of side r/√2, so
        // (⌊√2/r⌋ + 1)² of them.
        let most = tiled.exact().map_or_else(
            || {
                let per_side = (core::f64::consts::SQRT_2 / tiled.radius()).floor() + 1.0;
                per_side * per_side
            },
            f64::from,
        );
        if most > f64::from(MAX_SAMPLES_PER_PIXEL) {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a saturating float-to-int cast, for the report only"
            )]
            let spp = most as u32;
            return Err(Error::InvalidSamplesPerPixel {
                spp,
                max: MAX_SAMPLES_PER_PIXEL,
            });
        }
        Ok(Self {
            pixels: tiled.pixels_seeded(seed),
            seed: seed ^ SEED_SALT,
            extra_dims,
            samplers: Vec::new(),
            points: Vec::new(),
        })
    }

    /// How many top-up points exact mode has placed so far (see
    /// [`Pixels::top_ups`]).
    pub fn top_ups(&self) -> u64 {
        self.pixels.top_ups()
    }

    /// The sampler for `count` samples per pixel, built on first use.
    fn sampler(&mut self, count: u32) -> Option<&mut PoissonPixelSampler> {
        let index = usize::try_from(count).ok()?;
        if self.samplers.len() <= index {
            self.samplers.resize(index + 1, None);
        }
        let slot = self.samplers.get_mut(index)?;
        if slot.is_none() {
            // `new` checks only the range, which `CameraPixels::new` has.
            *slot = PoissonPixelSampler::new(count, self.seed).ok();
        }
        slot.as_mut()
    }
}

impl Iterator for CameraPixels {
    type Item = CameraPixel;

    fn next(&mut self) -> Option<CameraPixel> {
        let mut points = core::mem::take(&mut self.points);
        let (x, y) = self.pixels.next_into(&mut points)?;
        let extra_dims = self.extra_dims;
        let mut pixel = CameraPixel {
            x,
            y,
            samples: Vec::with_capacity(points.len()),
            extra: Vec::new(),
        };
        let count = u32::try_from(points.len()).ok();
        if let Some(sampler) = count.filter(|&c| c > 0).and_then(|c| self.sampler(c)) {
            for (index, p) in (0u32..).zip(&points) {
                // The index is below the count: never an error.
                if sampler.start_pixel_sample([x, y], index, 0).is_err() {
                    break;
                }
                let time = sampler.get_1d();
                let lens = sampler.get_2d();
                pixel.samples.push(super::CameraSample {
                    film: [p[0] - f64::from(x), p[1] - f64::from(y)],
                    time,
                    lens,
                });
                pixel
                    .extra
                    .extend((0..extra_dims).map(|_| sampler.get_1d()));
            }
        }
        self.points = points;
        Some(pixel)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.pixels.size_hint()
    }
}

impl ExactSizeIterator for CameraPixels {}
impl core::iter::FusedIterator for CameraPixels {}
