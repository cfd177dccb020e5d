//! Streaming mode: a 2-D Poisson disk set over a `W × H` raster, produced
//! pixel by pixel in scan order (left to right, top to bottom), each pixel
//! with its points in raster coordinates, while memory stays proportional to
//! one row of pixels.
//!
//! # Two schemes
//! - [`Scheme::Sweep`] (default): one Bridson process over the whole image,
//!   blind to pixels. Active points wait in a queue keyed by `y + u·J`
//!   (`u` uniform, `J = 4r`), cut into buckets `r/4` tall
//!   (`tiled/queue.rs`), and the process works a random point of the lowest
//!   bucket: `k` candidates around it, the first valid one kept, the point
//!   retired when none is. That is Bridson's loop on the lowest band of
//!   keys, with the batch sampler's machinery (conflict cache, offsets
//!   drawn ahead, the next pick's cells prefetched). The work front thus
//!   sweeps down the image in a band about `J` tall, in random order inside
//!   the band. Row `y` is complete once the lowest bucket starts past
//!   `y + 1 + 2r + J` (no active point left can reach it); its pixels are
//!   then gathered from the grid and emitted. Pausing to emit changes nothing in the order
//!   of the work, so pixel and row borders leave no trace in the set.
//!   Finishing pixel by pixel instead would stop the front `2r` below each
//!   row and leave a seam there (`docs/performance-journal.md`).
//! - [`Scheme::Paper`]: the scheme of Ye's "Implementing Bridson's Fast
//!   Poisson Disk Sampling in PBRT" (§3): every pixel starts from a fresh
//!   random seed, grows only inside itself, and checks its candidates against
//!   the points of the pixels already made. Valid too, but with a strong
//!   density bias inside each pixel (sparse near its left and top edges,
//!   dense near its right and bottom ones). Kept for comparison.
//!
//! Both keep the guarantee across pixel borders: every candidate is checked
//! against every point within `r`, whichever pixel holds it.

#[cfg(feature = "serde")]
mod config;
mod exact;
mod grid;
mod queue;
mod window;

use crate::candidates::{CandidateSampler, Candidates, OffsetBatch};
use crate::conflict_cache::{ConflictCache, NEAR_ORIGIN};
use crate::cpu::dispatch;
use crate::error::Error;
use crate::random::{DefaultRng, below, seeded_rng, unit};
use crate::sampler::{DEFAULT_ATTEMPTS, check_radius_and_attempts};
use crate::vector::add;
use core::iter::FusedIterator;
pub use exact::EXACT_ATTEMPTS;
pub use exact::ExactMethod;
use exact::{DEFAULT_OVERSAMPLE, Exact};
use queue::{BandQueue, Queued};
use rand::Rng;
use window::{Window, WindowPlan};

/// How the streaming mode builds each pixel.
///
/// See [`Tiled`] for the streaming API; the module docs explain why the
/// sweep has no border bias. With the `serde` feature the values are
/// `"sweep"` and `"paper"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
#[non_exhaustive]
pub enum Scheme {
    /// One process swept across the image in scan order: no border bias.
    #[default]
    Sweep,
    /// Ye's per-pixel scheme: a fresh seed per pixel, growth inside it.
    Paper,
}

/// Points per `r²` that the streaming mode produces at `k = 30` (other `k`
/// scale it by count mode's measured factor), used to
/// turn a desired number of samples per pixel into a radius:
/// `r = sqrt(DENSITY / n)`. Measured over large images (see
/// `examples/stream.rs`); the paper's rule `r = sqrt(8 / (5πn))` assumes
/// 0.509, which yields about 1.23× the points asked for.
const DENSITY_ANNULUS: f64 = 0.62;
/// As [`DENSITY_ANNULUS`], for the on-sphere candidates.
const DENSITY_SPHERE: f64 = 0.88;

/// The default memory budget of the rolling window: 256 MiB.
pub const DEFAULT_MAX_WINDOW_BYTES: u64 = 1 << 28;

/// A validated streaming sampler over a `width × height` raster.
///
/// Build it with [`Tiled::builder`], then stream the pixels with
/// [`pixels_seeded`](Self::pixels_seeded) or [`pixels`](Self::pixels).
///
/// # Example: four samples per pixel, pixel by pixel
/// ```
/// use bridson::Tiled;
/// let tiled = Tiled::builder(64, 48).per_pixel(4.0).build()?;
/// let mut total = 0;
/// for pixel in tiled.pixels_seeded(7) {
///     for p in &pixel.points {
///         // Raster coordinates, inside the pixel.
///         assert_eq!((p[0] as u32, p[1] as u32), (pixel.x, pixel.y));
///     }
///     total += pixel.points.len();
/// }
/// assert!((total as f64 / (64.0 * 48.0) - 4.0).abs() < 0.5);
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "TiledBuilder", into = "TiledBuilder")
)]
pub struct Tiled {
    settings: TiledBuilder,
    radius: f64,
    /// `k`, resolved from the settings.
    attempts: u32,
    plan: WindowPlan,
}

/// How the spacing of a streamed set is given.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Spacing {
    /// None given yet: `build` refuses it as [`Error::InvalidRadius`]. A
    /// variant rather than a NaN radius, so that settings equal themselves.
    Unset,
    Radius(f64),
    PerPixel(f64),
}

