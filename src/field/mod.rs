//! Poisson disk sampling as a pure function of place: [`Field`].
//!
//! # The algorithm
//! Hashed darts with priorities, resolved in rounds, refined Ebeida-style
//! until the set is maximal (design B of the field notes).
//!
//! - **Lattice.** Level-0 cells are a little under `r/√N` on a side (so a
//!   cell holds at most one point), laid from the box's lower corner, with
//!   a whole number of cells per period on a periodic axis, or, for an
//!   unbounded field, from the absolute origin with a side that depends
//!   only on `r`.
//! - **Darts.** In round `t` every *live* cell (at level `l`, a cell
//!   `2^-l` of a level-0 cell on a side) gets one dart. Its position in the
//!   cell and its priority are words of a hash of (seed, canonical level-0
//!   cell, sub-cell, level, round): SplitMix64's finaliser, integer
//!   operations only, and `f64` arithmetic limited to `+ - × ÷`, so a dart
//!   has the same bits on every machine.
//! - **Acceptance.** Each round is greedy in priority order: as if its
//!   darts were thrown one by one from the highest priority down, a dart
//!   becomes a point if no point (of an earlier round, or kept before it in
//!   this one) lies within `r`. So the whole set is random sequential
//!   adsorption in the order (round, priority). With that order fixed by
//!   the hash, no schedule can change the outcome (Xiang Ying et al. 2013;
//!   Blelloch, Fineman & Shun 2012, whose rounds of local maxima a window
//!   runs until the round is decided).
//! - **Refinement.** Two rounds run at level 0; from then on each round
//!   first splits every live cell into its `2^N` halves and drops those
//!   that a single disk of radius `r` covers (Ebeida et al. 2012), or that
//!   several disks together are proved to cover by halving it twice on
//!   every axis, so the darts go where space is left. Dropping a covered
//!   cell never changes the points (no dart in it could be kept), only the
//!   work. The process ends when no cell is live: every point of the
//!   domain is then within `r` of a point (maximal).
//!   Levels stop at 30 (cells `2^-30` of a level-0 cell), rounds at 40; in
//!   measured runs the last live cell goes at level 13 to 18.
//!
//! # Queries, the halo and exactness
//! A query for the half-open box `[a, b)` runs the rounds over the
//! level-0 cells meeting the box, grown by a *halo* of `h` cells on each
//! side (cut at a bounded box's faces, wrapped on a periodic axis that it
//! spans). Everything a decision could learn from beyond the window is
//! tracked as *unknown*: a dart is known only when every point and rival
//! within `r` of it is known, a cell only when every point that could
//! cover it is known. The query succeeds if the box's cells are settled (no
//! live cell left) before an unknown reaches them; otherwise it runs again
//! with twice the halo. So the answer is the whole set's points in the box,
//! exactly, whatever the halo: only the cost depends on it.
//!
//! The halo a box needs is bounded with high probability and does not grow
//! with the set: within a round unknowns spread only along chains of darts
//! within `r` of one another, each outranking the next, which are short,
//! and from round to round only through cells that are still live, which
//! thin out geometrically. In 2-D, over 300 boxes of `16r`, the least halo
//! that settles a box is 7 to 12 cells (5 to 8.5 `r`), median 9; queries
//! start at 13 cells in 2-D and 20 in 3-D (14 to 18 measured, median 16).
//!
//! # Cost
//! Work and memory are linear in the window's cells: about 3.3 level-0
//! cells and 6.5 live-cell rounds per point in 2-D, 8.7 cells and about 23
//! in 3-D. A chunk of side `c` pays for `(c + 2h)^N` cells. The stencil of
//! neighbour cells holds 25 cells in 2-D, 125 in 3-D and 841 in 4-D, and
//! every live cell splits into `2^N`, so the field is practical to about 4-D; the lattice and the
//! proofs hold in any `N`. `docs/field.md` has the measured figures.
//!
//! # Not yet
//! A radius that varies with position and region masks compose with the
//! rounds in principle (level-0 cells from the smallest radius; a dart
//! outside the mask dropped, a cell outside it dead; both are functions of
//! place), but are not implemented.

#![expect(
    clippy::indexing_slicing,
    reason = "indices are axes `< N` of `[_; N]` arrays"
)]

mod chunks;
mod hash;
mod lattice;
mod region;
mod window;

use crate::domain::Domain;
use crate::error::Error;
use crate::sampler::Everywhere;
use lattice::{Axis, Lattice};

pub use chunks::chunk_boxes;
pub use region::{FieldRegion, SignedDistance};

/// Smallest and largest radius accepted, as for every sampler of the crate.
const MIN_RADIUS: f64 = 1e-150;
const MAX_RADIUS: f64 = 1e150;

