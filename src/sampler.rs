//! The sampler: Bridson's algorithm, configured and validated up front, run
//! lazily as an iterator.

use crate::budget::{reserve_one, vec_bytes};
use crate::candidates::{CandidateSampler, Candidates, OffsetBatch};
use crate::conflict_cache::{ConflictCache, NEAR_ORIGIN};
use crate::cpu::dispatch;
use crate::density::{expected_count, radius_for_count};
use crate::domain::Domain;
use crate::error::Error;
use crate::grid::{DEFAULT_MAX_GRID_BYTES, Grid, GridLayout, GridPlan, NeighbourGrid, plan};
use crate::incomplete::Incomplete;
use crate::random::{DefaultRng, below, seeded_rng, unit};
use crate::vector::{add, all_finite, zip_map};
use core::iter::FusedIterator;
use rand::Rng;

/// The number of attempts per active point used unless told otherwise:
/// Bridson's `k = 30`.
pub const DEFAULT_ATTEMPTS: u32 = 30;

/// The largest number of attempts `k` accepted: 65 536. A run costs about
/// `2·n·k` candidate throws for `n` points; past a few hundred attempts the
/// packing hardly changes, and a `k` in the billions would keep a run going
/// for hours.
pub const MAX_ATTEMPTS: u32 = 1 << 16;

/// The attempts `k` count mode takes in 2-D and 3-D: the range of its
/// density tables (`density::ATTEMPTS_K`).
pub(crate) const COUNT_ATTEMPTS: core::ops::RangeInclusive<u32> = 3..=1000;

/// Where new points may go: the acceptance region of a run with
/// [`PoissonDisk::iter_with`] or [`PoissonDisk::iter_varying_with`].
/// Implemented for [`Everywhere`] (a plain run) and for every closure
/// `Fn(&[f64; N]) -> bool` (a mask: `true` where a point may go).
///
/// # A mask closure's argument type
/// Write it out: `|p: &[f64; 2]| p[0] < 5.0`. The compiler infers a
/// closure's argument types only from an `Fn` bound on the parameter, and
/// this one is a `Region` bound (so that [`Everywhere`], which is not a
/// closure, fits too); without the type it stops with E0282, "type
/// annotations needed", pointing at `p`. A named function or a closure
/// stored in a typed `let` works as well.
///
/// ```
/// use bridson::{Domain, PoissonDisk2};
/// let sampler = PoissonDisk2::new(Domain::from_extent([10.0, 10.0])?, 0.5)?;
/// let points: Vec<[f64; 2]> = sampler.iter_with_seeded(1, |p: &[f64; 2]| p[0] < 5.0, &[])?.collect();
/// assert!(points.iter().all(|p| p[0] < 5.0));
/// # Ok::<(), bridson::Error>(())
/// ```
///
/// Without the type (this example must not compile):
/// ```compile_fail,E0282
/// use bridson::{Domain, PoissonDisk2};
/// let sampler = PoissonDisk2::new(Domain::from_extent([10.0, 10.0])?, 0.5)?;
/// let points: Vec<[f64; 2]> = sampler.iter_with_seeded(1, |p| p[0] < 5.0, &[])?.collect();
/// # Ok::<(), bridson::Error>(())
/// ```
pub trait Region<const N: usize> {
    /// Whether a new point may lie at `p` (a point of the domain).
    fn admits(&self, p: &[f64; N]) -> bool;
}

/// The region of a plain run: the whole domain. A zero-sized type, so a
/// plain run's loop has no region check at all.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Everywhere;

impl<const N: usize> Region<N> for Everywhere {
    #[inline(always)]
    fn admits(&self, _p: &[f64; N]) -> bool {
        true
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> bool> Region<N> for F {
    #[inline(always)]
    fn admits(&self, p: &[f64; N]) -> bool {
        self(p)
    }
}

/// Smallest and largest radius accepted: beyond them `r²` (or the squared
/// distances compared with it) is no longer a normal `f64`.
const MIN_RADIUS: f64 = 1e-150;
const MAX_RADIUS: f64 = 1e150;

/// A validated Poisson disk sampler in `N` dimensions: domain, radius,
/// attempts, candidate distribution and grid choice.
///
/// Build it with [`PoissonDisk::new`] (defaults for everything but the
/// domain and radius) or [`PoissonDisk::builder`], then draw points with
/// [`iter`](Self::iter) / [`iter_seeded`](Self::iter_seeded) or collect them
/// with [`generate`](Self::generate) / [`generate_seeded`](Self::generate_seeded).
///
/// `N` is a const parameter: points are `[f64; N]`. The aliases
/// [`PoissonDisk2`] and [`PoissonDisk3`] name the common cases.
///
/// # Example: a periodic 3-D tile with the on-sphere candidates
/// ```
/// use bridson::{Candidates, Domain, PoissonDisk3};
/// let domain = Domain::from_extent([1.0, 1.0, 1.0])?.with_periodic([true; 3]);
/// let sampler = PoissonDisk3::builder(domain, 0.2)
///     .attempts(20)
///     .candidates(Candidates::Sphere)
///     .build()?;
/// let points = sampler.generate_seeded(42)?;
/// assert!(points.len() > 50);
/// assert!(points.iter().all(|p| domain.contains(p)));
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(try_from = "PoissonDiskBuilder<N>", into = "PoissonDiskBuilder<N>")
)]
pub struct PoissonDisk<const N: usize> {
    config: PoissonDiskBuilder<N>,
    plan: GridPlan<N>,
    /// The density model's expected point count, where it answers.
    expected: Option<f64>,
}

/// A sampler in the plane.
pub type PoissonDisk2 = PoissonDisk<2>;
/// A sampler in space.
pub type PoissonDisk3 = PoissonDisk<3>;

/// The settings of a [`PoissonDisk`], checked together by
/// [`build`](Self::build).
///
/// Setting a value never fails; `build` validates everything at once, so a
/// point cap or a larger budget can make feasible what the defaults would
/// reject. With the `serde` feature this is the serialised form of a
/// sampler: `domain` and `radius` (or, in count mode, `about_points`) are
/// required, absent fields take their defaults, and an unknown field is an
/// error (a misspelt `"atempts"` is not silently ignored).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename = "PoissonDisk", deny_unknown_fields))]
pub struct PoissonDiskBuilder<const N: usize> {
    domain: Domain<N>,
    /// Absent (NaN) in count mode, which derives it.
    #[cfg_attr(
        feature = "serde",
        serde(default = "unset_radius", skip_serializing_if = "is_unset")
    )]
    radius: f64,
    /// Count mode: about this many points; the radius follows. `Some(0)`
    /// (also for a negative count) is refused by `build`.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    about_points: Option<u64>,
    #[cfg_attr(feature = "serde", serde(default = "default_attempts"))]
    attempts: u32,
    #[cfg_attr(feature = "serde", serde(default))]
    candidates: Candidates,
    #[cfg_attr(feature = "serde", serde(default))]
    layout: GridLayout,
    #[cfg_attr(feature = "serde", serde(default = "default_budget"))]
    max_grid_bytes: u64,
    #[cfg_attr(feature = "serde", serde(default))]
    max_points: Option<u64>,
}

#[cfg(feature = "serde")]
fn unset_radius() -> f64 {
    f64::NAN
}

#[cfg(feature = "serde")]
#[expect(
    clippy::trivially_copy_pass_by_ref,
    reason = "serde passes a reference"
)]
fn is_unset(radius: &f64) -> bool {
    radius.is_nan()
}

