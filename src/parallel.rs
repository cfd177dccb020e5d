//! The parallel generator: the box cut into slabs along one axis, the even
//! slabs sampled side by side, then the odd slabs around them, each grown
//! from its neighbours' points as pre-placed points.
//!
//! Built on the sampler's own runs ([`PoissonDisk::iter_with_rng`]), so
//! every decision is the serial sampler's exact test: the union of the
//! slabs keeps the guarantees because no two points of different slabs
//! can come closer than `r` without one of them having been a pre-placed
//! point of the other's run.

use crate::domain::Domain;
use crate::error::Error;
use crate::grid::GridLayout;
use crate::random::{DefaultRng, seeded_rng};
use crate::sampler::PoissonDisk;
use core::num::NonZeroUsize;
use core::sync::atomic::{AtomicUsize, Ordering};

/// The most slab pairs: 32 slabs, so 16 jobs a phase. More slabs are
/// thinner, and the seams cost: at 250 000 points in 2-D, one thread runs
/// 12.7 % more instructions than one run with 16 slabs of 40 radii, 22 %
/// with 32 of 20 (cachegrind, performance journal).
const MAX_PAIRS: usize = 16;

/// The thinnest slab, in radii. A slab's seams take a band of about `2r`
/// on each side of it (its odd neighbours' pre-placed points), so at 16
/// radii the seams are a small share of the work; a box under 32 radii
/// across on every axis is one slab, an ordinary run.
const MIN_SLAB_RADII: f64 = 16.0;

/// How far, in radii, an even slab's run reaches past the slab on each
/// side, its points there dropped: past the border effect of a run, which
/// is about a radius deep (at 1 and 2 radii the border band's density is
/// within 1.6 % and 0.9 % of the interior's, against 58 % more with none;
/// `examples/seams.rs`, performance journal).
const TRIM_RADII: f64 = 2.0;

/// How a box is cut: `2·pairs` slabs along `axis`, slab `i` being
/// `borders[i] <= x[axis] < borders[i + 1]`.
#[derive(Debug)]
struct Slabs {
    axis: usize,
    /// `2·pairs + 1` increasing values, the first `lo`, the last `hi`.
    borders: Vec<f64>,
    /// How far beyond an odd slab its run takes its neighbours' points:
    /// `2r` (the reach of growth, and more than `r`, the reach of a
    /// conflict) plus room for the rounding of `border - margin`.
    margin: f64,
    periodic: bool,
}

impl Slabs {
    /// The cut of `domain` at `radius`, or `None` when it is one slab. The
    /// axis is the one with the most radii across (the first of equals);
    /// the number of pairs is the largest power of two, up to
    /// [`MAX_PAIRS`], that leaves slabs at least [`MIN_SLAB_RADII`] thick.
    /// A power of two, so that 2, 4, 8, … threads share a phase evenly;
    /// it depends on the box and `r` only, never on the threads.
    fn plan<const N: usize>(domain: &Domain<N>, radius: f64) -> Option<Self> {
        let extent = domain.extent();
        let (axis, across) =
            extent
                .iter()
                .map(|e| e / radius)
                .enumerate()
                .fold(
                    (0, 0.0),
                    |best, (axis, radii)| {
                        if radii > best.1 { (axis, radii) } else { best }
                    },
                );
        let mut pairs = 0_usize;
        loop {
            let more = (2 * pairs).max(1);
            if more > MAX_PAIRS || (2 * more) as f64 * MIN_SLAB_RADII > across {
                break;
            }
            pairs = more;
        }
        if pairs == 0 {
            return None;
        }
        let lo = *domain.lo().get(axis)?;
        let hi = *domain.hi().get(axis)?;
        let width = hi - lo;
        let count = 2 * pairs;
        // `i / count` is exact (a power of two), so each border rounds once.
        let borders: Vec<f64> = (0..=count)
            .map(|i| match i {
                0 => lo,
                i if i == count => hi,
                i => lo + width * (i as f64 / count as f64),
            })
            .collect();
        let rounding = lo.abs().max(hi.abs()) * f64::EPSILON * 4.0;
        let margin = 2.0 * radius * (1.0 + f64::EPSILON * 16.0) + rounding;
        // Every slab must be far thicker than the margins on both sides, so
        // that an even slab's points go to each neighbour at most once and
        // two odd slabs never meet. Rounding of far-from-zero boxes can
        // break that: they stay one slab.
        let thick = borders
            .windows(2)
            .all(|w| matches!(w, [a, b] if b - a > 2.0 * margin + radius));
        thick.then_some(Self {
            axis,
            borders,
            margin,
            periodic: *domain.periodic().get(axis)?,
        })
    }

