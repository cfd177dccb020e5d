//! The background grid: which layout, how big, and which neighbour cells a
//! candidate must be checked against.
//!
//! Three layouts implement [`NeighbourGrid`]:
//! - [`dense::Dense`]: Bridson's grid of cells of side `<= r/√N`, each
//!   holding the `u32` index of at most one point. Fast, memory ∝ box
//!   volume (4 bytes a cell) plus the points.
//! - [`bricks::Bricks`]: the same cells in 3-D, grouped in bricks of
//!   4×4×4; a brick is a 64-bit mask of its occupied cells followed by
//!   their points in cell order (up to 13, the rest in a spill chunk), so
//!   there is no per-cell array and a search's cache lines are few and
//!   known from its cell. About 5 bytes a cell, the points included. Used
//!   for [`GridLayout::Dense`] in 3-D wherever it fits the budget, the
//!   `u32` grid otherwise.
//! - [`paged::Paged`]: the `u32` cells in pages of `2^shift` cells a side,
//!   each with a halo copying its neighbours' edges, allocated where points
//!   land. Memory ∝ number of points (plus partly used edge pages). Chosen
//!   by [`GridLayout::Auto`] in bounded boxes where the dense grid would not
//!   fit the budget.
//! - [`paged_bricks::PagedBricks`]: the paged grid in 3-D (a reach of 2):
//!   the bricks, in pages of 8×8×8 bricks allocated where points land,
//!   with no halo.
//! - [`sparse::Sparse`]: a hash map (or an array of heads) from cells of
//!   side `≈ r` to the points in them. Memory ∝ number of points, whatever
//!   the box. Chosen by [`GridLayout::Auto`] from 4-D up, and where neither
//!   the dense grid nor pages apply.
//!
//! # Why the search reach is never a fixed ±2 cells
//! A point within `r` of a candidate can lie up to `ceil(r / side)` cells
//! away on each axis (3 for `N = 5..=8` with side `r/√N`), and rounding in
//! the cell index can move a point by one cell when it sits within a few
//! ulps of a cell face. Every cell count here is derived from `r`, the cell
//! side and a margin `η` (in cells) that bounds that rounding, so a point
//! closer than `r` is always found.

pub(crate) mod bricks;
pub(crate) mod dense;
pub(crate) mod paged;
pub(crate) mod paged_bricks;
pub(crate) mod sparse;

use crate::domain::Domain;
use crate::error::Error;
use crate::vector::unit_ball_volume;

/// Which background grid layout the sampler uses. With the `serde` feature
/// the values are `"auto"`, `"dense"` and `"sparse"`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
#[non_exhaustive]
pub enum GridLayout {
    /// Dense when `N <= 3` and the dense grid fits the memory budget;
    /// else [`Paged`](Self::Paged) in a bounded box; otherwise sparse.
    /// From 4-D up the dense grid's neighbourhood (504
    /// cells a check in 4-D, thousands from 5-D) costs more time and
    /// memory than the sparse grid's search (the journal's "Sparse grid
    /// from 4-D up" has the measurements).
    #[default]
    Auto,
    /// Bridson's dense grid; an error if it does not fit the budget.
    Dense,
    /// The sparse hash grid; memory grows with the number of points.
    Sparse,
    /// Bridson's dense cells, allocated in pages where the points land
    /// (1-D to 3-D, bounded boxes only; elsewhere `build()` returns
    /// [`Error::GridTooLarge`] with `needed: u64::MAX`): memory grows with
    /// the points, not the box. What [`Auto`](Self::Auto) takes in 2-D and
    /// 3-D where the dense grid does not fit the budget and no axis is
    /// periodic.
    Paged,
}

/// The default memory budget for the background grid: 1 GiB.
pub const DEFAULT_MAX_GRID_BYTES: u64 = 1 << 30;

/// The largest cell count allowed on one axis. Beyond it an `f64` cell index
/// is too coarse for the rounding margin to stay below a small fraction of a
/// cell.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 40) as f64;

/// Everything needed to build a grid, decided (and validated) up front.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum GridPlan<const N: usize> {
    Dense(DensePlan<N>),
    Paged(paged::PagedPlan<N>),
    Sparse(SparsePlan<N>),
}