#[cfg(feature = "serde")]
fn default_attempts() -> u32 {
    DEFAULT_ATTEMPTS
}

#[cfg(feature = "serde")]
fn default_budget() -> u64 {
    DEFAULT_MAX_GRID_BYTES
}

impl<const N: usize> PoissonDiskBuilder<N> {
    /// Sets `k`, the attempts around an active point before it retires
    /// (default 30, Bridson's choice). More attempts pack denser and cost
    /// more.
    #[must_use]
    pub fn attempts(mut self, k: u32) -> Self {
        self.attempts = k;
        self
    }

    /// Sets how candidates are drawn (default [`Candidates::Annulus`]).
    #[must_use]
    pub fn candidates(mut self, candidates: Candidates) -> Self {
        self.candidates = candidates;
        self
    }

    /// Chooses the grid layout (default [`GridLayout::Auto`]). The layout
    /// changes speed and memory, not the points: both search exactly.
    #[must_use]
    pub fn layout(mut self, layout: GridLayout) -> Self {
        self.layout = layout;
        self
    }

    /// Sets the memory budget of a run in bytes (default
    /// [`DEFAULT_MAX_GRID_BYTES`], 1 GiB): the
    /// most heap the grid, its points and the active list may hold at once,
    /// counted before each allocation. A run that would outgrow it stops
    /// ([`Points::error`]).
    #[must_use]
    pub fn max_grid_bytes(mut self, bytes: u64) -> Self {
        self.max_grid_bytes = bytes;
        self
    }

    /// Stops after `cap` points (default `None`: until the domain is full).
    /// A cap also bounds the memory a run grows to, so it can make a huge
    /// domain complete within the budget.
    ///
    /// A cap keeps the first `cap` points of the stream, and Bridson's
    /// algorithm grows the set outward from its first point: a capped set
    /// is a compact blob around a random point, not points spread over the
    /// box. In a 10⁶ × 10⁶ box at `r = 1`, a cap of 1 000 gives a blob about
    /// 52 × 45 units wide (seed 3). For about `n` points spread over the
    /// whole box, use count mode, [`about_points`](Self::about_points),
    /// which picks the radius instead.
    ///
    /// `u64::MAX` means no cap. The cap is unsigned, so a negative one does
    /// not compile:
    /// ```compile_fail
    /// # use bridson::{Domain, PoissonDisk2};
    /// let builder = PoissonDisk2::builder(Domain::from_extent([1.0, 1.0]).unwrap(), 0.1);
    /// let _ = builder.max_points(-1);
    /// ```
    #[must_use]
    pub fn max_points(mut self, cap: u64) -> Self {
        self.max_points = (cap != u64::MAX).then_some(cap);
        self
    }

    /// Count mode: asks for about `n` points instead of a radius. `build`
    /// derives the radius at which this sampler, in this box, makes `n`
    /// points on average (replacing any radius given), from the density the
    /// sampler reaches at `k = 30` in the box's interior and along its faces,
    /// and in 2-D and 3-D how both change with `k` ([`attempts`](Self::attempts)),
    /// measured once and tabulated (`examples/count_density.rs`; the model is
    /// in `src/density.rs`). One run, no trial runs.
    ///
    /// The expected count (the mean over seeds) is within ±2 % of `n` for
    /// `n >= 1000` in 2-D and 3-D, any `k` from 3 to 1000 (tabulated at 15
    /// values, linear in between), either candidate kind, any mix of
    /// bounded and periodic axes, in every box at least 4 radii thick on
    /// each axis at the radius derived (at 1 000 points, a 2-D strip up to
    /// about 1:60, a 3-D rod up to about 1:20:20). A single run scatters
    /// around it: at 1 000 points by about 0.9 % (standard deviation) in
    /// 2-D and 1.2 % in 3-D, falling as `1/√n`. Thinner boxes get the mean
    /// the sampler reaches there, but the count itself varies widely between
    /// seeds (annulus candidates mostly land outside a slab thinner than 2
    /// radii, so growth dies out early: raise `k`).
    ///
    /// Elsewhere it is measured, not promised: for 2 000 points in a unit
    /// cube (annulus, 4 seeds), the mean came within 1.1 % of `n` in 1-D and
    /// 4-D to 7-D, bounded or periodic, and 1 % (periodic) in 8-D; in a
    /// bounded 8-D cube it came 2.7 % above `n` (8 seeds). From 4-D up a thin box has no table of its own. Past 8-D
    /// there is none at all, and `build` gives [`Error::InvalidRadius`].
    /// In 2-D and 3-D, `k` below 3 or above 1000 makes `build` fail with
    /// [`Error::CountAttemptsOutOfRange`] rather than miss the count: below
    /// 3 growth dies out at random (in 2-D with `k = 1` after a handful of
    /// points), so no radius gives a count; above 1000 the density still
    /// creeps up (2 % from `k = 500` to `1000` in 3-D) and is not measured.
    /// Elsewhere the tables are for `k = 30` only; other `k` change the
    /// density there and are not corrected for (in 2-D, before the
    /// correction, `k = 10` gave about 7 % fewer points, `k = 100` 5 % more).
    ///
    /// This is the tool for "about `n` well-spread points": unlike a
    /// [`max_points`](Self::max_points) cap, it covers the whole box.
    /// `n = 0` makes `build` fail with [`Error::InvalidPointCount`]. [`PoissonDisk::radius`] tells the
    /// radius chosen.
    ///
    /// # Example: about 5 000 points in a periodic 3 × 1 box
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// let domain = Domain::from_extent([3.0, 1.0])?.with_periodic([true; 2]);
    /// let sampler = PoissonDisk2::about_points(domain, 5000)?;
    /// let n = sampler.generate_seeded(1)?.len();
    /// assert!((4900..=5100).contains(&n), "{n} points at r = {}", sampler.radius());
    /// # Ok::<(), bridson::Error>(())
    /// ```
    #[must_use]
    pub fn about_points(mut self, n: u64) -> Self {
        self.about_points = Some(n);
        self
    }

    /// Checks every setting and sizes the grid.
    ///
    /// # Errors
    /// [`Error::ZeroDimension`] if `N == 0`; the [`Domain::new`] errors if
    /// the domain was deserialised from bad values;
    /// [`Error::InvalidPointCount`] if count mode asks for 0 points;
    /// [`Error::CountAttemptsOutOfRange`] if it does in
    /// 2-D or 3-D with `k` outside `3 ..= 1000`; [`Error::InvalidRadius`] if the radius (given, or
    /// derived from the count) is NaN, infinite, `<= 0` or outside
    /// `1e-150 ..= 1e150`; [`Error::ZeroAttempts`] if `k == 0`;
    /// [`Error::TooManyAttempts`] if `k > MAX_ATTEMPTS`;
    /// [`Error::BoxTooWide`] if the box spans more than 2⁴⁰ radii;
    /// [`Error::GridTooLarge`] if what a grid allocates before its first
    /// point is over the budget (a dense grid asked for with a tiny radius,
    /// or a budget too small for a single point). Whether the points fit is
    /// known only as they come: see [`Points::error`].
    pub fn build(self) -> Result<PoissonDisk<N>, Error> {
        if N == 0 {
            return Err(Error::ZeroDimension);
        }
        // Re-checked: deserialisation can produce any Domain.
        let d = self.domain;
        let domain = Domain::new(d.lo(), d.hi())?.with_periodic(d.periodic());
        let radius = match self.about_points {
            None => self.radius,
            Some(0) => return Err(Error::InvalidPointCount),
            Some(n) => {
                if (N == 2 || N == 3) && !COUNT_ATTEMPTS.contains(&self.attempts) {
                    return Err(Error::CountAttemptsOutOfRange {
                        min: *COUNT_ATTEMPTS.start(),
                        max: *COUNT_ATTEMPTS.end(),
                    });
                }
                radius_for_count(
                    &domain.extent(),
                    &domain.periodic(),
                    self.candidates == Candidates::Sphere,
                    self.attempts,
                    n,
                )
            }
        };
        check_radius_and_attempts(radius, self.attempts)?;
        let expected = self.expected_count(&domain, radius);
        let plan = plan(
            &domain,
            radius,
            self.layout,
            self.max_grid_bytes,
            self.max_points,
            expected,
        )?;
        Ok(PoissonDisk {
            config: Self {
                domain,
                radius,
                ..self
            },
            plan,
            expected,
        })
    }