/// The settings of a [`Tiled`] sampler, checked together by
/// [`build`](Self::build).
///
/// With the `serde` feature this is the serialised form of a [`Tiled`]:
/// `width` and `height` are required; the spacing is one of `radius` and
/// `per_pixel`, and `exact` may come with either; absent fields take their
/// defaults, and an unknown field is an error. Reading a builder checks
/// nothing else; reading a [`Tiled`] runs [`build`](Self::build).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "config::TiledRepr", into = "config::TiledRepr")
)]
pub struct TiledBuilder {
    width: u32,
    height: u32,
    spacing: Spacing,
    /// `None`: [`DEFAULT_ATTEMPTS`], or
    /// [`EXACT_ATTEMPTS`] in exact mode.
    attempts: Option<u32>,
    candidates: Candidates,
    scheme: Scheme,
    max_window_bytes: u64,
    /// Exact mode: exactly this many points in every pixel.
    exact: Option<u32>,
    /// Exact mode: how excess points are dropped.
    exact_method: ExactMethod,
    /// Exact mode: the sweep's points per pixel over `n`.
    exact_oversample: f64,
    /// Exact mode: β along x and y, how much more readily points near a
    /// pixel's centre are dropped; `None` for the calibrated values.
    exact_bias: Option<[f64; 3]>,
}

impl TiledBuilder {
    /// Exact mode: exactly `n` points in every pixel (overrides the
    /// spacing). The sweep runs at the radius that gives about `s·n` points
    /// per pixel (`s` from [`exact_oversample`](Self::exact_oversample),
    /// 1.16 by default, at `k =` [`EXACT_ATTEMPTS`] unless
    /// [`attempts`](Self::attempts) is set) and each row is thinned to `n` per pixel (see
    /// [`exact_method`](Self::exact_method)). A pixel the sweep left short
    /// gets darts at least [`Tiled::radius`] from every point kept, room
    /// made by removing points of neighbouring pixels that have more than
    /// `n`. So the minimum distance is the sweep's radius,
    /// [`Tiled::radius`], except around top-ups: darts placed closer
    /// because no room could be made, which [`Pixels::top_ups`] counts (rare
    /// at the default oversampling: one in 1.07·10⁹ points in one run, one
    /// in 4.2·10⁶ in another; some at `1.0`).
    ///
    /// Exact mode always uses [`Scheme::Sweep`]: it thins whole rows
    /// jointly (see the `exact` module docs in the source). Its sweep always
    /// draws on the annulus ([`Candidates::Annulus`]): see
    /// [`candidates`](Self::candidates) for why.
    #[must_use]
    pub fn exact(mut self, n: u32) -> Self {
        self.exact = Some(n);
        self
    }

    /// Exact mode: how a pixel's excess points are dropped (default
    /// [`ExactMethod::Eliminate`]). Ignored outside exact mode.
    #[must_use]
    pub fn exact_method(mut self, method: ExactMethod) -> Self {
        self.exact_method = method;
        self
    }

    /// Exact mode: the oversampling `s`, the sweep's points per pixel over
    /// the `n` kept (default 1.16, from 1 to 16). The kept set's relative
    /// radius ρ is about ρₖ / √s, where ρₖ is the sweep's own (0.705 at
    /// exact mode's `k = 10`, 0.73 at 30): 0.655 at the defaults; a larger `s`
    /// leaves fewer pixels short and gives elimination more choice, at the
    /// cost of speed. Ignored outside exact mode.
    #[must_use]
    pub fn exact_oversample(mut self, s: f64) -> Self {
        self.exact_oversample = s;
        self
    }

    /// Exact mode: overrides the edge correction `[βx, βy]`, each in
    /// `-0.5 ..= 0.5`. The method drops a pixel's excess points with a
    /// preference `1 - βx·h(u) - βy·h(v)` by where they lie in the pixel
    /// (`h(t) = (2t - 1)² - 1/3`: `2/3` at the edges, `-1/3` at the
    /// centre), so a positive β keeps more points near the edges. Both
    /// methods, left alone, leave the edge bands a few per cent sparse at
    /// small `n`; by default β comes from a table calibrated with
    /// `examples/stream.rs` so that the density's first harmonic across a
    /// pixel vanishes, with, at small `n`, a term that favours each pixel's
    /// top band (the rows above deplete it) and one that favours its left
    /// half (short pixels are mended left to right). From `n = 2` up, the
    /// terms are then trimmed after each row by feedback from the in-pixel
    /// density the rows so far kept, which holds the pattern at the pixel
    /// frequency and its diagonals down however large the frame (measured
    /// from `n = 3` up; at `n = 2` random dropping's trims reach their
    /// bounds and only lower it); from `n = 3` up, waves at the pixel
    /// lattice's other frequencies (every one up to four cycles a pixel,
    /// and up to twelve along the axes) are trimmed the same way. Setting β here replaces the table, the other terms, the
    /// waves and the feedback, and `[0.0, 0.0, 0.0]` turns the
    /// correction off. Ignored outside exact mode.
    #[must_use]
    #[doc(hidden)]
    pub fn exact_edge_bias(mut self, beta: [f64; 3]) -> Self {
        self.exact_bias = Some(beta);
        self
    }

    /// The minimum distance, in pixels.
    #[must_use]
    pub fn radius(mut self, radius: f64) -> Self {
        self.spacing = Spacing::Radius(radius);
        self
    }

    /// Asks for about `n` points per pixel on average: the radius follows
    /// from the density the chosen candidates reach (`r = sqrt(0.62 / n)`
    /// for the annulus, `sqrt(0.88 / n)` on the sphere, at `k = 30`; at
    /// other `k` the density count mode measured there).
    #[must_use]
    pub fn per_pixel(mut self, n: f64) -> Self {
        self.spacing = Spacing::PerPixel(n);
        self
    }

    /// Attempts `k` per active point (default 30; in exact mode
    /// [`EXACT_ATTEMPTS`], 10). The radius that
    /// [`per_pixel`](Self::per_pixel) and [`exact`](Self::exact) derive
    /// follows the density reached at this `k`.
    #[must_use]
    pub fn attempts(mut self, k: u32) -> Self {
        self.attempts = Some(k);
        self
    }

