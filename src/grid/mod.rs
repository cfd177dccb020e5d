//! The background grid: which layout, how big, and which neighbour cells a
//! candidate must be checked against.
//!
//! Two layouts implement [`NeighbourGrid`]:
//! - [`dense::Dense`]: Bridson's grid of cells of side `<= r/√N`, each
//!   holding the `u32` index of at most one point. Fast, memory ∝ box
//!   volume (4 bytes a cell) plus the points.
//! - [`sparse::Sparse`]: a hash map from cells of side `≈ r` to the points
//!   in them. Memory ∝ number of points, whatever the box. Chosen from 5-D
//!   up, or when the dense grid would not fit the budget.
//!
//! # Why the search reach is never a fixed ±2 cells
//! A point within `r` of a candidate can lie up to `ceil(r / side)` cells
//! away on each axis (3 for `N = 5..=8` with side `r/√N`), and rounding in
//! the cell index can move a point by one cell when it sits within a few
//! ulps of a cell face. Every cell count here is derived from `r`, the cell
//! side and a margin `η` (in cells) that bounds that rounding, so a point
//! closer than `r` is always found.

pub(crate) mod dense;
pub(crate) mod sparse;

use crate::blockers::Blockers;
use crate::domain::Domain;
use crate::error::Error;

/// Which background grid layout the sampler uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum GridLayout {
    /// Dense when `N <= 4` and the dense grid fits the memory budget,
    /// otherwise sparse. From 5-D up the dense grid's neighbourhood
    /// (thousands of cells per check) costs more than the sparse grid's hash
    /// look-ups; in 4-D dense still wins (4.37 s against 5.70 s for 200 000
    /// points, medians of 5 interleaved runs of `examples/throughput.rs`).
    #[default]
    Auto,
    /// Bridson's dense grid; an error if it does not fit the budget.
    Dense,
    /// The sparse hash grid; memory grows with the number of points.
    Sparse,
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
    Sparse(SparsePlan<N>),
}

/// Geometry of a dense grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct DensePlan<const N: usize> {
    pub(crate) cells: [usize; N],
    pub(crate) side: [f64; N],
    pub(crate) reach: [usize; N],
    pub(crate) eta: f64,
    pub(crate) bytes: u64,
    /// A bound on the points the grid will store (the packing bound, the
    /// cells, or the cap), to reserve room for up front.
    pub(crate) points: usize,
}

/// Geometry of a sparse grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SparsePlan<const N: usize> {
    pub(crate) cells: [i64; N],
    pub(crate) side: [f64; N],
    pub(crate) reach: [i64; N],
    pub(crate) eta: f64,
    pub(crate) bytes: u64,
}

/// What the sampler needs of a grid.
pub(crate) trait NeighbourGrid<const N: usize> {
    /// A stored point closer than `r` to `p` (which lies in the domain), if
    /// any: the first one found, which the sampler remembers (see
    /// `blockers.rs`). Exact: compares squared distances summed in axis
    /// order.
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]>;
    /// Puts stored points near `p` into `cache` (up to its capacity `B`),
    /// where the grid finds them cheaply; by default none.
    fn seed<const B: usize>(&self, _p: &[f64; N], _cache: &mut Blockers<N, B>) {}
    /// Starts loading the cells [`seed`](Self::seed) will read around `p`;
    /// a hint only, by default nothing.
    fn prefetch(&self, _p: &[f64; N]) {}
    /// Stores `p`; returns `false` (and stores nothing) if the layout has no
    /// room for it, which the sampler treats as a failed attempt.
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