    /// The density model's expected point count for this box, radius and
    /// `k`, where the model answers: in 2-D and 3-D for `k` in
    /// `3 ..= 1000` (its tables' range), elsewhere (tables for `k = 30`
    /// only) for `k >= 30`, where a higher `k` packs a few per cent denser
    /// at most; below that growth can die out early and the model would
    /// overstate the count. `None` otherwise (the planning then assumes the
    /// worst case).
    fn expected_count(&self, domain: &Domain<N>, radius: f64) -> Option<f64> {
        let k = self.attempts;
        let answers = if N == 2 || N == 3 {
            COUNT_ATTEMPTS.contains(&k)
        } else {
            k >= DEFAULT_ATTEMPTS
        };
        let n = expected_count(
            &domain.extent(),
            &domain.periodic(),
            self.candidates == Candidates::Sphere,
            k,
            radius,
        );
        (answers && n.is_finite() && n >= 0.0).then_some(n)
    }
}

/// The checks on the radius and the attempts that every sampler of the
/// crate makes, in this order.
pub(crate) fn check_radius_and_attempts(radius: f64, attempts: u32) -> Result<(), Error> {
    if !(MIN_RADIUS..=MAX_RADIUS).contains(&radius) {
        return Err(Error::InvalidRadius);
    }
    if attempts == 0 {
        return Err(Error::ZeroAttempts);
    }
    if attempts > MAX_ATTEMPTS {
        return Err(Error::TooManyAttempts { max: MAX_ATTEMPTS });
    }
    Ok(())
}

#[cfg(feature = "serde")]
impl<const N: usize> TryFrom<PoissonDiskBuilder<N>> for PoissonDisk<N> {
    type Error = Error;
    fn try_from(builder: PoissonDiskBuilder<N>) -> Result<Self, Error> {
        builder.build()
    }
}

#[cfg(feature = "serde")]
impl<const N: usize> From<PoissonDisk<N>> for PoissonDiskBuilder<N> {
    fn from(sampler: PoissonDisk<N>) -> Self {
        sampler.config
    }
}

impl<const N: usize> PoissonDisk<N> {
    /// A sampler of `domain` with minimum distance `radius` and the
    /// defaults: `k = 30` annulus candidates, automatic grid layout, a
    /// 1 GiB grid budget, no point cap.
    ///
    /// # Errors
    /// As [`PoissonDiskBuilder::build`].
    pub fn new(domain: Domain<N>, radius: f64) -> Result<Self, Error> {
        Self::builder(domain, radius).build()
    }

    /// Settings to adjust before [`PoissonDiskBuilder::build`] checks them together.
    pub fn builder(domain: Domain<N>, radius: f64) -> PoissonDiskBuilder<N> {
        PoissonDiskBuilder {
            domain,
            radius,
            about_points: None,
            attempts: DEFAULT_ATTEMPTS,
            candidates: Candidates::default(),
            layout: GridLayout::default(),
            max_grid_bytes: DEFAULT_MAX_GRID_BYTES,
            max_points: None,
        }
    }

    /// A sampler of `domain` that makes about `n` points (count mode, see
    /// [`PoissonDiskBuilder::about_points`]) with the defaults otherwise.
    ///
    /// # Errors
    /// As [`PoissonDiskBuilder::build`]: [`Error::InvalidPointCount`] if
    /// `n == 0`, [`Error::InvalidRadius`] if no radius gives `n` points.
    pub fn about_points(domain: Domain<N>, n: u64) -> Result<Self, Error> {
        Self::about_points_builder(domain, n).build()
    }

    /// Settings for about `n` points in `domain` instead of a radius, to
    /// adjust before [`PoissonDiskBuilder::build`] derives the radius.
    pub fn about_points_builder(domain: Domain<N>, n: u64) -> PoissonDiskBuilder<N> {
        Self::builder(domain, f64::NAN).about_points(n)
    }

    /// The settings this sampler was built from, to adjust and rebuild.
    /// In count mode the radius is the one derived.
    pub fn to_builder(&self) -> PoissonDiskBuilder<N> {
        self.config
    }

    /// The domain.
    pub fn domain(&self) -> &Domain<N> {
        &self.config.domain
    }

    /// The minimum distance between points (in count mode, the one
    /// derived from the count).
    pub fn radius(&self) -> f64 {
        self.config.radius
    }

    /// The attempts `k`.
    pub fn attempts(&self) -> u32 {
        self.config.attempts
    }

    /// The candidate distribution.
    pub fn candidates(&self) -> Candidates {
        self.config.candidates
    }

    /// The layout asked for (possibly [`GridLayout::Auto`]).
    pub fn layout(&self) -> GridLayout {
        self.config.layout
    }

    /// The layout planned: [`GridLayout::Dense`] or [`GridLayout::Sparse`].
    /// [`Points::layout`] tells what was actually built.
    pub fn resolved_layout(&self) -> GridLayout {
        match self.plan {
            GridPlan::Dense(_) => GridLayout::Dense,
            GridPlan::Paged(_) => GridLayout::Paged,
            GridPlan::Sparse(_) => GridLayout::Sparse,
        }
    }

    /// The grid memory budget, in bytes.
    pub fn max_grid_bytes(&self) -> u64 {
        self.config.max_grid_bytes
    }

    /// The point cap.
    pub fn max_points(&self) -> Option<u64> {
        self.config.max_points
    }

    /// The count asked for in count mode ([`PoissonDiskBuilder::about_points`]).
    pub fn requested_count(&self) -> Option<u64> {
        self.config.about_points
    }

    /// The bytes the grid takes before its first point is stored, checked
    /// against the budget by `build()`: for the dense layout its cells and
    /// search stencils (a bound on their peak while built), for the sparse
    /// one a single point's share. What the points take comes on top, and
    /// is counted as they come ([`Points::heap_bytes`]).
    pub fn grid_bytes(&self) -> u64 {
        match self.plan {
            GridPlan::Dense(d) => d.bytes,
            GridPlan::Paged(p) => p.bytes,
            GridPlan::Sparse(s) => s.bytes,
        }
    }

