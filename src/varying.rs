//! A radius that varies with position ([`PoissonDisk::iter_varying`]): no
//! two points `p`, `q` closer than `max(r(p), r(q))`.
//!
//! Kept apart from the fixed-radius loop (`sampler.rs`), which it shares
//! nothing hot with: points of different radii do not fit the dense grid's
//! one point per cell, so this mode keeps a linked list per cell of side
//! `r_max` (slightly more): a head per cell, a next per point. A candidate
//! is checked first against the parent and the last 7 points that turned
//! its pick's candidates away (16 slots measured 3 % slower in 3-D), then
//! against every point of the 3^N cells around it, its own cell first;
//! away from the faces the neighbour cells are fixed offsets in the cell
//! array (15 % faster in 3-D). Exact, but about 3× the time of a fixed
//! radius at the same count.

use crate::candidates::{CandidateSampler, Candidates};
use crate::domain::Domain;
use crate::error::Error;
use crate::random::{DefaultRng, below, seeded_rng, unit};
use crate::sampler::{PoissonDisk, check_radius_and_attempts};
use crate::vector::{add, periodic_distance_squared, scale, zip_map};
use core::iter::FusedIterator;

/// Cells are this much wider than `r_max`, so that a pair closer than
/// `r_max` is never more than one cell apart on an axis, whatever the
/// rounding of the cell index (its error is far below 1e-6 of a cell with
/// at most [`MAX_CELLS_PER_AXIS`] cells).
const CELL_SLACK: f64 = 1.0 + 1e-6;
/// An empty list.
const NONE: u32 = u32::MAX;
/// The most cells on one axis.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 20) as f64;
/// Heap bytes counted per point: the point, its radius, its place in a
/// cell list and in the active list, and the hash map's share, each with
/// room for a vector's doubling.
fn bytes_per_point<const N: usize>() -> u64 {
    let n = u64::try_from(N).unwrap_or(u64::MAX);
    2_u64.saturating_mul(n.saturating_mul(12).saturating_add(64))
}