/// Dense geometry and size, or the bytes it would need if it cannot exist.
fn plan_dense<const N: usize>(
    domain: &Domain<N>,
    radius: f64,
    max_points: Option<u64>,
) -> Result<DensePlan<N>, u64> {
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
    let mut total: u64 = 1;
    for ((r, &s), &m) in reach.iter_mut().zip(&side).zip(&counts) {
        // Cells at |d| are needed while (|d| - 1 - η)·side < r.
        let p = cell_count((radius / s + eta).ceil()).ok_or(u64::MAX)?;
        *r = usize::try_from(p).map_err(|_| u64::MAX)?;
        let padded = p
            .checked_mul(2)
            .and_then(|pp| m.checked_add(pp))
            .ok_or(u64::MAX)?;
        total = total.checked_mul(padded).ok_or(u64::MAX)?;
    }
    // Cells hold u32 indices; the points live in a vector bounded by the
    // packing bound (and by one per inner cell), reserved up front; doubled
    // for the growth slack should that reservation be refused.
    let cell_bytes = total.checked_mul(4).ok_or(u64::MAX)?;
    let inner: f64 = counts.iter().map(|&m| to_f64(m)).product();
    let points = ln_max_points(domain, radius).exp().min(inner);
    #[expect(clippy::cast_precision_loss, reason = "N is small")]
    let point_bytes = 2.0 * (points.ceil() + 1.0) * (8 * N) as f64;
    if !point_bytes.is_finite() || point_bytes >= 1.8e19 {
        return Err(u64::MAX);
    }
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "finite, positive and below u64::MAX"
    )]
    let bytes = cell_bytes.saturating_add(point_bytes as u64);
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
    // Below u32::MAX (checked above), so it converts exactly.
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "finite, positive and below u32::MAX"
    )]
    let bound = points.ceil() as u64;
    let points = usize::try_from(bound.min(max_points.unwrap_or(u64::MAX))).unwrap_or(usize::MAX);
    Ok(DensePlan {
        cells,
        side,
        reach,
        eta,
        bytes,
        points,
    })
}

/// Bytes the sparse grid may use per stored point: the point, its share of
/// a hash-map entry (key, small inline vector, control byte, load factor),
/// and the doubling slack of the map and of the active list.
fn sparse_bytes_per_point(n: usize) -> f64 {
    #[expect(clippy::cast_precision_loss, reason = "N is small")]
    let n = n as f64;
    72.0 * n + 32.0
}

/// Volume of the unit ball in `n` dimensions.
pub(crate) fn unit_ball_volume(n: usize) -> f64 {
    let (mut v, start) = if n.is_multiple_of(2) {
        (1.0, 2)
    } else {
        (2.0, 3)
    };
    let mut k = start;
    while k <= n {
        #[expect(clippy::cast_precision_loss, reason = "N is small")]
        let kf = k as f64;
        v *= core::f64::consts::TAU / kf;
        k += 2;
    }
    v
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
    max_points: Option<u64>,
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
        let p = (radius / s + eta).ceil();
        // A periodic axis narrower than the reach is searched whole, once
        // (see `Sparse::conflicts`), so its reach never needs to exceed `m`.
        *r = match cell_count(p) {
            Some(p) => i64::try_from(p).map_err(|_| u64::MAX)?,
            None if periodic => m,
            None => return Err(u64::MAX),
        };
        if periodic {
            *r = (*r).min(m);
        }
    }
    let ln_points = ln_max_points(domain, radius);
    let mut points = ln_points.exp();
    if let Some(cap) = max_points {
        points = points.min(to_f64(cap));
    }
    let bytes_f = (points.ceil() + 1.0) * sparse_bytes_per_point(N);
    let bytes = if bytes_f.is_finite() && bytes_f < 1.8e19 {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "finite, positive and below u64::MAX"
        )]
        let b = bytes_f as u64;
        b
    } else {
        u64::MAX
    };
    Ok(SparsePlan {
        cells,
        side,
        reach,
        eta,
        bytes,
    })
}

/// Chooses and sizes the grid, or explains why none fits.
pub(crate) fn plan<const N: usize>(
    domain: &Domain<N>,
    radius: f64,
    layout: GridLayout,
    budget: u64,
    max_points: Option<u64>,
) -> Result<GridPlan<N>, Error> {
    for (axis, extent) in domain.extent().into_iter().enumerate() {
        let cells = extent / radius;
        if cells.is_nan() || cells > MAX_CELLS_PER_AXIS {
            return Err(Error::BoxTooWide { axis });
        }
    }
    let dense = || plan_dense(domain, radius, max_points);
    let sparse = || plan_sparse(domain, radius, max_points);
    let too_large = |needed: u64| Error::GridTooLarge { needed, budget };
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
        GridLayout::Auto => {
            let dense = if N <= 4 { dense() } else { Err(u64::MAX) };
            if let Ok(d) = dense
                && d.bytes <= budget
            {
                return Ok(GridPlan::Dense(d));
            }
            match sparse() {
                Ok(s) if s.bytes <= budget => Ok(GridPlan::Sparse(s)),
                Ok(s) => Err(too_large(
                    s.bytes.min(dense.map_or_else(|b| b, |d| d.bytes)),
                )),
                Err(needed) => Err(too_large(needed.min(dense.map_or_else(|b| b, |d| d.bytes)))),
            }
        }
    }
}

