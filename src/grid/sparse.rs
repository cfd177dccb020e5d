//! The sparse background grid: cells of side `≈ r`, each with the list of
//! the points in it.
//!
//! Used where a dense grid would not fit the memory budget (a huge box) or
//! would search too many cells (5-D and above). Cells have side `≈ r`, so a
//! cell holds a few points and a search visits only the cells whose box comes
//! within `r` of the candidate, found by branch and bound over the axes:
//! about `Σ_k C(N,k)·V_k` cells (9 in 2-D, 50 in 4-D, 1 170 in 8-D).
//!
//! The lists live in one of two stores ([`Store`]): where the box holds few
//! cells (at most [`MAX_ARRAY_BYTES`] of list heads, and a quarter of the
//! budget), an array with a head per cell, so that each of those look-ups
//! is an index; otherwise a hash table of the occupied cells, whose memory
//! grows with the number of points, never with the volume of the box. Both
//! find a conflict exactly when there is one; which one they report first
//! may differ, which changes no decision of the sampler.

use super::{NeighbourGrid, SparsePlan};
use crate::budget::{bytes_of, reserve_one, vec_bytes};
use crate::domain::Domain;
use crate::vector::{distance_squared, periodic_distance_squared};
use core::hash::{BuildHasherDefault, Hasher};
use smallvec::SmallVec;
use std::collections::HashMap;

type Cell<const N: usize> = SmallVec<[[f64; N]; 2]>;

/// Heap bytes of a hash table (hashbrown's layout, which std's map uses)
/// that holds `capacity` entries of `entry` bytes: a power-of-two count of
/// buckets, 7/8 of them usable from 8 buckets up (3 of 4, 7 of 8 below);
/// one entry and one control byte a bucket, plus a group of control bytes
/// and alignment.
pub(crate) fn table_bytes(capacity: usize, entry: u64) -> u64 {
    if capacity == 0 {
        return 0;
    }
    let buckets = if capacity < 8 {
        capacity.saturating_add(1).next_power_of_two()
    } else {
        capacity.saturating_mul(8).div_ceil(7).next_power_of_two()
    };
    u64::try_from(buckets)
        .unwrap_or(u64::MAX)
        .saturating_mul(entry.saturating_add(1))
        .saturating_add(64)
}

/// Bytes of one entry of the map: a key and a cell.
fn entry_bytes<const N: usize>() -> u64 {
    bytes_of::<([i64; N], Cell<N>)>(1)
}

/// The most bytes of list heads (4 a cell) the array store may take: 64 MiB,
/// 16 M cells. Past it, most cells of any set Bridson makes stay empty, and
/// the hash table is smaller.
pub(crate) const MAX_ARRAY_BYTES: u64 = 64 << 20;

/// What storing the first point takes beyond what is allocated up front:
/// with the array store, the entries' first block (the sentinel and the
/// point); with the hash table, its smallest table (4 buckets); and one
/// active entry either way.
pub(crate) fn first_point_bytes<const N: usize>(array: bool) -> u64 {
    let store = if array {
        bytes_of::<Entry<N>>(2)
    } else {
        table_bytes(3, entry_bytes::<N>())
    };
    store.saturating_add(bytes_of::<[f64; N]>(1))
}

/// A stored point and the index of the next one in its cell's list
/// ([`END`] for none).
#[derive(Clone, Copy, Debug)]
struct Entry<const N: usize> {
    point: [f64; N],
    next: u32,
}

/// The most cells on one axis that can come within `r` of a candidate. The
/// sparse plan's cells have side `>= r` (or the axis has one cell), so its
/// reach is at most 2: five offsets, or at most five cells on a periodic
/// axis searched whole.
const MAX_STEPS: usize = 5;

/// One cell on one axis that a search visits: the square of a lower bound
/// on the distance to it along that axis, its index there, and that index
/// times the axis's stride in the array store (0 with the hash table).
#[derive(Clone, Copy, Debug, Default)]
struct Step {
    gap2: f64,
    key: i64,
    offset: usize,
}

/// The end of a list: entry 0 is a sentinel, never a point.
const END: u32 = 0;

/// The fewest cells of an array store for which a search starts loading
/// its nearest cells' points first: 64 Ki cells, whose heads take 256 KiB
/// and whose points, at about 0.7 a cell in a full set, take 2 MB from
/// 5-D up, past a core's L2 cache (512 KiB here), so that a search waits on
/// its cells' points. Below (6-D r = 0.2 in the unit box: 15 625 cells),
/// the points mostly stay in cache and the loads cost more than they save.
const PREFETCH_CELLS: usize = 1 << 16;

/// Where the cells' point lists are kept.
#[derive(Debug)]
enum Store<const N: usize> {
    /// A head per cell of the box, into one vector of entries.
    Array {
        heads: Vec<u32>,
        entries: Vec<Entry<N>>,
        stride: [usize; N],
    },
    /// The occupied cells only, each with its points inline (two) or on
    /// the heap.
    Table {
        map: HashMap<[i64; N], Cell<N>, BuildHasherDefault<CellHasher>>,
        /// Heap bytes of the cells that spilled out of their inline room.
        spilled: u64,
    },
}