    /// Points in generation order, drawn from `rng`. Pass `&mut rng` to
    /// keep using your generator afterwards.
    ///
    /// The set grows outward from its first point, so a prefix of the
    /// stream (`take(n)`, or a [`max_points`](PoissonDiskBuilder::max_points) cap) is a
    /// compact blob, not `n` points spread over the box: for those, use
    /// count mode ([`PoissonDiskBuilder::about_points`]) and take the whole stream.
    ///
    /// The grid is allocated here. Should the dense allocation fail, the
    /// sampler falls back to the sparse layout (same points) rather than
    /// abort; [`Points::layout`] reports it.
    pub fn iter<R: Rng>(&self, rng: R) -> Points<N, R> {
        let mut points = self.iter_in(rng, Everywhere);
        if let Some(refused) = self.clearly_too_large() {
            points.error = Some(refused);
            points.remaining = 0;
        }
        points
    }

    /// As [`iter`](Self::iter), with every new point inside `region`.
    fn iter_in<R: Rng, G: Region<N>>(&self, rng: R, region: G) -> Points<N, R, G> {
        let c = &self.config;
        Points {
            rng,
            region,
            domain: c.domain,
            grid: Grid::build(&self.plan, &c.domain, c.radius),
            active: Vec::new(),
            candidates: CandidateSampler::new(c.candidates, c.radius, c.attempts),
            radius_squared: c.radius * c.radius,
            attempts: c.attempts,
            remaining: c.max_points.unwrap_or(u64::MAX),
            made: 0,
            single_point: c.domain.holds_one_point(c.radius),
            budget: c.max_grid_bytes,
            error: None,
            started: false,
            ahead: OffsetBatch::new(),
            next_pick: [None; 2],
            first_alone: None,
            first_found: None,
        }
    }

    /// Points in generation order, drawn from `rng`, that lie in `region`
    /// and keep their distance `r` from the pre-placed points `fixed`
    /// (as from each other): the guarantees hold for the union of `fixed`
    /// and the points yielded. The pre-placed points are not yielded; they
    /// count against the memory budget but not against the point cap.
    ///
    /// Growth starts from the pre-placed points in the domain (candidates
    /// are thrown around them as around any point), or, if there are none,
    /// from a uniform point of the region, drawn here: up to `64·k` uniform
    /// tries over the box, and [`Error::RegionMissed`] if none lands in the
    /// region (an empty mask, or one too small a part of the box: pre-place
    /// a point in it, or sample a smaller box around it). It reaches every part of the region within
    /// `2r` hops of where it started: parts of a mask farther apart (islands)
    /// need a pre-placed point, or a run of their own. `region(p) == true`
    /// means a new point may lie at `p`; [`Everywhere`] is the whole box.
    /// A mask closure needs its argument type written out,
    /// `|p: &[f64; 2]| …`, or the compiler stops with E0282 ("type
    /// annotations needed"): see [`Region`].
    ///
    /// # Errors
    /// [`Error::RegionMissed`] if there are no pre-placed points and no
    /// first point lands in the region;
    /// [`Error::InvalidFixedPoint`] naming the first pre-placed point that is
    /// not finite, lies outside the domain, or lies closer than `r` to an
    /// earlier one; [`Error::MemoryBudgetExceeded`] (with `points: 0`) if
    /// the pre-placed points alone outgrow the budget.
    ///
    /// # Example: points in a disc, around two given points
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, 0.05)?;
    /// let disc = |p: &[f64; 2]| (p[0] - 0.5).powi(2) + (p[1] - 0.5).powi(2) < 0.16;
    /// let fixed = [[0.5, 0.5], [0.6, 0.5]];
    /// let points: Vec<[f64; 2]> = sampler.iter_with_seeded(7, disc, &fixed)?.collect();
    /// assert!(points.len() > 100);
    /// for p in &points {
    ///     assert!(disc(p));
    ///     for q in &fixed {
    ///         assert!((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) >= 0.05 * 0.05);
    ///     }
    /// }
    /// # Ok::<(), bridson::Error>(())
    /// ```
    pub fn iter_with<R: Rng, G: Region<N>>(
        &self,
        rng: R,
        region: G,
        fixed: &[[f64; N]],
    ) -> Result<Points<N, R, G>, Error> {
        let mut it = self.iter_in(rng, region);
        for (index, p) in fixed.iter().enumerate() {
            let bad = Error::InvalidFixedPoint { index };
            if !all_finite(p) || !it.domain.contains(p) {
                return Err(bad);
            }
            let stored = match &mut it.grid {
                Grid::Bricks(g) => place(g, &mut it.active, *p, it.budget),
                Grid::Dense(g) => place(g, &mut it.active, *p, it.budget),
                Grid::Paged(g) => place(g, &mut it.active, *p, it.budget),
                Grid::PagedBricks(g) => place(g, &mut it.active, *p, it.budget),
                Grid::Sparse(g) => place(g, &mut it.active, *p, it.budget),
            };
            match stored {
                Stored::Yes => {}
                Stored::NoRoom => return Err(bad),
                Stored::OverBudget => {
                    return Err(Error::MemoryBudgetExceeded {
                        points: 0,
                        budget: it.budget,
                    });
                }
            }
        }
        if fixed.is_empty() {
            // The first point is drawn here, as the first step would draw
            // it (the same generator calls, so the same points), so that a
            // region no try hits is an error rather than an empty stream.
            let tries = first_point_tries(it.attempts);
            it.first_found = Some(it.first_in_region().ok_or(Error::RegionMissed { tries })?);
        } else {
            // Growth starts from the pre-placed points.
            it.started = true;
            if it.single_point {
                it.active.clear();
            }
        }
        Ok(it)
    }

    /// As [`iter_with`](Self::iter_with), drawing from [`DefaultRng`]
    /// seeded with `seed`: the same seed gives the same points on every run
    /// and platform.
    ///
    /// # Errors
    /// As [`iter_with`](Self::iter_with).
    pub fn iter_with_seeded<G: Region<N>>(
        &self,
        seed: u64,
        region: G,
        fixed: &[[f64; N]],
    ) -> Result<Points<N, DefaultRng, G>, Error> {
        self.iter_with(seeded_rng(seed), region, fixed)
    }

    /// Points in generation order from [`DefaultRng`] seeded with `seed`:
    /// the same seed gives the same points on every run and platform.
    pub fn iter_seeded(&self, seed: u64) -> Points<N, DefaultRng> {
        self.iter(seeded_rng(seed))
    }

    /// All points, drawn from `rng`.
    ///
    /// # Errors
    /// An [`Incomplete`] holding the valid points made so far and the
    /// reason: [`Error::MemoryBudgetExceeded`] if the run outgrew the memory
    /// budget before it ended, [`Error::RunTooLarge`] (no points) if its
    /// expected size was clearly over the budget from the start.
    pub fn generate<R: Rng>(&self, rng: R) -> Result<Vec<[f64; N]>, Incomplete<N>> {
        let mut points = self.iter(rng);
        let all = points.by_ref().collect();
        match points.error() {
            None => Ok(all),
            Some(error) => Err(Incomplete::new(all, error)),
        }
    }

    /// All points for `seed` (see [`iter_seeded`](Self::iter_seeded)).
    ///
    /// # Errors
    /// As [`generate`](Self::generate).
    pub fn generate_seeded(&self, seed: u64) -> Result<Vec<[f64; N]>, Incomplete<N>> {
        self.generate(seeded_rng(seed))
    }

    /// The refusal of a run over the whole box whose expected points, at
    /// the bare `8·N` bytes each (no layout stores a point in less) on top
    /// of what the grid allocates up front, need more than twice the budget
    /// ([`Error::RunTooLarge`]). A factor of two, where the density model is
    /// within a few per cent, never refuses a run that would have fit.
    fn clearly_too_large(&self) -> Option<Error> {
        let mean = self.expected?;
        let points = self
            .config
            .max_points
            .map_or(mean, |cap| mean.min(to_f64(cap)));
        #[expect(clippy::cast_precision_loss, reason = "N is small")]
        let needed = points * (8 * N) as f64 + to_f64(self.grid_bytes());
        let budget = self.config.max_grid_bytes;
        (needed > 2.0 * to_f64(budget)).then(|| Error::RunTooLarge {
            expected_points: saturating_u64(points),
            needed: saturating_u64(needed),
            budget,
        })
    }
}