/// The built grid, one variant per layout.
#[derive(Debug)]
pub(crate) enum Grid<const N: usize> {
    Dense(dense::Dense<N>),
    Sparse(sparse::Sparse<N>),
}

impl<const N: usize> Grid<N> {
    /// Allocates the planned grid. If the dense allocation fails (the
    /// machine has less free memory than the budget), falls back to the
    /// sparse layout, whose memory grows only with the points made.
    pub(crate) fn build(plan: &GridPlan<N>, domain: &Domain<N>, radius: f64) -> Self {
        match plan {
            GridPlan::Dense(d) => match dense::Dense::try_new(d, domain, radius) {
                Some(grid) => Grid::Dense(grid),
                None => Grid::Sparse(sparse::Sparse::new(&fallback_sparse(d), domain, radius)),
            },
            GridPlan::Sparse(s) => Grid::Sparse(sparse::Sparse::new(s, domain, radius)),
        }
    }
}

/// A sparse grid on the dense plan's cells. The sparse search is exact for
/// any cell geometry whose cells tile each period, so this is always valid;
/// it is used only when the dense allocation itself failed, and is not
/// budget-checked (its memory grows with the points made).
fn fallback_sparse<const N: usize>(d: &DensePlan<N>) -> SparsePlan<N> {
    SparsePlan {
        cells: d.cells.map(|m| i64::try_from(m).unwrap_or(i64::MAX)),
        side: d.side,
        reach: d.reach.map(|p| i64::try_from(p).unwrap_or(i64::MAX)),
        eta: d.eta,
        bytes: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_ball_volumes() {
        let expected = [
            1.0,
            2.0,
            core::f64::consts::PI,
            4.0 / 3.0 * core::f64::consts::PI,
        ];
        for (n, v) in expected.iter().enumerate() {
            assert!((unit_ball_volume(n) - v).abs() < 1e-12, "V_{n}");
        }
        let v8 = core::f64::consts::PI.powi(4) / 24.0;
        assert!((unit_ball_volume(8) - v8).abs() < 1e-12, "V_8");
    }

    #[test]
    fn dense_reach_follows_the_dimension() {
        // side = r/√N, so ceil(√N) cells, plus the margin for perfect squares.
        let r = 0.05;
        let d2 = plan_dense(&Domain::from_extent([1.0; 2]).unwrap(), r, None).unwrap();
        assert_eq!(d2.reach, [2; 2], "2-D");
        let d3 = plan_dense(&Domain::from_extent([1.0; 3]).unwrap(), r, None).unwrap();
        assert_eq!(d3.reach, [2; 3], "3-D");
        let d5 = plan_dense(&Domain::from_extent([1.0; 5]).unwrap(), 0.5, None).unwrap();
        assert_eq!(d5.reach, [3; 5], "5-D needs 3 cells, not 2");
        for i in 0..2 {
            assert!(d2.side[i] <= r / 2f64.sqrt(), "side within r/√2");
        }
    }

    #[test]
    fn huge_grids_are_errors_not_aborts() {
        let d = Domain::from_extent([1e300, 1e300]).unwrap();
        let e = plan(&d, 1e-100, GridLayout::Auto, DEFAULT_MAX_GRID_BYTES, None);
        assert_eq!(
            e,
            Err(Error::BoxTooWide { axis: 0 }),
            "too wide for any grid"
        );
        let d = Domain::from_extent([1.0, 1e6]).unwrap();
        let e = plan(&d, 1e-7, GridLayout::Auto, DEFAULT_MAX_GRID_BYTES, Some(10));
        assert_eq!(e, Err(Error::BoxTooWide { axis: 1 }), "a cap cannot help");
        let e = plan(
            &Domain::from_extent([1.0; 3]).unwrap(),
            1e-6,
            GridLayout::Dense,
            1 << 30,
            None,
        );
        assert!(matches!(e, Err(Error::GridTooLarge { .. })), "{e:?}");
    }

    #[test]
    fn a_point_cap_makes_a_huge_box_feasible() {
        let d = Domain::from_extent([1e6, 1e6]).unwrap();
        let none = plan(&d, 1e-3, GridLayout::Auto, DEFAULT_MAX_GRID_BYTES, None);
        assert!(none.is_err(), "uncapped must not fit: {none:?}");
        let capped = plan(
            &d,
            1e-3,
            GridLayout::Auto,
            DEFAULT_MAX_GRID_BYTES,
            Some(1000),
        );
        assert!(matches!(capped, Ok(GridPlan::Sparse(_))), "{capped:?}");
    }
}