impl<const N: usize> Store<N> {
    /// An array store for `counts` cells, if it can be allocated.
    fn array(counts: &[i64; N]) -> Option<Self> {
        let mut stride = [0usize; N];
        let mut total = 1usize;
        for (s, &m) in stride.iter_mut().zip(counts) {
            *s = total;
            total = total.checked_mul(usize::try_from(m).ok()?)?;
        }
        let mut heads = Vec::new();
        heads.try_reserve_exact(total).ok()?;
        heads.resize(total, END);
        let mut entries = Vec::new();
        entries.try_reserve_exact(1).ok()?;
        entries.push(Entry {
            point: [f64::INFINITY; N],
            next: END,
        });
        Some(Self::Array {
            heads,
            entries,
            stride,
        })
    }

    fn table() -> Self {
        Self::Table {
            map: HashMap::default(),
            spilled: 0,
        }
    }
}

/// Index of a cell (every coordinate in `0..counts`) in the array store.
#[inline(always)]
fn linear<const N: usize>(cell: &[i64; N], stride: &[usize; N]) -> usize {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "cell coordinates are in 0..counts, whose product fits usize"
    )]
    let index = cell.iter().zip(stride).map(|(&c, &s)| c as usize * s).sum();
    index
}

#[derive(Debug)]
pub(crate) struct Sparse<const N: usize> {
    store: Store<N>,
    lo: [f64; N],
    side: [f64; N],
    inv_side: [f64; N],
    counts: [i64; N],
    reach: [i64; N],
    eta: f64,
    periodic: [bool; N],
    any_periodic: bool,
    periods: [f64; N],
    radius_squared: f64,
    /// Whether a search starts loading its nearer cells' points
    /// ([`Self::nearer`]) before its own cell's check: an array store of at least
    /// [`PREFETCH_CELLS`] cells.
    prefetch: bool,
    /// Whether a search checks the cells nearer on one or two axes right
    /// after its own ([`Self::nearer`]): with the array store, unless a
    /// periodic axis has fewer than 3 cells (there both neighbours are one
    /// cell, half the computed ones are other cells, and the walk's bounds
    /// on nearest images skip more: the 8-D torus at r = 0.4, two cells an
    /// axis, took 1.31× the time with the check).
    nearer: bool,
}

impl<const N: usize> Sparse<N> {
    /// How many cells [`Self::nearer`] visits: `N` singles and
    /// `N(N-1)/2` pairs.
    const NEARER: usize = N * (N + 1) / 2;

    pub(crate) fn new(plan: &SparsePlan<N>, domain: &Domain<N>, radius: f64) -> Self {
        // The array only where planned; should it not be granted, the table
        // (whose memory is counted as it grows) serves instead.
        let store = if plan.array {
            Store::array(&plan.cells).unwrap_or_else(Store::table)
        } else {
            Store::table()
        };
        let prefetch =
            matches!(&store, Store::Array { heads, .. } if heads.len() >= PREFETCH_CELLS);
        let nearer = matches!(&store, Store::Array { .. })
            && (!domain.any_periodic() || plan.cells.iter().all(|&m| m >= 3));
        Self {
            prefetch,
            nearer,
            store,
            lo: domain.lo(),
            side: plan.side,
            inv_side: plan.side.map(|s| 1.0 / s),
            counts: plan.cells,
            reach: plan.reach,
            eta: plan.eta,
            periodic: domain.periodic(),
            any_periodic: domain.any_periodic(),
            periods: domain.periods(),
            radius_squared: radius * radius,
        }
    }