    /// Candidate distribution (default [`Candidates::Annulus`]). Ignored in
    /// exact mode, whose sweep always draws on the annulus: its `k`, its
    /// oversampling and its edge correction were measured and calibrated
    /// there, and they fail on the sphere: drawn on the sphere, exact mode
    /// gives about 200 top-ups per 10⁶ points (the distance broken around
    /// each) and pixel-frequency power up to 207 at `n = 4`. With settings
    /// of the sphere's own (`k = 3`,
    /// oversampling 1.3) the top-ups go and ρ rises to 0.696 (0.657 on the
    /// annulus), but elimination locks onto the pixel grid (at `n = 16`
    /// its in-pixel density jumps between two patterns as the correction
    /// moves by 0.01, so no correction cancels it), and random dropping's
    /// render error in the tracer study rose by up to 6.5 % over its own on
    /// the annulus (the journal's "Exact mode's sweep on the sphere").
    #[must_use]
    pub fn candidates(mut self, candidates: Candidates) -> Self {
        self.candidates = candidates;
        self
    }

    /// Streaming scheme (default [`Scheme::Sweep`]).
    #[must_use]
    pub fn scheme(mut self, scheme: Scheme) -> Self {
        self.scheme = scheme;
        self
    }

    /// Memory budget of the rolling window in bytes (default
    /// [`DEFAULT_MAX_WINDOW_BYTES`], 256 MiB): [`build`](Self::build)
    /// refuses a raster whose window ([`Tiled::window_bytes`]) would
    /// exceed it.
    ///
    /// It bounds the window, not the whole stream: the stream's working
    /// memory (the queue of active points, a row's gathered points, the
    /// per-pixel points past the first eight, exact mode's band of two
    /// rows being thinned) comes on top, also proportional to the width
    /// and independent of the height. Under a counting allocator the peak
    /// heap of a whole stream is 1.15–1.32 times the window's bytes for the
    /// sweep and Ye's scheme at 4 and 64 points per pixel, 1.3–2.0 times in
    /// exact mode at `n` = 1 and 4 (oversampling up to 3), and 3.0 times at
    /// `n` = 24 and 64; `tests/stream_memory.rs`
    /// holds the stream near that, and its peak flat in the height. Leave
    /// room for that when the budget is what stands between a wide raster
    /// and the machine's memory.
    #[must_use]
    pub fn max_window_bytes(mut self, bytes: u64) -> Self {
        self.max_window_bytes = bytes;
        self
    }

    /// Checks every setting and sizes the window.
    ///
    /// # Errors
    /// [`Error::EmptyRaster`] if the width (axis 0) or height (axis 1) is
    /// 0; [`Error::InvalidPerPixel`] if the samples per pixel are not a
    /// positive finite number, or exact mode asks for 0 points per pixel,
    /// an oversampling outside `1.0 ..= 16.0` or an edge correction outside
    /// `-0.5 ..= 0.5`;
    /// [`Error::InvalidRadius`] if the radius — given, or derived from the
    /// samples per pixel — is NaN, infinite, `<= 0` or outside
    /// `1e-150 ..= 1e150`, or if no spacing was given; [`Error::ZeroAttempts`]
    /// if `k == 0`; [`Error::TooManyAttempts`] if `k` is above
    /// [`MAX_ATTEMPTS`](crate::MAX_ATTEMPTS); [`Error::WindowTooLarge`] if
    /// the window exceeds its budget.
    /// The window's row and cell counts are bounded too, so a radius above
    /// about `1.2e8` pixels, or below about `2.2e-5` (more than 65 536 cells
    /// per pixel), gives [`Error::WindowTooLarge`] with `needed: u64::MAX`
    /// whatever the budget, even on a 1 × 1 raster.
    pub fn build(self) -> Result<Tiled, Error> {
        if self.width == 0 {
            return Err(Error::EmptyRaster { axis: 0 });
        }
        if self.height == 0 {
            return Err(Error::EmptyRaster { axis: 1 });
        }
        let attempts = self.resolved_attempts();
        // Points per r² at this k: the k = 30 figure scaled as count mode
        // measured it (`density::attempts_factors`).
        let sphere = self.sweep_candidates() == Candidates::Sphere;
        let density = if sphere {
            DENSITY_SPHERE
        } else {
            DENSITY_ANNULUS
        } * crate::density::attempts_factors::<2>(sphere, attempts)[0];
        let radius = match (self.exact, self.spacing) {
            (Some(0), _) => return Err(Error::InvalidPerPixel),
            (Some(_), _)
                if !(1.0..=16.0).contains(&self.exact_oversample)
                    || self
                        .exact_bias
                        .is_some_and(|b| !b.iter().all(|v| (-0.5..=0.5).contains(v))) =>
            {
                return Err(Error::InvalidPerPixel);
            }
            (Some(n), _) => (density / (self.exact_oversample * f64::from(n))).sqrt(),
            (None, Spacing::Unset) => return Err(Error::InvalidRadius),
            (None, Spacing::Radius(r)) => r,
            (None, Spacing::PerPixel(n)) if n > 0.0 && n.is_finite() => (density / n).sqrt(),
            (None, Spacing::PerPixel(_)) => return Err(Error::InvalidPerPixel),
        };
        check_radius_and_attempts(radius, attempts)?;
        let too_large = |needed| Error::WindowTooLarge {
            needed,
            budget: self.max_window_bytes,
        };
        let width = usize::try_from(self.width).map_err(|_| too_large(u64::MAX))?;
        let height = usize::try_from(self.height).map_err(|_| too_large(u64::MAX))?;
        // Per-pixel lists only where a pixel's points are kept apart: the
        // paper's scheme grows each pixel from its own list, exact mode
        // thins them; the sweep gathers each row from its grid.
        let lists = self.scheme == Scheme::Paper || self.exact.is_some();
        let plan = WindowPlan::new(width, height, radius, lists).ok_or(too_large(u64::MAX))?;
        if plan.bytes > self.max_window_bytes {
            return Err(too_large(plan.bytes));
        }
        Ok(Tiled {
            settings: self,
            radius,
            attempts,
            plan,
        })
    }

