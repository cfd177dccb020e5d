//! Weighted sample elimination on the unit torus, after Yuksel (2015,
//! "Sample Elimination for Generating Poisson Disk Sample Sets"): thin a
//! set of points to exactly `n` by repeatedly removing the point most
//! crowded by its neighbours.
//!
//! Used to turn a Bridson set, which has about (never exactly) the wanted
//! count, into a set of exactly `n` points. Removing points never brings
//! two closer, so the Bridson set's minimum distance is kept.

/// The largest minimum distance `n` points can have in the unit volume,
/// from the densest packing: `1/n` on the line, the hexagonal lattice's
/// `sqrt(2 / (√3 n))` in the plane. Only `N = 1` and `N = 2` are used.
pub(crate) fn max_min_distance<const N: usize>(n: usize) -> f64 {
    #[expect(clippy::cast_precision_loss, reason = "a count, in a ratio")]
    let n = n.max(1) as f64;
    if N == 1 {
        1.0 / n
    } else {
        (2.0 / (3f64.sqrt() * n)).sqrt()
    }
}

/// Squared toroidal distance on the unit torus, summed in axis order: the
/// difference on each axis is `min(|Δ|, 1 - |Δ|)`.
#[inline]
pub(crate) fn torus_distance_squared<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    let mut acc = 0.0;
    for (x, y) in a.iter().zip(b) {
        let d = (x - y).abs();
        let d = d.min(1.0 - d);
        acc += d * d;
    }
    acc
}

/// A uniform grid over the unit torus with cells at least `reach` wide, so
/// that every point within `reach` of a point lies in its cell or one of
/// the `3^N` around it.
struct TorusGrid<const N: usize> {
    /// Cells per axis; 1 when fewer than 3 would fit (then every point is
    /// in the one cell, and each is checked once).
    side: usize,
    /// Point indices of each cell, cell-major.
    cells: Vec<Vec<usize>>,
}

impl<const N: usize> TorusGrid<N> {
    fn new(points: &[[f64; N]], reach: f64) -> Self {
        // floor(1 / reach) cells of side >= reach; capped so the grid stays
        // near the point count.
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a positive, bounded cell count"
        )]
        let fit = (1.0 / reach).floor().clamp(1.0, 4096.0) as usize;
        let side = if fit < 3 { 1 } else { fit };
        let mut cells = vec![Vec::new(); power::<N>(side)];
        for (i, p) in points.iter().enumerate() {
            if let Some(cell) = cells.get_mut(Self::cell_of(side, p)) {
                cell.push(i);
            }
        }
        Self { side, cells }
    }

    fn coord(side: usize, x: f64) -> usize {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            clippy::cast_precision_loss,
            reason = "x in [0, 1) times a small count"
        )]
        let c = (x * side as f64) as usize;
        c.min(side - 1)
    }

    fn cell_of(side: usize, p: &[f64; N]) -> usize {
        p.iter()
            .rev()
            .fold(0, |acc, &x| acc * side + Self::coord(side, x))
    }

    /// Every point index in the cells around `p` (each cell once).
    fn around(&self, p: &[f64; N], mut visit: impl FnMut(usize)) {
        if self.side == 1 {
            self.cells.iter().flatten().for_each(|&j| visit(j));
            return;
        }
        let centre = p.map(|x| Self::coord(self.side, x));
        // 3^N offsets, each axis in {-1, 0, +1} modulo the side (>= 3, so
        // the three are distinct).
        for code in 0..power::<N>(3) {
            let mut index = 0;
            let mut rest = code;
            let mut stride = 1;
            for &c in &centre {
                let shifted = (c + self.side + rest % 3 - 1) % self.side;
                index += shifted * stride;
                stride *= self.side;
                rest /= 3;
            }
            if let Some(cell) = self.cells.get(index) {
                cell.iter().for_each(|&j| visit(j));
            }
        }
    }
}

/// `base^N`.
fn power<const N: usize>(base: usize) -> usize {
    (0..N).fold(1, |acc, _| acc * base)
}

/// A max-heap of point indices ordered by weight (ties to the larger
/// index, so the order is total and the result reproducible), tracking each
/// point's position so that a weight can drop in place.
struct WeightHeap {
    /// Point indices in heap order.
    heap: Vec<usize>,
    /// `position[i]`: where point `i` sits in `heap`, if still there.
    position: Vec<usize>,
    weight: Vec<f64>,
}

