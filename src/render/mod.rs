//! Camera samples for renderers: the [`PixelSampler`] trait, shaped like
//! pbrt-v4's `Sampler`, its Poisson disk implementation
//! [`PoissonPixelSampler`], its Poisson disk net implementation
//! [`NetPixelSampler`], and [`CameraPixels`], the paper's streaming
//! form, whose film points come from a [`Tiled`](crate::Tiled) stream.

mod bank;
mod eliminate;
mod hash;
mod net;
mod net_keys;
mod net_table;
mod net_tile;
mod pixel;
mod stream;

pub use net::{NET_MAX_SAMPLES_PER_PIXEL, NetPixelSampler};
pub use pixel::{MAX_SAMPLES_PER_PIXEL, PoissonPixelSampler};
pub use stream::{CameraPixel, CameraPixels};

use crate::Error;

/// The sample a camera needs to make one ray: where in the pixel, when,
/// and where on the lens.
///
/// Drawn by [`PixelSampler::camera_sample`] in pbrt-v4's order: film, then
/// time, then lens.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraSample {
    /// The offset inside the pixel, in `[0, 1)²`: add the pixel's corner
    /// (or pass it through a reconstruction filter's warp first, as pbrt
    /// does) to get raster coordinates.
    pub film: [f64; 2],
    /// The time within the shutter interval, in `[0, 1)`.
    pub time: f64,
    /// The position on the lens, in `[0, 1)²`, to be warped to the
    /// aperture.
    pub lens: [f64; 2],
}

/// A source of sample values for a renderer, pixel by pixel, in the shape
/// of pbrt-v4's `Sampler`.
///
/// A renderer calls [`start_pixel_sample`](Self::start_pixel_sample) for
/// sample `index` of a pixel, then draws that sample's values in a fixed
/// order: [`camera_sample`](Self::camera_sample) (film, time, lens), then
/// whatever its integrator needs with [`get_1d`](Self::get_1d) and
/// [`get_2d`](Self::get_2d). Each draw moves a dimension counter on (one for
/// `get_1d`, two for `get_2d`), so the `d`-th value of every sample in a
/// pixel comes from the same well-spread set.
///
/// # Contract
/// 1. A value is a pure function of the sampler's seed, the pixel, the
///    sample index and the dimension: re-entering `start_pixel_sample` in
///    any order, from any clone, on any thread, gives bit-identical values
///    (pbrt-v4's `ConsistentValues` test).
/// 2. Every value lies in `[0, 1)`.
/// 3. Bad input is an [`Error`], never a panic.
///
/// # Values are `f64`
/// Values are `f64`, the crate's number type, in which its minimum-distance
/// guarantees are stated and checked. A renderer in `f32` should round
/// down, not to nearest: an `f64` just below 1 rounds to `1.0_f32` under
/// `as f32`, outside `[0, 1)`.
///
/// # Why `Clone` is not a supertrait
/// Implementations are `Clone` (cheaply: shared tables behind an `Arc`), so
/// each render thread takes its own copy. The trait does not require it,
/// so that it stays dyn-compatible: a renderer can hold a
/// `Box<dyn PixelSampler>` chosen at run time. It does require
/// `Send + Sync`.
///
/// # Example: the camera samples of one pixel
/// ```
/// use bridson::{PixelSampler, PoissonPixelSampler};
/// let mut sampler = PoissonPixelSampler::new(16, 7)?;
/// let mut films = Vec::new();
/// for index in 0..sampler.samples_per_pixel() {
///     sampler.start_pixel_sample([3, 5], index, 0)?;
///     let cs = sampler.camera_sample();
///     assert!((0.0..1.0).contains(&cs.time));
///     films.push(cs.film);
///     // The integrator's dimensions follow the camera's.
///     let light = sampler.get_2d();
///     assert!(light.iter().all(|u| (0.0..1.0).contains(u)));
/// }
/// // Exactly 16 film offsets, and revisiting gives the same values.
/// assert_eq!(films.len(), 16);
/// sampler.start_pixel_sample([3, 5], 9, 0)?;
/// assert_eq!(sampler.camera_sample().film, films[9]);
/// # Ok::<(), bridson::Error>(())
/// ```
pub trait PixelSampler: Send + Sync {
    /// The number of samples taken in every pixel.
    fn samples_per_pixel(&self) -> u32;

    /// Moves to sample `index` of `pixel`, with the dimension counter at
    /// `dimension` (0 to start a sample; a larger value skips dimensions,
    /// as when an integrator resumes a path).
    ///
    /// # Errors
    /// [`Error::SampleIndexOutOfRange`] if `index >= samples_per_pixel()`;
    /// [`Error::PixelOutOfImage`] if the sampler knows the image size and
    /// `pixel` lies outside it. On error the sampler stays where it was.
    fn start_pixel_sample(
        &mut self,
        pixel: [u32; 2],
        index: u32,
        dimension: u32,
    ) -> Result<(), Error>;

    /// The next value, in `[0, 1)`; moves the dimension counter on by one.
    fn get_1d(&mut self) -> f64;

    /// The next pair of values, in `[0, 1)²`; moves the dimension counter
    /// on by two.
    fn get_2d(&mut self) -> [f64; 2];

    /// The film offset of the current sample inside its pixel, in
    /// `[0, 1)²`. It comes from its own set, apart from the dimension
    /// counter, which it leaves alone (as pbrt-v4's PMJ02BN sampler does).
    fn get_pixel_2d(&mut self) -> [f64; 2];

    /// The camera's values for the current sample, in pbrt-v4's order:
    /// the film offset ([`get_pixel_2d`](Self::get_pixel_2d)), then time
    /// ([`get_1d`](Self::get_1d)), then lens ([`get_2d`](Self::get_2d)).
    fn camera_sample(&mut self) -> CameraSample {
        let film = self.get_pixel_2d();
        let time = self.get_1d();
        let lens = self.get_2d();
        CameraSample { film, time, lens }
    }
}