    /// The candidates the sweep draws: the ones set, except in exact mode,
    /// which always draws on the annulus (see [`candidates`](Self::candidates)).
    fn sweep_candidates(&self) -> Candidates {
        if self.exact.is_some() {
            Candidates::Annulus
        } else {
            self.candidates
        }
    }

    /// The `k` the sweep runs with: the one set, else exact mode's default
    /// or the crate's.
    fn resolved_attempts(&self) -> u32 {
        self.attempts.unwrap_or(if self.exact.is_some() {
            EXACT_ATTEMPTS
        } else {
            DEFAULT_ATTEMPTS
        })
    }
}

/// One pixel of the stream: its position and its points, in raster
/// coordinates (`x <= p[0] < x + 1`, `y <= p[1] < y + 1`). The sweep lists
/// a pixel's points in the order of the background grid's cells (rows of
/// cells of side `r/√2`, each left to right), the paper's scheme in
/// generation order, exact mode in elimination order; none of these orders
/// is part of the contract beyond being fixed for a seed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Pixel {
    /// Column, from 0 at the left.
    pub x: u32,
    /// Row, from 0 at the top.
    pub y: u32,
    /// The pixel's points.
    pub points: Vec<[f64; 2]>,
}

impl Tiled {
    /// Settings for a `width × height` raster; give the spacing with
    /// [`TiledBuilder::radius`] or [`TiledBuilder::per_pixel`].
    pub fn builder(width: u32, height: u32) -> TiledBuilder {
        TiledBuilder {
            width,
            height,
            spacing: Spacing::Unset,
            attempts: None,
            candidates: Candidates::default(),
            scheme: Scheme::default(),
            max_window_bytes: DEFAULT_MAX_WINDOW_BYTES,
            exact: None,
            exact_method: ExactMethod::default(),
            exact_oversample: DEFAULT_OVERSAMPLE,
            exact_bias: None,
        }
    }

    /// The settings this sampler was built from, to adjust and rebuild.
    pub fn to_builder(&self) -> TiledBuilder {
        self.settings
    }

    /// The minimum distance actually used, in pixels.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The attempts `k` the sweep runs with (the one set, else 30, or
    /// [`EXACT_ATTEMPTS`] in exact mode).
    pub fn attempts(&self) -> u32 {
        self.attempts
    }

    /// The candidates the sweep draws: the ones set, except in exact mode,
    /// whose sweep always draws on the annulus (see
    /// [`TiledBuilder::candidates`]).
    pub fn candidates(&self) -> Candidates {
        self.settings.sweep_candidates()
    }

    /// Raster width in pixels.
    pub fn width(&self) -> u32 {
        self.settings.width
    }

    /// Raster height in pixels.
    pub fn height(&self) -> u32 {
        self.settings.height
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.settings.scheme
    }

    /// In exact mode ([`TiledBuilder::exact`]), the number of points every
    /// pixel holds; `None` for natural counts.
    pub fn exact(&self) -> Option<u32> {
        self.settings.exact
    }

    /// Bytes of the rolling window (the grid, which holds the sweep's
    /// points, per-pixel counts, and for the paper's scheme and exact mode
    /// the per-pixel lists with their first eight points, not the points
    /// past those): proportional to the width, independent of the height.
    /// The stream's working memory comes on top of it
    /// ([`TiledBuilder::max_window_bytes`] says how much).
    pub fn window_bytes(&self) -> u64 {
        self.plan.bytes
    }

    /// The pixels in scan order, drawn from `rng`.
    pub fn pixels<R: Rng>(&self, rng: R) -> Pixels<R> {
        let s = &self.settings;
        Pixels {
            rng,
            window: Window::new(self.plan, self.radius),
            candidates: CandidateSampler::new(s.sweep_candidates(), self.radius, self.attempts),
            ahead: OffsetBatch::new(),
            attempts: self.attempts,
            scheme: s.scheme,
            width: self.plan.width,
            height: self.plan.height,
            lead: self.plan.lead(self.radius),
            near: near_offsets(self.radius, self.plan.width.max(self.plan.height)),
            queue: BandQueue::new(self.radius),
            scratch: BandQueue::new(self.radius),
            block_width: BLOCK_CELLS * self.plan.side,
            rows_per_round: self.plan.rows_per_round,
            blocks: Vec::new(),
            order: Vec::new(),
            pending: Vec::new(),
            jitter: SWEEP_BAND * self.radius,
            reach: 2.0 * self.radius,
            radius_squared: self.radius * self.radius,
            started: false,
            next: 0,
            exact: s
                .exact
                .and_then(|n| usize::try_from(n).ok())
                .map(|n| Exact::new(n, s.exact_method, self.radius, s.exact_bias)),
            top_ups: 0,
        }
    }

    /// The pixels in scan order for `seed`: the same seed gives the same
    /// stream, byte for byte, on every run and platform.
    pub fn pixels_seeded(&self, seed: u64) -> Pixels<DefaultRng> {
        self.pixels(seeded_rng(seed))
    }
}