    fn count(&self) -> usize {
        self.borders.len() - 1
    }

    /// Slab `i`'s bounds along the axis.
    fn bounds(&self, i: usize) -> Option<(f64, f64)> {
        Some((*self.borders.get(i)?, *self.borders.get(i + 1)?))
    }
}

impl<const N: usize> PoissonDisk<N> {
    /// All points for `seed`, generated on up to `threads` threads: a set
    /// with every guarantee of [`generate_seeded`](Self::generate_seeded)
    /// (no two points closer than `r`, each inside the box, maximal to `k`
    /// attempts), the same density and spacing statistics, but not the same
    /// points.
    ///
    /// The box is cut into an even number of slabs along the axis with the
    /// most radii across: a power of two up to 32, each slab at least 16
    /// radii thick, the
    /// number following from the box and `r` alone. The even slabs are
    /// sampled first, side by side, each by a run reaching `2r` past it
    /// (its points there dropped, so that none is pressed against the
    /// slab's border); then each odd slab is sampled around
    /// the points of its two neighbours that lie within `2r` of it, taken
    /// as pre-placed points ([`iter_with`](Self::iter_with)), so that growth
    /// runs on across the seams and the union keeps the guarantee. On a
    /// periodic slab axis the last slab's neighbours wrap around. A box
    /// under 32 radii across on every axis is one slab: the points are then
    /// `generate_seeded(seed)`'s.
    ///
    /// # Determinism
    /// The points, and their order (slab by slab along the axis, each slab
    /// in generation order), depend on the sampler's settings and `seed`
    /// only, never on `threads` or on scheduling: slab `i` draws from
    /// [`DefaultRng`] seeded with `seed` and then jumped `i` times (2¹²⁸
    /// steps each, so the slabs' streams never overlap). `threads = 1` runs
    /// everything on the calling thread and gives the same points.
    ///
    /// # Memory
    /// Up to half the slabs run at once, so each slab's run gets an equal
    /// share of [`max_grid_bytes`](Self::max_grid_bytes): the budget over
    /// half the number of slabs, whatever `threads` is, so that whether a
    /// run fits never depends on the threads. On top come the points made
    /// (as with [`generate`](Self::generate), whose result is not counted
    /// either). A layout that does not fit a slab's share is replaced by the
    /// sparse one for that slab, which changes no point. Count mode
    /// ([`Builder::about_points`](crate::Builder::about_points)) works: the
    /// radius it derived is used.
    ///
    /// # Errors
    /// [`Error::PointCapInParallel`] if the sampler has a point cap
    /// ([`Builder::max_points`](crate::Builder::max_points)): a cap keeps a
    /// prefix of one run's stream, and here there is no single stream.
    /// [`Error::MemoryBudgetExceeded`] from the first slab (along the axis)
    /// that outgrew its share, its `budget` being that share, and
    /// [`Error::GridTooLarge`] if not even the sparse layout fits a share
    /// (a budget of a few bytes). No points are returned then.
    ///
    /// # Example: a million-point scale set on all cores
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// use std::num::NonZeroUsize;
    /// let sampler = PoissonDisk2::new(Domain::from_extent([2.0, 1.0])?, 0.01)?;
    /// let threads = std::thread::available_parallelism().unwrap_or(NonZeroUsize::MIN);
    /// let points = sampler.generate_parallel(5, threads)?;
    /// // About as many points as one run makes, and the same on one thread.
    /// let serial = sampler.generate_seeded(5)?.len() as f64;
    /// assert!((points.len() as f64 / serial - 1.0).abs() < 0.02);
    /// assert_eq!(points, sampler.generate_parallel(5, NonZeroUsize::MIN)?);
    /// # Ok::<(), bridson::Error>(())
    /// ```
    pub fn generate_parallel(
        &self,
        seed: u64,
        threads: NonZeroUsize,
    ) -> Result<Vec<[f64; N]>, Error> {
        if self.max_points().is_some_and(|cap| cap != u64::MAX) {
            return Err(Error::PointCapInParallel);
        }
        let Some(slabs) = Slabs::plan(self.domain(), self.radius()) else {
            return self.generate_seeded(seed);
        };
        let pairs = slabs.count() / 2;
        let share = self.max_grid_bytes() / pairs as u64;
        let mut rng = seeded_rng(seed);
        let mut streams = Vec::with_capacity(slabs.count());
        for _ in 0..slabs.count() {
            streams.push(rng.clone());
            rng.jump();
        }
        let even: Vec<(usize, DefaultRng)> =
            streams.iter().cloned().enumerate().step_by(2).collect();
        let odd: Vec<(usize, DefaultRng)> =
            streams.into_iter().enumerate().skip(1).step_by(2).collect();
        let evens = run_all(&even, threads, |(i, rng)| {
            self.even_slab(&slabs, *i, rng.clone(), share)
        })?;
        let odds = run_all(&odd, threads, |(i, rng)| {
            self.odd_slab(&slabs, *i, rng.clone(), share, &evens)
        })?;
        // Joined in slab order into the first slab's vector, each slab freed
        // once copied: the peak is about the points once, not twice.
        let total = evens.iter().chain(&odds).map(Vec::len).sum::<usize>();
        let mut evens = evens.into_iter();
        let mut all = evens.next().unwrap_or_default();
        all.reserve_exact(total - all.len());
        for (o, e) in odds
            .into_iter()
            .zip(evens.chain(core::iter::once(Vec::new())))
        {
            all.extend_from_slice(&o);
            drop(o);
            all.extend_from_slice(&e);
        }
        Ok(all)
    }

