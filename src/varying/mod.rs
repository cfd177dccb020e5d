//! A radius that varies with position ([`PoissonDisk::iter_varying`]): no
//! two points `p`, `q` closer than `max(r(p), r(q))`.
//!
//! Bridson's loop as the fixed radius runs it (a pick drawn two ahead, a
//! per-pick [`ConflictCache`] seeded with the parent's neighbours, annulus
//! offsets drawn eight ahead), over an index of its own: points of
//! different radii do not fit the fixed radius's grid of one point per cell
//! of side `r/√N`.
//!
//! - [`Levels`] (`levels.rs`), the usual index: a dense grid per band of
//!   radii (a factor `2^(3/4)`, cells sized to the band's top, a cell's
//!   extra points chained), searched with stencils of `grid/dense.rs`.
//! - [`Lists`] (`lists.rs`), the fallback when the bands' grids would not
//!   fit the memory budget, past 4-D, or past `r_max / r_min = 16`: a
//!   linked list per cell of side `r_max`, every point of the 3^N cells
//!   around a candidate checked (slow where a cell holds many points).
//! - `coarse.rs`: the grid of cells of side `r_max` both hang data on.
//!
//! Both find every point too close, and the loop's decisions are exact
//! (`f64`, as the oracle), so the points do not depend on the index (a
//! unit test compares them).

mod coarse;
mod levels;
mod lists;

use crate::candidates::{CandidateSampler, Candidates, OffsetBatch};
use crate::conflict_cache::{ConflictCache, NEAR_ORIGIN};
use crate::cpu::dispatch;
use crate::domain::Domain;
use crate::error::Error;
use crate::random::{DefaultRng, below, seeded_rng, unit};
use crate::sampler::{
    Everywhere, PoissonDisk, Region, check_radius_and_attempts, first_point_tries,
};
use crate::vector::{add, all_finite, periodic_distance_squared, scale, zip_map};
use coarse::Coarse;
use core::iter::FusedIterator;
use levels::Levels;
use lists::Lists;
use rand::Rng;

/// The conflict cache's unit, in units of the parent's radius (`r0 /
/// r(p)`): its quick test serves candidates with `r0 <= r(c) <= 4·r0`,
/// from half the parent's radius to twice it.
const QUICK_RADIUS: f64 = 0.5;
/// `r(p) / r0` as `f32` (exact), to put the offsets drawn ahead (units of
/// `r(p)`) in units of `r0`.
const QUICK_STRETCH: f32 = 2.0;

/// A stored point and its radius, side by side.
type Stored<const N: usize> = ([f64; N], f64);

/// Heap bytes counted per point: the point and its radius, twice (the
/// points and the active list), and its link (the lists' next, or the levels'
/// chain of a cell), each with room for a vector's doubling.
fn bytes_per_point<const N: usize>() -> u64 {
    let n = u64::try_from(N).unwrap_or(u64::MAX);
    2_u64.saturating_mul(n.saturating_mul(16).saturating_add(32))
}

/// Whether stored point `i` lies closer to `c` than `max(rc, r(i))`
/// (squares summed in axis order, toroidal on axes with a period).
#[inline(always)]
fn too_close<const N: usize>(
    points: &[Stored<N>],
    periods: &[f64; N],
    c: &[f64; N],
    rc: f64,
    i: usize,
) -> bool {
    let Some((q, rq)) = points.get(i) else {
        return false;
    };
    let bound = rc.max(*rq);
    periodic_distance_squared(c, q, periods) < bound * bound
}

/// Where the stored points are looked up. Either finds every point closer
/// than the rule allows, so the points made do not depend on which is used.
#[derive(Debug)]
enum Index<const N: usize> {
    Levels(Levels<N>),
    Lists(Lists<N>),
}