/// The pixel stream of a [`Tiled`] sampler, in scan order.
#[derive(Debug)]
pub struct Pixels<R> {
    rng: R,
    window: Window,
    candidates: CandidateSampler<2>,
    /// Annulus offsets drawn eight ahead, as in the batch sampler.
    ahead: OffsetBatch<2>,
    attempts: u32,
    scheme: Scheme,
    width: usize,
    height: usize,
    /// How far below the current row's bottom the sweep's children can
    /// land: `(8 + BUCKET)·r`.
    lead: f64,
    /// Pixel offsets `(dx, dy)` whose box comes within `2r` of a pixel.
    near: Vec<(isize, isize)>,
    /// Sweep scheme: the active points, by key (wide windows: but for
    /// those of the block being worked).
    queue: BandQueue,
    /// Wide windows: the active points of the block being worked.
    scratch: BandQueue,
    /// Width of a block of columns, in pixels.
    block_width: f64,
    /// Wide windows: rows made per round of blocks (see [`BLOCK_CELLS`]);
    /// 0 for narrow windows, worked across their whole width.
    rows_per_round: usize,
    /// Per block, the points to work in it before the current key limit,
    /// with their buckets.
    blocks: Vec<Vec<(Queued, u64)>>,
    /// The blocks in the order they are worked, and which are still to be.
    order: Vec<usize>,
    pending: Vec<bool>,
    /// `J`: height of the band in which the sweep works in random order.
    jitter: f64,
    /// `2r`: no candidate lands farther than this from its parent.
    reach: f64,
    radius_squared: f64,
    started: bool,
    /// Index of the next pixel in scan order.
    next: usize,
    /// Exact mode's elimination.
    exact: Option<Exact>,
    top_ups: u64,
}

/// Width of the sweep's blocks of columns, in grid cells, on wide windows
/// (`WindowPlan::rows_per_round`). There the sweep works the points due
/// before the next few rows are emitted one block at a time, the blocks in
/// random order and their edges shifted at random every round: a block's
/// cells (about 100 KB at 4 a pixel) stay in cache while it is worked,
/// where picks uniform along a front as wide as the image missed the L2
/// cache (`docs/performance-journal.md`).
const BLOCK_CELLS: f64 = 256.0;

/// Height of the sweep's random-order band, in radii. Taller bands are
/// closer to Bridson's fully random pick and cost window rows.
const SWEEP_BAND: f64 = 4.0;

impl<R: Rng> Pixels<R> {
    /// Makes the next pixel and puts its points into `points` (whose old
    /// contents are dropped), reusing its allocation: the sweep copies them
    /// from the row it gathered, exact mode from the pixel's final points
    /// (kept for the rows below), the paper's scheme from the pixel's list,
    /// which it empties. Returns the pixel's `(x, y)`, or `None` at the end
    /// of the image.
    pub fn next_into(&mut self, points: &mut Vec<[f64; 2]>) -> Option<(u32, u32)> {
        let (x, y) = self.advance()?;
        points.clear();
        if self.exact.is_some() {
            points.extend_from_slice(&self.window.slot(x, y).kept);
        } else if self.lists() {
            if let Some(slot) = self.window.slot_mut(x, y) {
                points.extend_from_slice(&slot.points);
                slot.points.clear();
            }
        } else {
            points.extend_from_slice(self.window.pixel_points(x));
        }
        Some((u32::try_from(x).ok()?, u32::try_from(y).ok()?))
    }

    /// Makes the next pixel, leaving its points in its slot; its `(x, y)`,
    /// or `None` at the end of the image.
    fn advance(&mut self) -> Option<(usize, usize)> {
        let total = self.width.checked_mul(self.height)?;
        if self.next >= total {
            return None;
        }
        let (x, y) = (self.next % self.width, self.next / self.width);
        if x == 0 {
            self.window.advance_to_row(y);
        }
        // Exact mode always sweeps: it thins whole rows.
        if self.scheme == Scheme::Paper && self.exact.is_none() {
            self.finish_alone(x, y);
        } else if x == 0 {
            self.finish_row(y);
            if let Some(exact) = &mut self.exact {
                let dims = (self.width, self.height);
                let placed = exact.thin_row(&mut self.window, y, dims, &mut self.rng);
                self.top_ups += placed as u64;
            } else {
                self.window.gather_row(y);
            }
        }
        self.next += 1;
        Some((x, y))
    }

    /// Whether the pixels' points come from per-pixel lists (the paper's
    /// scheme, exact mode) rather than the sweep's gathered rows.
    fn lists(&self) -> bool {
        self.scheme == Scheme::Paper || self.exact.is_some()
    }

    /// Exact mode: how many points so far were top-ups: darts placed in a
    /// pixel the oversampled sweep left with fewer than `n` points where no
    /// room could be made at the sweep's radius, so closer than
    /// [`Tiled::radius`] to some point. Zero means the whole stream keeps
    /// that radius.
    pub fn top_ups(&self) -> u64 {
        self.top_ups
    }

    /// Sweep scheme: work the queue until no active point can reach row
    /// `y`, seeding pixels of the row that no process has come near.
    fn finish_row(&mut self, y: usize) {
        // The loop compiled for AVX2 where the processor has it
        // (`cpu.rs`): the same points, faster.
        dispatch(
            #[inline(always)]
            || self.sweep_past(y),
        );
    }

    /// [`Self::finish_row`]'s work, inlined into each copy.
    #[inline(always)]
    fn sweep_past(&mut self, y: usize) {
        if !self.started {
            self.started = true;
            self.seed_row(0);
        }
        #[expect(clippy::cast_precision_loss, reason = "row indices < 2^32")]
        let mut done_at = (y + 1) as f64 + self.reach + self.jitter;
        // Wide windows: a round of blocks makes `rows_per_round` rows.
        if self.rows_per_round > 1 && y.is_multiple_of(self.rows_per_round) {
            #[expect(clippy::cast_precision_loss, reason = "a few rows")]
            let more = (self.rows_per_round - 1) as f64;
            done_at += more;
        }
        loop {
            if self.rows_per_round == 0 {
                self.work_band(done_at, y);
            } else {
                while self.work_blocks(done_at, y) {}
            }
            // A connected front reaches every pixel; this only seeds
            // pixels no point has come within 2r of (say, r much larger
            // than the image), and then goes on working the queue.
            if !self.seed_row(y) {
                return;
            }
        }
    }

