//! Poisson disk sampling in any dimension: well-spread random points that
//! are never closer than a radius `r`, by Bridson's algorithm (SIGGRAPH
//! 2007 sketch "Fast Poisson disk sampling in arbitrary dimensions").
//!
//! Three samplers, from the general to the specialised:
//!
//! - [`PoissonDisk`] fills a box of any dimension `N` (points are
//!   `[f64; N]`), each axis bounded or periodic, given the minimum
//!   distance `r`, or about how many points to make
//!   ([`PoissonDisk::about_points`]), from which it derives `r`. It yields
//!   points lazily, in generation order, or collects them all;
//!   [`PoissonDisk::iter_with`] keeps new points inside a region (a mask)
//!   and clear of pre-placed points, which also gives seamless chunks of
//!   an endless world made chunk by chunk, and
//!   [`PoissonDisk::iter_varying`] lets the radius vary with position
//!   ([`PoissonDisk::iter_varying_with`]: in a region, around pre-placed
//!   points); [`PoissonDisk::for_f32`] pads the radius so that the points
//!   rounded to `f32` keep it in `f32` arithmetic;
//!   [`PoissonDisk::generate_parallel`] makes a set on several threads,
//!   slab by slab (a different set from one run's, with its statistics).
//! - [`Tiled`] streams a 2-D set over a `W × H` raster pixel by pixel, in
//!   scan order, while its memory stays proportional to one row of pixels:
//!   for rasters too large to hold a set of, or a renderer that works a
//!   pixel at a time. The spacing is a radius in pixels or a number of
//!   points per pixel ([`TiledBuilder::per_pixel`]), and
//!   [`TiledBuilder::exact`] gives exactly `n` points in every pixel. Its
//!   default [`Scheme::Sweep`] runs one Bridson process across the image, so
//!   pixel borders leave no trace in the set; [`Scheme::Paper`] is Ye's
//!   per-pixel scheme, kept for comparison.
//! - [`Field`] is a maximal Poisson disk set that is a pure function of
//!   place: any box asked of it (a chunk of an endless world, a tile, a
//!   slab on another thread or machine) returns exactly the whole set's
//!   points there, whatever the order, chunk size or thread count, bit for
//!   bit; bounded, periodic or unbounded, in a region if one is given
//!   ([`FieldRegion`], [`SignedDistance`]; `docs/field.md`).
//!   [`PoissonDisk::generate_parallel`] stays beside it for the serial
//!   sampler's statistics (Bridson at `k`, not maximal) on several threads.
//! - For a renderer's camera samples, [`PixelSampler`] is a sampler trait
//!   in the shape of pbrt-v4's (`start_pixel_sample`, `get_1d`, `get_2d`,
//!   `camera_sample`). [`PoissonPixelSampler`] implements it with exactly
//!   `spp` samples in every dimension of every pixel, each dimension a
//!   periodic Poisson disk set, the values a pure function of (seed, pixel,
//!   sample index, dimension), so pixels can be visited in any order.
//!   [`CameraPixels`] is the streaming form: pixels in scan order, their
//!   film points from a `Tiled` stream (one Poisson set across pixel
//!   borders), their lens, time and further dimensions from sets of as many
//!   points as the pixel has.
//!
//! # Examples
//!
//! ## Example: points in the unit square
//! ```
//! use bridson::{Domain, PoissonDisk2};
//! let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, 0.05)?;
//! let points = sampler.generate_seeded(7)?;
//! for (i, a) in points.iter().enumerate() {
//!     for b in &points[..i] {
//!         let d2 = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
//!         assert!(d2 >= 0.05 * 0.05);
//!     }
//! }
//! # Ok::<(), bridson::Error>(())
//! ```
//!
//! ## Example: a lazy stream from your own generator
//! ```
//! use bridson::{Domain, PoissonDisk};
//! use rand::SeedableRng;
//! let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(1);
//! let sampler = PoissonDisk::<4>::new(Domain::from_extent([1.0; 4])?, 0.3)?;
//! let first_ten: Vec<[f64; 4]> = sampler.iter(&mut rng).take(10).collect();
//! assert_eq!(first_ten.len(), 10);
//! # Ok::<(), bridson::Error>(())
//! ```
//!
//! ## Example: a raster streamed pixel by pixel
//! ```
//! use bridson::Tiled;
//! let tiled = Tiled::builder(32, 24).per_pixel(4.0).build()?;
//! let mut total = 0;
//! for pixel in tiled.pixels_seeded(3) {
//!     // Each pixel's points, in raster coordinates, inside the pixel.
//!     let (x, y) = (f64::from(pixel.x), f64::from(pixel.y));
//!     assert!(pixel.points.iter().all(|p| p[0] - x < 1.0 && p[1] - y < 1.0));
//!     total += pixel.points.len();
//! }
//! assert!((total as f64 / (32.0 * 24.0) - 4.0).abs() < 0.5);
//! # Ok::<(), bridson::Error>(())
//! ```
//!
//! ## Example: a renderer's camera samples
//! ```
//! use bridson::{PixelSampler, PoissonPixelSampler};
//! let mut sampler = PoissonPixelSampler::new(16, 7)?;
//! for index in 0..16 {
//!     sampler.start_pixel_sample([3, 5], index, 0)?;
//!     let camera = sampler.camera_sample(); // film, time, lens
//!     let light = sampler.get_2d(); // the integrator's next dimensions
//!     assert!(camera.film.iter().chain(&light).all(|u| (0.0..1.0).contains(u)));
//! }
//! # Ok::<(), bridson::Error>(())
//! ```
//!
//! # Which rand
//! The crate is built on rand **0.10** (`rand_core` 0.10):
//! [`PoissonDisk::iter`] takes any generator implementing that version's
//! `Rng`, and [`rand`](mod@rand) re-exports that version so the names
//! match. A generator from another rand version, such as rand 0.9's
//! `StdRng`, implements that version's traits instead, and the compiler
//! says so obliquely ("the trait `DerefMut` is not implemented for
//! `StdRng`", from rand 0.10's impl for `&mut` generators). Two ways out,
//! shown with rand 0.9 (named `rand_09` in this crate's tests; `rand` in
//! your project):
//!
//! ## Example: seeding from a generator of another rand version
//! ```
//! use bridson::{Domain, PoissonDisk2};
//! use rand_09::{Rng as _, SeedableRng as _};
//! let mut my_rng = rand_09::rngs::SmallRng::seed_from_u64(5);
//! let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, 0.1)?;
//! // One u64 from your generator seeds the crate's own (`DefaultRng`):
//! // the points follow from your generator's state, on every platform.
//! let seed: u64 = my_rng.random();
//! let points = sampler.generate_seeded(seed)?;
//! assert!(points.len() > 50);
//! # Ok::<(), bridson::Error>(())
//! ```
//!
//! ## Example: drawing from a generator of another rand version
//! A newtype that implements rand 0.10's `TryRng` (infallibly) lends the
//! sampler your generator's stream itself:
//! ```
//! use bridson::rand::TryRng;
//! use bridson::{Domain, PoissonDisk2};
//! use core::convert::Infallible;
//! use rand_09::SeedableRng as _;
//!
//! struct Rand09<R>(R);
//!
//! impl<R: rand_09::RngCore> TryRng for Rand09<R> {
//!     type Error = Infallible;
//!     fn try_next_u32(&mut self) -> Result<u32, Infallible> {
//!         Ok(self.0.next_u32())
//!     }
//!     fn try_next_u64(&mut self) -> Result<u64, Infallible> {
//!         Ok(self.0.next_u64())
//!     }
//!     fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
//!         self.0.fill_bytes(dst);
//!         Ok(())
//!     }
//! }
//!
//! let mut my_rng = Rand09(rand_09::rngs::SmallRng::seed_from_u64(5));
//! let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, 0.1)?;
//! let points: Vec<[f64; 2]> = sampler.iter(&mut my_rng).collect();
//! assert!(points.len() > 50);
//! # Ok::<(), bridson::Error>(())
//! ```
//!
//! # Guarantees
//! For every sampler that [`PoissonDisk::new`] accepts:
//! 1. No two points are closer than `r`: for every pair,
//!    `Σ_i (a[i] - b[i])² >= r * r` evaluated in `f64`, summing axes in
//!    order. On periodic axes the difference is `min(|Δ|, L - |Δ|)`. This
//!    holds in every dimension: the neighbour search reach is derived from
//!    `r`, the cell size and a bound on rounding, never a fixed ±2 cells;
//!    points are stored as `f64`, never rounded to `f32`. Rounded to
//!    `f32` (`as f32`), points can come closer than `r`; a sampler from
//!    [`PoissonDisk::for_f32`] keeps `r` in `f32` arithmetic too.
//! 2. Every point lies in the half-open box: `lo <= x < hi` on every axis.
//! 3. Nothing panics, aborts or allocates without bound on any input: bad
//!    parameters are an [`Error`] from the constructor, and the heap a run
//!    holds (grid, stencils, points, active list) is counted against a
//!    budget before each allocation; a run that would outgrow it stops,
//!    with [`Error::MemoryBudgetExceeded`] from [`Points::error`], its points
//!    so far still valid.
//! 4. The set is maximal to `k` attempts: the stream ends only when every
//!    point has failed `k` candidate throws around it.
//!
//! # Limits
//! What each awkward input gives. Errors come from [`Domain::new`] (box) or
//! [`PoissonDiskBuilder::build`] (everything else), checked in this order: dimension,
//! box, radius, attempts, point cap, grid; the budget is then checked as the run
//! grows. Each row is a test in `tests/invalid_input.rs`,
//! `tests/count_mode.rs` or `tests/memory_budget.rs`; the fuzz targets in
//! `fuzz/` check the rest.
//!
//! | Input | Outcome |
//! |---|---|
//! | `N = 0` | [`Error::ZeroDimension`] |
//! | `N = 1` | works like any other `N` |
//! | a bound NaN, `+∞` or `-∞` | [`Error::NonFiniteBound`] naming the first bad axis |
//! | `lo == hi` (also `0.0 .. -0.0`) or `lo > hi` | [`Error::EmptyBox`] |
//! | `hi - lo` overflows, e.g. `-1e308 .. 1e308` | [`Error::ExtentOverflow`] |
//! | negative, subnormal or far-from-zero bounds | ordinary values: valid points |
//! | radius NaN, `±∞`, `<= 0`, subnormal, outside `1e-150 ..= 1e150` | [`Error::InvalidRadius`] |
//! | box thinner than `r` on some axis (bounded or periodic) | valid points: a row, or a single point |
//! | `r` far larger than the box (a radius in the wrong units: `r = 200` in a unit box) | one point, at once, in a few kilobytes: the search reach stops at the box (periodic: at one period), and a box whose diameter is below `r` ends after its first point |
//! | box wider than 2⁴⁰ radii on some axis | [`Error::BoxTooWide`], whatever the cap or budget |
//! | `r` small against the box (within 2⁴⁰ radii) | in 2-D and 3-D [`GridLayout::Auto`] takes the dense grid where the run's expected peak fits the budget: the bytes allocated up front plus the points the density model expects, with 5 % to spare, at their bytes a point (about 2.5 points' worth with `u32` cells, 0.5 in 3-D bricks); where the model has no answer (`k` outside `3 ..= 1000`) it assumes the box full at the packing bound. Where the dense grid does not fit, a bounded box gets the paged grid ([`GridLayout::Paged`]: the dense cells, allocated a page at a time where points land, so memory follows the points, at about 0.8 of the dense grid's speed in 2-D and 0.9 in 3-D); a periodic box and every box from 4-D up get the sparse grid, which allocates nothing up front. A run over the whole box ([`PoissonDisk::iter`], [`PoissonDisk::generate`]) whose expected points need more than twice the budget even at 8 bytes a coordinate is refused at once with [`Error::RunTooLarge`] (`points --dim 3 --radius 1e-9` in milliseconds); a run that starts and then outgrows the budget (none of 800 runs given exactly their planned peak did) ends with [`Error::MemoryBudgetExceeded`] (from [`Points::error`], or an [`Incomplete`] that keeps the points). A run in a region ([`PoissonDisk::iter_with`]) is never refused up front: a small region in a huge box runs. A point cap stops a run sooner, with no error |
//! | [`PoissonDiskBuilder::max_grid_bytes`] | bounds the peak heap of a run: what the grid allocates before its first point ([`PoissonDisk::grid_bytes`]: the dense cells and stencils) is checked in `build()`, which gives [`Error::GridTooLarge`] `{ needed, budget }` if it alone is over (`needed` saturated at `u64::MAX` for a grid no budget allows, e.g. a forced dense grid of 10¹⁸ cells); every later growth (points, hash table, active list) is checked before it is allocated, counting old and new block together. `0` refuses every grid. [`Points::heap_bytes`] tells what a run holds. With `u64::MAX` the budget no longer protects: a failed dense allocation falls back to the sparse grid, but an allocation the system grants is used |
//! | a [`Field`] query over a big box, or in a [`FieldRegion`] of zero volume | [`Error::GridTooLarge`] `{ needed, budget }` against [`Field::with_max_window_bytes`] (default 1 GiB): before it starts if its window's cells, at the bytes a cell that whole boxes were measured to peak at, are over; while it runs if its rounds' heap outgrows it (a region that meets ever smaller boxes around places it never admits, such as a line, splits cells without end). Chunks ([`Field::points_in_parallel`]) stay within it |
//! | count mode asking for 0 points (`about_points(domain, 0)`); a negative cap or count does not compile (both are `u64`) | [`Error::InvalidPointCount`] |
//! | count mode asking for more points than radii down to `1e-150` give | [`Error::InvalidRadius`] |
//! | count mode in 2-D or 3-D with `k` below 3 or above 1000 (its density tables' range) | [`Error::CountAttemptsOutOfRange`] |
//! | `k = 0` | [`Error::ZeroAttempts`] |
//! | `k` above [`MAX_ATTEMPTS`] (65 536) | [`Error::TooManyAttempts`] |
//! | large `k`, up to [`MAX_ATTEMPTS`] | accepted, and the stream ends, but late: every point retires only after `k` failed throws, so a run of `n` points costs up to about `(2n + 1)·k` throws, whatever the cap, since points start retiring once the first ones are surrounded. The stream is lazy: with annulus candidates the first points come at once; 2-D [`Candidates::Sphere`] spaces its `k` directions `2π/k` apart, so a parent blocked on one side can take about `k` throws from the third point on. Keep `k` in the hundreds |
//! | point cap `0` | an empty stream |
//! | point cap `c` | the first `c` points of the uncapped stream, a blob around the first point; also bounds the sparse grid's memory |
//! | point cap `u64::MAX` | no cap |
//! | a region ([`PoissonDisk::iter_with`], [`PoissonDisk::iter_varying_with`]) that none of `64·k` uniform tries over the box hits, with no pre-placed point | [`Error::RegionMissed`] `{ tries }` (`tries = 64·k`) from `iter_with` or `iter_varying_with`, before any point |
//! | a mask closure without its argument type, `\|p\| p[0] < 5.0` | does not compile (E0282): write `\|p: &[f64; 2]\| …` ([`Region`]) |
//! | [`PoissonDisk::for_f32`] with `r` within a few `f32` ulps of the box's largest coordinate (padding over `r/4`) | [`Error::F32TooCoarse`] `{ ulps }`; `r` outside `2⁻⁴⁰ ..= 2⁶⁰`: [`Error::InvalidRadius`] |
//! | any point, any input | `lo <= x < hi`: a candidate that rounds onto `hi` is dropped, never clamped |
//!
//! ## Memory a point takes
//! The heap a run holds on top of what its grid allocates up front
//! ([`PoissonDisk::grid_bytes`]), in bytes a point, at the peak of one run
//! (seed 1, unit box, budget off; vectors counted at their capacity, so a
//! count just past a doubling reads up to twice as much). The dense layout
//! holds a `u32` a cell up front (2-D: about 13 bytes a point; 3-D bricks
//! about 50, their points included); from 4-D up its up-front grid
//! dominates and [`GridLayout::Auto`] takes the sparse one.
//!
//! | `N` | 1 | 2 | 3 | 4 | 5 | 6 | 7 | 8 |
//! |---|--:|--:|--:|--:|--:|--:|--:|--:|
//! | dense, after its grid | 13 | 17 | 2 | 36 | 69 | – | – | – |
//! | paged (bounded boxes), all of it | 19 | 46 | 67 | – | – | – | – | – |
//! | sparse, cell array (small boxes) | 25 | 25 | 52 | 64 | 109 | 147 | 166 | 167 |
//! | sparse, hash table (huge boxes) | 31 | 114 | 166 | 190 | 194 | 404 | 395 | 447 |
//!
//! (Paged: 1-D at `r = 2e-6`, 2-D at `0.002`, 3-D at `0.02`; a box of a
//! few pages a side, so partly used edge pages count.) So the default
//! 1 GiB budget holds about 19 million points in 2-D on the dense grid
//! (`points --dim 2 --radius 0.00018` makes 18 988 665 at a peak RSS of
//! 771 MB) and about 20 million on pages (at `0.000175` the dense plan no
//! longer fits; the paged grid makes 20 089 318 in 19 s at 629 MB, where
//! the sparse grid stopped at 7.5 million after 80 s); in 3-D about 16
//! million on the bricks (`points --dim 3 --radius 0.0033`: 16 102 616 at
//! 760 MB). Elsewhere 1 GiB over the table's bytes gives the largest set
//! (derived, not run): about 55 million in 1-D; from 4-D to 8-D, 17, 10,
//! 7, 6.5 and 6.4 million with the cell array, 5.7, 5.5, 2.7, 2.7 and 2.4
//! million with the hash table. For more, raise
//! [`PoissonDiskBuilder::max_grid_bytes`] by about 60 bytes a point in 2-D.
//!
//! # Determinism
//! A `u64` seed ([`PoissonDisk::iter_seeded`]) gives the same points, in the
//! same order, on every run and platform: the sampler uses only integer
//! operations and correctly rounded `+ - × ÷ √`, never `sin`, `ln` or
//! `powf`, whose last bit varies between math libraries; the copy of the
//! loops compiled for AVX2 (used where the processor has it) rounds every
//! operation as the portable one does. Any `rand::Rng` can be passed
//! instead ([`PoissonDisk::iter`]). Value-breaking changes to the stream
//! for a seed are flagged in the CHANGELOG.
//!
//! # Feature flags
//! - `serde`: `Serialize`/`Deserialize` for [`Domain`], [`PoissonDisk`]
//!   (written as its [`PoissonDiskBuilder`]), [`Tiled`] (written as its
//!   [`TiledBuilder`]), [`Candidates`], [`GridLayout`] and [`Scheme`].
//!   Deserialising validates again, so a bad file is an [`Error`], not a
//!   bad sampler. Every field with a default may be left out; an unknown
//!   field is an error; enum values are lower-case (`"sphere"`), as on the
//!   `points` command line. It never changes output.
//!   To reproduce a saved configuration exactly, use a format that
//!   round-trips every `f64` (for `serde_json`, its `float_roundtrip`
//!   feature).
//!
//! # Performance
//! Up to 3-D the dense grid has cells of side `r/√N`, each holding the index
//! of at most one point, and checks a precomputed, nearest-first list of the
//! neighbour cells within reach of the half-cell the candidate lies in. In
//! 3-D the cells are grouped in bricks of 4×4×4, each brick a 64-bit mask of
//! its occupied cells followed by their points, so that a neighbourhood is a
//! few cache lines known in advance.
//! Each pick also keeps a small cache of points, starting with its active point's
//! neighbours and adding each point that rejects a candidate, and checks it
//! first: that settles over 90 % of attempts in 2-D without a grid search.
//! 2-D and 3-D candidates are drawn without rejection, several ahead. Each
//! pick is drawn two picks early, so that its neighbourhood is fetched from
//! memory while earlier picks run (a cache hint), and on Linux the grid asks
//! for transparent huge pages (a paging hint). On x86-64 the sampling loops
//! are compiled a second time for AVX2 and run that way where the processor
//! has it, with the same points (run-time dispatch). Those are the crate's
//! three `unsafe` blocks. Where the dense grid would exceed the memory
//! budget, a bounded box in 1-D to 3-D keeps its cells in pages allocated
//! where the points land. From 4-D up (and on periodic boxes over budget)
//! a sparse grid is used, whose memory grows with the number of points; its search walks the cells within reach by branch and
//! bound, nearest first, where the dense grid's stencil would check 504
//! cells in 4-D. `docs/performance.md` compares throughput with a textbook
//! implementation and the published crates.
#![doc(test(attr(deny(warnings))))]
// No panics on user input: library code neither unwraps nor indexes
// unchecked; where an index is provably in range and a rewrite would cost
// the hot loop, an `#[expect]` on the narrowest item states the proof.
#![warn(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::indexing_slicing,
    clippy::panic,
    clippy::unreachable,
    clippy::todo,
    clippy::unimplemented
)]
#![cfg_attr(
    test,
    allow(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::indexing_slicing,
        clippy::panic,
        reason = "unit tests may panic: that is how they fail"
    )
)]