// Every index below is a heap slot `< heap.len()` or a point `< weight.len()
// == position.len()`: points enter once, at construction, and slots are
// checked against the length before use.
#[expect(
    clippy::indexing_slicing,
    reason = "slots are < heap.len() and points < weight.len(), see above"
)]
impl WeightHeap {
    fn new(weight: Vec<f64>) -> Self {
        let m = weight.len();
        let mut h = Self {
            heap: (0..m).collect(),
            position: (0..m).collect(),
            weight,
        };
        for slot in (0..m / 2).rev() {
            h.sift_down(slot);
        }
        h
    }

    /// Whether point `a` comes out before point `b`.
    fn above(&self, a: usize, b: usize) -> bool {
        self.weight[a]
            .total_cmp(&self.weight[b])
            .then(a.cmp(&b))
            .is_gt()
    }

    fn swap(&mut self, s: usize, t: usize) {
        self.heap.swap(s, t);
        self.position[self.heap[s]] = s;
        self.position[self.heap[t]] = t;
    }

    fn sift_down(&mut self, mut slot: usize) {
        loop {
            let (left, right) = (2 * slot + 1, 2 * slot + 2);
            let mut top = slot;
            if left < self.heap.len() && self.above(self.heap[left], self.heap[top]) {
                top = left;
            }
            if right < self.heap.len() && self.above(self.heap[right], self.heap[top]) {
                top = right;
            }
            if top == slot {
                return;
            }
            self.swap(slot, top);
            slot = top;
        }
    }

    /// Removes and returns the heaviest point.
    fn pop(&mut self) -> Option<usize> {
        let last = self.heap.len().checked_sub(1)?;
        self.swap(0, last);
        let top = self.heap.pop()?;
        self.sift_down(0);
        Some(top)
    }

    /// Lowers the weight of point `i`, still in the heap, by `by >= 0`.
    fn lower(&mut self, i: usize, by: f64) {
        self.weight[i] -= by;
        self.sift_down(self.position[i]);
    }
}

/// `(1 - d / reach)^8`, Yuksel's weight with exponent α = 8, by repeated
/// squaring (correctly rounded steps only, so the same bits everywhere).
fn weight(d: f64, reach: f64) -> f64 {
    let t = 1.0 - d / reach;
    let t2 = t * t;
    let t4 = t2 * t2;
    t4 * t4
}

/// The `n` points of `points` that survive weighted elimination, in their
/// input order. `points` lie in the unit torus `[0, 1)^N`; if there are no
/// more than `n`, all are kept.
///
/// Each point `i` carries the weight `Σ_j (1 - d̂_ij / R)^8` over its
/// neighbours `j` closer than `R`, the largest minimum distance `n` points
/// can have, with `d̂ = max(d, r_min)` and
/// `r_min = R · (1 - (n/m)^1.5) · 0.65` (`m` input points), Yuksel's
/// defaults. The heaviest point is removed and its neighbours' weights
/// drop, until `n` remain.
pub(crate) fn eliminate<const N: usize>(points: &[[f64; N]], n: usize) -> Vec<[f64; N]> {
    let m = points.len();
    if m <= n {
        return points.to_vec();
    }
    let reach = max_min_distance::<N>(n);
    #[expect(clippy::cast_precision_loss, reason = "counts, in a ratio")]
    let ratio = n as f64 / m as f64;
    let r_min = reach * (1.0 - ratio * ratio.sqrt()) * 0.65;
    let grid = TorusGrid::new(points, reach);
    let reach_squared = reach * reach;

    // Neighbour lists with their weights, back to back (`starts[i]..
    // starts[i + 1]` for point i), in the grid's fixed visiting order, so
    // each total sums in a reproducible order; and each point's total.
    let mut starts = Vec::with_capacity(m + 1);
    let mut links: Vec<(usize, f64)> = Vec::new();
    let mut totals = Vec::with_capacity(m);
    for (i, p) in points.iter().enumerate() {
        starts.push(links.len());
        let mut total = 0.0;
        grid.around(p, |j| {
            if let Some(q) = points.get(j) {
                let d2 = torus_distance_squared(p, q);
                if j != i && d2 < reach_squared {
                    let w = weight(d2.sqrt().max(r_min), reach);
                    total += w;
                    links.push((j, w));
                }
            }
        });
        totals.push(total);
    }
    starts.push(links.len());

    let mut heap = WeightHeap::new(totals);
    let mut removed = vec![false; m];
    for _ in n..m {
        let Some(i) = heap.pop() else { break };
        if let Some(r) = removed.get_mut(i) {
            *r = true;
        }
        let range = starts.get(i).copied().unwrap_or(0)..starts.get(i + 1).copied().unwrap_or(0);
        for &(j, w) in links.get(range).into_iter().flatten() {
            if !removed.get(j).copied().unwrap_or(true) {
                heap.lower(j, w);
            }
        }
    }
    points
        .iter()
        .zip(&removed)
        .filter(|&(_, &gone)| !gone)
        .map(|(p, _)| *p)
        .collect()
}