    /// Works every queued point whose bucket starts below `limit` until it
    /// fails, across the whole width (narrow windows).
    #[inline(always)]
    fn work_band(&mut self, limit: f64, y: usize) {
        // Bridson's loop over the lowest band: a random active point of
        // it throws its candidates; it stays active until it fails.
        loop {
            let window = &self.window;
            let Some((place, cell)) = self
                .queue
                .pick(limit, &mut self.rng, |key| window.prefetch(key))
            else {
                break;
            };
            let parent = window.point(cell);
            match self.spawn((&parent, cell), (0, y), false) {
                Some(child) => self.push(child),
                None => self.queue.retire(place),
            }
        }
    }

    /// Works every queued point whose bucket starts below `limit` until it
    /// fails, block of columns by block of columns (wide windows, see
    /// [`BLOCK_CELLS`]); whether there was any. A child that lands in a
    /// block already worked is queued, for the next call.
    #[inline(always)]
    fn work_blocks(&mut self, limit: f64, y: usize) -> bool {
        let width = self.block_width;
        let shift = width * unit(&mut self.rng);
        #[expect(clippy::cast_precision_loss, reason = "pixel counts < 2^32")]
        let span = self.width as f64 + shift;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a few blocks per row: the width over the block width, plus one"
        )]
        let count = (span / width) as usize + 1;
        let inv_width = 1.0 / width;
        let block_of = move |p: &[f64; 2]| -> usize {
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a point of the raster: in 0..count; through i64, cheaper than f64 -> usize"
            )]
            let b = ((p[0] + shift) * inv_width) as i64 as usize;
            b.min(count - 1)
        };
        if self.blocks.len() < count {
            self.blocks.resize_with(count, Vec::new);
        }
        let mut any = false;
        let blocks = &mut self.blocks;
        let window = &self.window;
        self.queue.drain_below(limit, |cell, bucket| {
            any = true;
            if let Some(list) = blocks.get_mut(block_of(&window.point(cell))) {
                list.push((cell, bucket));
            }
        });
        if !any {
            return false;
        }
        // The blocks in random order (Fisher–Yates), so that across a
        // block's edge either side is as likely to be worked first.
        self.order.clear();
        self.order.extend(0..count);
        for i in (1..count).rev() {
            let j = below(&mut self.rng, i + 1);
            self.order.swap(i, j);
        }
        self.pending.clear();
        self.pending.resize(count, true);
        for k in 0..count {
            let Some(&b) = self.order.get(k) else {
                break;
            };
            if let Some(list) = self.blocks.get_mut(b) {
                for &(p, bucket) in list.iter() {
                    self.scratch.push_in(p, bucket);
                }
                list.clear();
            }
            self.scratch.forget_ahead();
            if let Some(flag) = self.pending.get_mut(b) {
                *flag = false;
            }
            // Bridson's loop over the block's lowest band: a random active
            // point of it throws its candidates; it stays active until it
            // fails.
            loop {
                let window = &self.window;
                let Some((place, cell)) = self
                    .scratch
                    .pick(limit, &mut self.rng, |key| window.prefetch(key))
                else {
                    break;
                };
                let parent = window.point(cell);
                match self.spawn((&parent, cell), (0, y), false) {
                    Some(child) => {
                        let (child, cell) = child;
                        let key = child[1] + self.jitter * unit(&mut self.rng);
                        let bucket = self.queue.bucket(key);
                        let at = block_of(&child);
                        if !self.queue.starts_below(bucket, limit) {
                            self.queue.push_in(cell, bucket);
                        } else if at == b {
                            self.scratch.push_in(cell, bucket);
                        } else if self.pending.get(at) == Some(&true)
                            && let Some(list) = self.blocks.get_mut(at)
                        {
                            list.push((cell, bucket));
                        } else {
                            self.queue.push_in(cell, bucket);
                        }
                    }
                    None => self.scratch.retire(place),
                }
            }
        }
        true
    }

    /// Seeds each pixel of row `y` with nothing within `2r`; whether any
    /// seed was placed.
    fn seed_row(&mut self, y: usize) -> bool {
        let mut seeded = false;
        for x in 0..self.width {
            if !self.anything_near(x, y) && self.seed(x, y) {
                seeded = true;
            }
        }
        seeded
    }

    /// Queues the point `p`, stored in the cell with key `cell`.
    fn push(&mut self, (p, cell): ([f64; 2], Queued)) {
        let key = p[1] + self.jitter * unit(&mut self.rng);
        self.queue.push(cell, key);
    }

    /// Paper scheme: a fresh seed, then Bridson inside the pixel only.
    fn finish_alone(&mut self, x: usize, y: usize) {
        self.seed(x, y);
        loop {
            let len = self.window.slot(x, y).active.len();
            if len == 0 {
                return;
            }
            let i = below(&mut self.rng, len);
            let Some(&parent) = self.window.slot(x, y).active.get(i) else {
                return;
            };
            let cell = self.window.key(&parent);
            if self.spawn((&parent, cell), (x, y), true).is_none()
                && let Some(slot) = self.window.slot_mut(x, y)
            {
                slot.active.swap_remove(i);
            }
        }
    }

    /// Up to `k` candidates around `parent`, whose cell key is `cell`;
    /// stores and returns the first valid one, with its cell key.
    /// Candidates in pixels already emitted (before `current` in scan
    /// order), outside the raster or below the window are refused; with
    /// `only_current`, so is any outside the current pixel.
    ///
    /// The batch sampler's loop (`sampler.rs`, `grow_cached`): offsets drawn
    /// ahead, and a [`ConflictCache`] of the parent's neighbours and of the
    /// points that turned candidates away, checked before the grid. The
    /// cache changes no decision.
    #[inline(always)]
    fn spawn(
        &mut self,
        (parent, cell): (&[f64; 2], usize),
        current: (usize, usize),
        only_current: bool,
    ) -> Option<([f64; 2], usize)> {
        // The rectangle candidates may land in: the current pixel, or the
        // rows from the current one to the window's last (pixels before
        // `current` in the current row are never refused by it: the sweep
        // finishes whole rows, from column 0).
        #[expect(clippy::cast_precision_loss, reason = "pixel counts < 2^32")]
        let (x0, x1, y0, y1) = if only_current {
            let (x, y) = (current.0 as f64, current.1 as f64);
            (x, x + 1.0, y, y + 1.0)
        } else {
            // No child lands farther below the row's top than this (see
            // `WindowPlan::new`); the window's grid holds no more.
            let last = (current.1 + 1) as f64 + self.lead;
            (
                0.0,
                self.width as f64,
                current.1 as f64,
                last.min(self.height as f64),
            )
        };
        let radius = self.reach / 2.0;
        let ahead = self.candidates.reads_ahead();
        // Below `2²⁸·r` from the origin, a candidate is its parent plus its
        // offset to within far less than the cache's and the interior
        // test's margins (`ConflictCache::block_relative`).
        let small = parent.iter().all(|x| x.abs() < radius * NEAR_ORIGIN);
        let near_origin = ahead && small;
        let mut cache = ConflictCache::<2, 16>::new(*parent, radius);
        self.window.seed(cell, 16, |q| cache.push(q));
        // Far from the rectangle's sides (the usual case), no candidate can
        // leave it: skip the per-attempt test, as the batch sampler does
        // far from the box's faces. 2-D candidates lie within
        // `2r·(1 + 10⁻⁷)` of the parent, and below `2²⁸·r` from the origin
        // the sum's rounding is far below the slack.
        let m = self.reach * (1.0 + 1e-6);
        let interior = small
            && parent[0] - x0 >= m
            && x1 - parent[0] > m
            && parent[1] - y0 >= m
            && y1 - parent[1] > m;
        let mut state = self.candidates.start(&mut self.rng);
        for _ in 0..self.attempts {
            let offset = if ahead {
                let (j, offset_in_r) = self.ahead.next_unit(&self.candidates, &mut self.rng);
                // The quick check first, as the batch sampler does: most
                // candidates fail it, and it does not depend on the
                // rectangle (the same decisions in either order).
                if near_origin && cache.block_relative(&offset_in_r) {
                    continue;
                }
                self.ahead.offset(j, &self.candidates)
            } else {
                self.candidates.offset(&mut self.rng, &mut state)
            };
            let c = add(parent, &offset);
            if !(interior || (c[0] >= x0 && c[0] < x1 && c[1] >= y0 && c[1] < y1)) {
                continue;
            }
            if !near_origin && cache.block(&c, self.radius_squared) {
                continue;
            }
            let (key, hit) = self.window.conflict(&c);
            if let Some(q) = hit {
                cache.push(&q);
                continue;
            }
            // Through u32 (cheaper than f64 -> usize on x86-64): the raster
            // is at most 2^32 - 1 pixels a side.
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "inside the raster, so in 0..width and 0..height"
            )]
            let pixel = (c[0] as u32 as usize, c[1] as u32 as usize);
            let list = only_current || self.exact.is_some();
            if self.window.insert((c, key), pixel, (list, only_current)) {
                return Some((c, key));
            }
        }
        None
    }

    /// Up to `k` uniform darts in the pixel; stores the first valid one
    /// (queued, for the sweep) and says whether there was one.
    fn seed(&mut self, x: usize, y: usize) -> bool {
        #[expect(clippy::cast_precision_loss, reason = "pixel indices < 2^32")]
        let (fx, fy) = (x as f64, y as f64);
        for _ in 0..self.attempts {
            let p = [fx + unit(&mut self.rng), fy + unit(&mut self.rng)];
            if self.pixel_of(&p) != Some((x, y)) {
                continue;
            }
            let (key, hit) = self.window.conflict(&p);
            if hit.is_some() {
                continue;
            }
            let paper = self.scheme == Scheme::Paper;
            if self
                .window
                .insert((p, key), (x, y), (paper || self.exact.is_some(), paper))
            {
                if self.scheme != Scheme::Paper {
                    self.push((p, key));
                }
                return true;
            }
        }
        false
    }

    /// Whether any point, emitted or not, lies in a pixel within `2r` of
    /// pixel `(x, y)`: if none does, no process has reached it yet and it
    /// gets a seed.
    fn anything_near(&self, x: usize, y: usize) -> bool {
        self.near_pixels(x, y)
            .any(|(qx, qy)| self.window.count(qx, qy) > 0)
    }

    /// Pixels of the window within `2r` of `(x, y)`.
    fn near_pixels(&self, x: usize, y: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.near
            .iter()
            .filter_map(move |&(dx, dy)| self.in_window(x, y, dx, dy))
    }

    fn in_window(&self, x: usize, y: usize, dx: isize, dy: isize) -> Option<(usize, usize)> {
        let qx = x.checked_add_signed(dx)?;
        let qy = y.checked_add_signed(dy)?;
        (qx < self.width && qy < self.height && self.window.holds_row(qy)).then_some((qx, qy))
    }

    /// The pixel holding `p`, or `None` outside the raster.
    fn pixel_of(&self, p: &[f64; 2]) -> Option<(usize, usize)> {
        #[expect(clippy::cast_precision_loss, reason = "pixel counts < 2^32")]
        let (w, h) = (self.width as f64, self.height as f64);
        if !(p[0] >= 0.0 && p[0] < w && p[1] >= 0.0 && p[1] < h) {
            return None;
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "inside the raster, so in 0..width and 0..height"
        )]
        let (x, y) = (p[0] as usize, p[1] as usize);
        Some((x.min(self.width - 1), y.min(self.height - 1)))
    }
}

