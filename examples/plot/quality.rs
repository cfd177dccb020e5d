//! The numbers of the quality report: minimum distance and pairs closer
//! than `r` (the guarantee, checked independently of the sampler with the
//! distance of the tests' oracle, `tests/common/mod.rs`, and a grid to stay
//! fast on large sets), and the share of the domain left uncovered (0 for a
//! maximal set).

use crate::oracle;
use bridson::Domain;
use bridson::rand::RngExt;
use core::ops::ControlFlow;

/// `Σ_i d_i²` in axis order, with the toroidal difference
/// `min(|Δ|, L − |Δ|)` on periodic axes: the distance of the guarantee, as
/// the integration tests' naive oracle (`tests/common/mod.rs`) computes it,
/// so that the plot and the tests share one checker independent of the
/// sampler.
fn distance_squared<const N: usize>(domain: &Domain<N>, a: &[f64; N], b: &[f64; N]) -> f64 {
    oracle::distance_squared(a, b, &domain.lo(), &domain.hi(), &domain.periodic())
}

/// Points bucketed by their first two coordinates, for neighbour queries in
/// any dimension `N >= 2`: a query visits the cells of the plane within
/// reach and checks the full `N`-dimensional distance. Cells are at least
/// `side` wide (wider if the box would need more than about 4 cells a
/// point).
#[derive(Debug)]
pub(crate) struct PlaneGrid<'a, const N: usize> {
    points: &'a [[f64; N]],
    domain: Domain<N>,
    cells: [usize; 2],
    width: [f64; 2],
    /// `order[start[c]..start[c + 1]]` are the points of cell `c`.
    start: Vec<usize>,
    order: Vec<usize>,
}

impl<'a, const N: usize> PlaneGrid<'a, N> {
    pub(crate) fn new(points: &'a [[f64; N]], domain: Domain<N>, side: f64) -> Self {
        assert!(N >= 2, "the plane grid needs two axes");
        let extent = domain.extent();
        let budget = 4 * points.len() + 16;
        let mut side = side;
        let cells = loop {
            let cells = [0, 1].map(|k| {
                let c = (extent[k] / side).floor().clamp(1.0, 1e9);
                #[expect(
                    clippy::cast_possible_truncation,
                    clippy::cast_sign_loss,
                    reason = "a whole number in 1..=1e9"
                )]
                let c = c as usize;
                c
            });
            if cells[0].saturating_mul(cells[1]) <= budget {
                break cells;
            }
            side *= 1.5;
        };
        let width = [0, 1].map(|k| extent[k] / cells[k] as f64);
        let mut grid = Self {
            points,
            domain,
            cells,
            width,
            start: vec![0; cells[0] * cells[1] + 1],
            order: vec![0; points.len()],
        };
        let cell_of: Vec<usize> = points.iter().map(|p| grid.cell(p)).collect();
        for &c in &cell_of {
            grid.start[c + 1] += 1;
        }
        for c in 0..cells[0] * cells[1] {
            grid.start[c + 1] += grid.start[c];
        }
        let mut next = grid.start.clone();
        for (i, &c) in cell_of.iter().enumerate() {
            grid.order[next[c]] = i;
            next[c] += 1;
        }
        grid
    }

    /// The cell column (axis 0) or row (axis 1) of coordinate `x`, clamped
    /// into the grid.
    fn axis_cell(&self, axis: usize, x: f64) -> usize {
        let t = ((x - self.domain.lo()[axis]) / self.width[axis]).floor();
        let last = self.cells[axis] - 1;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to 0..=last first (NaN casts to 0)"
        )]
        let c = t.clamp(0.0, last as f64) as usize;
        c
    }

    fn cell(&self, p: &[f64; N]) -> usize {
        self.axis_cell(1, p[1]) * self.cells[0] + self.axis_cell(0, p[0])
    }

    /// The cells along `axis` within `reach` of the cell `c` (one spare cell
    /// each side covers a cell index off by one from rounding), each once,
    /// wrapping on a periodic axis.
    fn axis_range(&self, axis: usize, c: usize, reach: f64) -> Vec<usize> {
        let count = self.cells[axis];
        let m = (reach / self.width[axis]).ceil().min(count as f64);
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a whole number in 0..=count"
        )]
        let m = m.max(0.0) as usize + 1;
        if self.domain.periodic()[axis] {
            if 2 * m + 1 >= count {
                (0..count).collect()
            } else {
                (0..=2 * m).map(|k| (c + count + k - m) % count).collect()
            }
        } else {
            (c.saturating_sub(m)..=(c + m).min(count - 1)).collect()
        }
    }

    /// Calls `visit(index, distance²)` for every point within `reach` of
    /// `q` (and some farther ones) until it breaks.
    pub(crate) fn visit(
        &self,
        q: &[f64; N],
        reach: f64,
        mut visit: impl FnMut(usize, f64) -> ControlFlow<()>,
    ) -> ControlFlow<()> {
        let columns = self.axis_range(0, self.axis_cell(0, q[0]), reach);
        let rows = self.axis_range(1, self.axis_cell(1, q[1]), reach);
        for &row in &rows {
            for &column in &columns {
                let c = row * self.cells[0] + column;
                for &i in &self.order[self.start[c]..self.start[c + 1]] {
                    visit(i, distance_squared(&self.domain, q, &self.points[i]))?;
                }
            }
        }
        ControlFlow::Continue(())
    }
}