/// The smallest toroidal distance between two of `points`, or `None` for
/// fewer than two. Searches the grid within the packing bound first and
/// falls back to all pairs when no pair is that close.
pub(crate) fn min_distance<const N: usize>(points: &[[f64; N]]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let reach = max_min_distance::<N>(points.len());
    let grid = TorusGrid::new(points, reach);
    let mut best = f64::INFINITY;
    for (i, p) in points.iter().enumerate() {
        grid.around(p, |j| {
            if let Some(q) = points.get(j)
                && j != i
            {
                best = best.min(torus_distance_squared(p, q));
            }
        });
    }
    if best >= reach * reach {
        for (i, p) in points.iter().enumerate() {
            for q in points.iter().skip(i + 1) {
                best = best.min(torus_distance_squared(p, q));
            }
        }
    }
    Some(best.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::hash::mix;

    /// `m` hashed uniform points.
    fn uniform<const N: usize>(m: usize, seed: u64) -> Vec<[f64; N]> {
        let mut state = mix(seed);
        (0..m)
            .map(|_| {
                core::array::from_fn(|_| {
                    state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
                    (mix(state) >> 11) as f64 / (1u64 << 53) as f64
                })
            })
            .collect()
    }

    fn naive_min<const N: usize>(points: &[[f64; N]]) -> f64 {
        let mut best = f64::INFINITY;
        for (i, p) in points.iter().enumerate() {
            for q in &points[..i] {
                best = best.min(torus_distance_squared(p, q));
            }
        }
        best.sqrt()
    }

    #[test]
    fn keeps_exactly_n_points_of_the_input() {
        for (m, n) in [(10, 1), (50, 7), (400, 100), (1000, 999), (5, 5), (3, 9)] {
            let input = uniform::<2>(m, 3);
            let out = eliminate(&input, n);
            assert_eq!(out.len(), n.min(m), "m={m} n={n}");
            assert!(
                out.iter().all(|p| input.contains(p)),
                "m={m} n={n}: new point"
            );
        }
    }

    #[test]
    fn spreads_random_points() {
        // Eliminating 5n uniform points to n leaves a far larger minimum
        // distance than n uniform points have (ρ about 0.6 against ~0.05).
        let n = 256;
        let out = eliminate(&uniform::<2>(5 * n, 4), n);
        let rho = naive_min(&out) / max_min_distance::<2>(n);
        assert!(rho > 0.5, "ρ = {rho}");
        let out = eliminate(&uniform::<1>(5 * n, 5), n);
        let rho = naive_min(&out) / max_min_distance::<1>(n);
        assert!(rho > 0.4, "1-D ρ = {rho}");
    }

    #[test]
    fn grid_minimum_matches_all_pairs() {
        for (m, seed) in [(2, 1), (3, 2), (40, 3), (500, 4)] {
            let p2 = uniform::<2>(m, seed);
            assert_eq!(min_distance(&p2), Some(naive_min(&p2)), "2-D m={m}");
            let p1 = uniform::<1>(m, seed);
            assert_eq!(min_distance(&p1), Some(naive_min(&p1)), "1-D m={m}");
        }
        assert_eq!(min_distance::<2>(&[[0.5, 0.5]]), None, "one point");
        // Across the seam: 0.01 apart through the wrap.
        let d = min_distance(&[[0.995, 0.5], [0.005, 0.5]]).unwrap();
        assert!((d - 0.01).abs() < 1e-12, "toroidal distance {d}");
    }
}