/// Geometry of a dense grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DensePlan<const N: usize> {
    pub(crate) cells: [usize; N],
    pub(crate) side: [f64; N],
    pub(crate) reach: [usize; N],
    pub(crate) eta: f64,
    /// Whether the cells are laid out in bricks with their points
    /// ([`bricks::Bricks`], 3-D) rather than as `u32` indices
    /// ([`dense::Dense`]).
    pub(crate) bricked: bool,
    /// What the grid allocates before its first point: the padded cells
    /// and the search stencils (a bound on their peak while built), plus
    /// the first point and its active entry.
    pub(crate) bytes: u64,
    /// [`bytes`](Self::bytes) plus the points the box could hold at most
    /// (the packing bound, or the cap), doubled for the growth of the point
    /// vector and the active list: the worst case, which [`peak`](Self::peak)
    /// falls back on where the density model has no answer.
    pub(crate) bytes_when_full: u64,
    /// The point cap, if any.
    pub(crate) max_points: Option<u64>,
    /// The images a point has in the padding on average: the padded
    /// cells over the box's own on the periodic axes, less one. Bricks
    /// store a point again for each image; `u32` cells only an index.
    pub(crate) images_per_point: f64,
}

/// The planned count over the density model's mean: the model's mean is
/// within 2 % of the count in 2-D and 3-D, a single run scatters about 1 %
/// around it at 1 000 points (less above), so 5 % covers both with room.
/// With a budget of exactly the planned peak, 0 of 800 runs stopped (200
/// seeds each of 2-D `r = 0.002` and 3-D `r = 0.02`, bounded and periodic:
/// `cargo test --release --lib -- --ignored --nocapture budget_stops`).
pub(crate) const EXPECTED_MARGIN: f64 = 1.05;

/// Bytes a point adds to a dense run's peak, in points' worth (`8·N`
/// bytes), beyond what the grid allocates up front, besides the point
/// vector (see [`DensePlan::peak`]): the active list, and in 3-D the bricks'
/// spill. The active list's capacity reaches about 0.2 points' worth on
/// a million 3-D points and 0.35 on a few thousand (a larger share of them
/// near the faces); the planning tests in `sampler.rs` hold the plan above
/// the peaks runs reach.
const ACTIVE_PER_POINT: f64 = 0.5;

impl<const N: usize> DensePlan<N> {
    /// The peak heap a run on this plan is expected to reach, the figure
    /// [`GridLayout::Auto`] holds against the budget: the bytes allocated up
    /// front plus the expected points (the density model's mean with
    /// [`EXPECTED_MARGIN`], or the cap if lower) at their bytes per point.
    /// With `u32` cells the point vector counts two points' worth a point:
    /// the budget counts its old and new block together while it grows, and
    /// lets it grow by less than double near the limit, so twice the final
    /// length always suffices; the bricks hold their points in the bytes
    /// allocated up front. On top, [`ACTIVE_PER_POINT`].
    /// Where the model has no answer (`expected` is `None`) the worst case,
    /// [`bytes_when_full`](Self::bytes_when_full).
    pub(crate) fn peak(&self, expected: Option<f64>) -> u64 {
        let Some(mean) = expected.filter(|n| n.is_finite() && *n >= 0.0) else {
            return self.bytes_when_full;
        };
        let mut points = (mean * EXPECTED_MARGIN).ceil() + 1.0;
        if let Some(cap) = self.max_points {
            points = points.min(to_f64(cap) + 1.0);
        }
        let per_point = if self.bricked {
            self.images_per_point
        } else {
            2.0
        } + ACTIVE_PER_POINT;
        #[expect(clippy::cast_precision_loss, reason = "N is small")]
        let bytes = points * per_point * (8 * N) as f64;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "finite and positive; saturates at u64::MAX"
        )]
        let extra = bytes.ceil().min(u64::MAX as f64) as u64;
        self.bytes.saturating_add(extra).min(self.bytes_when_full)
    }
}

/// Geometry of a sparse grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SparsePlan<const N: usize> {
    pub(crate) cells: [i64; N],
    pub(crate) side: [f64; N],
    pub(crate) reach: [i64; N],
    pub(crate) eta: f64,
    /// Whether the cells' lists start from an array of every cell (a
    /// small box in cells) rather than a hash table of the occupied ones.
    pub(crate) array: bool,
    /// What the grid allocates before its first point (the array, if any)
    /// and what the first point costs (with the hash table, its smallest
    /// table), plus one active entry.
    pub(crate) bytes: u64,
}

