//! The sampler: Bridson's algorithm, configured and validated up front, run
//! lazily as an iterator.

use crate::annulus::{CandidateSampler, Candidates};
use crate::domain::Domain;
use crate::error::Error;
use crate::grid::{DEFAULT_MAX_GRID_BYTES, Grid, GridLayout, GridPlan, NeighbourGrid, plan};
use crate::random::{DefaultRng, below, seeded_rng, unit};
use crate::vector::{add, all_finite};
use core::iter::FusedIterator;
use rand::Rng;

/// The number of attempts per active point used unless told otherwise:
/// Bridson's `k = 30`.
pub const DEFAULT_ATTEMPTS: u32 = 30;

/// Smallest and largest radius accepted: beyond them `r²` (or the squared
/// distances compared with it) is no longer a normal `f64`.
const MIN_RADIUS: f64 = 1e-150;
const MAX_RADIUS: f64 = 1e150;

/// A validated Poisson disk sampler in `N` dimensions: domain, radius,
/// attempts, candidate distribution and grid choice.
///
/// Build it with [`PoissonDisk::new`] and the `with_*` methods (each checks
/// its input), then draw points with [`iter`](Self::iter) /
/// [`iter_seeded`](Self::iter_seeded) or collect them with
/// [`generate`](Self::generate) / [`generate_seeded`](Self::generate_seeded).
///
/// `N` is a const parameter: points are `[f64; N]`. The aliases
/// [`PoissonDisk2`] and [`PoissonDisk3`] name the common cases.
///
/// # Example: a periodic 3-D tile with the on-sphere candidates
/// ```
/// use bridson::{Candidates, Domain, PoissonDisk3};
/// let domain = Domain::from_extent([1.0, 1.0, 1.0])?.with_periodic([true; 3]);
/// let sampler = PoissonDisk3::new(domain, 0.2)?
///     .with_attempts(20)?
///     .with_candidates(Candidates::Sphere);
/// let points = sampler.generate_seeded(42);
/// assert!(points.len() > 50);
/// assert!(points.iter().all(|p| domain.contains(p)));
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(try_from = "PoissonDiskRepr<N>"))]
pub struct PoissonDisk<const N: usize> {
    domain: Domain<N>,
    radius: f64,
    attempts: u32,
    candidates: Candidates,
    layout: GridLayout,
    max_grid_bytes: u64,
    max_points: Option<u64>,
    #[cfg_attr(feature = "serde", serde(skip_serializing))]
    plan: GridPlan<N>,
}

/// A sampler in the plane.
pub type PoissonDisk2 = PoissonDisk<2>;
/// A sampler in space.
pub type PoissonDisk3 = PoissonDisk<3>;

impl<const N: usize> PoissonDisk<N> {
    /// A sampler of `domain` with minimum distance `radius`, `k = 30`
    /// annulus candidates, automatic grid layout and the default 1 GiB grid
    /// budget ([`DEFAULT_MAX_GRID_BYTES`](crate::DEFAULT_MAX_GRID_BYTES)).
    ///
    /// # Errors
    /// [`Error::InvalidRadius`] if `radius` is NaN, infinite, `<= 0` or
    /// outside `1e-150 ..= 1e150`; [`Error::GridTooLarge`] if no grid fits
    /// the budget (a tiny radius in a huge box: cap the points with
    /// [`with_max_points`](Self::with_max_points) or raise the budget).
    pub fn new(domain: Domain<N>, radius: f64) -> Result<Self, Error> {
        Self::validated(
            domain,
            radius,
            DEFAULT_ATTEMPTS,
            Candidates::default(),
            GridLayout::default(),
            DEFAULT_MAX_GRID_BYTES,
            None,
        )
    }

    fn validated(
        domain: Domain<N>,
        radius: f64,
        attempts: u32,
        candidates: Candidates,
        layout: GridLayout,
        max_grid_bytes: u64,
        max_points: Option<u64>,
    ) -> Result<Self, Error> {
        if N == 0 {
            return Err(Error::ZeroDimension);
        }
        // Re-checked here because deserialisation can build a Domain too.
        let domain = Domain::new(domain.lo(), domain.hi())?.with_periodic(domain.periodic());
        if !(MIN_RADIUS..=MAX_RADIUS).contains(&radius) {
            return Err(Error::InvalidRadius);
        }
        if attempts == 0 {
            return Err(Error::ZeroAttempts);
        }
        let plan = plan(&domain, radius, layout, max_grid_bytes, max_points)?;
        Ok(Self {
            domain,
            radius,
            attempts,
            candidates,
            layout,
            max_grid_bytes,
            max_points,
            plan,
        })
    }

    fn revalidated(self) -> Result<Self, Error> {
        Self::validated(
            self.domain,
            self.radius,
            self.attempts,
            self.candidates,
            self.layout,
            self.max_grid_bytes,
            self.max_points,
        )
    }