    #[inline(always)]
    fn cell_of(&self, p: &[f64; N]) -> [i64; N] {
        let mut cell = [0i64; N];
        let axes = self.lo.iter().zip(&self.inv_side).zip(&self.counts);
        for ((c, x), ((lo, inv_side), &m)) in cell.iter_mut().zip(p).zip(axes) {
            #[expect(
                clippy::cast_possible_truncation,
                reason = "saturating float-to-int cast, then clamped into the grid"
            )]
            let i = ((x - lo) * inv_side) as i64;
            // Not `clamp`, which panics if `m < 1` (never: see `cell_count`).
            *c = i.max(0).min(m - 1);
        }
        cell
    }

    /// The cells on `axis` that can hold a point closer than `r` to a
    /// candidate at `t` (from `lo`) in cell `c`, each with the square of a
    /// lower bound on the distance to it along that axis, into `out`,
    /// nearest first; returns how many, or `None` if more than
    /// [`MAX_STEPS`] (which the plan rules out: see there).
    #[inline(always)]
    fn axis_steps(
        &self,
        axis: usize,
        c: i64,
        t: f64,
        out: &mut [Step; MAX_STEPS],
    ) -> Option<usize> {
        let (Some(&m), Some(&reach), Some(&side), Some(&periodic)) = (
            self.counts.get(axis),
            self.reach.get(axis),
            self.side.get(axis),
            self.periodic.get(axis),
        ) else {
            return Some(0);
        };
        let stride = match &self.store {
            Store::Array { stride, .. } => stride.get(axis).copied().unwrap_or(0),
            Store::Table { .. } => 0,
        };
        // Distance along the axis from `t` to cell `c + d`, less the
        // rounding margin: a lower bound for any point filed there.
        let gap = |d: i64| {
            #[expect(clippy::cast_precision_loss, reason = "cell indices are <= 2^40")]
            let g = match d {
                0 => 0.0,
                d if d > 0 => ((c + d) as f64 - self.eta) * side - t,
                d => t - ((c + d + 1) as f64 + self.eta) * side,
            };
            g.max(0.0)
        };
        let mut n = 0;
        let mut push = |key: i64, gap: f64| {
            let gap2 = gap * gap;
            if gap2 >= self.radius_squared {
                return Some(());
            }
            #[expect(
                clippy::cast_sign_loss,
                clippy::cast_possible_truncation,
                reason = "keys are in 0..counts, whose product fits usize in the array store"
            )]
            let offset = key as usize * stride;
            *out.get_mut(n)? = Step { gap2, key, offset };
            n += 1;
            Some(())
        };
        if periodic && 2 * reach + 1 >= m {
            // The reach wraps onto itself: each cell once, at its nearest
            // image (periodic distances are per-axis minimums).
            for k in 0..m {
                let d = k - c;
                push(k, gap(d).min(gap(d - m)).min(gap(d + m)))?;
            }
        } else if reach <= 1 || gap(-2).min(gap(2)) * gap(-2).min(gap(2)) >= self.radius_squared {
            // No cell past ±1 within reach: the usual case, since cells
            // have side `>= r` and only a candidate within η of a face
            // reaches ±2. The own cell, the nearer neighbour, the farther:
            // already nearest first, no sort.
            // Each neighbour is written, and counted only if it exists and
            // is within reach: no branch on either, which depend on where
            // the candidate fell (about half the searches in 6-D meet a
            // face of the box on some axis).
            push(c, 0.0)?;
            if reach >= 1 {
                let (down, up) = (gap(-1), gap(1));
                let (near, far) = if up < down {
                    ((1, up), (-1, down))
                } else {
                    ((-1, down), (1, up))
                };
                for (d, g) in [near, far] {
                    let k = if periodic {
                        (c + d).rem_euclid(m)
                    } else {
                        c + d
                    };
                    let gap2 = g * g;
                    #[expect(
                        clippy::cast_sign_loss,
                        clippy::cast_possible_truncation,
                        reason = "keys are in -1..=counts, whose product fits usize in the \
                                  array store; -1 (no such cell) makes a stray offset, never counted"
                    )]
                    let offset = (k as usize).wrapping_mul(stride);
                    *out.get_mut(n)? = Step {
                        gap2,
                        key: k,
                        offset,
                    };
                    n += usize::from((k >= 0) & (k < m) & (gap2 < self.radius_squared));
                }
            }
            return Some(n);
        } else {
            // The own cell first, for an early exit, then -1, 1, -2, 2, …
            push(c, 0.0)?;
            for j in 1..=reach {
                for d in [-j, j] {
                    let k = c + d;
                    if periodic {
                        push(k.rem_euclid(m), gap(d))?;
                    } else if (0..m).contains(&k) {
                        push(k, gap(d))?;
                    }
                }
            }
        }
        // Nearest first: a conflict is found sooner (in a small torus every
        // cell holds close points), and a walk stops at the first step too
        // far. An insertion sort: at most five steps, nearly in order.
        let steps = out.get_mut(..n)?;
        for i in 1..steps.len() {
            let mut j = i;
            while j > 0 {
                let (Some(a), Some(b)) = (steps.get(j - 1), steps.get(j)) else {
                    break;
                };
                if a.gap2 <= b.gap2 {
                    break;
                }
                steps.swap(j - 1, j);
                j -= 1;
            }
        }
        Some(n)
    }

    /// Lists each axis's steps around `p`, in `cell`, (see
    /// [`Self::axis_steps`]) into `steps` and `lens`; `None` if an axis has
    /// more than the plan allows.
    #[inline(always)]
    fn steps(
        &self,
        p: &[f64; N],
        cell: &[i64; N],
        steps: &mut [[Step; MAX_STEPS]; N],
        lens: &mut [usize; N],
    ) -> Option<()> {
        let axes = cell.iter().zip(p).zip(&self.lo);
        for (axis, ((out, len), ((&c, &x), &lo))) in
            steps.iter_mut().zip(lens.iter_mut()).zip(axes).enumerate()
        {
            *len = self.axis_steps(axis, c, x - lo, out)?;
        }
        Some(())
    }

    /// Depth-first over the axes in `order`, through each axis's steps
    /// nearest first, while the bound summed over the axes so far stays
    /// below `limit_squared`; calls `visit` with each cell reached (its key
    /// and, for the array store, its index), stopping at the first `Some`.
    /// Iterative, and the last axis a plain loop: a search visits a dozen
    /// cells, and a call per cell cost more than the cells.
    #[inline(always)]
    fn walk<T>(
        steps: &[[Step; MAX_STEPS]; N],
        lens: &[usize; N],
        order: &[usize; N],
        limit_squared: f64,
        mut visit: impl FnMut(&[i64; N], usize) -> Option<T>,
    ) -> Option<T> {
        let mut key = [0i64; N];
        // Per depth: the step being tried, and the bound and index offset
        // summed over the axes before it.
        let mut at = [0usize; N];
        let mut partial = [0.0f64; N];
        let mut offset = [0usize; N];
        let last = N.checked_sub(1)?;
        let mut depth = 0;
        loop {
            // The cells along the last axis, from what the axes before
            // summed (`depth == last` only when `N == 1`).
            let (bound, base) = if depth == last {
                (0.0, 0)
            } else {
                let axis = *order.get(depth)?;
                let i = *at.get(depth)?;
                let s = steps
                    .get(axis)?
                    .get(i)
                    .filter(|_| i < *lens.get(axis).unwrap_or(&0))
                    .copied();
                let p = *partial.get(depth)?;
                match s {
                    Some(s) if p + s.gap2 < limit_squared => {
                        *key.get_mut(axis)? = s.key;
                        let o = *offset.get(depth)? + s.offset;
                        if depth + 1 < last {
                            depth += 1;
                            *at.get_mut(depth)? = 0;
                            *partial.get_mut(depth)? = p + s.gap2;
                            *offset.get_mut(depth)? = o;
                            continue;
                        }
                        (p + s.gap2, o)
                    }
                    _ => {
                        // This axis is done: back to the one before.
                        if depth == 0 {
                            return None;
                        }
                        depth -= 1;
                        *at.get_mut(depth)? += 1;
                        continue;
                    }
                }
            };
            let axis = *order.get(last)?;
            let n = *lens.get(axis)?;
            for s in steps.get(axis)?.iter().take(n) {
                if bound + s.gap2 >= limit_squared {
                    break;
                }
                *key.get_mut(axis)? = s.key;
                if let Some(found) = visit(&key, base + s.offset) {
                    return Some(found);
                }
            }
            if depth == last {
                return None;
            }
            *at.get_mut(depth)? += 1;
        }
    }

    /// [`NeighbourGrid::conflict`], with `close` the exact test.
    #[inline(always)]
    fn conflict_with(
        &self,
        p: &[f64; N],
        close: impl Fn(&[f64; N]) -> bool + Copy,
    ) -> Option<[f64; N]> {
        // The candidate's own cell first: it holds the conflict in a third
        // of the searches that find one in 5-D and 6-D (a fifth in 8-D),
        // and those skip listing the axes' steps. The walk visits it again
        // when it holds none, which costs less than a list of steps.
        let cell = self.cell_of(p);
        // The nearer cells' heads, listed once: loaded here, before the own
        // cell's check, where the store is large enough for their points
        // to be worth loading early.
        let mut near = None;
        if self.prefetch
            && let Store::Array { entries, .. } = &self.store
        {
            let mut heads = [[END; N]; N];
            let slots = heads.as_flattened_mut();
            let mut k = 0;
            self.nearer(p, &cell, |head| {
                crate::prefetch::prefetch(entries, head as usize);
                if let Some(slot) = slots.get_mut(k) {
                    *slot = head;
                }
                k += 1;
                None::<()>
            });
            near = Some(heads);
        }
        if let Some(q) = self.conflict_in(&cell, close) {
            return Some(q);
        }
        // Then the cells nearer on one or two axes, where most of the other
        // conflicts lie: a search that finds one there skips listing the
        // axes' steps and the walk. Without the early loads, the heads are
        // read as they are checked, up to the first conflict.
        if self.nearer
            && let Store::Array { entries, .. } = &self.store
        {
            let found = if let Some(heads) = near {
                let mut found = None;
                for &head in heads.as_flattened().iter().take(Self::NEARER) {
                    found = first_close(entries, head, close);
                    if found.is_some() {
                        break;
                    }
                }
                found
            } else {
                self.nearer(p, &cell, |head| first_close(entries, head, close))
            };
            if found.is_some() {
                return found;
            }
        }
        let mut steps = [[Step::default(); MAX_STEPS]; N];
        let mut lens = [0usize; N];
        // More steps than the plan allows cannot happen; were it to, the
        // candidate is refused: the set stays valid.
        if self.steps(p, &cell, &mut steps, &mut lens).is_none() {
            return Some(*p);
        }
        self.search(&steps, &lens, close)
    }

    /// Calls `visit` with the head of each cell next to `p`'s own (`cell`)
    /// on the nearer side along one axis, then along two, with the array
    /// store, stopping at the first `Some`: [`Self::NEARER`] cells, the
    /// singles in axis order, then the pairs `(i, j)`, `i < j`, by `j`,
    /// then `i`. Most conflicts not in the own cell lie in one of them.
    /// (Axes ordered by the gap to their nearer face instead looked at
    /// 11 % fewer cells in 5-D but took longer.) An index off the box (a
    /// face, a periodic wrap) names another cell or none: a wasted look,
    /// never a missed one, since the full search follows.
    #[inline(always)]
    fn nearer<T>(
        &self,
        p: &[f64; N],
        cell: &[i64; N],
        mut visit: impl FnMut(u32) -> Option<T>,
    ) -> Option<T> {
        let Store::Array { heads, stride, .. } = &self.store else {
            return None;
        };
        let own = linear(cell, stride);
        let mut step = [0usize; N];
        let axes = self.lo.iter().zip(&self.inv_side).zip(stride);
        for (n, ((&c, x), ((lo, inv_side), &s))) in
            step.iter_mut().zip(cell.iter().zip(p).zip(axes))
        {
            #[expect(clippy::cast_precision_loss, reason = "cell indices are <= 2^40")]
            let upper = (x - lo) * inv_side - c as f64 >= 0.5;
            *n = if upper { s } else { s.wrapping_neg() };
        }
        let head = |at: usize| heads.get(at).copied().unwrap_or(END);
        for &a in &step {
            if let Some(found) = visit(head(own.wrapping_add(a))) {
                return Some(found);
            }
        }
        for (j, &b) in step.iter().enumerate().skip(1) {
            let at = own.wrapping_add(b);
            for &a in step.iter().take(j) {
                if let Some(found) = visit(head(at.wrapping_add(a))) {
                    return Some(found);
                }
            }
        }
        None
    }

    /// A stored point of `cell` for which `close` holds, if any.
    #[inline(always)]
    fn conflict_in(
        &self,
        cell: &[i64; N],
        close: impl Fn(&[f64; N]) -> bool + Copy,
    ) -> Option<[f64; N]> {
        match &self.store {
            Store::Array {
                heads,
                entries,
                stride,
            } => {
                let head = heads.get(linear(cell, stride)).copied().unwrap_or(END);
                first_close(entries, head, close)
            }
            Store::Table { map, .. } => map.get(cell)?.iter().find(|q| close(q)).copied(),
        }
    }

    /// The first stored point closer than `r` to `p` among the cells the
    /// steps reach.
    #[inline(always)]
    fn search(
        &self,
        steps: &[[Step; MAX_STEPS]; N],
        lens: &[usize; N],
        close: impl Fn(&[f64; N]) -> bool + Copy,
    ) -> Option<[f64; N]> {
        let r2 = self.radius_squared;
        let order = nearest_last(steps, lens);
        match &self.store {
            Store::Array { heads, entries, .. } => {
                Self::walk(steps, lens, &order, r2, |_, index| {
                    first_close(entries, heads.get(index).copied().unwrap_or(END), close)
                })
            }
            Store::Table { map, .. } => Self::walk(steps, lens, &order, r2, |key, _| {
                map.get(key)?.iter().find(|q| close(q)).copied()
            }),
        }
    }
}