/// The closest pair and the pairs violating the radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PairStats {
    /// The smallest distance between two points; `None` for fewer than 2.
    pub(crate) min_distance: Option<f64>,
    /// Pairs with `distance² < r²` (0 for a correct sampler).
    pub(crate) closer_than_radius: u64,
}

/// Every pair closer than `radius`, and the closest pair, found with a grid
/// (each pair once). A maximal set has a neighbour within `2r` of every
/// point; otherwise the search widens until it finds the closest pair.
pub(crate) fn pair_stats<const N: usize>(
    points: &[[f64; N]],
    domain: Domain<N>,
    radius: f64,
) -> PairStats {
    let r2 = radius * radius;
    let mut closer = 0;
    let mut best = f64::INFINITY;
    if points.len() >= 2 {
        let grid = PlaneGrid::new(points, domain, radius);
        let extent = domain.extent();
        let diagonal = (0..N)
            .map(|i| {
                let half = if domain.periodic()[i] { 0.5 } else { 1.0 };
                (extent[i] * half).powi(2)
            })
            .sum::<f64>()
            .sqrt();
        let mut reach = 2.0 * radius;
        let mut first = true;
        loop {
            for (i, p) in points.iter().enumerate() {
                let _ = grid.visit(p, reach, |j, d2| {
                    if j > i {
                        if first && d2 < r2 {
                            closer += 1;
                        }
                        best = best.min(d2);
                    }
                    ControlFlow::Continue(())
                });
            }
            first = false;
            // Exact once the closest pair lies within reach: every pair
            // within reach was visited.
            if best <= reach * reach || reach >= diagonal {
                break;
            }
            reach *= 2.0;
        }
    }
    PairStats {
        min_distance: best.is_finite().then(|| best.sqrt()),
        closer_than_radius: closer,
    }
}