/// What the sampler needs of a grid.
pub(crate) trait NeighbourGrid<const N: usize> {
    /// A stored point closer than `r` to `p` (which lies in the domain), if
    /// any: the first one found, which the sampler remembers (see
    /// `conflict_cache.rs`). Exact: compares squared distances summed in axis
    /// order.
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]>;
    /// Hands up to `limit` stored points near `p` to `take`, nearest cells
    /// first, where the grid finds them cheaply; by default none. (The
    /// sampler seeds its per-pick cache with them.)
    fn seed(&self, _p: &[f64; N], _limit: usize, _take: impl FnMut(&[f64; N])) {}
    /// Whether [`seed`](Self::seed) reads out to `2r` in 2-D (about 14
    /// points, where the search stencil holds about 6): the sampler then
    /// keeps 16 conflicts a pick instead of 8.
    const WIDE_SEED: bool = false;
    /// Starts loading the cells [`seed`](Self::seed) will read around `p`;
    /// a hint only, by default nothing.
    fn prefetch(&self, _p: &[f64; N]) {}
    /// The heap bytes the grid holds now (see `budget.rs`).
    fn bytes(&self) -> u64;
    /// Makes room to [`insert`](Self::insert) `p` without allocating, if
    /// the growth fits in `spare` more bytes at its peak; `false` if not.
    fn reserve(&mut self, p: &[f64; N], spare: u64) -> bool;
    /// Stores `p`; returns `false` (and stores nothing) if the layout has no
    /// room for it, which the sampler treats as a failed attempt.
    /// [`reserve`](Self::reserve) comes first: this never allocates more
    /// than it allowed for.
    fn insert(&mut self, p: [f64; N]) -> bool;
}

/// Rounding margin, in cells, for an index computed as
/// `floor((x - lo) * (1/side))` on a grid of at most `max_cells` cells per
/// axis: a few relative roundings of a value `<= max_cells`, doubled because
/// both points of a pair can be off, plus a floor for the stencil test's own
/// rounding.
pub(crate) fn rounding_margin(max_cells: f64) -> f64 {
    64.0 * f64::EPSILON * (max_cells + 4.0) + 1e-9
}

/// Cell count along one axis, or `None` if past [`MAX_CELLS_PER_AXIS`].
fn cell_count(cells: f64) -> Option<u64> {
    if cells.is_finite() && cells <= MAX_CELLS_PER_AXIS {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a finite value in 0..=2^40 converts exactly"
        )]
        let n = cells as u64;
        Some(n.max(1))
    } else {
        None
    }
}

fn to_f64(n: u64) -> f64 {
    #[expect(
        clippy::cast_precision_loss,
        reason = "cell counts are <= 2^40 and convert exactly"
    )]
    let x = n as f64;
    x
}

/// The dense grid's cells: their count and side on each axis, the
/// rounding margin `η`, and the search reach. Shared by the dense plan and
/// the paged one; `Err(u64::MAX)` past [`MAX_CELLS_PER_AXIS`].
struct Cells<const N: usize> {
    counts: [u64; N],
    side: [f64; N],
    eta: f64,
    reach: [usize; N],
}

fn dense_cells<const N: usize>(domain: &Domain<N>, radius: f64) -> Result<Cells<N>, u64> {
    let extent = domain.extent();
    #[expect(clippy::cast_precision_loss, reason = "N is small")]
    let max_side = radius / (N as f64).sqrt();
    let mut counts = [0u64; N];
    let mut side = [0.0; N];
    for ((count, s), &e) in counts.iter_mut().zip(&mut side).zip(&extent) {
        let mut m = cell_count((e / max_side).ceil()).ok_or(u64::MAX)?;
        // Division can round the side up past r/√N; one more cell fixes it.
        if e / to_f64(m) > max_side {
            m = m.checked_add(1).ok_or(u64::MAX)?;
        }
        *count = m;
        *s = e / to_f64(m);
    }
    let max_cells = counts.iter().copied().max().unwrap_or(1);
    let eta = rounding_margin(to_f64(max_cells));
    let mut reach = [0usize; N];
    let axes = side.iter().zip(&counts).zip(domain.periodic());
    for (r, ((&s, &m), periodic)) in reach.iter_mut().zip(axes) {
        // Cells at |d| are needed while (|d| - 1 - η)·side < r, up to what
        // the axis holds: on a bounded axis two cells of the box are at
        // most `m - 1` apart; on a periodic one every cell has an image
        // within `m` (see `bounded_reach`).
        let p = bounded_reach(needed_reach(radius, s, eta), m, periodic);
        *r = usize::try_from(p).map_err(|_| u64::MAX)?;
    }
    Ok(Cells {
        counts,
        side,
        eta,
        reach,
    })
}