/// The stream of a [`PoissonDisk::iter_varying`] run.
#[derive(Debug)]
pub struct Varying<const N: usize, F> {
    rng: DefaultRng,
    field: F,
    domain: Domain<N>,
    periods: [f64; N],
    r_min: f64,
    r_max: f64,
    attempts: u32,
    candidates: CandidateSampler<N>,
    /// On-sphere candidates: moved out to `r(c)` where the field grows.
    sphere: bool,
    side: f64,
    cells_per_axis: [u32; N],
    /// The first point of each cell (row-major, axis 0 fastest), or `NONE`.
    heads: Vec<u32>,
    /// The 3^N neighbours of a cell away from every face, as offsets in
    /// `heads`, its own first.
    deltas: Vec<isize>,
    /// The next point in the same cell, or `NONE`.
    next: Vec<u32>,
    points: Vec<[f64; N]>,
    radii: Vec<f64>,
    active: Vec<u32>,
    remaining: u64,
    budget: u64,
    started: bool,
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
    /// budget on an estimate of the bytes per point); the layout does not.
    ///
    /// The guarantee is symmetric, so it does not depend on which point
    /// came first. Speed: with `r_max / r_min = 4` (a linear field), a
    /// whole `points --radius-range` run took 3.4× (2-D) and 3.1× (3-D)
    /// the CPU time of a fixed radius making the same number of points
    /// (README has the commands).
    ///
    /// # Errors
    /// [`Error::InvalidRadius`] if `r_min` is not a valid radius or is above
    /// the sampler's radius; [`Error::BoxTooWide`] if the box spans more
    /// than 2²⁰ cells of side `r_max` on some axis; [`Error::GridTooLarge`]
    /// if its cells (4 bytes each) do not fit the memory budget.
    ///
    /// # Example: a radius growing from left to right
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// let sampler = PoissonDisk2::new(Domain::from_extent([1.0, 1.0])?, 0.08)?;
    /// let field = |p: &[f64; 2]| 0.02 + 0.06 * p[0];
    /// let points: Vec<[f64; 2]> = sampler.iter_varying(3, 0.02, field)?.collect();
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
    pub fn iter_varying<F: Fn(&[f64; N]) -> f64>(
        &self,
        seed: u64,
        r_min: f64,
        field: F,
    ) -> Result<Varying<N, F>, Error> {
        let r_max = self.radius();
        check_radius_and_attempts(r_min, self.attempts())?;
        if r_min > r_max {
            return Err(Error::InvalidRadius);
        }
        let domain = *self.domain();
        let side = r_max * CELL_SLACK;
        let mut cells_per_axis = [1u32; N];
        for (axis, (count, extent)) in cells_per_axis.iter_mut().zip(domain.extent()).enumerate() {
            let cells = (extent / side).floor();
            if cells.is_nan() || cells > MAX_CELLS_PER_AXIS {
                return Err(Error::BoxTooWide { axis });
            }
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a whole number in 0..=2^20"
            )]
            let whole = cells as u32;
            *count = whole.max(1);
        }
        // The cell heads are allocated up front: they must fit the budget.
        let cells = cells_per_axis
            .iter()
            .try_fold(1_usize, |n, &m| n.checked_mul(m as usize));
        let needed = cells.and_then(|n| u64::try_from(n).ok()?.checked_mul(4));
        let budget = self.max_grid_bytes();
        let (Some(cells), Some(needed)) = (cells, needed) else {
            return Err(Error::GridTooLarge {
                needed: u64::MAX,
                budget,
            });
        };
        if needed > budget {
            return Err(Error::GridTooLarge { needed, budget });
        }
        let mut deltas = Vec::new();
        for t in 0..3_usize.pow(u32::try_from(N).unwrap_or(0)) {
            let (mut digits, mut delta, mut stride) = (t, 0_isize, 1_isize);
            for &m in &cells_per_axis {
                // Digit 0 is offset 0, so that t = 0 is the cell itself.
                let o = match digits % 3 {
                    0 => 0,
                    1 => 1,
                    _ => -1,
                };
                digits /= 3;
                delta += o * stride;
                stride = stride.saturating_mul(isize::try_from(m).unwrap_or(isize::MAX));
            }
            deltas.push(delta);
        }
        Ok(Varying {
            rng: seeded_rng(seed),
            field,
            domain,
            periods: zip_map(&domain.extent(), &domain.periodic(), |l, p| {
                if p { l } else { 0.0 }
            }),
            r_min,
            r_max,
            attempts: self.attempts(),
            candidates: CandidateSampler::new(self.candidates(), 1.0, self.attempts()),
            sphere: self.candidates() == Candidates::Sphere,
            side,
            cells_per_axis,
            heads: vec![NONE; cells],
            deltas,
            next: Vec::new(),
            points: Vec::new(),
            radii: Vec::new(),
            active: Vec::new(),
            remaining: self.max_points().unwrap_or(u64::MAX),
            budget: budget.saturating_sub(needed),
            started: false,
            error: None,
        })
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64> Varying<N, F> {
    /// Why the stream ended early, if it did: as [`Iter::error`](crate::Iter::error).
    pub fn error(&self) -> Option<Error> {
        self.error
    }

    /// `r(p)`: the field clamped to `r_min ..= r_max`, NaN as `r_max`.
    fn radius_at(&self, p: &[f64; N]) -> f64 {
        let r = (self.field)(p);
        if r.is_nan() {
            self.r_max
        } else {
            r.clamp(self.r_min, self.r_max)
        }
    }

    fn cell_of(&self, p: &[f64; N]) -> [u32; N] {
        let lo = self.domain.lo();
        let mut cell = [0u32; N];
        for (axis, c) in cell.iter_mut().enumerate() {
            let (Some(&x), Some(&l), Some(&m)) =
                (p.get(axis), lo.get(axis), self.cells_per_axis.get(axis))
            else {
                continue;
            };
            let u = ((x - l) / self.side).floor();
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "clamped to 0..m, m <= 2^20"
            )]
            let i = u.clamp(0.0, f64::from(m - 1)) as u32;
            *c = i;
        }
        cell
    }

    /// A stored point closer to `p` than `max(r, its radius)`, if any:
    /// every point of the 3^N cells around `p`'s is checked.
    fn blocked(&self, p: &[f64; N], r: f64) -> Option<usize> {
        let centre = self.cell_of(p);
        // Away from every face (and the wrap), the neighbours are fixed
        // offsets in `heads`.
        let inner = centre
            .iter()
            .zip(&self.cells_per_axis)
            .all(|(&c, &m)| c >= 1 && c + 2 <= m);
        if inner {
            let base = self.linear(&centre);
            for &delta in &self.deltas {
                let Some(cell) = base.checked_add_signed(delta) else {
                    continue;
                };
                let mut k = self.heads.get(cell).copied().unwrap_or(NONE);
                while k != NONE {
                    let i = k as usize;
                    if self.too_close(p, r, i) {
                        return Some(i);
                    }
                    k = self.next.get(i).copied().unwrap_or(NONE);
                }
            }
            return None;
        }
        let neighbourhood = 3_usize.pow(u32::try_from(N).unwrap_or(u32::MAX));
        'cells: for t in 0..neighbourhood {
            let mut cell = [0u32; N];
            // Digit 1 is offset 0: shifting by the centre's index visits the
            // centre cell first, the nearest points being the likeliest to
            // block.
            let mut digits = (t + neighbourhood / 2) % neighbourhood;
            for (axis, slot) in cell.iter_mut().enumerate() {
                // The offset on this axis, -1, 0 or 1.
                let o = i64::try_from(digits % 3).unwrap_or(0) - 1;
                digits /= 3;
                let (Some(&c), Some(&m), Some(&period)) = (
                    centre.get(axis),
                    self.cells_per_axis.get(axis),
                    self.periods.get(axis),
                ) else {
                    continue 'cells;
                };
                let (c, m) = (i64::from(c), i64::from(m));
                let j = if period > 0.0 {
                    // Fewer than 3 cells around: each is visited once.
                    if (m == 1 && o != 0) || (m == 2 && o == -1) {
                        continue 'cells;
                    }
                    (c + o).rem_euclid(m)
                } else {
                    c + o
                };
                let Ok(j) = u32::try_from(j) else {
                    continue 'cells;
                };
                if i64::from(j) >= m {
                    continue 'cells;
                }
                *slot = j;
            }
            let mut k = self.heads.get(self.linear(&cell)).copied().unwrap_or(NONE);
            while k != NONE {
                let i = k as usize;
                if self.too_close(p, r, i) {
                    return Some(i);
                }
                k = self.next.get(i).copied().unwrap_or(NONE);
            }
        }
        None
    }

    /// Whether stored point `i` lies closer to `p` than `max(r, r(i))`.
    #[inline]
    fn too_close(&self, p: &[f64; N], r: f64, i: usize) -> bool {
        let (Some(q), Some(&rq)) = (self.points.get(i), self.radii.get(i)) else {
            return false;
        };
        let bound = r.max(rq);
        periodic_distance_squared(p, q, &self.periods) < bound * bound
    }

    /// The index of a cell in `heads`.
    fn linear(&self, cell: &[u32; N]) -> usize {
        cell.iter()
            .zip(&self.cells_per_axis)
            .rev()
            .fold(0, |acc, (&c, &m)| acc * m as usize + c as usize)
    }

    /// Stores `p` with radius `r`, if the estimated memory fits.
    fn store(&mut self, p: [f64; N], r: f64) -> bool {
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
            return false;
        }
        let Ok(index) = u32::try_from(self.points.len()) else {
            self.active.clear();
            return false;
        };
        let cell = self.linear(&self.cell_of(&p));
        let Some(head) = self.heads.get_mut(cell) else {
            self.active.clear();
            return false;
        };
        self.next.push(*head);
        *head = index;
        self.points.push(p);
        self.radii.push(r);
        self.active.push(index);
        true
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64> Iterator for Varying<N, F> {
    type Item = [f64; N];

    fn next(&mut self) -> Option<[f64; N]> {
        if self.remaining == 0 || self.error.is_some() {
            return None;
        }
        if !self.started {
            self.started = true;
            let (lo, extent) = (self.domain.lo(), self.domain.extent());
            let p = zip_map(&lo, &extent, |l, e| l + unit(&mut self.rng) * e);
            if !self.domain.contains(&p) {
                return None;
            }
            let r = self.radius_at(&p);
            if !self.store(p, r) {
                return None;
            }
            self.remaining -= 1;
            return Some(p);
        }
        while !self.active.is_empty() {
            let i = below(&mut self.rng, self.active.len());
            let &index = self.active.get(i)?;
            let k = index as usize;
            let (Some(&parent), Some(&rp)) = (self.points.get(k), self.radii.get(k)) else {
                return None;
            };
            let mut state = self.candidates.start(&mut self.rng);
            // The points that turned this pick's last candidates away (and
            // the parent): likely to turn the next ones away too.
            let mut recent = [k; 8];
            let mut slot = 0;
            for _ in 0..self.attempts {
                let offset = self.candidates.offset(&mut self.rng, &mut state);
                let mut c = add(&parent, &scale(&offset, rp));
                if !self.domain.wrap(&mut c) {
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
                if recent.iter().any(|&q| self.too_close(&c, rc, q)) {
                    continue;
                }
                if let Some(q) = self.blocked(&c, rc) {
                    // Slot 0 keeps the parent.
                    if let Some(s) = recent.get_mut(1 + slot % 7) {
                        *s = q;
                    }
                    slot += 1;
                    continue;
                }
                if !self.store(c, rc) {
                    return None;
                }
                self.remaining -= 1;
                return Some(c);
            }
            self.active.swap_remove(i);
        }
        None
    }
}

impl<const N: usize, F: Fn(&[f64; N]) -> f64> FusedIterator for Varying<N, F> {}