/// The first point of the list that starts at entry `at` for which
/// `close` holds.
///
/// The first entry is tested even for an empty list, whose head is the
/// sentinel (entry 0, at infinity: never close, and always in cache): a
/// search meets empty and occupied cells in random order, and a branch on
/// it was mispredicted more than any other in the search (a third of them
/// in 6-D, cachegrind's model); the loop's exit after one point is the
/// common, predictable case.
#[inline(always)]
fn first_close<const N: usize>(
    entries: &[Entry<N>],
    mut at: u32,
    close: impl Fn(&[f64; N]) -> bool,
) -> Option<[f64; N]> {
    loop {
        let entry = entries.get(at as usize)?;
        if close(&entry.point) {
            return Some(entry.point);
        }
        at = entry.next;
        if at == END {
            return None;
        }
    }
}

/// The order in which a search walks the axes: the axis whose nearest
/// neighbour cell is nearest last, since the walk runs along the last axis
/// first. The cells it visits first then hold the most of the ball around
/// the candidate, and a conflict is found sooner: in 5-D to 8-D, 29 % to
/// 56 % fewer cells in searches that find one.
#[inline(always)]
fn nearest_last<const N: usize>(steps: &[[Step; MAX_STEPS]; N], lens: &[usize; N]) -> [usize; N] {
    let mut near = [f64::INFINITY; N];
    for (g, (s, &n)) in near.iter_mut().zip(steps.iter().zip(lens)) {
        if n > 1 {
            *g = s.get(1).map_or(f64::INFINITY, |s| s.gap2);
        }
    }
    // Farthest first, ties in axis order (a stable sort), by rank: each
    // axis's place is the count of the axes that go before it. No branch:
    // the gaps are random, and an insertion sort's branches were
    // mispredicted about half the time.
    let mut order = [0usize; N];
    for (axis, g) in near.iter().enumerate() {
        let rank = near
            .iter()
            .enumerate()
            .map(|(other, h)| usize::from((h > g) | ((h == g) & (other < axis))))
            .sum::<usize>();
        if let Some(slot) = order.get_mut(rank) {
            *slot = axis;
        }
    }
    order
}