/// The paged grid's plan (bounded boxes, 1-D to 3-D), or `u64::MAX` if
/// it cannot exist.
fn plan_paged<const N: usize>(
    domain: &Domain<N>,
    radius: f64,
    max_points: Option<u64>,
    budget: u64,
) -> Result<paged::PagedPlan<N>, u64> {
    if N > 3 || domain.any_periodic() {
        return Err(u64::MAX);
    }
    let Cells {
        counts,
        side,
        eta,
        reach,
    } = dense_cells(domain, radius)?;
    let mut cells = [0usize; N];
    for (c, &m) in cells.iter_mut().zip(&counts) {
        *c = usize::try_from(m).map_err(|_| u64::MAX)?;
    }
    // `u32` point indices, as the dense grid's: the box (at the packing
    // bound), the cap or the budget (at 8 bytes a coordinate) must keep
    // the points below 2³² - 1, or the sparse grid takes the run.
    let mut most = ln_max_points(domain, radius)
        .exp()
        .min(to_f64(budget / (8 * N as u64).max(1)));
    if let Some(cap) = max_points {
        most = most.min(to_f64(cap));
    }
    if most >= f64::from(u32::MAX) {
        return Err(u64::MAX);
    }
    let dense = DensePlan {
        cells,
        side,
        reach,
        eta,
        bricked: false,
        bytes: 0,
        bytes_when_full: u64::MAX,
        max_points,
        images_per_point: 0.0,
    };
    paged::PagedPlan::new(dense, budget).ok_or(u64::MAX)
}

/// Dense geometry and size, or the bytes it would need if it cannot exist.
fn plan_dense<const N: usize>(
    domain: &Domain<N>,
    radius: f64,
    max_points: Option<u64>,
    bricked: bool,
) -> Result<DensePlan<N>, u64> {
    let Cells {
        counts,
        side,
        eta,
        reach,
    } = dense_cells(domain, radius)?;
    let mut padded_cells = [0u64; N];
    let mut total: u64 = 1;
    let mut window: u64 = 1;
    for ((padded_axis, &p), &m) in padded_cells.iter_mut().zip(&reach).zip(&counts) {
        let side_cells = u64::try_from(p)
            .ok()
            .and_then(|p| p.checked_mul(2))
            .ok_or(u64::MAX)?;
        let padded = m.checked_add(side_cells).ok_or(u64::MAX)?;
        *padded_axis = padded;
        total = total.checked_mul(padded).ok_or(u64::MAX)?;
        window = window.checked_mul(side_cells + 1).ok_or(u64::MAX)?;
    }
    // Cells hold u32 indices, or bricks hold the cells and their points.
    let cell_bytes = if bricked {
        bricks::bytes_for(&padded_cells).ok_or(u64::MAX)?
    } else {
        total.checked_mul(4).ok_or(u64::MAX)?
    };
    let stencil_bytes = window
        .checked_mul(dense::stencil_bytes_per_cell(N))
        .ok_or(u64::MAX)?;
    let point = (8 * N) as u64;
    // The sentinel and the first point, and the first active entry.
    let bytes = cell_bytes
        .checked_add(stencil_bytes)
        .and_then(|b| b.checked_add(3 * point))
        .ok_or(u64::MAX)?;
    let inner: f64 = counts.iter().map(|&m| to_f64(m)).product();
    let mut points = ln_max_points(domain, radius).exp().min(inner);
    // u32 indices, with 0 reserved for the empty sentinel. Past that, or
    // past the address space, no budget makes a dense grid possible: report
    // it as `u64::MAX` like every other impossible grid, never as `bytes`,
    // which can be within the budget.
    if points >= f64::from(u32::MAX) {
        return Err(u64::MAX);
    }
    let cells = counts.map(|m| usize::try_from(m).unwrap_or(usize::MAX));
    if cells.contains(&usize::MAX) || usize::try_from(total).is_err() {
        return Err(u64::MAX);
    }
    if let Some(cap) = max_points {
        points = points.min(to_f64(cap));
    }
    // Points and active entries, each vector up to twice its length.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "finite, positive and below u32::MAX (checked above)"
    )]
    let when_full = (points.ceil() as u64 + 1).saturating_mul(4 * point);
    Ok(DensePlan {
        cells,
        side,
        reach,
        eta,
        bricked,
        bytes,
        bytes_when_full: bytes.saturating_add(when_full),
        max_points,
        images_per_point: images_per_point(&counts, &padded_cells, domain),
    })
}