/// The share of `probes` uniform random points of the domain that lie
/// farther than `radius` from every point: an estimate of the uncovered
/// fraction of the domain (0 for a maximal set, which leaves no room for
/// another point).
pub(crate) fn uncovered_fraction<const N: usize>(
    points: &[[f64; N]],
    domain: Domain<N>,
    radius: f64,
    probes: u64,
    seed: u64,
) -> f64 {
    if probes == 0 {
        return f64::NAN;
    }
    let r2 = radius * radius;
    let grid = PlaneGrid::new(points, domain, radius);
    let mut rng = bridson::seeded_rng(seed);
    let (lo, extent) = (domain.lo(), domain.extent());
    let mut uncovered = 0u64;
    for _ in 0..probes {
        let q: [f64; N] = core::array::from_fn(|i| lo[i] + rng.random::<f64>() * extent[i]);
        let covered = grid.visit(&q, radius, |_, d2| {
            if d2 <= r2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        uncovered += u64::from(covered.is_continue());
    }
    uncovered as f64 / probes as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn random<const N: usize>(n: usize, seed: u64) -> Vec<[f64; N]> {
        let mut rng = bridson::seeded_rng(seed);
        (0..n)
            .map(|_| core::array::from_fn(|_| rng.random::<f64>()))
            .collect()
    }

    /// The oracle's O(n²) answer: its violations, and the closest pair.
    fn brute<const N: usize>(points: &[[f64; N]], domain: &Domain<N>, r: f64) -> PairStats {
        let (lo, hi, periodic) = (domain.lo(), domain.hi(), domain.periodic());
        let closer = oracle::min_distance_violations(points, r, lo, hi, periodic).len();
        let best = points
            .iter()
            .enumerate()
            .flat_map(|(i, a)| points[..i].iter().map(move |b| (a, b)))
            .map(|(a, b)| distance_squared(domain, a, b))
            .fold(f64::INFINITY, f64::min);
        PairStats {
            min_distance: best.is_finite().then(|| best.sqrt()),
            closer_than_radius: u64::try_from(closer).expect("a count"),
        }
    }

    #[test]
    fn pair_stats_match_brute_force() {
        let unit2 = Domain::from_extent([1.0, 1.0]).expect("box");
        let unit3 = Domain::from_extent([1.0; 3]).expect("box");
        for seed in 0..4 {
            for periodic in [false, true] {
                let d2 = unit2.with_periodic([periodic; 2]);
                let pts = random::<2>(300, seed);
                for r in [0.01, 0.03, 0.2] {
                    assert_eq!(
                        pair_stats(&pts, d2, r),
                        brute(&pts, &d2, r),
                        "2-D seed {seed} periodic {periodic} r {r}"
                    );
                }
                let d3 = unit3.with_periodic([periodic; 3]);
                let pts = random::<3>(200, seed);
                assert_eq!(
                    pair_stats(&pts, d3, 0.05),
                    brute(&pts, &d3, 0.05),
                    "3-D seed {seed} periodic {periodic}"
                );
            }
        }
    }

    #[test]
    fn pair_stats_widen_for_sparse_sets() {
        let d = Domain::from_extent([10.0, 1.0]).expect("box");
        let pts = [[0.5, 0.5], [9.5, 0.5], [5.0, 0.2]];
        let s = pair_stats(&pts, d, 0.1);
        assert_eq!(s, brute(&pts, &d, 0.1), "far apart");
        assert_eq!(s.closer_than_radius, 0, "none close");
        assert_eq!(
            pair_stats(&pts[..1], d, 0.1).min_distance,
            None,
            "one point has no pair"
        );
        let wrapped = d.with_periodic([true, false]);
        let s = pair_stats(&pts[..2], wrapped, 0.1);
        assert!(
            (s.min_distance.expect("a pair") - 1.0).abs() < 1e-12,
            "the short way round"
        );
    }

    #[test]
    fn a_maximal_sampler_set_checks_out() {
        let d = Domain::from_extent([1.0, 1.0]).expect("box");
        let r = 0.05;
        let pts = bridson::PoissonDisk2::new(d, r)
            .expect("sampler")
            .generate_seeded(3)
            .unwrap();
        let s = pair_stats(&pts, d, r);
        assert_eq!(s.closer_than_radius, 0, "the guarantee");
        let min = s.min_distance.expect("pairs");
        assert!(min >= r && min < 2.0 * r, "min distance {min}");
        let u = uncovered_fraction(&pts, d, r, 20_000, 9);
        assert!(u < 0.01, "nearly maximal: uncovered {u}");
    }

    #[test]
    fn one_point_covers_a_disc() {
        let d = Domain::from_extent([1.0, 1.0]).expect("box");
        let r = 0.25;
        let u = uncovered_fraction(&[[0.5, 0.5]], d, r, 40_000, 1);
        let expected = 1.0 - core::f64::consts::PI * r * r;
        // Binomial 1σ ≈ 0.0023.
        assert!((u - expected).abs() < 0.012, "{u} vs {expected}");
        let wrapped = d.with_periodic([true, true]);
        let u = uncovered_fraction(&[[0.0, 0.0]], wrapped, r, 40_000, 1);
        assert!((u - expected).abs() < 0.012, "periodic corner: {u}");
        assert_eq!(uncovered_fraction::<2>(&[], d, r, 100, 1), 1.0, "empty set");
    }

    #[test]
    fn the_grid_stays_small_for_a_huge_box() {
        let d = Domain::from_extent([1e9, 1e9]).expect("box");
        let pts = [[1.0, 1.0], [1.0, 2.5]];
        let g = PlaneGrid::new(&pts, d, 1.0);
        assert!(g.cells[0] * g.cells[1] <= 24, "cells {:?}", g.cells);
        let s = pair_stats(&pts, d, 1.0);
        assert_eq!(s.min_distance, Some(1.5), "min distance");
    }
}