impl<const N: usize> NeighbourGrid<N> for Sparse<N> {
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]> {
        // Squares summed in axis order either way; on a bounded box
        // without the per-axis test for a period (`|x - y|` squares as
        // `x - y` does: the same bits).
        let r2 = self.radius_squared;
        if self.any_periodic {
            self.conflict_with(p, |q| periodic_distance_squared(p, q, &self.periods) < r2)
        } else {
            self.conflict_with(p, |q| distance_squared(p, q) < r2)
        }
    }

    fn bytes(&self) -> u64 {
        match &self.store {
            Store::Array { heads, entries, .. } => {
                vec_bytes(heads).saturating_add(vec_bytes(entries))
            }
            Store::Table { map, spilled } => {
                table_bytes(map.capacity(), entry_bytes::<N>()).saturating_add(*spilled)
            }
        }
    }

    fn reserve(&mut self, p: &[f64; N], spare: u64) -> bool {
        let cell = self.cell_of(p);
        let (map, spilled) = match &mut self.store {
            Store::Array { entries, .. } => return reserve_one(entries, spare).is_some(),
            Store::Table { map, spilled } => (map, spilled),
        };
        if let Some(points) = map.get_mut(&cell) {
            if points.len() < points.capacity() {
                return true;
            }
            // A full cell moves to a heap block twice its size.
            let wanted = points.capacity().saturating_mul(2);
            if bytes_of::<[f64; N]>(wanted) > spare {
                return false;
            }
            let before = heap_bytes(points);
            if points.try_reserve_exact(wanted - points.len()).is_err() {
                return false;
            }
            *spilled = spilled.saturating_add(heap_bytes(points) - before);
            return true;
        }
        let (len, capacity) = (map.len(), map.capacity());
        if len < capacity {
            return true;
        }
        // A full table moves to one with twice the buckets; both are held
        // while the entries move.
        let entry = entry_bytes::<N>();
        let wanted = capacity.saturating_mul(2).max(3);
        if table_bytes(wanted, entry) > spare {
            return false;
        }
        map.try_reserve(wanted - len).is_ok()
    }

    fn insert(&mut self, p: [f64; N]) -> bool {
        let cell = self.cell_of(&p);
        match &mut self.store {
            Store::Array {
                heads,
                entries,
                stride,
            } => {
                // u32 indices: past them the run ends, the set stays valid.
                let (Ok(at), Some(head)) = (
                    u32::try_from(entries.len()),
                    heads.get_mut(linear(&cell, stride)),
                ) else {
                    return false;
                };
                entries.push(Entry {
                    point: p,
                    next: *head,
                });
                *head = at;
            }
            Store::Table { map, spilled } => {
                let points = map.entry(cell).or_default();
                let before = heap_bytes(points);
                points.push(p);
                *spilled = spilled.saturating_add(heap_bytes(points).saturating_sub(before));
            }
        }
        true
    }
}