/// `n` as an `f64` (rounded above 2⁵³: only compared with a model).
fn to_f64(n: u64) -> f64 {
    #[expect(clippy::cast_precision_loss, reason = "a model's scale")]
    let x = n as f64;
    x
}

/// A non-negative `f64` rounded up to a `u64`, saturating.
fn saturating_u64(x: f64) -> u64 {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "saturating: `as` clamps to 0 ..= u64::MAX"
    )]
    let n = x.ceil() as u64;
    n
}

/// The lazy point stream of a [`PoissonDisk`]: yields each point as soon as
/// it is accepted, in generation order.
///
/// Ends when no active point is left (the domain is full, to `k` attempts),
/// the point cap is reached, or storing the next point would take the
/// run's memory past the budget ([`error`](Self::error) then says so);
/// stays ended ([`FusedIterator`]).
///
/// A first point whose `k` candidates all fail (they can only leave the
/// box, or the region) is given more picks, up to `64·k` candidates in
/// all, rather than end the run at one point: from 5-D up a point near a
/// corner of the box loses most of its candidates (in an 8-D unit cube at
/// `r = 0.4`, 15 of seeds 1–300 would otherwise end at one point). A set
/// can still end tiny when its first few points all sit near a corner:
/// there, seed 230 stops at 2 points, where the other 299 seeds make 2 110
/// to 2 280.
///
/// `G` is the region new points must lie in ([`Everywhere`] unless the run
/// came from [`PoissonDisk::iter_with`]).
#[derive(Debug)]
pub struct Points<const N: usize, R, G = Everywhere> {
    rng: R,
    region: G,
    domain: Domain<N>,
    grid: Grid<N>,
    /// Points that may still have room around them, stored inline.
    active: Vec<[f64; N]>,
    candidates: CandidateSampler<N>,
    radius_squared: f64,
    attempts: u32,
    remaining: u64,
    /// Points yielded so far.
    made: u64,
    /// No two points of the box can be `r` apart: the first is the last.
    single_point: bool,
    /// The memory budget, in bytes, for the grid and the active list.
    budget: u64,
    /// Why the stream ended early, if it did.
    error: Option<Error>,
    started: bool,
    ahead: OffsetBatch<N, true>,
    /// The indices of the next two picks, drawn ahead (see
    /// [`State::grow_cached`]).
    next_pick: [Option<usize>; 2],
    /// The first point of a plain run and the picks around it left
    /// ([`Points::again_around_first`]).
    first_alone: Option<([f64; N], u32)>,
    /// A first point already drawn in the region (by
    /// [`PoissonDisk::iter_with`], which reports a region it cannot hit),
    /// to be stored on the first step.
    first_found: Option<[f64; N]>,
}

impl<const N: usize, R: Rng, G: Region<N>> Iterator for Points<N, R, G> {
    type Item = [f64; N];

    fn next(&mut self) -> Option<[f64; N]> {
        // A loop, not a call of itself: a first point left alone gets more
        // picks (at most 63), and a debug build's frames are large.
        loop {
            if self.remaining == 0 {
                return None;
            }
            if let Some(point) = self.step() {
                self.remaining -= 1;
                self.made += 1;
                return Some(point);
            }
            if !self.again_around_first() {
                return None;
            }
        }
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        if self.remaining == 0 || (self.started && self.active.is_empty()) {
            (0, Some(0))
        } else {
            (0, usize::try_from(self.remaining).ok())
        }
    }
}

impl<const N: usize, R: Rng, G: Region<N>> FusedIterator for Points<N, R, G> {}

impl<const N: usize, R: Rng, G: Region<N>> Points<N, R, G> {
    /// The next point of Bridson's loop (the first point on the first
    /// call), or `None` when the active list runs empty, the budget is hit
    /// or no first point fits the region.
    fn step(&mut self) -> Option<[f64; N]> {
        if self.started {
            let Self {
                rng,
                region,
                domain,
                grid,
                active,
                candidates,
                radius_squared,
                attempts,
                ahead,
                next_pick,
                budget,
                error,
                ..
            } = self;
            let state = State {
                rng,
                region,
                domain,
                active,
                candidates,
                radius_squared: *radius_squared,
                attempts: *attempts,
                ahead,
                next_pick,
                budget: *budget,
                made: self.made,
                error,
            };
            // The loop compiled for AVX2 where the processor has it
            // (`cpu.rs`): the same points, faster.
            match grid {
                Grid::Bricks(g) => dispatch(
                    #[inline(always)]
                    || state.grow(g),
                ),
                Grid::Dense(g) => dispatch(
                    #[inline(always)]
                    || state.grow(g),
                ),
                Grid::Paged(g) => dispatch(
                    #[inline(always)]
                    || state.grow(g),
                ),
                Grid::PagedBricks(g) => dispatch(
                    #[inline(always)]
                    || state.grow(g),
                ),
                Grid::Sparse(g) => dispatch(
                    #[inline(always)]
                    || state.grow(g),
                ),
            }
        } else {
            self.started = true;
            let first = match self.first_found.take() {
                Some(first) => first,
                None => self.first_in_region()?,
            };
            let stored = match &mut self.grid {
                Grid::Bricks(g) => store(g, &mut self.active, first, self.budget),
                Grid::Dense(g) => store(g, &mut self.active, first, self.budget),
                Grid::Paged(g) => store(g, &mut self.active, first, self.budget),
                Grid::PagedBricks(g) => store(g, &mut self.active, first, self.budget),
                Grid::Sparse(g) => store(g, &mut self.active, first, self.budget),
            };
            match stored {
                Stored::Yes => {
                    if self.single_point {
                        // No second point can be far enough: done.
                        self.active.clear();
                    } else {
                        self.first_alone = Some((first, FIRST_POINT_PICKS - 1));
                    }
                    Some(first)
                }
                Stored::NoRoom => None,
                Stored::OverBudget => {
                    self.error = Some(Error::MemoryBudgetExceeded {
                        points: 0,
                        budget: self.budget,
                    });
                    None
                }
            }
        }
    }
}

/// The uniform tries for a run's first point in its region: `64·k`.
pub(crate) fn first_point_tries(attempts: u32) -> u64 {
    64 * u64::from(attempts)
}

impl<const N: usize, R: Rng, G: Region<N>> Points<N, R, G> {
    /// A uniform point of the box that the region admits, in up to
    /// [`first_point_tries`] tries, or `None`.
    fn first_in_region(&mut self) -> Option<[f64; N]> {
        let mut first = first_point(&self.domain, &mut self.rng);
        let mut tries = first_point_tries(self.attempts);
        while !self.region.admits(&first) {
            tries -= 1;
            if tries == 0 {
                return None;
            }
            first = first_point(&self.domain, &mut self.rng);
        }
        Some(first)
    }
}