/// The halo a query starts with, in level-0 cells on each side; it doubles
/// until the answer is settled. Measured over boxes of `16r`, the least
/// halo that settles a box is at most 12 cells in 2-D (300 boxes) and 14
/// to 18 in 3-D (100 boxes); a retry doubles the window's side, so the
/// start sits just above those. It never changes the points.
pub(crate) const fn start_halo(n: usize) -> i64 {
    match n {
        2 => 13,
        3 => 20,
        _ => 16,
    }
}

/// The default memory budget of one window: 1 GiB.
pub const DEFAULT_MAX_WINDOW_CELLS_BYTES: u64 = 1 << 30;

/// Heap bytes per level-0 cell of a window, for the check before a query
/// starts: 2.5 times its slots (point, taint and dart list, 9 bytes; a
/// live cell and a dart at level 0), since deeper levels' cells and the
/// near lists come on top. Measured peaks of whole boxes ran to 155 bytes
/// a cell in 2-D (r 0.000784) and 195 in 3-D (r 0.00835), against 187 and
/// 227 here. The rounds then count their heap as they go (`window::run`),
/// so the budget is a bound, not an estimate.
const fn bytes_per_cell(n: usize) -> u64 {
    let slots = 9 + (8 * n as u64 + 1) + (8 * n as u64 + 32) + 1;
    slots * 5 / 2
}

/// A Poisson disk set that is a pure function of (seed, radius, domain,
/// position): any box asked of it returns exactly the points of the whole
/// set that lie in it, whatever the order of the queries, their size, the
/// number of threads or the machine, bit for bit. The set is maximal: every
/// point of the domain is within `r` of one of its points.
///
/// The domain is a box ([`Field::new`], each axis bounded or periodic) or
/// all of space ([`Field::unbounded`], for endless worlds).
///
/// # How it works
/// Space is cut into level-0 cells a little under `r/√N` on a side, from
/// the box's lower corner (a whole number of cells per period on a
/// periodic axis) or, unbounded, from the absolute origin, so the lattice
/// depends only on `r`. The set is made in rounds. In each round every
/// *live* cell (one not yet proved covered by the disks of radius `r`
/// around the points) gets one dart, its position and priority a hash of
/// (seed, cell, level, round). Within a round the darts are taken greedily
/// from the highest priority down: a dart becomes a point if no point lies
/// within `r` (random sequential adsorption in a hashed order, as in Xiang
/// Ying et al. 2013; the schedule cannot change the outcome). After two rounds at level 0, each round
/// first splits every live cell into `2^N` halves and drops those a point
/// covers (Ebeida et al. 2012), so the darts go where space is left, until
/// no cell is live: the set is then maximal.
///
/// A query computes the rounds over its box grown by a halo, and tracks
/// everything that could depend on points outside as *unknown*. If an
/// unknown reaches the box before the box's cells are settled, it retries
/// with twice the halo. So the answer never depends on where the halo is
/// cut; only the cost does. `docs/field.md` has the measured halo and cost.
///
/// # Example: two orders, one world
/// ```
/// use bridson::Field;
/// let world = Field::<2>::unbounded(1.0, 7)?;
/// let a = world.points_in([0.0, 0.0], [20.0, 10.0])?;
/// let mut b = world.points_in([0.0, 0.0], [10.0, 10.0])?;
/// b.extend(world.points_in([10.0, 0.0], [20.0, 10.0])?);
/// b.sort_by(bridson::field_order);
/// assert_eq!(a, b);
/// # Ok::<(), bridson::Error>(())
/// ```
///
/// A region ([`Field::with_region`]) keeps the points inside it, and the
/// set maximal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Field<const N: usize, R = Everywhere> {
    lattice: Lattice<N>,
    radius: f64,
    seed: u64,
    max_window_bytes: u64,
    region: R,
}

/// One answered query with what it cost: see [`Field::query`].
#[derive(Clone, Debug, PartialEq)]
pub struct Query<const N: usize> {
    /// The points in the box, in [`field_order`].
    pub points: Vec<[f64; N]>,
    /// The halo that settled the box, in level-0 cells (side a little
    /// under `r/√N`) on each side.
    pub halo_cells: u64,
    /// The rounds the settling window ran.
    pub rounds: u32,
}

/// The canonical order of a field's points: lexicographic by coordinate,
/// the last axis first (`x[N-1]`, then `x[N-2]`, …). Every query returns its
/// points in this order, so the same points are the same bytes.
pub fn field_order<const N: usize>(a: &[f64; N], b: &[f64; N]) -> core::cmp::Ordering {
    for axis in (0..N).rev() {
        match a[axis].total_cmp(&b[axis]) {
            core::cmp::Ordering::Equal => {}
            other => return other,
        }
    }
    core::cmp::Ordering::Equal
}