/// The padded cells over the box's own on the periodic axes, less one:
/// how many images a point has in the padding on average.
fn images_per_point<const N: usize>(
    counts: &[u64; N],
    padded: &[u64; N],
    domain: &Domain<N>,
) -> f64 {
    let mut ratio = 1.0;
    for ((&m, &p), periodic) in counts.iter().zip(padded).zip(domain.periodic()) {
        if periodic {
            ratio *= to_f64(p) / to_f64(m);
        }
    }
    ratio - 1.0
}

/// Cells on each side that can hold a point closer than `radius` to a
/// point of the centre cell, on an axis of cells of side `side`: while
/// `(|d| - 1 - η)·side < r`. Saturates at `u64::MAX` (cut by
/// [`bounded_reach`]).
fn needed_reach(radius: f64, side: f64, eta: f64) -> u64 {
    cell_count((radius / side + eta).ceil()).unwrap_or(u64::MAX)
}

/// The search reach on an axis of `m` cells, given the reach `r` calls
/// for. A bounded axis needs at most `m - 1`: cells of the box are no
/// further apart. A periodic axis needs at most `m`: a point's nearest
/// image is within half a period, at most `⌈m/2⌉ + 1` cells away counting
/// the rounding margin, which is at most `m` from `m = 2` up; with `m = 1`
/// every point shares the candidate's cell on that axis, at offset 0.
/// Bounding the reach bounds the stencil (and the padding), which would
/// otherwise grow as `(r / side)^N` for a radius far larger than the box.
fn bounded_reach(needed: u64, m: u64, periodic: bool) -> u64 {
    // `m >= 1` (`cell_count`).
    if periodic {
        needed.min(m)
    } else {
        needed.min(m - 1)
    }
}

/// Upper bound on the number of points of any set with minimum distance
/// `r` in the domain: balls of radius `r/2` around them are disjoint and lie
/// in the box grown by `r/2` on bounded axes. Returned as a natural log, so
/// a huge box does not overflow.
fn ln_max_points<const N: usize>(domain: &Domain<N>, radius: f64) -> f64 {
    let extent = domain.extent();
    let periodic = domain.periodic();
    let half = radius / 2.0;
    let mut ln = -unit_ball_volume(N).ln();
    for (&e, &periodic) in extent.iter().zip(&periodic) {
        let grown = if periodic { e } else { e + radius };
        ln += (grown / half).ln();
    }
    ln
}

fn plan_sparse<const N: usize>(
    domain: &Domain<N>,
    radius: f64,
    budget: u64,
) -> Result<SparsePlan<N>, u64> {
    let extent = domain.extent();
    let periodic = domain.periodic();
    let mut cells = [0i64; N];
    let mut side = [0.0; N];
    let axes = extent.iter().zip(&periodic);
    for ((c, s), (&e, &periodic)) in cells.iter_mut().zip(&mut side).zip(axes) {
        let m = if periodic {
            // Whole cells per period, so wrapped cells line up.
            cell_count((e / radius).floor()).ok_or(u64::MAX)?
        } else {
            cell_count((e / radius).ceil()).ok_or(u64::MAX)?
        };
        *c = i64::try_from(m).map_err(|_| u64::MAX)?;
        *s = if periodic { e / to_f64(m) } else { radius };
    }
    let max_cells = cells.iter().copied().max().unwrap_or(1);
    #[expect(clippy::cast_precision_loss, reason = "<= 2^40")]
    let eta = rounding_margin(max_cells as f64);
    let mut reach = [0i64; N];
    let axes = side.iter().zip(&cells).zip(&periodic);
    for (r, ((&s, &m), &periodic)) in reach.iter_mut().zip(axes) {
        // A periodic axis narrower than the reach is searched whole, once
        // (see `Sparse::visit`), and a bounded one ends at the box.
        let m = u64::try_from(m).map_err(|_| u64::MAX)?;
        let p = bounded_reach(needed_reach(radius, s, eta), m, periodic);
        *r = i64::try_from(p).map_err(|_| u64::MAX)?;
    }
    // Cell lists in an array rather than a hash table where the array is
    // small: a look-up is then an index, not a hash and a probe.
    let array_bytes = cells
        .iter()
        .try_fold(4u64, |acc, &m| acc.checked_mul(u64::try_from(m).ok()?))
        .filter(|&b| b <= sparse::MAX_ARRAY_BYTES && b <= budget / 4);
    let first = sparse::first_point_bytes::<N>(array_bytes.is_some());
    Ok(SparsePlan {
        cells,
        side,
        reach,
        eta,
        array: array_bytes.is_some(),
        bytes: array_bytes.unwrap_or(0).saturating_add(first),
    })
}