/// The most picks around a run's first point while it is the only one:
/// `64·k` throws.
const FIRST_POINT_PICKS: u32 = 64;

impl<const N: usize, R, G> Points<N, R, G> {
    /// Whether a run that is ending with its first point alone gets
    /// another pick around it (then the point is active again): up to
    /// [`FIRST_POINT_PICKS`] picks in all. A first point's throws fail only
    /// by leaving the box (or the region), and from 5-D up a point near a
    /// corner loses most of them: in an 8-D unit cube at `r = 0.4`, 15 of
    /// seeds 1–300 lose all `k = 30`, and would end at one point where the
    /// others make about 2 200. A run with a second point never comes here,
    /// so its points are as before.
    fn again_around_first(&mut self) -> bool {
        let Some((first, left)) = &mut self.first_alone else {
            return false;
        };
        // Room for the point without growing the list (it held it before).
        if self.made != 1 || *left == 0 || self.error.is_some() || self.active.capacity() == 0 {
            return false;
        }
        *left -= 1;
        self.active.push(*first);
        true
    }
}

impl<const N: usize, R, G> Points<N, R, G> {
    /// Why the stream ended before the domain was full, if it did:
    /// [`Error::MemoryBudgetExceeded`] when storing the next point would
    /// have taken the run's memory past the budget, [`Error::RunTooLarge`]
    /// when a plain run was refused before its first point. `None` while the stream
    /// runs, and after it ends normally (full domain or point cap). The
    /// points yielded before are a valid set either way.
    ///
    /// # Example: telling a full set from one cut short by the budget
    /// ```
    /// use bridson::{Domain, Error, PoissonDisk2};
    /// let domain = Domain::from_extent([1.0, 1.0])?;
    /// // About 45 000 points expected: under twice the budget even at 16
    /// // bytes a point (so not refused), over it as stored.
    /// let sampler = PoissonDisk2::builder(domain, 0.0037)
    ///     .max_grid_bytes(1 << 20)
    ///     .build()?;
    /// let mut points = sampler.iter_seeded(1);
    /// let made = points.by_ref().count();
    /// assert!(made > 0);
    /// assert!(matches!(points.error(), Some(Error::MemoryBudgetExceeded { .. })));
    /// # Ok::<(), bridson::Error>(())
    /// ```
    pub fn error(&self) -> Option<Error> {
        self.error
    }

    /// The heap bytes the run holds now, as counted against the budget:
    /// the grid (cells, stencils, points or hash table) and the active
    /// list. Never above [`PoissonDisk::max_grid_bytes`].
    pub fn heap_bytes(&self) -> u64 {
        let grid = match &self.grid {
            Grid::Bricks(g) => g.bytes(),
            Grid::Dense(g) => g.bytes(),
            Grid::Paged(g) => g.bytes(),
            Grid::PagedBricks(g) => g.bytes(),
            Grid::Sparse(g) => g.bytes(),
        };
        grid.saturating_add(vec_bytes(&self.active))
    }

    /// The grid layout actually built: [`GridLayout::Dense`] or
    /// [`GridLayout::Sparse`] (the latter also when a dense allocation
    /// failed and the sampler fell back).
    pub fn layout(&self) -> GridLayout {
        match self.grid {
            Grid::Bricks(_) | Grid::Dense(_) => GridLayout::Dense,
            Grid::Paged(_) | Grid::PagedBricks(_) => GridLayout::Paged,
            Grid::Sparse(_) => GridLayout::Sparse,
        }
    }
}

/// The parts of [`Points`] the growth loop mutates, borrowed apart from the
/// grid so the loop can be monomorphised per grid layout.
struct State<'a, const N: usize, R, G> {
    rng: &'a mut R,
    region: &'a G,
    domain: &'a Domain<N>,
    active: &'a mut Vec<[f64; N]>,
    candidates: &'a CandidateSampler<N>,
    radius_squared: f64,
    attempts: u32,
    ahead: &'a mut OffsetBatch<N, true>,
    next_pick: &'a mut [Option<usize>; 2],
    budget: u64,
    made: u64,
    error: &'a mut Option<Error>,
}

impl<const N: usize, R: Rng, G: Region<N>> State<'_, N, R, G> {
    /// Bridson's loop up to the next accepted point, with a cache of
    /// `B` recent conflicts sized for the dimension.
    #[inline(always)]
    fn grow<T: NeighbourGrid<N>>(self, grid: &mut T) -> Option<[f64; N]> {
        // How many conflicts a pick remembers: its active point's
        // neighbours, then whatever the grid finds. 16 where the seed holds
        // about 14 points: the dense grid's 2-D seed (its 44 cells,
        // `grid/dense.rs`, `wide_seed`) and the 3-D stencil's 125 cells.
        // 8 in 1-D (the stencil holds at most 4) and in 2-D on the sparse
        // grid, which seeds nothing (16 slots there cost 2–3 % more time).
        if N <= 1 || (N == 2 && !T::WIDE_SEED) {
            self.grow_cached::<T, 8>(grid)
        } else {
            self.grow_cached::<T, 16>(grid)
        }
    }

    /// Bridson's loop, up to the next accepted point: pick a random active
    /// point, throw up to `k` candidates around it, keep the first that is
    /// at least `r` from every point; if none is, retire the active point.
    /// The active point's neighbours, and the points that turn candidates
    /// away, are remembered for the rest of the pick and checked first
    /// ([`ConflictCache`]); that changes no decision.
    #[inline(always)]
    fn grow_cached<T: NeighbourGrid<N>, const B: usize>(self, grid: &mut T) -> Option<[f64; N]> {
        let periodic = self.domain.any_periodic();
        let periods = self.domain.periods();
        let ahead = self.candidates.reads_ahead();
        let radius = self.radius_squared.sqrt();
        let reach = 2.0 * radius;
        while !self.active.is_empty() {
            let len = self.active.len();
            // Picks are drawn two picks ahead, so that memory is fetched
            // while earlier picks run: the active entry of the pick after
            // next, and the stencil of the next one. Each is uniform over
            // `0..len + 2` when drawn, and `len + 2` bounds the list's length
            // when it is used (a pick adds or removes one entry). Kept if it
            // is below the length, redrawn otherwise: either way uniform
            // over `0..len`.
            let [now, soon] = *self.next_pick;
            let i = kept(now, len).unwrap_or_else(|| below(self.rng, len));
            let parent = *self.active.get(i)?;
            let later = below(self.rng, len + 2);
            *self.next_pick = [soon, Some(later)];
            crate::prefetch::prefetch(self.active, later);
            if let Some(p) = soon.and_then(|j| self.active.get(j)) {
                grid.prefetch(p);
            }
            let mut state = self.candidates.start(self.rng);
            let mut cache = ConflictCache::<N, B>::new(parent, radius);
            if periodic {
                grid.seed(&parent, B, |q| cache.push_periodic(q, &periods));
            } else {
                grid.seed(&parent, B, |q| cache.push(q));
            }
            // Far from every face (the usual case), no candidate can leave
            // the box: skip the per-attempt test. Candidates lie within
            // 2r·(1 + 1e-6) of the parent (the `f32` draws of `wide.rs`
            // round; the others stay within 2r·(1 + 1e-7)); the test
            // keeps 4r.
            let interior = !periodic && self.domain.holds_ball(&parent, reach);
            // Coordinates below 2²⁸·r: the candidate is its offset from the
            // parent to within 2⁻²⁵·r, so the cache takes the offset drawn
            // ahead in units of r instead of recomputing it
            // (`ConflictCache::block_relative`); on a torus, periods below
            // 2²⁸·r too, for the remembered points' nearest images
            // (`ConflictCache::push_periodic`).
            let near_origin = ahead
                && parent
                    .iter()
                    .chain(&periods)
                    .all(|x| x.abs() < radius * NEAR_ORIGIN);
            for _ in 0..self.attempts {
                let offset = if ahead {
                    let (j, offset_in_r) = self.ahead.next_unit(self.candidates, self.rng);
                    // The quick check first: it needs only the offset in
                    // units of `r`, and most candidates fail it, so most
                    // never become a point in `f64`. (Its answer does not
                    // depend on the box or the region, and a blocked
                    // candidate is turned away whatever they say: the same
                    // decisions in either order.)
                    if near_origin && cache.block_relative(&offset_in_r) {
                        continue;
                    }
                    self.ahead.offset(j, self.candidates)
                } else {
                    self.candidates.offset(self.rng, &mut state)
                };
                let mut candidate = add(&parent, &offset);
                if !interior && !self.domain.wrap(&mut candidate) {
                    continue;
                }
                // Compiled out for `Everywhere`.
                if !self.region.admits(&candidate) {
                    continue;
                }
                let blocked = if near_origin {
                    false
                } else if periodic {
                    cache.block_periodic(&candidate, self.radius_squared, &periods)
                } else {
                    cache.block(&candidate, self.radius_squared)
                };
                if blocked {
                    continue;
                }
                if let Some(q) = grid.conflict(&candidate) {
                    if periodic {
                        cache.push_periodic(&q, &periods);
                    } else {
                        cache.push(&q);
                    }
                    continue;
                }
                match store(grid, self.active, candidate, self.budget) {
                    Stored::Yes => return Some(candidate),
                    Stored::NoRoom => {}
                    Stored::OverBudget => {
                        *self.error = Some(Error::MemoryBudgetExceeded {
                            points: self.made,
                            budget: self.budget,
                        });
                        self.active.clear();
                        return None;
                    }
                }
            }
            self.active.swap_remove(i);
        }
        None
    }
}