impl<R: Rng> Iterator for Pixels<R> {
    type Item = Pixel;

    fn next(&mut self) -> Option<Pixel> {
        let (x, y) = self.advance()?;
        // A copy of exactly the pixel's size; a slot keeps its allocation.
        let points = if self.exact.is_some() {
            self.window.slot(x, y).kept.clone()
        } else if self.lists() {
            self.window
                .slot_mut(x, y)
                .map(|slot| {
                    let points = slot.points.to_vec();
                    slot.points.clear();
                    points
                })
                .unwrap_or_default()
        } else {
            self.window.pixel_points(x).to_vec()
        };
        Some(Pixel {
            x: u32::try_from(x).ok()?,
            y: u32::try_from(y).ok()?,
            points,
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = (self.width * self.height).saturating_sub(self.next);
        (left, Some(left))
    }
}

impl<R: Rng> ExactSizeIterator for Pixels<R> {}
impl<R: Rng> FusedIterator for Pixels<R> {}

/// Offsets `(dx, dy)` of the pixels whose box comes within `2r` of a
/// pixel's box (with a relative slack for rounding), clamped to the
/// raster's size.
fn near_offsets(radius: f64, size: usize) -> Vec<(isize, isize)> {
    #[expect(clippy::cast_precision_loss, reason = "pixel counts < 2^32")]
    let reach_f = (2.0 * radius).ceil().min(size as f64);
    #[expect(
        clippy::cast_possible_truncation,
        reason = "clamped to the raster size"
    )]
    let reach = reach_f as isize;
    let limit = 2.0 * radius * (1.0 + 1e-9);
    let gap = |d: isize| {
        #[expect(clippy::cast_precision_loss, reason = "small offsets")]
        let a = d.unsigned_abs() as f64;
        (a - 1.0).max(0.0)
    };
    let mut offsets = Vec::new();
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            if gap(dx) * gap(dx) + gap(dy) * gap(dy) < limit * limit {
                offsets.push((dx, dy));
            }
        }
    }
    offsets
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sweep compiled for AVX2 (`cpu.rs`) streams the portable sweep's
    /// points bit for bit: narrow and wide windows, exact mode by both
    /// methods.
    #[test]
    fn both_copies_stream_the_same_points() {
        use crate::cpu::tests::{assert_same, both_copies};
        let stream = |tiled: &Tiled| {
            let mut all = Vec::new();
            let mut points = Vec::new();
            let mut pixels = tiled.pixels_seeded(4);
            while pixels.next_into(&mut points).is_some() {
                all.extend(points.iter().map(|p| p.map(f64::to_bits)));
            }
            all
        };
        let narrow = Tiled::builder(24, 20).per_pixel(4.0).build().unwrap();
        let wide = Tiled::builder(600, 3).per_pixel(4.0).build().unwrap();
        assert!(wide.plan.rows_per_round >= 1, "a wide window");
        let exact = |method| {
            Tiled::builder(20, 16)
                .exact(4)
                .exact_method(method)
                .build()
                .unwrap()
        };
        for (what, tiled) in [
            ("narrow", narrow),
            ("wide", wide),
            ("exact, elimination", exact(ExactMethod::Eliminate)),
            ("exact, random", exact(ExactMethod::Random)),
        ] {
            assert_same(what, both_copies(|| stream(&tiled)), 1000);
        }
    }

    /// Wide windows' rounds of blocks, forced on a small raster with
    /// blocks a few pixels wide: every pixel comes in scan order holding
    /// only its own points, and no two points of the union are closer
    /// than `r` (checked pair by pair).
    #[test]
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        clippy::cast_precision_loss,
        reason = "pixel indices and counts of a small raster"
    )]
    fn rounds_of_blocks_keep_the_union_and_the_scan_order() {
        for (w, h, r, block) in [(40, 24, 0.39, 5.0), (23, 31, 0.9, 2.5), (30, 12, 0.2, 1.7)] {
            let tiled = Tiled::builder(w, h).radius(r).build().unwrap();
            let (wu, hu) = (w as usize, h as usize);
            let plan = WindowPlan::sized(wu, hu, r, false, 0).unwrap();
            assert!(plan.rows_per_round >= 1, "forced wide");
            let tiled = Tiled { plan, ..tiled };
            let mut stream = tiled.pixels_seeded(3);
            stream.block_width = block;
            let mut union = Vec::new();
            let mut points = Vec::new();
            for k in 0..wu * hu {
                let at = stream.next_into(&mut points);
                let (x, y) = ((k % wu) as u32, (k / wu) as u32);
                assert_eq!(at, Some((x, y)), "scan order");
                for p in &points {
                    assert_eq!((p[0] as u32, p[1] as u32), (x, y), "{p:?} in its pixel");
                }
                union.extend_from_slice(&points);
            }
            assert_eq!(stream.next_into(&mut points), None);
            let expected = f64::from(w * h) * 0.62 / (r * r);
            assert!(
                union.len() as f64 > 0.8 * expected,
                "{w}x{h} r={r}: {} points",
                union.len()
            );
            for (i, p) in union.iter().enumerate() {
                for q in &union[i + 1..] {
                    let d = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
                    assert!(d >= r * r, "{w}x{h} r={r}: {p:?} and {q:?} closer than r");
                }
            }
        }
    }
}