fn check_radius(radius: f64) -> Result<(), Error> {
    if (MIN_RADIUS..=MAX_RADIUS).contains(&radius) {
        Ok(())
    } else {
        Err(Error::InvalidRadius)
    }
}

impl<const N: usize> Field<N> {
    /// The field on a box, each axis bounded or periodic as the domain
    /// says, with minimum distance `radius` and the given seed.
    ///
    /// # Errors
    /// [`Error::ZeroDimension`] if `N == 0`; [`Error::InvalidRadius`] if the
    /// radius is not finite and positive with a normal square (about
    /// `1e-150 ..= 1e150`); [`Error::BoxTooWide`] if the box spans more
    /// than 2⁴⁰ radii on some axis.
    pub fn new(domain: Domain<N>, radius: f64, seed: u64) -> Result<Self, Error> {
        if N == 0 {
            return Err(Error::ZeroDimension);
        }
        check_radius(radius)?;
        Ok(Self {
            lattice: Lattice::of_domain(&domain, radius)?,
            radius,
            seed,
            max_window_bytes: DEFAULT_MAX_WINDOW_CELLS_BYTES,
            region: Everywhere,
        })
    }

    /// The field on all of space: an endless world. Its lattice is anchored
    /// at the origin with a side that depends only on `radius`, so every
    /// box of any size or origin sees the same world.
    ///
    /// # Errors
    /// [`Error::ZeroDimension`] if `N == 0`; [`Error::InvalidRadius`] as
    /// for [`Field::new`].
    pub fn unbounded(radius: f64, seed: u64) -> Result<Self, Error> {
        if N == 0 {
            return Err(Error::ZeroDimension);
        }
        check_radius(radius)?;
        Ok(Self {
            lattice: Lattice::unbounded(radius),
            radius,
            seed,
            max_window_bytes: DEFAULT_MAX_WINDOW_CELLS_BYTES,
            region: Everywhere,
        })
    }

    /// The field restricted to a region: darts outside it are dropped and
    /// cells that do not meet it die, so the points lie in the region and
    /// every point of the region is within `r` of one of them (maximal
    /// there). The region is part of the set's definition, as the seed is:
    /// every query of the returned field sees the same points.
    ///
    /// Only a region a field can test boxes against will do
    /// ([`FieldRegion`]); a signed distance is the usual way to give one
    /// ([`SignedDistance`]).
    #[must_use]
    pub fn with_region<S: FieldRegion<N>>(self, region: S) -> Field<N, S> {
        Field {
            lattice: self.lattice,
            radius: self.radius,
            seed: self.seed,
            max_window_bytes: self.max_window_bytes,
            region,
        }
    }
}

impl<const N: usize, R: FieldRegion<N>> Field<N, R> {
    /// The same field with another memory budget for one query's window
    /// (default [`DEFAULT_MAX_WINDOW_CELLS_BYTES`], 1 GiB). It never
    /// changes the points, only which queries are refused. A query is
    /// refused before it starts if its window's level-0 cells, at a size
    /// each that covers the measured peaks, exceed it, and stops if its
    /// rounds' heap outgrows it. Chunks of 64 `r` take about 10 MB each in
    /// 2-D and 460 MB in 3-D.
    #[must_use]
    pub fn with_max_window_bytes(mut self, bytes: u64) -> Self {
        self.max_window_bytes = bytes;
        self
    }

    /// The field's region ([`Everywhere`] unless [`Field::with_region`]
    /// gave one).
    pub fn region(&self) -> &R {
        &self.region
    }

    /// The minimum distance `r`.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The box of a bounded or periodic field (`None` when unbounded).
    pub fn domain(&self) -> Option<([f64; N], [f64; N])> {
        let mut lo = [0.0; N];
        let mut hi = [0.0; N];
        for axis in 0..N {
            match self.lattice.axes[axis] {
                Axis::Bounded { lo: l, hi: h, .. } | Axis::Periodic { lo: l, hi: h, .. } => {
                    lo[axis] = l;
                    hi[axis] = h;
                }
                Axis::Unbounded => return None,
            }
        }
        Some((lo, hi))
    }

    /// Every point of a bounded or periodic field, in [`field_order`].
    ///
    /// # Errors
    /// [`Error::EmptyBox`] `{ axis: 0 }` for an unbounded field (ask for a
    /// box with [`Field::points_in`]); [`Error::GridTooLarge`] if the box's
    /// window is over the memory budget.
    pub fn points(&self) -> Result<Vec<[f64; N]>, Error> {
        let (lo, hi) = self.domain().ok_or(Error::EmptyBox { axis: 0 })?;
        self.points_in(lo, hi)
    }