/// What became of a valid candidate.
enum Stored {
    /// In the grid and the active list.
    Yes,
    /// The grid had no room for it (see [`NeighbourGrid::insert`]): a
    /// failed attempt.
    NoRoom,
    /// Storing it would take the memory past the budget.
    OverBudget,
}

/// Stores a valid candidate in the grid and the active list, if the memory
/// that takes fits the budget: the active list's growth is checked first,
/// then the grid's, each against what is left.
fn store<const N: usize, G: NeighbourGrid<N>>(
    grid: &mut G,
    active: &mut Vec<[f64; N]>,
    p: [f64; N],
    budget: u64,
) -> Stored {
    let spare = budget.saturating_sub(grid.bytes().saturating_add(vec_bytes(active)));
    let Some(grown) = reserve_one(active, spare) else {
        return Stored::OverBudget;
    };
    if !grid.reserve(&p, spare.saturating_sub(grown)) {
        return Stored::OverBudget;
    }
    if !grid.insert(p) {
        return Stored::NoRoom;
    }
    active.push(p);
    Stored::Yes
}

/// Stores a pre-placed point if no stored point lies closer than `r`
/// (`NoRoom` otherwise), within the budget.
fn place<const N: usize, T: NeighbourGrid<N>>(
    grid: &mut T,
    active: &mut Vec<[f64; N]>,
    p: [f64; N],
    budget: u64,
) -> Stored {
    if grid.conflict(&p).is_some() {
        return Stored::NoRoom;
    }
    store(grid, active, p, budget)
}

/// A pick index drawn ahead, uniform over `0..bound` with `bound >= len`
/// independently of how the list changed since: kept if below `len`, else
/// `None` (draw again). Either way the pick is uniform over `0..len`.
fn kept(drawn: Option<usize>, len: usize) -> Option<usize> {
    drawn.filter(|&i| i < len)
}