/// Heap bytes of a cell: none while its points fit inline.
fn heap_bytes<const N: usize>(points: &Cell<N>) -> u64 {
    if points.spilled() {
        bytes_of::<[f64; N]>(points.capacity())
    } else {
        0
    }
}

/// A small multiplicative hasher for integer cell keys (in the manner of
/// FxHash, with a final mix so that the low bits used for buckets depend on
/// every input bit). Keys are not attacker-controlled secrets, and SipHash
/// would cost more than the whole distance check.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CellHasher(u64);

impl CellHasher {
    const K: u64 = 0xf135_7aea_2e62_a9c5;

    #[inline(always)]
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(26) ^ word).wrapping_mul(Self::K);
    }
}

impl Hasher for CellHasher {
    #[inline(always)]
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            if let Some(head) = word.get_mut(..chunk.len()) {
                head.copy_from_slice(chunk);
            }
            self.add(u64::from_le_bytes(word));
        }
    }

    #[inline(always)]
    fn write_u64(&mut self, word: u64) {
        self.add(word);
    }

    #[inline(always)]
    fn write_usize(&mut self, word: usize) {
        self.add(word as u64);
    }

    #[inline(always)]
    fn finish(&self) -> u64 {
        let mut x = self.0;
        x ^= x >> 32;
        x = x.wrapping_mul(Self::K);
        x ^ (x >> 29)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{GridLayout, GridPlan, SparsePlan, plan};
    use super::*;

    fn sparse<const N: usize>(domain: &Domain<N>, r: f64) -> Sparse<N> {
        match plan(domain, r, GridLayout::Sparse, 1 << 30, None, None) {
            Ok(GridPlan::Sparse(p)) => Sparse::new(&p, domain, r),
            other => panic!("no sparse plan: {other:?}"),
        }
    }

    #[test]
    fn finds_neighbours_in_every_direction() {
        let d = Domain::from_extent([1.0; 3]).unwrap();
        // Dyadic values: 0.5 ± 0.125 is exactly r away.
        let mut g = sparse(&d, 0.125);
        assert!(g.insert([0.5, 0.5, 0.5]), "insert");
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut q = [0.5; 3];
                q[axis] += sign * 0.124;
                assert!(g.conflict(&q).is_some(), "axis {axis} sign {sign}");
                q[axis] = 0.5 + sign * 0.125;
                assert!(
                    g.conflict(&q).is_none(),
                    "exactly r is allowed: axis {axis}"
                );
            }
        }
    }

    /// Both stores against a brute-force check, in 1-D to 8-D, bounded and
    /// periodic, for radii small and large against the box (periodic axes
    /// searched whole), with points on and next to cell faces, where a
    /// rounded cell index is off by one.
    #[test]
    fn both_stores_find_exactly_the_conflicts_brute_force_finds() {
        /// Returns whether the array store prefetches and checks the
        /// nearer cells first ([`Sparse::nearer`]), and how many candidates
        /// had a conflict.
        fn check<const N: usize>(
            extent: f64,
            periodic: [bool; N],
            r: f64,
            seed: u64,
        ) -> (bool, usize) {
            use crate::random::{below, seeded_rng, symmetric, unit};
            let d = Domain::new([-0.3; N], [extent - 0.3; N])
                .unwrap()
                .with_periodic(periodic);
            let Ok(GridPlan::Sparse(p)) = plan(&d, r, GridLayout::Sparse, 1 << 30, None, None)
            else {
                panic!("no sparse plan");
            };
            let mut grids = [
                Sparse::new(&SparsePlan { array: true, ..p }, &d, r),
                Sparse::new(&SparsePlan { array: false, ..p }, &d, r),
            ];
            assert!(matches!(grids[0].store, Store::Array { .. }), "array store");
            assert!(matches!(grids[1].store, Store::Table { .. }), "table store");
            let periods = d.periods();
            let mut rng = seeded_rng(seed);
            let mut stored: Vec<[f64; N]> = Vec::new();
            let mut conflicts = 0;
            for i in 0..600 {
                // A third of the candidates, once there are points, near
                // one of them: within r of it about half the time.
                let near = (!stored.is_empty() && unit(&mut rng) < 0.3)
                    .then(|| stored[below(&mut rng, stored.len())]);
                let mut q = [0.0; N];
                for (axis, x) in q.iter_mut().enumerate() {
                    let (lo, side) = (d.lo()[axis], p.side[axis]);
                    *x = if let Some(a) = near {
                        a[axis] + symmetric(&mut rng) * 0.7 * r
                    } else if unit(&mut rng) < 0.3 {
                        // On a cell face, or an ulp either side.
                        let cells = usize::try_from(p.cells[axis]).unwrap();
                        let face = lo + below(&mut rng, cells + 3) as f64 * side;
                        match below(&mut rng, 3) {
                            0 => face.next_down(),
                            1 => face,
                            _ => face.next_up(),
                        }
                    } else {
                        lo + unit(&mut rng) * extent
                    };
                }
                if !d.contains(&q) {
                    continue;
                }
                let close = |a: &[f64; N]| periodic_distance_squared(a, &q, &periods) < r * r;
                let expected = stored.iter().any(close);
                conflicts += usize::from(expected);
                for (g, name) in grids.iter().zip(["array", "table"]) {
                    let found = g.conflict(&q);
                    assert_eq!(
                        found.is_some(),
                        expected,
                        "{N}-D {name} r = {r}, seed {seed}, #{i} {q:?}"
                    );
                    if let Some(a) = found {
                        assert!(
                            close(&a),
                            "{N}-D {name}: reported {a:?} is not closer than r"
                        );
                    }
                }
                if !expected {
                    for g in &mut grids {
                        assert!(g.reserve(&q, u64::MAX) && g.insert(q), "insert");
                    }
                    stored.push(q);
                }
            }
            assert!(
                stored.len() > 1,
                "{N}-D r = {r}: only {} points",
                stored.len()
            );
            (grids[0].prefetch && grids[0].nearer, conflicts)
        }
        for seed in 0..3 {
            for periodic in [false, true] {
                check::<1>(1.0, [periodic], 0.05, seed);
                check::<2>(1.0, [periodic, false], 0.1, seed);
                check::<2>(1.0, [periodic; 2], 0.45, seed);
                check::<3>(1.0, [periodic; 3], 0.2, seed);
                check::<4>(1.0, [false, periodic, true, periodic], 0.3, seed);
                check::<5>(1.0, [periodic; 5], 0.2, seed);
                // 10^5 cells: the path that checks the nearer cells first.
                let (nearer, conflicts) = check::<5>(1.0, [periodic; 5], 0.1, seed);
                assert!(
                    nearer && conflicts > 50,
                    "nearer cells: {conflicts} conflicts"
                );
                check::<5>(1.0, [periodic; 5], 0.5, seed);
                check::<6>(1.0, [periodic; 6], 0.3, seed);
                check::<7>(1.0, [periodic; 7], 0.4, seed);
                check::<8>(1.0, [periodic; 8], 0.4, seed);
                check::<8>(1.0, [periodic; 8], 0.7, seed);
            }
        }
    }

    /// Each axis's steps are exactly the cells within reach whose gap is
    /// below `r`, nearest first, whether listed by the short path (no cell
    /// past ±1 in reach) or the general one (a candidate within η of a
    /// face, a periodic axis searched whole).
    #[test]
    fn axis_steps_list_every_cell_in_reach_nearest_first() {
        use crate::random::{below, seeded_rng, unit};
        let mut rng = seeded_rng(9);
        let (mut short, mut general) = (0, 0);
        for (extent, periodic, r) in [
            (1.0, false, 0.1),
            (1.0, true, 0.1),
            (1.0, false, 0.3),
            (1.0, true, 0.4),
            (0.35, true, 0.1),
            (0.05, false, 0.1),
        ] {
            let d = Domain::from_extent([extent; 2])
                .unwrap()
                .with_periodic([periodic; 2]);
            let g = sparse(&d, r);
            let (m, side, reach) = (g.counts[0], g.side[0], g.reach[0]);
            let whole = periodic && 2 * reach + 1 >= m;
            for round in 0..3000 {
                let c = i64::try_from(below(&mut rng, usize::try_from(m).unwrap())).unwrap();
                // A point in cell `c`, a third of them on a face or an ulp
                // from it, where the cell index may be off by one.
                #[expect(clippy::cast_precision_loss, reason = "small")]
                let face = c as f64 * side;
                let t = match below(&mut rng, 6) {
                    0 => face.next_up(),
                    1 => face,
                    2 => ((c + 1) as f64 * side).next_down(),
                    _ => face + unit(&mut rng) * side,
                };
                let mut out = [Step::default(); MAX_STEPS];
                let n = g.axis_steps(0, c, t, &mut out).unwrap();
                let far_in_reach = (2..=reach).any(|j| {
                    [-j, j].iter().any(|&dd| {
                        let k = c + dd;
                        (periodic || (0..m).contains(&k)) && {
                            let (lo, hi) = (k as f64 * side, (k + 1) as f64 * side);
                            let gap = (lo - t).max(t - hi).max(0.0) - g.eta * side;
                            gap * gap < r * r
                        }
                    })
                });
                if whole || far_in_reach {
                    general += 1;
                } else {
                    short += 1;
                }
                let steps = &out[..n];
                assert!(
                    steps.windows(2).all(|w| w[0].gap2 <= w[1].gap2),
                    "round {round}: not nearest first: {steps:?}"
                );
                // Every cell within reach (each once on a periodic axis
                // searched whole) whose gap, less the margin, is below r.
                let mut expected: Vec<i64> = Vec::new();
                let offsets: Vec<i64> = if whole {
                    (0..m).map(|k| k - c).collect()
                } else {
                    (-reach..=reach).collect()
                };
                for dd in offsets {
                    let k = if periodic {
                        (c + dd).rem_euclid(m)
                    } else {
                        c + dd
                    };
                    if !(0..m).contains(&k) {
                        continue;
                    }
                    let images: &[i64] = if whole { &[-1, 0, 1] } else { &[0] };
                    let gap = images
                        .iter()
                        .map(|&w| {
                            let at = c + dd + w * m;
                            let (lo, hi) = (at as f64 * side, (at + 1) as f64 * side);
                            (lo - t).max(t - hi).max(0.0)
                        })
                        .fold(f64::INFINITY, f64::min);
                    // Plainly inside or plainly out: the margin decides
                    // only within 2η cells of r.
                    if gap < r * (1.0 - 4.0 * g.eta) || dd == 0 {
                        expected.push(k);
                    } else if gap > r + 2.0 * g.eta * side {
                        continue;
                    } else if steps.iter().any(|s| s.key == k) {
                        expected.push(k);
                    }
                }
                let mut listed: Vec<i64> = steps.iter().map(|s| s.key).collect();
                listed.sort_unstable();
                expected.sort_unstable();
                assert_eq!(
                    listed, expected,
                    "extent {extent}, periodic {periodic}, r {r}, c {c}, t {t}"
                );
            }
        }
        assert!(
            short > 1000 && general > 100,
            "paths: {short} short, {general} general"
        );
    }

    #[test]
    fn wraps_on_periodic_axes() {
        let d = Domain::from_extent([1.0, 0.25])
            .unwrap()
            .with_periodic([true, true]);
        let mut g = sparse(&d, 0.1);
        assert!(g.insert([0.99, 0.01]), "insert");
        assert!(g.conflict(&[0.02, 0.24]).is_some(), "both axes wrap");
        assert!(g.conflict(&[0.5, 0.12]).is_none(), "far");
    }
}