    /// Sets `k`, the attempts around an active point before it retires.
    /// More attempts pack denser and cost more; 30 is Bridson's choice.
    ///
    /// # Errors
    /// [`Error::ZeroAttempts`] if `k == 0`.
    pub fn with_attempts(mut self, k: u32) -> Result<Self, Error> {
        self.attempts = k;
        self.revalidated()
    }

    /// Sets how candidates are drawn (see [`Candidates`]).
    #[must_use]
    pub fn with_candidates(mut self, candidates: Candidates) -> Self {
        self.candidates = candidates;
        self
    }

    /// Chooses the grid layout (see [`GridLayout`]). The layout changes
    /// speed and memory, never the points: both search exactly.
    ///
    /// # Errors
    /// [`Error::GridTooLarge`] if the chosen layout does not fit the budget.
    pub fn with_layout(mut self, layout: GridLayout) -> Result<Self, Error> {
        self.layout = layout;
        self.revalidated()
    }

    /// Sets the memory budget of the background grid, in bytes.
    ///
    /// # Errors
    /// [`Error::GridTooLarge`] if no layout fits the new budget.
    pub fn with_max_grid_bytes(mut self, bytes: u64) -> Result<Self, Error> {
        self.max_grid_bytes = bytes;
        self.revalidated()
    }

    /// Stops after `cap` points (`None`: until the domain is full). A cap
    /// also bounds the sparse grid's memory, so it can make a huge domain
    /// feasible.
    ///
    /// # Errors
    /// [`Error::GridTooLarge`] if no layout fits the budget even so.
    pub fn with_max_points(mut self, cap: Option<u64>) -> Result<Self, Error> {
        self.max_points = cap;
        self.revalidated()
    }

    /// The domain.
    pub fn domain(&self) -> &Domain<N> {
        &self.domain
    }

    /// The minimum distance between points.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The attempts `k`.
    pub fn attempts(&self) -> u32 {
        self.attempts
    }

    /// The candidate distribution.
    pub fn candidates(&self) -> Candidates {
        self.candidates
    }

    /// The layout asked for (possibly [`GridLayout::Auto`]).
    pub fn layout(&self) -> GridLayout {
        self.layout
    }

    /// The layout that will be built: [`GridLayout::Dense`] or
    /// [`GridLayout::Sparse`].
    pub fn resolved_layout(&self) -> GridLayout {
        match self.plan {
            GridPlan::Dense(_) => GridLayout::Dense,
            GridPlan::Sparse(_) => GridLayout::Sparse,
        }
    }

    /// The grid memory budget, in bytes.
    pub fn max_grid_bytes(&self) -> u64 {
        self.max_grid_bytes
    }

    /// The point cap.
    pub fn max_points(&self) -> Option<u64> {
        self.max_points
    }

    /// The planned size of the background grid in bytes: exact for the
    /// dense layout, an upper bound for the sparse one.
    pub fn grid_bytes(&self) -> u64 {
        match self.plan {
            GridPlan::Dense(d) => d.bytes,
            GridPlan::Sparse(s) => s.bytes,
        }
    }

    /// Points in generation order, drawn from `rng`. Pass `&mut rng` to
    /// keep using your generator afterwards.
    ///
    /// The grid is allocated here. Should the dense allocation fail, the
    /// sampler falls back to the sparse layout (same points) rather than
    /// abort.
    pub fn iter<R: Rng>(&self, rng: R) -> Iter<N, R> {
        Iter {
            rng,
            domain: self.domain,
            grid: Grid::build(&self.plan, &self.domain, self.radius),
            active: Vec::new(),
            candidates: CandidateSampler::new(self.candidates, self.radius, self.attempts),
            attempts: self.attempts,
            remaining: self.max_points.map_or(u64::MAX, |c| c),
            started: false,
        }
    }

    /// Points in generation order from [`DefaultRng`] seeded with `seed`:
    /// the same seed gives the same points on every run and platform.
    pub fn iter_seeded(&self, seed: u64) -> Iter<N, DefaultRng> {
        self.iter(seeded_rng(seed))
    }

    /// All points, drawn from `rng`.
    pub fn generate<R: Rng>(&self, rng: R) -> Vec<[f64; N]> {
        self.iter(rng).collect()
    }

    /// All points for `seed` (see [`iter_seeded`](Self::iter_seeded)).
    pub fn generate_seeded(&self, seed: u64) -> Vec<[f64; N]> {
        self.iter_seeded(seed).collect()
    }
}

/// The unchecked form read by serde before validation.
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
#[serde(rename = "PoissonDisk")]
struct PoissonDiskRepr<const N: usize> {
    domain: Domain<N>,
    radius: f64,
    #[serde(default = "default_attempts")]
    attempts: u32,
    #[serde(default)]
    candidates: Candidates,
    #[serde(default)]
    layout: GridLayout,
    #[serde(default = "default_budget")]
    max_grid_bytes: u64,
    #[serde(default)]
    max_points: Option<u64>,
}