    /// A sampler like this one on `domain`, within `budget`; the sparse
    /// layout if this one's does not fit (same points, less up front).
    fn slab_sampler(&self, domain: Domain<N>, budget: u64) -> Result<Self, Error> {
        let builder = Self::builder(domain, self.radius())
            .attempts(self.attempts())
            .candidates(self.candidates())
            .layout(self.layout())
            .max_grid_bytes(budget);
        match builder.build() {
            Err(Error::GridTooLarge { .. }) if self.layout() != GridLayout::Sparse => {
                builder.layout(GridLayout::Sparse).build()
            }
            built => built,
        }
    }

    /// The points of even slab `i`: an ordinary run in the slab grown by
    /// [`TRIM_RADII`] on each side (not past a bounded box's faces), those
    /// outside the slab dropped. The points near its borders are then like
    /// any interior point's, not pressed against a wall, where a run in
    /// the slab itself puts 1.6 times the density in the half radius along
    /// its border (measured by `examples/seams.rs`).
    fn even_slab(
        &self,
        slabs: &Slabs,
        i: usize,
        rng: DefaultRng,
        budget: u64,
    ) -> Result<Vec<[f64; N]>, Error> {
        let Some((lo, hi)) = slabs.bounds(i) else {
            return Ok(Vec::new());
        };
        let trim = TRIM_RADII * self.radius();
        let axis = slabs.axis;
        let (box_lo, box_hi) = (
            *self.domain().lo().get(axis).unwrap_or(&lo),
            *self.domain().hi().get(axis).unwrap_or(&hi),
        );
        let (grown_lo, grown_hi) = if slabs.periodic {
            (lo - trim, hi + trim)
        } else {
            ((lo - trim).max(box_lo), (hi + trim).min(box_hi))
        };
        let domain = self.along(slabs, grown_lo, grown_hi)?;
        let mut points = self.slab_sampler(domain, budget)?.generate(rng)?;
        points.retain(|p| p.get(axis).is_some_and(|&x| lo <= x && x < hi));
        Ok(points)
    }

    /// The points of odd slab `i`, kept in the slab and grown from its
    /// neighbours' points within the margin (pre-placed). Its domain is
    /// the slab grown by the margin (cut at a bounded box's faces), and,
    /// for the last slab on a periodic axis, the whole box: its neighbour
    /// across the wrap is then measured with the box's own periodic
    /// distance, exactly as the guarantee states it, which shifting the
    /// neighbour's points by the period would only approximate (`p + L`
    /// rounds).
    fn odd_slab(
        &self,
        slabs: &Slabs,
        i: usize,
        rng: DefaultRng,
        budget: u64,
        evens: &[Vec<[f64; N]>],
    ) -> Result<Vec<[f64; N]>, Error> {
        let Some((lo, hi)) = slabs.bounds(i) else {
            return Ok(Vec::new());
        };
        let axis = slabs.axis;
        let box_lo = *self.domain().lo().get(axis).unwrap_or(&lo);
        let box_hi = *self.domain().hi().get(axis).unwrap_or(&hi);
        let wraps = slabs.periodic && i + 1 == slabs.count();
        let domain = if wraps {
            *self.domain()
        } else {
            self.along(
                slabs,
                (lo - slabs.margin).max(box_lo),
                (hi + slabs.margin).min(box_hi),
            )?
        };
        // Within the margin of the slab, across the wrap too.
        let near = |x: f64| {
            (lo - slabs.margin <= x && x < hi + slabs.margin)
                || (wraps && x < box_lo + slabs.margin)
        };
        let right = if wraps { 0 } else { i / 2 + 1 };
        let left = evens.get(i / 2);
        // Two slabs in all on a periodic axis: one neighbour, both sides.
        let right = evens.get(right).filter(|_| right != i / 2);
        let fixed: Vec<[f64; N]> = left
            .into_iter()
            .chain(right)
            .flatten()
            .filter(|p| p.get(axis).is_some_and(|&x| near(x)) && domain.contains(p))
            .copied()
            .collect();
        let inside = move |p: &[f64; N]| p.get(axis).is_some_and(|&x| lo <= x && x < hi);
        let sampler = self.slab_sampler(domain, budget)?;
        let mut run = sampler.iter_with_rng(rng, inside, &fixed)?;
        let points: Vec<[f64; N]> = run.by_ref().collect();
        run.error().map_or(Ok(points), Err)
    }