// Layers, top to bottom; each imports only from its own layer or below
// (ARCHITECTURE.md has the map).
// Renderer: camera samples behind a pbrt-shaped trait (public API only).
mod render;
// Streaming.
mod tiled;
// Core: the sampler, where its candidates fall, its per-pick cache, its
// parallel form (slabs), its f32 padding (`single`).
mod candidates;
mod conflict_cache;
mod field;
mod parallel;
mod sampler;
mod single;
mod varying;
// The background grid.
mod grid;
// Helpers.
mod budget;
mod cpu;
mod density;
mod domain;
mod error;
mod huge_pages;
mod incomplete;
mod prefetch;
mod random;
#[cfg(feature = "serde")]
mod serde_array;
mod vector;

pub use crate::candidates::Candidates;
pub use crate::density::relative_radius;
pub use crate::domain::Domain;
pub use crate::error::Error;
pub use crate::field::{
    DEFAULT_MAX_WINDOW_CELLS_BYTES, Field, FieldRegion, Query, SignedDistance, chunk_boxes,
    field_order,
};
pub use crate::grid::{DEFAULT_MAX_GRID_BYTES, GridLayout};
pub use crate::incomplete::Incomplete;
pub use crate::random::{DefaultRng, seeded_rng};
pub use crate::render::{
    CameraPixel, CameraPixels, CameraSample, MAX_SAMPLES_PER_PIXEL, NET_MAX_SAMPLES_PER_PIXEL,
    NetPixelSampler, PixelSampler, PoissonPixelSampler,
};
pub use crate::sampler::{
    DEFAULT_ATTEMPTS, Everywhere, MAX_ATTEMPTS, Points, PoissonDisk, PoissonDisk2, PoissonDisk3,
    PoissonDiskBuilder, Region,
};
pub use crate::tiled::{
    DEFAULT_MAX_WINDOW_BYTES, EXACT_ATTEMPTS, ExactMethod, Pixel, Pixels, Scheme, Tiled,
    TiledBuilder,
};
pub use crate::varying::VaryingPoints;
/// rand **0.10**, the version whose `Rng` trait [`PoissonDisk::iter`] and
/// [`Tiled::pixels`] take, re-exported so that `bridson::rand::Rng` always
/// names the right trait whatever rand your project uses (see "Which rand"
/// in the crate docs).
///
/// It is rand with its default features off, as this crate needs it: the
/// traits (`Rng`, `TryRng`, `SeedableRng`, `RngExt`), `distr`, `seq` and
/// the small generators of `rngs` (`SmallRng`, `Xoshiro256PlusPlus`). It
/// does not bring `rngs::StdRng`, the thread generator `rand::rng()` or OS
/// entropy: for those, depend on rand 0.10 yourself with its default
/// features (cargo builds one copy with the features merged). For seeded
/// runs the crate has its own generator, [`DefaultRng`] ([`seeded_rng`]).
pub use rand;

/// The README's examples, run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;