/// A uniform point in the half-open box. Rounding can carry `lo + u·L` up
/// to `hi`; such draws are repeated (at most 64 times, then `lo` is used).
fn first_point<const N: usize, R: Rng + ?Sized>(domain: &Domain<N>, rng: &mut R) -> [f64; N] {
    let (lo, extent) = (domain.lo(), domain.extent());
    for _ in 0..64 {
        // Axis order, one draw each: part of the value-stable stream.
        let p = zip_map(&lo, &extent, |l, e| l + unit(rng) * e);
        if all_finite(&p) && domain.contains(&p) {
            return p;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Exact law of a pick drawn ahead: uniform over `0..drawn_over`, kept
    /// if below `len`, else redrawn uniform over `0..len`. Every index below
    /// `len` must get probability `1/len`, that is (times `drawn_over·len`)
    /// `len` for keeping it plus one for each redraw.
    #[test]
    fn picks_drawn_ahead_stay_uniform() {
        for old_len in 1..40usize {
            let drawn_over = old_len + 2;
            for len in old_len.saturating_sub(2).max(1)..=drawn_over {
                let redraws = (0..drawn_over)
                    .filter(|&i| kept(Some(i), len).is_none())
                    .count();
                for j in 0..len {
                    let keeps = (0..drawn_over)
                        .filter(|&i| kept(Some(i), len) == Some(j))
                        .count();
                    assert_eq!(
                        keeps * len + redraws,
                        drawn_over,
                        "drawn over 0..{drawn_over}, used at length {len}: index {j}"
                    );
                }
            }
        }
        assert_eq!(kept(None, 5), None, "nothing drawn: draw now");
    }

    #[test]
    fn cap_stops_the_stream() {
        let s = PoissonDisk2::builder(Domain::from_extent([1.0, 1.0]).unwrap(), 0.01)
            .max_points(10)
            .build()
            .unwrap();
        let mut it = s.iter_seeded(1);
        assert_eq!(it.by_ref().count(), 10, "cap");
        assert_eq!(it.next(), None, "fused");
    }

    #[test]
    fn a_huge_box_runs_until_the_budget() {
        let huge = Domain::from_extent([1e6, 1e6]).unwrap();
        let budget = 1 << 20;
        let uncapped = PoissonDisk2::builder(huge, 1e-3)
            .max_grid_bytes(budget)
            .build()
            .unwrap();
        // In a region (here the whole box), the run is never refused up
        // front: it grows until the budget.
        let mut it = uncapped.iter_with_seeded(3, Everywhere, &[]).unwrap();
        assert_eq!(it.layout(), GridLayout::Paged, "paged");
        let mut made = 0u64;
        while it.next().is_some() {
            made += 1;
            assert!(it.heap_bytes() <= budget, "{} bytes", it.heap_bytes());
        }
        assert!(made > 1000, "only {made} points in 1 MiB");
        assert_eq!(
            it.error(),
            Some(Error::MemoryBudgetExceeded {
                points: made,
                budget
            }),
            "the reason is kept"
        );
        assert_eq!(it.next(), None, "fused");
        // Over the whole box, its 10^18 expected points are refused at once.
        let refused = uncapped.generate_seeded(3).unwrap_err();
        assert!(
            matches!(refused.error(), Error::RunTooLarge { budget: b, .. } if b == budget),
            "{refused:?}"
        );
        assert!(refused.points().is_empty(), "no point made");
        let capped = uncapped.to_builder().max_points(100).build().unwrap();
        let mut it = capped.iter_seeded(3);
        assert_eq!(it.by_ref().count(), 100, "capped count");
        assert_eq!(it.error(), None, "a cap is no error");
    }

    #[test]
    fn a_box_for_one_point_ends_after_it() {
        for (extent, periodic, r) in [
            ([1.0, 1.0], [false; 2], 1.5),
            ([1.0, 1.0], [true; 2], 0.75),
            ([0.9, 1.0], [true, false], 1e6),
        ] {
            let d = Domain::from_extent(extent).unwrap().with_periodic(periodic);
            let s = PoissonDisk2::builder(d, r)
                .attempts(MAX_ATTEMPTS)
                .build()
                .unwrap();
            let mut it = s.iter_seeded(1);
            assert!(it.next().is_some(), "one point");
            assert!(
                it.active.is_empty(),
                "{extent:?} {periodic:?} {r}: no throws"
            );
        }
        // Just wide enough for two points: the shortcut must not fire.
        let d = Domain::from_extent([1.0, 1.0]).unwrap();
        assert!(!d.holds_one_point(1.414), "the diagonal is longer");
        let d = d.with_periodic([true; 2]);
        assert!(!d.holds_one_point(0.7), "half-period diagonal 0.707");
    }

    /// The loop compiled for AVX2 (`cpu.rs`) makes the portable loop's
    /// points bit for bit: every grid (3-D's bricks under `Dense`), bounded
    /// and periodic, 2-D to 4-D. On a processor without AVX2 both runs take
    /// the portable copy and the test checks only that a seed repeats.
    #[test]
    fn both_copies_make_the_same_points() {
        use crate::cpu::tests::{assert_same, both_copies};
        fn run<const N: usize>(
            extent: [f64; N],
            periodic: bool,
            r: f64,
            layout: GridLayout,
        ) -> Vec<[u64; N]> {
            let d = Domain::from_extent(extent)
                .unwrap()
                .with_periodic([periodic; N]);
            let s = PoissonDisk::builder(d, r).layout(layout).build().unwrap();
            s.iter_seeded(11).map(|p| p.map(f64::to_bits)).collect()
        }
        for layout in [GridLayout::Dense, GridLayout::Sparse] {
            for periodic in [false, true] {
                let what = format!("{layout:?}, periodic {periodic}");
                let plane = both_copies(|| run([1.0, 0.7], periodic, 0.02, layout));
                assert_same(&format!("2-D, {what}"), plane, 500);
                let cube = both_copies(|| run([1.0; 3], periodic, 0.08, layout));
                assert_same(&format!("3-D, {what}"), cube, 500);
                let tesseract = both_copies(|| run([1.0; 4], periodic, 0.25, layout));
                assert_same(&format!("4-D, {what}"), tesseract, 100);
            }
        }
    }

    #[test]
    fn first_point_handles_a_one_ulp_box() {
        let lo = 1.0_f64;
        let hi = f64::from_bits(lo.to_bits() + 1);
        let d = Domain::new([lo], [hi]).unwrap();
        let mut rng = seeded_rng(5);
        for _ in 0..100 {
            let p = first_point(&d, &mut rng);
            assert!(d.contains(&p), "{p:?}");
        }
    }
}

/// The expected-size plan (`GridLayout::Auto` in 2-D and 3-D) against the
/// peaks runs reach.
#[cfg(test)]
mod planning_tests {
    use super::*;
    use crate::grid::GridPlan;

    /// The plan's expected peak for a dense run, if the sampler has one.
    fn planned<const N: usize>(s: &PoissonDisk<N>) -> Option<u64> {
        match s.plan {
            GridPlan::Dense(d) => Some(d.peak(s.expected)),
            GridPlan::Paged(_) | GridPlan::Sparse(_) => None,
        }
    }

    /// Over both candidate kinds, bounded and periodic boxes and two `k`:
    /// the heap a run holds never passes the planned peak, a run whose
    /// budget is exactly that peak completes with the same points, and
    /// the plan is not a worst case (within 3× the bytes up front plus the
    /// points' own).
    fn check<const N: usize>(r: f64) {
        for periodic in [false, true] {
            for kind in [Candidates::Annulus, Candidates::Sphere] {
                for k in [10, 30] {
                    for seed in 1..=2 {
                        let domain = Domain::from_extent([1.0; N])
                            .unwrap()
                            .with_periodic([periodic; N]);
                        let open = PoissonDisk::builder(domain, r)
                            .candidates(kind)
                            .attempts(k)
                            .max_grid_bytes(u64::MAX)
                            .build()
                            .unwrap();
                        let ctx =
                            format!("{N}-D, periodic {periodic}, {kind:?}, k {k}, seed {seed}");
                        let plan = planned(&open).unwrap_or_else(|| panic!("{ctx}: dense"));
                        let mut it = open.iter_seeded(seed);
                        let mut peak = 0;
                        let mut points = Vec::new();
                        while let Some(p) = it.next() {
                            peak = u64::max(peak, it.heap_bytes());
                            points.push(p);
                        }
                        assert!(
                            peak <= plan,
                            "{ctx}: held {peak} > planned {plan} ({} up front, {} points)",
                            open.grid_bytes(),
                            points.len()
                        );
                        let own = points.len() as u64 * (8 * N) as u64;
                        assert!(
                            plan <= 3 * (open.grid_bytes() + own),
                            "{ctx}: planned {plan} is a worst case ({} up front, {own} points)",
                            open.grid_bytes()
                        );
                        let tight = open.to_builder().max_grid_bytes(plan).build().unwrap();
                        assert_eq!(tight.resolved_layout(), GridLayout::Dense, "{ctx}: dense");
                        assert_eq!(
                            tight.generate_seeded(seed).map_err(|e| e.error()),
                            Ok(points),
                            "{ctx}: the planned budget suffices"
                        );
                    }
                }
            }
        }
    }

    /// How often a run outgrows a budget of exactly its planned peak, over
    /// many seeds (a study, not a check: `cargo test --profile bench --lib
    /// -- --ignored --nocapture budget_stops`).
    #[test]
    #[ignore = "a study of a few minutes; prints its figures"]
    fn budget_stops_at_the_planned_peak() {
        fn study<const N: usize>(r: f64, periodic: bool, seeds: u64) {
            let domain = Domain::from_extent([1.0; N])
                .unwrap()
                .with_periodic([periodic; N]);
            let open = PoissonDisk::new(domain, r).unwrap();
            let plan = planned(&open).unwrap();
            let tight = open.to_builder().max_grid_bytes(plan).build().unwrap();
            let stops = (0..seeds)
                .filter(|&seed| tight.generate_seeded(seed).is_err())
                .count();
            println!("{N}-D r {r} periodic {periodic}: {stops} of {seeds} runs stopped");
        }
        for periodic in [false, true] {
            study::<2>(0.002, periodic, 200);
            study::<3>(0.02, periodic, 200);
        }
    }

    #[test]
    fn the_plan_holds_the_peak_of_2d_runs() {
        check::<2>(0.01);
    }

    #[test]
    fn the_plan_holds_the_peak_of_3d_runs() {
        check::<3>(0.05);
    }
}