    /// The box with `lo <= x < hi` along the slab axis, bounded there.
    fn along(&self, slabs: &Slabs, lo: f64, hi: f64) -> Result<Domain<N>, Error> {
        let mut lower = self.domain().lo();
        let mut upper = self.domain().hi();
        let mut periodic = self.domain().periodic();
        if let (Some(l), Some(h), Some(p)) = (
            lower.get_mut(slabs.axis),
            upper.get_mut(slabs.axis),
            periodic.get_mut(slabs.axis),
        ) {
            (*l, *h, *p) = (lo, hi, false);
        }
        Ok(Domain::new(lower, upper)?.with_periodic(periodic))
    }
}

/// `job` for each of `jobs`, on up to `threads` threads (the calling one
/// among them), the results in the order of `jobs`, or the error of the
/// first job (in that order) that failed. Jobs are handed out in order, so
/// every job before a failed one has been started and runs to its end:
/// which error comes back does not depend on the threads either.
fn run_all<I: Sync, T: Send>(
    jobs: &[I],
    threads: NonZeroUsize,
    job: impl Fn(&I) -> Result<T, Error> + Sync,
) -> Result<Vec<T>, Error> {
    let next = AtomicUsize::new(0);
    let failed = AtomicUsize::new(usize::MAX);
    let work = || {
        let mut done = Vec::new();
        loop {
            let index = next.fetch_add(1, Ordering::Relaxed);
            let Some(input) = jobs.get(index) else { break };
            if index > failed.load(Ordering::Relaxed) {
                break;
            }
            let result = job(input);
            if result.is_err() {
                failed.fetch_min(index, Ordering::Relaxed);
            }
            done.push((index, result));
        }
        done
    };
    let helpers = threads.get().min(jobs.len()).saturating_sub(1);
    let mut done = std::thread::scope(|scope| {
        // A thread the system refuses is one fewer helper, not an error.
        let handles: Vec<_> = (0..helpers)
            .filter_map(|_| std::thread::Builder::new().spawn_scoped(scope, work).ok())
            .collect();
        let mut done = work();
        for handle in handles {
            match handle.join() {
                Ok(mut theirs) => done.append(&mut theirs),
                // A panic is a bug of the sampler's: passed on as it is.
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
        done
    });
    done.sort_unstable_by_key(|(index, _)| *index);
    done.into_iter().map(|(_, result)| result).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slab_counts_follow_the_box_and_radius() {
        let unit = Domain::from_extent([1.0, 1.0]).unwrap();
        let count = |d: &Domain<2>, r: f64| Slabs::plan(d, r).map_or(1, |s| s.count());
        assert_eq!(count(&unit, 1.0 / 31.0), 1, "under 32 radii: one slab");
        assert_eq!(count(&unit, 1.0 / 32.0), 2, "32 radii: two slabs of 16");
        assert_eq!(count(&unit, 1.0 / 127.0), 4, "127 radii: four slabs");
        assert_eq!(count(&unit, 1.0 / 128.0), 8, "128 radii: eight slabs of 16");
        assert_eq!(count(&unit, 0.000_785), 32, "1 M points: the most slabs");
        let wide = Domain::from_extent([0.1, 1.0]).unwrap();
        let slabs = Slabs::plan(&wide, 0.01).unwrap();
        assert_eq!((slabs.axis, slabs.count()), (1, 4), "the widest axis");
        // Borders far from zero that rounding would squeeze: one slab.
        let far = Domain::new([1e15], [1e15 + 0.25]).unwrap();
        assert!(Slabs::plan(&far, 0.25 / 1e6).is_none(), "rounded borders");
    }
}
