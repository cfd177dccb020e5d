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
use crate::vector::{periodic_distance_squared, zip_map};
use core::hash::{BuildHasherDefault, Hasher};
use smallvec::SmallVec;
use std::collections::HashMap;

type Cell<const N: usize> = SmallVec<[[f64; N]; 2]>;

/// Heap bytes of a hash table (hashbrown's layout, which std's map uses)
/// that holds `capacity` entries of `entry` bytes: a power-of-two count of
/// buckets, 7/8 of them usable from 8 buckets up (3 of 4, 7 of 8 below);
/// one entry and one control byte a bucket, plus a group of control bytes
/// and alignment.
fn table_bytes(capacity: usize, entry: u64) -> u64 {
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

/// One cell on one axis that a search visits: its index there and the
/// square of a lower bound on the distance to it along that axis.
#[derive(Clone, Copy, Debug, Default)]
struct Step {
    key: i64,
    gap2: f64,
}

/// The end of a list: entry 0 is a sentinel, never a point.
const END: u32 = 0;

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
    periods: [f64; N],
    radius_squared: f64,
}

impl<const N: usize> Sparse<N> {
    pub(crate) fn new(plan: &SparsePlan<N>, domain: &Domain<N>, radius: f64) -> Self {
        // The array only where planned; should it not be granted, the table
        // (whose memory is counted as it grows) serves instead.
        let store = if plan.array {
            Store::array(&plan.cells).unwrap_or_else(Store::table)
        } else {
            Store::table()
        };
        Self {
            store,
            lo: domain.lo(),
            side: plan.side,
            inv_side: plan.side.map(|s| 1.0 / s),
            counts: plan.cells,
            reach: plan.reach,
            eta: plan.eta,
            periodic: domain.periodic(),
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
    /// nearest first;
    /// returns how many, or `None` if more than [`MAX_STEPS`]
    /// (which the plan rules out: see there).
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
            *out.get_mut(n)? = Step { key, gap2 };
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
        } else {
            // 0, -1, 1, -2, 2, …: the own cell first, for an early exit.
            for j in 0..=2 * reach {
                let d = if j % 2 == 1 { -(j + 1) / 2 } else { j / 2 };
                let k = c + d;
                if periodic {
                    push(k.rem_euclid(m), gap(d))?;
                } else if (0..m).contains(&k) {
                    push(k, gap(d))?;
                }
            }
        }
        // Nearest first: a conflict is found sooner (in a small torus every
        // cell holds close points), and a walk can stop at the first step
        // too far.
        out.get_mut(..n)?
            .sort_unstable_by(|a, b| a.gap2.total_cmp(&b.gap2));
        Some(n)
    }

    /// Depth-first over the axes, through each axis's steps nearest first,
    /// while the bound summed so far (`partial`) stays below `r²`; at the
    /// last axis, the cell's points.
    fn walk(
        &self,
        axis: usize,
        steps: &[[Step; MAX_STEPS]; N],
        lens: &[usize; N],
        key: &mut [i64; N],
        partial: f64,
        p: &[f64; N],
    ) -> Option<[f64; N]> {
        let (Some(axis_steps), Some(&n)) = (steps.get(axis), lens.get(axis)) else {
            return self.conflict_in(key, p);
        };
        for step in axis_steps.iter().take(n) {
            let bound = partial + step.gap2;
            if bound >= self.radius_squared {
                break;
            }
            if let Some(k) = key.get_mut(axis) {
                *k = step.key;
            }
            if let Some(q) = self.walk(axis + 1, steps, lens, key, bound, p) {
                return Some(q);
            }
        }
        None
    }
}

impl<const N: usize> Sparse<N> {
    /// A point of cell `key` closer than `r` to `p`, if any.
    #[inline(always)]
    fn conflict_in(&self, key: &[i64; N], p: &[f64; N]) -> Option<[f64; N]> {
        let close =
            |q: &[f64; N]| periodic_distance_squared(p, q, &self.periods) < self.radius_squared;
        match &self.store {
            Store::Array {
                heads,
                entries,
                stride,
            } => {
                let mut at = heads.get(linear(key, stride)).copied().unwrap_or(END);
                while at != END {
                    let entry = entries.get(at as usize)?;
                    if close(&entry.point) {
                        return Some(entry.point);
                    }
                    at = entry.next;
                }
                None
            }
            Store::Table { map, .. } => map.get(key)?.iter().find(|q| close(q)).copied(),
        }
    }
}

impl<const N: usize> NeighbourGrid<N> for Sparse<N> {
    fn conflict(&self, p: &[f64; N]) -> Option<[f64; N]> {
        let cell = self.cell_of(p);
        let offset = zip_map(p, &self.lo, |x, lo| x - lo);
        let mut steps = [[Step::default(); MAX_STEPS]; N];
        let mut lens = [0usize; N];
        for (axis, ((out, len), (&c, &t))) in steps
            .iter_mut()
            .zip(&mut lens)
            .zip(cell.iter().zip(&offset))
            .enumerate()
        {
            // More steps than the plan allows cannot happen; were it to,
            // the candidate is refused: the set stays valid.
            let Some(n) = self.axis_steps(axis, c, t, out) else {
                return Some(*p);
            };
            *len = n;
        }
        let mut key = [0i64; N];
        self.walk(0, &steps, &lens, &mut key, 0.0, p)
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
    use super::super::{GridLayout, GridPlan, plan};
    use super::*;

    fn sparse<const N: usize>(domain: &Domain<N>, r: f64) -> Sparse<N> {
        match plan(domain, r, GridLayout::Sparse, 1 << 30, None) {
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