/// Chooses and sizes the grid, or explains why none fits.
///
/// `expected` is the density model's expected point count, where it has
/// one (see [`DensePlan::peak`]).
pub(crate) fn plan<const N: usize>(
    domain: &Domain<N>,
    radius: f64,
    layout: GridLayout,
    budget: u64,
    max_points: Option<u64>,
    expected: Option<f64>,
) -> Result<GridPlan<N>, Error> {
    for (axis, extent) in domain.extent().into_iter().enumerate() {
        let cells = extent / radius;
        if cells.is_nan() || cells > MAX_CELLS_PER_AXIS {
            return Err(Error::BoxTooWide { axis });
        }
    }
    // Bricks where they apply (3-D) and fit, else `u32` cells: a
    // budget the `u32` grid fits is never refused for the bricks' sake.
    let bricks_fit = |d: &DensePlan<N>, bound: u64| {
        d.reach.iter().all(|&r| r <= bricks::MAX_REACH) && bound <= budget
    };
    let dense_when = |full: bool| {
        if bricks::applies(N)
            && let Ok(d) = plan_dense(domain, radius, max_points, true)
            && bricks_fit(&d, if full { d.peak(expected) } else { d.bytes })
        {
            return Ok(d);
        }
        plan_dense(domain, radius, max_points, false)
    };
    let dense = || dense_when(false);
    let sparse = || plan_sparse(domain, radius, budget);
    let too_large = |needed: u64| Error::GridTooLarge { needed, budget };
    // Only what is allocated before the first point is checked here: the
    // points themselves are counted as they come (see `budget.rs`).
    match layout {
        GridLayout::Dense => match dense() {
            Ok(d) if d.bytes <= budget => Ok(GridPlan::Dense(d)),
            Ok(d) => Err(too_large(d.bytes)),
            Err(needed) => Err(too_large(needed)),
        },
        GridLayout::Sparse => match sparse() {
            Ok(s) if s.bytes <= budget => Ok(GridPlan::Sparse(s)),
            Ok(s) => Err(too_large(s.bytes)),
            Err(needed) => Err(too_large(needed)),
        },
        GridLayout::Paged => match plan_paged(domain, radius, max_points, budget) {
            Ok(p) if p.bytes <= budget => Ok(GridPlan::Paged(p)),
            Ok(p) => Err(too_large(p.bytes)),
            // Past 3-D or on a periodic axis: no budget makes it possible.
            Err(needed) => Err(too_large(needed)),
        },
        GridLayout::Auto => {
            // Dense where the run is expected to fit, sparse otherwise: the
            // sparse grid's memory grows with the points only.
            let dense = if N <= 3 {
                dense_when(true)
            } else {
                Err(u64::MAX)
            };
            if let Ok(d) = dense
                && d.peak(expected) <= budget
            {
                return Ok(GridPlan::Dense(d));
            }
            // Pages where the box is bounded: memory that follows the
            // points, at about 0.9 of the dense grid's speed in 2-D and
            // 3-D (pages of bricks, there), where in 3-D the sparse grid
            // takes 2.2× the pages' time with its array of heads and 4.6×
            // with its hash table. The journal's "Pages of bricks in 3-D"
            // has the runs.
            if let Ok(p) = plan_paged(domain, radius, max_points, budget)
                && p.bytes <= budget
            {
                return Ok(GridPlan::Paged(p));
            }
            let sparse_plan = sparse();
            let dense_bytes = dense.map_or_else(|b| b, |d| d.bytes);
            match sparse_plan {
                Ok(s) if s.bytes <= budget => Ok(GridPlan::Sparse(s)),
                Ok(s) => Err(too_large(s.bytes.min(dense_bytes))),
                Err(needed) => Err(too_large(needed.min(dense_bytes))),
            }
        }
    }
}

/// The built grid, one variant per layout.
#[derive(Debug)]
pub(crate) enum Grid<const N: usize> {
    Bricks(bricks::Bricks<N>),
    Dense(dense::Dense<N>),
    Paged(paged::Paged<N>),
    PagedBricks(paged_bricks::PagedBricks<N>),
    Sparse(sparse::Sparse<N>),
}