    /// The points in the half-open box `lo <= x < hi`, in [`field_order`]:
    /// exactly the whole set's points there.
    ///
    /// # Errors
    /// As [`Field::query`].
    pub fn points_in(&self, lo: [f64; N], hi: [f64; N]) -> Result<Vec<[f64; N]>, Error> {
        Ok(self.query(lo, hi)?.points)
    }

    /// The points in the half-open box `lo <= x < hi` with what they cost:
    /// the halo that settled them and the rounds run.
    ///
    /// # Errors
    /// [`Error::NonFiniteBound`] if a bound is NaN or infinite;
    /// [`Error::EmptyBox`] if `lo >= hi` on some axis (an empty box is an
    /// error, not an empty answer, as for [`Domain::new`]);
    /// [`Error::BoxTooWide`] if the box reaches more than about 2⁴⁰ radii
    /// from the lattice's origin; [`Error::GridTooLarge`] if the window the
    /// query needs is over the memory budget (ask in smaller boxes, see
    /// [`Field::points_in_parallel`]), or if its live cells outgrow the
    /// budget, which only a region of (nearly) zero volume makes happen
    /// ([`FieldRegion::meets`]).
    pub fn query(&self, lo: [f64; N], hi: [f64; N]) -> Result<Query<N>, Error> {
        for axis in 0..N {
            if !lo[axis].is_finite() || !hi[axis].is_finite() {
                return Err(Error::NonFiniteBound { axis });
            }
            if lo[axis] >= hi[axis] {
                return Err(Error::EmptyBox { axis });
            }
        }
        let (qa, qb) = self
            .lattice
            .cells_of(&lo, &hi)
            .ok_or(Error::BoxTooWide { axis: 0 })?;
        let mut halo = start_halo(N);
        loop {
            self.check_window(&qa, &qb, halo)?;
            let run = window::run(self.window_job(&qa, &qb, halo))?;
            if let Some(mut points) = run.points {
                points.retain(|p| (0..N).all(|a| lo[a] <= p[a] && p[a] < hi[a]));
                points.sort_by(field_order);
                return Ok(Query {
                    points,
                    halo_cells: u64::try_from(halo).unwrap_or(u64::MAX),
                    rounds: run.rounds,
                });
            }
            halo = halo.saturating_mul(2);
        }
    }

    /// Whether a window of `halo` level-0 cells around the box settles it,
    /// and after how many rounds (`None`: an unknown reached the box). For
    /// measuring the halo's distribution (`examples/field_study.rs`); the
    /// points are those of [`Field::query`].
    ///
    /// # Errors
    /// As [`Field::query`].
    #[doc(hidden)]
    pub fn settles_with_halo(
        &self,
        lo: [f64; N],
        hi: [f64; N],
        halo: u32,
    ) -> Result<Option<u32>, Error> {
        let (qa, qb) = self
            .lattice
            .cells_of(&lo, &hi)
            .ok_or(Error::BoxTooWide { axis: 0 })?;
        let halo = i64::from(halo);
        self.check_window(&qa, &qb, halo)?;
        let run = window::run(self.window_job(&qa, &qb, halo))?;
        Ok(run.points.map(|_| run.rounds))
    }

    /// What one window run needs to know.
    fn window_job<'a>(
        &'a self,
        qa: &'a [i64; N],
        qb: &'a [i64; N],
        halo: i64,
    ) -> window::Job<'a, N, R> {
        window::Job {
            lat: &self.lattice,
            radius: self.radius,
            seed: self.seed,
            region: &self.region,
            qa,
            qb,
            margin: halo,
            max_bytes: self.max_window_bytes,
        }
    }

    /// Checks the window of cells `[qa, qb)` grown by `halo` against the
    /// budget.
    fn check_window(&self, qa: &[i64; N], qb: &[i64; N], halo: i64) -> Result<(), Error> {
        let mut cells: u64 = 1;
        for axis in 0..N {
            let mut len = (qb[axis] - qa[axis]).saturating_add(halo.saturating_mul(2));
            match self.lattice.axes[axis] {
                Axis::Bounded { n, .. } | Axis::Periodic { n, .. } => len = len.min(n),
                Axis::Unbounded => {}
            }
            cells = cells.saturating_mul(u64::try_from(len).unwrap_or(u64::MAX));
        }
        let needed = cells.saturating_mul(bytes_per_cell(N));
        if needed > self.max_window_bytes || cells >= u64::from(u32::MAX) {
            return Err(Error::GridTooLarge {
                needed,
                budget: self.max_window_bytes,
            });
        }
        Ok(())
    }
}