#[cfg(feature = "serde")]
fn default_attempts() -> u32 {
    DEFAULT_ATTEMPTS
}

#[cfg(feature = "serde")]
fn default_budget() -> u64 {
    DEFAULT_MAX_GRID_BYTES
}

#[cfg(feature = "serde")]
impl<const N: usize> TryFrom<PoissonDiskRepr<N>> for PoissonDisk<N> {
    type Error = Error;
    fn try_from(raw: PoissonDiskRepr<N>) -> Result<Self, Error> {
        Self::validated(
            raw.domain,
            raw.radius,
            raw.attempts,
            raw.candidates,
            raw.layout,
            raw.max_grid_bytes,
            raw.max_points,
        )
    }
}

/// The lazy point stream of a [`PoissonDisk`]: yields each point as soon as
/// it is accepted, in generation order.
///
/// Ends when no active point is left (the domain is full, to `k` attempts)
/// or the point cap is reached; stays ended ([`FusedIterator`]).
#[derive(Debug)]
pub struct Iter<const N: usize, R> {
    rng: R,
    domain: Domain<N>,
    grid: Grid<N>,
    /// Points that may still have room around them, stored inline.
    active: Vec<[f64; N]>,
    candidates: CandidateSampler<N>,
    attempts: u32,
    remaining: u64,
    started: bool,
}

impl<const N: usize, R: Rng> Iterator for Iter<N, R> {
    type Item = [f64; N];

    fn next(&mut self) -> Option<[f64; N]> {
        if self.remaining == 0 {
            return None;
        }
        let point = if self.started {
            let Self {
                rng,
                domain,
                grid,
                active,
                candidates,
                attempts,
                ..
            } = self;
            let state = State {
                rng,
                domain,
                active,
                candidates,
                attempts: *attempts,
            };
            match grid {
                Grid::Dense(g) => state.grow(g),
                Grid::Sparse(g) => state.grow(g),
            }
        } else {
            self.started = true;
            let first = first_point(&self.domain, &mut self.rng);
            let stored = match &mut self.grid {
                Grid::Dense(g) => g.insert(first),
                Grid::Sparse(g) => g.insert(first),
            };
            stored.then(|| {
                self.active.push(first);
                first
            })
        }?;
        self.remaining -= 1;
        Some(point)
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        if self.remaining == 0 || (self.started && self.active.is_empty()) {
            (0, Some(0))
        } else {
            (0, usize::try_from(self.remaining).ok())
        }
    }
}

impl<const N: usize, R: Rng> FusedIterator for Iter<N, R> {}

/// The parts of [`Iter`] the growth loop mutates, borrowed apart from the
/// grid so the loop can be monomorphised per grid layout.
struct State<'a, const N: usize, R> {
    rng: &'a mut R,
    domain: &'a Domain<N>,
    active: &'a mut Vec<[f64; N]>,
    candidates: &'a CandidateSampler<N>,
    attempts: u32,
}

impl<const N: usize, R: Rng> State<'_, N, R> {
    /// Bridson's loop, up to the next accepted point: pick a random active
    /// point, throw up to `k` candidates around it, keep the first that is
    /// at least `r` from every point; if none is, retire the active point.
    #[inline(always)]
    fn grow<G: NeighbourGrid<N>>(self, grid: &mut G) -> Option<[f64; N]> {
        while !self.active.is_empty() {
            let i = below(self.rng, self.active.len());
            let parent = *self.active.get(i)?;
            let mut state = self.candidates.start(self.rng);
            for _ in 0..self.attempts {
                let offset = self.candidates.offset(self.rng, &mut state);
                let mut candidate = add(&parent, &offset);
                if !self.domain.wrap(&mut candidate) || grid.conflicts(&candidate) {
                    continue;
                }
                if grid.insert(candidate) {
                    self.active.push(candidate);
                    return Some(candidate);
                }
            }
            self.active.swap_remove(i);
        }
        None
    }
}

/// A uniform point in the half-open box. Rounding can carry `lo + u·L` up
/// to `hi`; such draws are repeated (at most 64 times, then `lo` is used).
fn first_point<const N: usize, R: Rng + ?Sized>(domain: &Domain<N>, rng: &mut R) -> [f64; N] {
    let (lo, extent) = (domain.lo(), domain.extent());
    for _ in 0..64 {
        let p: [f64; N] = core::array::from_fn(|i| lo[i] + unit(rng) * extent[i]);
        if all_finite(&p) && domain.contains(&p) {
            return p;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cap_stops_the_stream() {
        let s = PoissonDisk2::new(Domain::from_extent([1.0, 1.0]).unwrap(), 0.01)
            .unwrap()
            .with_max_points(Some(10))
            .unwrap();
        let mut it = s.iter_seeded(1);
        assert_eq!(it.by_ref().count(), 10, "cap");
        assert_eq!(it.next(), None, "fused");
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