impl<const N: usize> Grid<N> {
    /// Allocates the planned grid. If the dense allocation fails (the
    /// machine has less free memory than the budget), falls back to the
    /// sparse layout, whose memory grows only with the points made.
    pub(crate) fn build(plan: &GridPlan<N>, domain: &Domain<N>, radius: f64) -> Self {
        match plan {
            GridPlan::Dense(d) if d.bricked => match bricks::Bricks::try_new(d, domain, radius) {
                Some(grid) => Grid::Bricks(grid),
                None => Self::build(
                    &GridPlan::Dense(DensePlan {
                        bricked: false,
                        ..*d
                    }),
                    domain,
                    radius,
                ),
            },
            GridPlan::Dense(d) => match dense::Dense::try_new(d, domain, radius) {
                Some(grid) => Grid::Dense(grid),
                None => {
                    // The sparse plan's geometry (cells of side >= r) with
                    // the hash table; `plan` has ruled out its errors
                    // (`BoxTooWide`), but should one come, the dense cells.
                    let s = plan_sparse(domain, radius, 0).unwrap_or_else(|_| fallback_sparse(d));
                    Grid::Sparse(sparse::Sparse::new(&s, domain, radius))
                }
            },
            GridPlan::Paged(p) => {
                // Bricks in pages where their masks apply (3-D, a reach
                // of 2), else `u32` cells; the sparse grid if neither can
                // be allocated.
                let paged = if paged_bricks::applies(&p.dense.reach) {
                    paged_bricks::PagedBricks::try_new(p, domain, radius).map(Grid::PagedBricks)
                } else {
                    paged::Paged::try_new(p, domain, radius).map(Grid::Paged)
                };
                paged.unwrap_or_else(|| {
                    let s = plan_sparse(domain, radius, 0)
                        .unwrap_or_else(|_| fallback_sparse(&p.dense));
                    Grid::Sparse(sparse::Sparse::new(&s, domain, radius))
                })
            }
            GridPlan::Sparse(s) => Grid::Sparse(sparse::Sparse::new(s, domain, radius)),
        }
    }
}