impl<const N: usize> Index<N> {
    #[inline(always)]
    fn blocked(
        &mut self,
        points: &[Stored<N>],
        periods: &[f64; N],
        c: &[f64; N],
        rc: f64,
    ) -> Option<usize> {
        match self {
            Self::Levels(l) => l.blocked(points, periods, c, rc),
            Self::Lists(l) => l.blocked(points, periods, c, rc),
        }
    }

    fn insert(&mut self, index: u32, p: &[f64; N], r: f64) -> bool {
        match self {
            Self::Levels(l) => l.insert(index, p, r),
            Self::Lists(l) => l.insert(index, p),
        }
    }
}

/// What [`VaryingPoints::store`] did with a point.
enum Filed {
    Yes,
    /// Out of memory or indices: the run ends.
    Stop,
}

/// The stream of a [`PoissonDisk::iter_varying`] run, or of a
/// [`PoissonDisk::iter_varying_with`] run in region `G` ([`Everywhere`]
/// unless the run came from `iter_varying_with`).
#[derive(Debug)]
pub struct VaryingPoints<const N: usize, F, R = DefaultRng, G = Everywhere> {
    rng: R,
    field: F,
    region: G,
    domain: Domain<N>,
    periods: [f64; N],
    r_min: f64,
    r_max: f64,
    attempts: u32,
    candidates: CandidateSampler<N>,
    /// On-sphere candidates: moved out to `r(c)` where the field grows.
    sphere: bool,
    /// Annulus offsets drawn eight ahead (2-D and 3-D).
    ahead: OffsetBatch<N>,
    index: Index<N>,
    points: Vec<Stored<N>>,
    /// The active points, with their radii (copies: no indirection to
    /// wait on).
    active: Vec<Stored<N>>,
    /// The next two picks, drawn ahead so that their memory is fetched
    /// while earlier picks run (as the fixed radius's loop).
    next_pick: [Option<usize>; 2],
    remaining: u64,
    budget: u64,
    started: bool,
    /// A first point already drawn in the region (by
    /// [`PoissonDisk::iter_varying_with`], which reports a region it cannot
    /// hit), to be stored on the first step.
    first_found: Option<[f64; N]>,
    error: Option<Error>,
}