/// A sparse grid on the dense plan's cells. The sparse search is exact for
/// any cell geometry whose cells tile each period, so this is always valid;
/// it is used only when the dense allocation itself failed. Its memory is
/// counted against the budget as it grows, like any sparse grid's.
fn fallback_sparse<const N: usize>(d: &DensePlan<N>) -> SparsePlan<N> {
    SparsePlan {
        cells: d.cells.map(|m| i64::try_from(m).unwrap_or(i64::MAX)),
        side: d.side,
        reach: d.reach.map(|p| i64::try_from(p).unwrap_or(i64::MAX)),
        eta: d.eta,
        array: false,
        bytes: sparse::first_point_bytes::<N>(false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_reach_follows_the_dimension() {
        // side = r/√N, so ceil(√N) cells, plus the margin for perfect squares.
        let r = 0.05;
        let d2 = plan_dense(&Domain::from_extent([1.0; 2]).unwrap(), r, None, false).unwrap();
        assert_eq!(d2.reach, [2; 2], "2-D");
        let d3 = plan_dense(&Domain::from_extent([1.0; 3]).unwrap(), r, None, false).unwrap();
        assert_eq!(d3.reach, [2; 3], "3-D");
        let d5 = plan_dense(&Domain::from_extent([1.0; 5]).unwrap(), 0.5, None, false).unwrap();
        assert_eq!(d5.reach, [3; 5], "5-D needs 3 cells, not 2");
        for i in 0..2 {
            assert!(d2.side[i] <= r / 2f64.sqrt(), "side within r/√2");
        }
    }

    #[test]
    fn huge_grids_are_errors_not_aborts() {
        let d = Domain::from_extent([1e300, 1e300]).unwrap();
        let e = plan(
            &d,
            1e-100,
            GridLayout::Auto,
            DEFAULT_MAX_GRID_BYTES,
            None,
            None,
        );
        assert_eq!(
            e,
            Err(Error::BoxTooWide { axis: 0 }),
            "too wide for any grid"
        );
        let d = Domain::from_extent([1.0, 1e6]).unwrap();
        let e = plan(
            &d,
            1e-7,
            GridLayout::Auto,
            DEFAULT_MAX_GRID_BYTES,
            Some(10),
            None,
        );
        assert_eq!(e, Err(Error::BoxTooWide { axis: 1 }), "a cap cannot help");
        let e = plan(
            &Domain::from_extent([1.0; 3]).unwrap(),
            1e-6,
            GridLayout::Dense,
            1 << 30,
            None,
            None,
        );
        assert!(matches!(e, Err(Error::GridTooLarge { .. })), "{e:?}");
    }

    /// `Auto` is dense up to 3-D and sparse from 4-D, where the dense grid
    /// fits easily (the journal's "Sparse grid from 4-D up" has the times);
    /// `Dense` still gives the dense grid in 4-D.
    #[test]
    fn auto_is_dense_up_to_3d_and_sparse_from_4d() {
        fn auto<const N: usize>(r: f64, layout: GridLayout) -> Option<bool> {
            let d = Domain::from_extent([1.0; N]).ok()?;
            let p = plan(&d, r, layout, DEFAULT_MAX_GRID_BYTES, None, None).ok()?;
            Some(matches!(p, GridPlan::Dense(_)))
        }
        assert_eq!(auto::<2>(0.01, GridLayout::Auto), Some(true), "2-D");
        assert_eq!(auto::<3>(0.02, GridLayout::Auto), Some(true), "3-D");
        assert_eq!(auto::<4>(0.05, GridLayout::Auto), Some(false), "4-D");
        assert_eq!(auto::<5>(0.1, GridLayout::Auto), Some(false), "5-D");
        assert_eq!(auto::<4>(0.05, GridLayout::Dense), Some(true), "4-D dense");
    }

    /// A huge box: pages (the stencils and one page up front) where it is
    /// bounded, the sparse grid (nothing up front) where it is periodic;
    /// never the dense grid.
    #[test]
    fn a_huge_box_plans_pages_or_a_sparse_grid_that_allocate_little_up_front() {
        let d = Domain::from_extent([1e6, 1e6]).unwrap();
        let p = plan(
            &d,
            1e-3,
            GridLayout::Auto,
            DEFAULT_MAX_GRID_BYTES,
            None,
            None,
        );
        assert!(
            matches!(p, Ok(GridPlan::Paged(p)) if p.bytes < 32 << 10 && p.directory == 0),
            "{p:?}"
        );
        let torus = d.with_periodic([true; 2]);
        let p = plan(
            &torus,
            1e-3,
            GridLayout::Auto,
            DEFAULT_MAX_GRID_BYTES,
            None,
            None,
        );
        assert!(
            matches!(p, Ok(GridPlan::Sparse(s)) if s.bytes < 1024),
            "{p:?}"
        );
        let dense = plan(
            &d,
            1e-3,
            GridLayout::Dense,
            DEFAULT_MAX_GRID_BYTES,
            None,
            None,
        );
        assert!(
            matches!(dense, Err(Error::GridTooLarge { .. })),
            "{dense:?}"
        );
        let none = plan(&d, 1e-3, GridLayout::Auto, 16, None, None);
        assert!(matches!(none, Err(Error::GridTooLarge { .. })), "{none:?}");
    }

    /// A radius far larger than the box: the reach stops at the box (or,
    /// periodic, at one period), so the stencils and padding stay tiny.
    #[test]
    fn the_reach_is_bounded_by_the_box() {
        fn check<const N: usize>(extent: [f64; N], periodic: bool, r: f64) {
            let d = Domain::from_extent(extent)
                .unwrap()
                .with_periodic([periodic; N]);
            let p = plan_dense(&d, r, None, false).unwrap();
            for (&reach, &m) in p.reach.iter().zip(&p.cells) {
                assert!(reach <= m, "{N}-D r = {r}: reach {reach} > {m} cells");
                if !periodic {
                    assert!(reach < m, "{N}-D r = {r}: bounded reach {reach}");
                }
            }
            assert!(p.bytes < 1 << 20, "{N}-D r = {r}: {} bytes", p.bytes);
            let s = plan_sparse(&d, r, DEFAULT_MAX_GRID_BYTES).unwrap();
            for (&reach, &m) in s.reach.iter().zip(&s.cells) {
                assert!(reach <= m, "sparse {N}-D r = {r}: reach {reach} > {m}");
            }
        }
        for periodic in [false, true] {
            check([1.0, 1.0], periodic, 49.0);
            check([0.9, 1.0, 1.0], periodic, 200.0);
            check([1.0; 4], periodic, 50.0);
            check([1.0; 8], periodic, 1e100);
            // A long thin box: many cells on one axis only.
            check([100.0, 0.01, 0.01], periodic, 5.0);
        }
    }
}