impl<const N: usize> PoissonDisk<N> {
    /// Points whose spacing follows the radius field `field`: no two points
    /// `p`, `q` closer than `max(r(p), r(q))` (squared distances summed in
    /// axis order, toroidal on periodic axes, as for a fixed radius), every
    /// point in the box, and no room left for another point to `k` attempts
    /// around each. `r(x)` is `field(x)` clamped to `r_min ..= r_max`, where
    /// `r_max` is this sampler's radius (NaN counts as `r_max`); annulus
    /// candidates are thrown at `r(p) .. 2·r(p)` around a point `p`,
    /// on-sphere ones at `r(p)`, moved out (up to 8 times) to `r(c)` where
    /// the field is larger at the candidate `c`. The same seed and
    /// field give the same points. The point cap and budget apply (the
    /// budget on the grids allocated up front and an estimate of the bytes
    /// per point); [`PoissonDiskBuilder::layout`](crate::PoissonDiskBuilder::layout) does not.
    ///
    /// The guarantee is symmetric, so it does not depend on which point
    /// came first. Speed: up to 4-D and `r_max / r_min <= 16`, each band
    /// of radii (a factor `2^(3/4)`) gets a dense grid of its own, cells of
    /// side `top/√N` for the band's top radius (together about half the
    /// cells of one grid at `r_min` in 2-D, a quarter in 3-D, 4 bytes
    /// each), when they fit the memory budget. Otherwise a slower index of
    /// lists per cell of side `r_max` serves, with the same points.
    /// `docs/performance.md` compares its speed with a fixed radius's.
    ///
    /// # Errors
    /// [`Error::InvalidRadius`] if `r_min` is not a valid radius or is above
    /// the sampler's radius; [`Error::BoxTooWide`] if the box spans more
    /// than 2²⁰ cells of side `r_max` on some axis; [`Error::GridTooLarge`]
    /// if not even the slower index's cells of side `r_max` (4 bytes each)
    /// fit the memory budget.
    ///
    /// # Example: a radius growing from left to right
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, 0.08)?;
    /// let field = |p: &[f64; 2]| 0.02 + 0.06 * p[0];
    /// let points: Vec<[f64; 2]> = sampler.iter_varying_seeded(3, 0.02, field)?.collect();
    /// for (i, p) in points.iter().enumerate() {
    ///     for q in &points[..i] {
    ///         let d2 = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    ///         let r = field(p).max(field(q));
    ///         assert!(d2 >= r * r);
    ///     }
    /// }
    /// // Denser on the left, where the radius is small.
    /// let left = points.iter().filter(|p| p[0] < 0.5).count();
    /// assert!(left > 2 * (points.len() - left));
    /// # Ok::<(), bridson::Error>(())
    /// ```
    pub fn iter_varying<R: Rng, F: Fn(&[f64; N]) -> f64>(
        &self,
        rng: R,
        r_min: f64,
        field: F,
    ) -> Result<VaryingPoints<N, F, R>, Error> {
        self.varying(rng, r_min, field, Everywhere, true)
    }

    /// As [`iter_varying`](Self::iter_varying), drawing from [`DefaultRng`]
    /// seeded with `seed`: the same seed and field give the same points on
    /// every run and platform.
    ///
    /// # Errors
    /// As [`iter_varying`](Self::iter_varying).
    pub fn iter_varying_seeded<F: Fn(&[f64; N]) -> f64>(
        &self,
        seed: u64,
        r_min: f64,
        field: F,
    ) -> Result<VaryingPoints<N, F>, Error> {
        self.iter_varying(seeded_rng(seed), r_min, field)
    }

    /// As [`iter_varying`](Self::iter_varying), with every new point
    /// inside `region` and clear of the pre-placed points `fixed`, as
    /// [`iter_with`](Self::iter_with) does for a fixed radius: a forest
    /// whose spacing follows a function, kept out of a lake, around trees
    /// already planted.
    ///
    /// A pre-placed point `q` carries the radius the field gives it,
    /// `r(q)` (clamped as any point's), so the guarantee, no two points `p`,
    /// `q` closer than `max(r(p), r(q))`, holds for the union of `fixed`
    /// and the points yielded. The pre-placed points are not yielded; they
    /// count against the memory budget but not against the point cap.
    /// Growth starts from the pre-placed points (candidates are thrown
    /// around them as around any point), or, if there are none, from a
    /// uniform point of the region, drawn here: up to `64·k` uniform tries
    /// over the box, and [`Error::RegionMissed`] if none lands in the
    /// region, as `iter_with`. It reaches every part of the region within
    /// `2·r_max` hops of where it started: islands of a mask need a
    /// pre-placed point each. With [`Everywhere`] and no pre-placed point
    /// it makes the points of [`iter_varying`](Self::iter_varying) for the
    /// same generator.
    ///
    /// A method of its own, not two more parameters on `iter_varying`: a
    /// plain run keeps its short call and its type
    /// (`VaryingPoints<N, F, R>`, region [`Everywhere`]), and the pair
    /// mirrors `iter` / `iter_with` (the naming rule's `name(rng, …)`,
    /// `name_seeded(seed, …)`).
    ///
    /// A mask closure needs its argument type written out,
    /// `|p: &[f64; 2]| …`: the compiler does not infer it through the
    /// [`Region`] bound (error E0282).
    ///
    /// # Errors
    /// As [`iter_varying`](Self::iter_varying), and:
    /// [`Error::InvalidFixedPoint`] naming the first pre-placed point that
    /// is not finite, lies outside the domain, or lies closer than
    /// `max(r(p), r(q))` to an earlier one `p`;
    /// [`Error::MemoryBudgetExceeded`] (with `points: 0`) if the pre-placed
    /// points alone outgrow the budget; [`Error::RegionMissed`] if there
    /// are no pre-placed points and no first point lands in the region.
    ///
    /// # Example: trees thinning out eastward, kept out of a lake
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, 0.08)?;
    /// let field = |p: &[f64; 2]| 0.02 + 0.06 * p[0];
    /// let dry = |p: &[f64; 2]| (p[0] - 0.5).powi(2) + (p[1] - 0.5).powi(2) > 0.04;
    /// let planted = [[0.1, 0.1], [0.9, 0.9]];
    /// let new: Vec<[f64; 2]> =
    ///     sampler.iter_varying_with_seeded(3, 0.02, field, dry, &planted)?.collect();
    /// assert!(new.iter().all(|p| dry(p)));
    /// let all: Vec<[f64; 2]> = planted.iter().chain(&new).copied().collect();
    /// for (i, p) in all.iter().enumerate() {
    ///     for q in &all[..i] {
    ///         let d2 = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    ///         let r = field(p).max(field(q));
    ///         assert!(d2 >= r * r);
    ///     }
    /// }
    /// # Ok::<(), bridson::Error>(())
    /// ```
    pub fn iter_varying_with<R: Rng, F: Fn(&[f64; N]) -> f64, G: Region<N>>(
        &self,
        rng: R,
        r_min: f64,
        field: F,
        region: G,
        fixed: &[[f64; N]],
    ) -> Result<VaryingPoints<N, F, R, G>, Error> {
        let mut it = self.varying(rng, r_min, field, region, true)?;
        for (index, p) in fixed.iter().enumerate() {
            it.place_fixed(*p)
                .map_err(|e| e.unwrap_or(Error::InvalidFixedPoint { index }))?;
        }
        if fixed.is_empty() {
            let tries = first_point_tries(it.attempts);
            it.first_found = Some(it.first_in_region().ok_or(Error::RegionMissed { tries })?);
        } else {
            // Growth starts from the pre-placed points.
            it.started = true;
        }
        Ok(it)
    }

    /// As [`iter_varying_with`](Self::iter_varying_with), drawing from
    /// [`DefaultRng`] seeded with `seed`: the same seed, field, region and
    /// pre-placed points give the same points on every run and platform.
    ///
    /// # Errors
    /// As [`iter_varying_with`](Self::iter_varying_with).
    pub fn iter_varying_with_seeded<F: Fn(&[f64; N]) -> f64, G: Region<N>>(
        &self,
        seed: u64,
        r_min: f64,
        field: F,
        region: G,
        fixed: &[[f64; N]],
    ) -> Result<VaryingPoints<N, F, DefaultRng, G>, Error> {
        self.iter_varying_with(seeded_rng(seed), r_min, field, region, fixed)
    }

    /// [`Self::iter_varying`], on the lists if `levels` is false (tests
    /// compare the two).
    fn varying<R: Rng, F: Fn(&[f64; N]) -> f64, G: Region<N>>(
        &self,
        rng: R,
        r_min: f64,
        field: F,
        region: G,
        levels: bool,
    ) -> Result<VaryingPoints<N, F, R, G>, Error> {
        let r_max = self.radius();
        check_radius_and_attempts(r_min, self.attempts())?;
        if r_min > r_max {
            return Err(Error::InvalidRadius);
        }
        let domain = *self.domain();
        let budget = self.max_grid_bytes();
        let coarse = Coarse::new(&domain, r_max).map_err(|e| match e {
            Error::GridTooLarge { needed, .. } => Error::GridTooLarge { needed, budget },
            e => e,
        })?;
        let levels = if levels {
            Levels::new(coarse, &domain, r_min, r_max, budget)
        } else {
            Err(coarse)
        };
        let (index, needed) = match levels {
            Ok((levels, needed)) => (Index::Levels(levels), needed),
            Err(coarse) => {
                // The lists' heads are allocated up front: they must fit.
                let needed = u64::try_from(coarse.count())
                    .ok()
                    .and_then(|n| n.checked_mul(4))
                    .unwrap_or(u64::MAX);
                if needed > budget {
                    return Err(Error::GridTooLarge { needed, budget });
                }
                (Index::Lists(Lists::new(coarse)), needed)
            }
        };
        Ok(VaryingPoints {
            rng,
            field,
            region,
            domain,
            periods: zip_map(&domain.extent(), &domain.periodic(), |l, p| {
                if p { l } else { 0.0 }
            }),
            r_min,
            r_max,
            attempts: self.attempts(),
            candidates: CandidateSampler::new(self.candidates(), 1.0, self.attempts()),
            sphere: self.candidates() == Candidates::Sphere,
            ahead: OffsetBatch::new(),
            index,
            points: Vec::new(),
            active: Vec::new(),
            next_pick: [None; 2],
            remaining: self.max_points().unwrap_or(u64::MAX),
            budget: budget.saturating_sub(needed),
            started: false,
            first_found: None,
            error: None,
        })
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64, R: Rng, G: Region<N>> VaryingPoints<N, F, R, G> {
    /// Why the stream ended early, if it did: as [`Points::error`](crate::Points::error).
    pub fn error(&self) -> Option<Error> {
        self.error
    }

    /// `r(p)`: the field clamped to `r_min ..= r_max`, NaN as `r_max`.
    #[inline(always)]
    fn radius_at(&self, p: &[f64; N]) -> f64 {
        let r = (self.field)(p);
        if r.is_nan() {
            self.r_max
        } else {
            r.clamp(self.r_min, self.r_max)
        }
    }

    /// Stores pre-placed point `p` at its radius `r(p)`: `Err(None)` if it
    /// is not finite, lies outside the box or closer than `max(r(p), r(q))`
    /// to a stored point `q`; `Err(Some(MemoryBudgetExceeded))` if it does
    /// not fit the budget (or the index).
    fn place_fixed(&mut self, p: [f64; N]) -> Result<(), Option<Error>> {
        if !all_finite(&p) || !self.domain.contains(&p) {
            return Err(None);
        }
        let r = self.radius_at(&p);
        if self
            .index
            .blocked(&self.points, &self.periods, &p, r)
            .is_some()
        {
            return Err(None);
        }
        match self.store(p, r) {
            Filed::Yes => Ok(()),
            Filed::Stop => {
                self.error = None;
                Err(Some(Error::MemoryBudgetExceeded {
                    points: 0,
                    budget: self.budget,
                }))
            }
        }
    }

    /// A uniform point of the box that the region admits, drawn as a
    /// plain run's first point is, in up to [`first_point_tries`] tries,
    /// or `None`.
    fn first_in_region(&mut self) -> Option<[f64; N]> {
        let (lo, extent) = (self.domain.lo(), self.domain.extent());
        for _ in 0..first_point_tries(self.attempts) {
            let p = zip_map(&lo, &extent, |l, e| l + unit(&mut self.rng) * e);
            if self.domain.contains(&p) && self.region.admits(&p) {
                return Some(p);
            }
        }
        None
    }

    /// Stores `p` with radius `r`, if the estimated memory fits.
    fn store(&mut self, p: [f64; N], r: f64) -> Filed {
        let count = u64::try_from(self.points.len()).unwrap_or(u64::MAX);
        if count
            .saturating_add(1)
            .saturating_mul(bytes_per_point::<N>())
            > self.budget
        {
            self.error = Some(Error::MemoryBudgetExceeded {
                points: count,
                budget: self.budget,
            });
            self.active.clear();
            return Filed::Stop;
        }
        let filed =
            u32::try_from(self.points.len()).is_ok_and(|index| self.index.insert(index, &p, r));
        if !filed {
            // More points than the index can number.
            self.active.clear();
            return Filed::Stop;
        }
        self.points.push((p, r));
        self.active.push((p, r));
        Filed::Yes
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64, R: Rng, G: Region<N>> VaryingPoints<N, F, R, G> {
    /// Up to `k` candidates around active entry `i`, keeping the first
    /// that no stored point is too close to. The points that turn
    /// candidates away, the parent and its nearest neighbours of its band
    /// are remembered for the pick ([`ConflictCache`]) and checked first,
    /// exactly (in `f64`, as the oracle), at the candidate's radius: a
    /// point closer than `r(c)` is closer than `max(r(c), r(q))`. A
    /// blocker only its own larger radius reaches is left to the index.
    #[inline(always)]
    fn pick<const B: usize>(&mut self, i: usize) -> Step<N> {
        let Some(&(parent, rp)) = self.active.get(i) else {
            return Step::Stop;
        };
        let periods = self.periods;
        // The cache's quick test (`f32`, in units of `r0`) says "closer
        // than `r(c)`" for candidates with `r0 <= r(c) <= 4·r0`: every
        // candidate where the field is smooth; the others take its exact
        // test at `r(c)`.
        let r0 = rp * QUICK_RADIUS;
        let inv_r0 = 1.0 / r0;
        let mut cache = ConflictCache::<N, B>::new(parent, r0);
        let periodic = self.domain.any_periodic();
        cache.push(&parent);
        if let Index::Levels(levels) = &mut self.index {
            if periodic {
                levels.seed(&self.points, &parent, rp, B - 1, |q| {
                    cache.push_periodic(q, &periods);
                });
            } else {
                levels.seed(&self.points, &parent, rp, B - 1, |q| cache.push(q));
            }
        }
        // Far from every face, no candidate can leave the box (annulus
        // candidates lie within 2·r(p)·(1 + 1e-7), on-sphere ones within
        // r_max·(1 + 1e-7); the test keeps twice its reach).
        let reach = if self.sphere { self.r_max } else { 2.0 * rp };
        let interior = !periodic && self.domain.holds_ball(&parent, reach);
        let ahead = self.candidates.reads_ahead();
        // Coordinates below 2²⁸·r0: the candidate is its offset from the
        // parent to within 2⁻²⁵·r0 (`ConflictCache::block_relative`); on a
        // torus, periods below 2²⁸·r0 too, for the remembered points'
        // nearest images (`ConflictCache::push_periodic`).
        let quick = ahead
            && parent
                .iter()
                .chain(&periods)
                .all(|x| x.abs() < r0 * NEAR_ORIGIN);
        let mut state = if ahead {
            [0.0; N]
        } else {
            self.candidates.start(&mut self.rng)
        };
        for _ in 0..self.attempts {
            let (offset, unit) = if ahead {
                self.ahead.next(&self.candidates, &mut self.rng)
            } else {
                (self.candidates.offset(&mut self.rng, &mut state), [0.0; N])
            };
            let mut c = add(&parent, &scale(&offset, rp));
            if !interior && !self.domain.wrap(&mut c) {
                continue;
            }
            let mut rc = self.radius_at(&c);
            if self.sphere {
                // Thrown at r(p), it is too close to its parent where
                // the field grows: move it out along the same direction
                // to r(c), a few times, as r(c) moves with it.
                let mut at = rp;
                for _ in 0..8 {
                    if rc <= at {
                        break;
                    }
                    at = rc;
                    c = add(&parent, &scale(&offset, at));
                    if !self.domain.wrap(&mut c) {
                        break;
                    }
                    rc = self.radius_at(&c);
                }
                if !self.domain.contains(&c) {
                    continue;
                }
            }
            let blocked = if quick && rc >= r0 && rc <= 4.0 * r0 {
                // The offset in units of r0: `unit` is in units of r(p).
                // `rc·(1/r0)` is within 2⁻⁵² of `rc/r0`, and `s² >= 1` up
                // to that: far inside the quick test's margin.
                let s = (rc * inv_r0).max(1.0);
                #[expect(
                    clippy::cast_possible_truncation,
                    reason = "f32 on purpose: the quick test has a margin"
                )]
                let scale_squared = (s * s) as f32;
                cache.block_relative_scaled(&unit.map(|u| u * QUICK_STRETCH), scale_squared)
            } else {
                cache.block_periodic(&c, rc * rc, &periods)
            };
            if blocked {
                continue;
            }
            if let Some(q) = self.index.blocked(&self.points, &periods, &c, rc) {
                if let Some((q, _)) = self.points.get(q) {
                    if periodic {
                        cache.push_periodic(q, &periods);
                    } else {
                        cache.push(q);
                    }
                }
                continue;
            }
            // Last, where most candidates have already failed: the mask
            // may be the caller's costly test (a shore, a polygon).
            if !self.region.admits(&c) {
                continue;
            }
            match self.store(c, rc) {
                Filed::Yes => {
                    self.remaining -= 1;
                    return Step::Made(c);
                }
                Filed::Stop => return Step::Stop,
            }
        }
        Step::Retired
    }
}

/// How a pick ended.
enum Step<const N: usize> {
    Made([f64; N]),
    Retired,
    Stop,
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64, R: Rng, G: Region<N>> Iterator
    for VaryingPoints<N, F, R, G>
{
    type Item = [f64; N];

    fn next(&mut self) -> Option<[f64; N]> {
        if self.remaining == 0 || self.error.is_some() {
            return None;
        }
        if !self.started {
            self.started = true;
            if let Some(p) = self.first_found.take() {
                let r = self.radius_at(&p);
                if !matches!(self.store(p, r), Filed::Yes) {
                    return None;
                }
                self.remaining -= 1;
                return Some(p);
            }
            let (lo, extent) = (self.domain.lo(), self.domain.extent());
            let p = zip_map(&lo, &extent, |l, e| l + unit(&mut self.rng) * e);
            if !self.domain.contains(&p) {
                return None;
            }
            let r = self.radius_at(&p);
            if !matches!(self.store(p, r), Filed::Yes) {
                return None;
            }
            self.remaining -= 1;
            return Some(p);
        }
        while !self.active.is_empty() {
            let len = self.active.len();
            // Each drawn uniform over `0..len + 2`, which bounds the list's
            // length when it is used (a pick adds or removes one entry);
            // kept if below the length then, redrawn otherwise: uniform
            // over `0..len` either way.
            let [now, soon] = self.next_pick;
            let i = now
                .filter(|&i| i < len)
                .unwrap_or_else(|| below(&mut self.rng, len));
            let later = below(&mut self.rng, len + 2);
            self.next_pick = [soon, Some(later)];
            crate::prefetch::prefetch(&self.active, later);
            if let (Some(&(p, r)), Index::Levels(levels)) =
                (soon.and_then(|j| self.active.get(j)), &mut self.index)
            {
                levels.prefetch(&p, r);
            }
            // A conflict cache sized for the dimension: 8 slots in 2-D
            // (the fixed radius's 2-D seed reads out to `2r` and takes 16;
            // this one's seed is the levels'), 16 from 3-D up.
            // The pick compiled for AVX2 where the processor has it
            // (`cpu.rs`): the same points.
            let step = if N <= 2 {
                dispatch(
                    #[inline(always)]
                    || self.pick::<8>(i),
                )
            } else {
                dispatch(
                    #[inline(always)]
                    || self.pick::<16>(i),
                )
            };
            match step {
                Step::Made(p) => return Some(p),
                Step::Retired => {
                    self.active.swap_remove(i);
                }
                Step::Stop => return None,
            }
        }
        None
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64, R: Rng, G: Region<N>> FusedIterator
    for VaryingPoints<N, F, R, G>
{
}

#[cfg(test)]
mod tests {
    use crate::{Domain, PoissonDisk};

    /// A sampler of `N`-D points whose radius runs from `r_max / ratio` to
    /// `r_max` in a wave along the box's diagonal (the radius changes
    /// direction, so levels meet in places), on levels or on lists.
    fn wave<const N: usize>(
        (periodic, sphere): (bool, bool),
        r_max: f64,
        ratio: f64,
        seed: u64,
        levels: bool,
    ) -> super::VaryingPoints<N, impl Fn(&[f64; N]) -> f64> {
        let domain = Domain::from_extent([1.0; N])
            .unwrap()
            .with_periodic([periodic; N]);
        let kind = if sphere {
            crate::Candidates::Sphere
        } else {
            crate::Candidates::Annulus
        };
        let sampler = PoissonDisk::builder(domain, r_max)
            .candidates(kind)
            .build()
            .unwrap();
        let r_min = r_max / ratio;
        let field = move |p: &[f64; N]| {
            let t = p.iter().sum::<f64>() * 3.0;
            r_min + (r_max - r_min) * (t - t.floor())
        };
        sampler
            .varying(
                crate::random::seeded_rng(seed),
                r_min,
                field,
                crate::Everywhere,
                levels,
            )
            .unwrap()
    }

    /// The two indexes find the same conflicts, so they make the same
    /// points, bit for bit, whatever the box, the field or the candidates.
    fn same_points<const N: usize>(periodic: bool, sphere: bool, ratio: f64, seed: u64) {
        let r_max = [0.0, 0.02, 0.06, 0.18, 0.35][N];
        let on_levels = wave::<N>((periodic, sphere), r_max, ratio, seed, true);
        assert!(matches!(on_levels.index, super::Index::Levels(_)), "{N}-D");
        let levels: Vec<_> = on_levels.collect();
        let lists: Vec<_> = wave::<N>((periodic, sphere), r_max, ratio, seed, false).collect();
        assert!(levels.len() > 20, "{N}-D: {} points", levels.len());
        assert_eq!(levels, lists, "{N}-D periodic {periodic} sphere {sphere}");
    }

    /// The pick as compiled for AVX2 (where this processor has it) and as
    /// compiled for the baseline make the same points, bit for bit, on
    /// both indexes, bounded and periodic, with either candidates.
    #[test]
    fn both_copies_make_the_same_points() {
        use crate::cpu::tests::{assert_same, both_copies};
        fn run<const N: usize>(kind: (bool, bool), levels: bool) -> Vec<[u64; N]> {
            let r_max = [0.0, 0.01, 0.04, 0.12, 0.3][N];
            wave::<N>(kind, r_max, 3.0, 7, levels)
                .map(|p| p.map(f64::to_bits))
                .collect()
        }
        for (periodic, sphere, levels) in [
            (false, false, true),
            (true, false, true),
            (false, true, true),
            (false, false, false),
        ] {
            let what = format!("periodic {periodic}, sphere {sphere}, levels {levels}");
            let plane = both_copies(|| run::<2>((periodic, sphere), levels));
            assert_same(&format!("2-D, {what}"), plane, 500);
            let cube = both_copies(|| run::<3>((periodic, sphere), levels));
            assert_same(&format!("3-D, {what}"), cube, 200);
        }
    }

    #[test]
    fn levels_and_lists_make_the_same_points() {
        for (i, (periodic, sphere)) in [(false, false), (true, false), (false, true), (true, true)]
            .into_iter()
            .enumerate()
        {
            let seed = u64::try_from(i).unwrap();
            same_points::<1>(periodic, sphere, 4.0, seed);
            same_points::<2>(periodic, sphere, 4.0, seed);
            same_points::<2>(periodic, sphere, 1.5, seed);
            same_points::<3>(periodic, sphere, 3.0, seed);
            same_points::<4>(periodic, sphere, 2.0, seed);
        }
    }
}
