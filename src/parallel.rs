//! The parallel generator: the box cut into slabs along one axis, the even
//! slabs sampled side by side, then the odd slabs around them, each grown
//! from its neighbours' points as pre-placed points.
//!
//! Built on the sampler's own runs ([`PoissonDisk::iter_with`]), so
//! every decision is the serial sampler's exact test: the union of the
//! slabs keeps the guarantees because no two points of different slabs
//! can come closer than `r` without one of them having been a pre-placed
//! point of the other's run.

use crate::candidates::Candidates;
use crate::density::expected_count;
use crate::domain::Domain;
use crate::error::Error;
use crate::grid::GridLayout;
use crate::incomplete::Incomplete;
use crate::random::{DefaultRng, seeded_rng};
use crate::sampler::PoissonDisk;
use core::num::NonZeroUsize;
use core::sync::atomic::{AtomicUsize, Ordering};
use rand::Rng;
use std::sync::Mutex;

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

/// A slab's room in the output buffer over count mode's model of its
/// points ([`expected_count`]) in 2-D and 3-D: the model's share plus this
/// fraction plus [`ROOM_POINTS`]. Points past the room go to a vector of
/// the slab's own (the same points; the memory the shared buffer saves is
/// spent again). At `k` from 5 to 1000, bounded and periodic, 1 M points
/// down to a few hundred, the fullest slab kept 2.8 % of its room free
/// (performance journal).
const ROOM_SLACK: f64 = 0.03;

/// [`ROOM_SLACK`] in 1-D and from 4-D up, where count mode's model does not
/// follow `k` (calibrated at 30 only): 4-D holds 9 % more points at
/// `k = 100` than the model says, 18 % at 300, 5-D 17 % at 100, and an
/// 8-D box 5 radii thick 10 % at 30. A room's unused tail costs address
/// space, not memory (the buffer's pages are touched only by points).
const ROOM_SLACK_UNCALIBRATED: f64 = 0.25;

/// Points of room each slab gets beyond the model and [`ROOM_SLACK`], for
/// small slabs, whose counts vary more.
const ROOM_POINTS: f64 = 256.0;

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
    /// either), held once: before any slab runs, the returned vector is
    /// allocated zeroed, with a room for each slab sized from count mode's
    /// model of its points plus a slack (3 % in 2-D and 3-D, 25 % elsewhere,
    /// where the model does not follow `k`; at most the budget in all), and
    /// each slab writes its points into its room. Pages no point reaches
    /// cost nothing where the allocator takes a large zeroed block fresh
    /// from the system, as glibc does. The rooms are moved together at the
    /// end and the rest given back; no slab's points are copied into or
    /// freed from a vector of their own, so the peak does not depend on
    /// the allocator returning freed memory. Points past a slab's room
    /// (the model fell short: 4-D up at large `k`) are kept aside and
    /// inserted in their place: the same points, more memory. A layout
    /// that does not fit a slab's share is replaced by the sparse one for
    /// that slab, which changes no point. Count mode
    /// ([`PoissonDiskBuilder::about_points`](crate::PoissonDiskBuilder::about_points)) works: the
    /// radius it derived is used.
    ///
    /// # Errors
    /// [`Error::PointCapInParallel`] if the sampler has a point cap
    /// ([`PoissonDiskBuilder::max_points`](crate::PoissonDiskBuilder::max_points)): a cap keeps a
    /// prefix of one run's stream, and here there is no single stream.
    /// [`Error::MemoryBudgetExceeded`] from the first slab (along the axis)
    /// that outgrew its share, its `budget` being that share, and
    /// [`Error::GridTooLarge`] if not even the sparse layout fits a share
    /// (a budget of a few bytes), each as an [`Incomplete`] that keeps the
    /// points made up to the stop, in slab order: the slabs before the
    /// failed one in its pass (all of the even slabs, if an odd one failed)
    /// and the failed slab's own points up to its stop. Slabs after it are
    /// dropped even where a thread had run them, so the kept points are
    /// the same on any number of threads.
    ///
    /// # Example: a million-point scale set on all cores
    /// ```
    /// use bridson::{Domain, PoissonDisk2};
    /// use std::num::NonZeroUsize;
    /// let sampler = PoissonDisk2::new(Domain::from_extent([2.0, 1.0])?, 0.01)?;
    /// let threads = std::thread::available_parallelism().unwrap_or(NonZeroUsize::MIN);
    /// let points = sampler.generate_parallel_seeded(5, threads)?;
    /// // About as many points as one run makes, and the same on one thread.
    /// let serial = sampler.generate_seeded(5)?.len() as f64;
    /// assert!((points.len() as f64 / serial - 1.0).abs() < 0.02);
    /// assert_eq!(points, sampler.generate_parallel_seeded(5, NonZeroUsize::MIN)?);
    /// # Ok::<(), bridson::Error>(())
    /// ```
    pub fn generate_parallel_seeded(
        &self,
        seed: u64,
        threads: NonZeroUsize,
    ) -> Result<Vec<[f64; N]>, Incomplete<N>> {
        self.generate_parallel_in(seed, threads, |rooms| rooms)
    }

    /// As [`generate_parallel_seeded`](Self::generate_parallel_seeded),
    /// seeded with one `u64` drawn from `rng`: the slabs need independent
    /// streams, which a seed jumped per slab gives and one shared generator
    /// cannot.
    ///
    /// # Errors
    /// As [`generate_parallel_seeded`](Self::generate_parallel_seeded).
    pub fn generate_parallel<R: Rng>(
        &self,
        mut rng: R,
        threads: NonZeroUsize,
    ) -> Result<Vec<[f64; N]>, Incomplete<N>> {
        self.generate_parallel_seeded(rng.next_u64(), threads)
    }

    /// [`generate_parallel_seeded`](Self::generate_parallel_seeded) with the slabs' rooms
    /// in the output buffer passed through `rooms` (the identity but in
    /// tests, which shrink them to force the spill path).
    fn generate_parallel_in(
        &self,
        seed: u64,
        threads: NonZeroUsize,
        rooms: impl FnOnce(Vec<usize>) -> Vec<usize>,
    ) -> Result<Vec<[f64; N]>, Incomplete<N>> {
        if self.max_points().is_some_and(|cap| cap != u64::MAX) {
            return Err(Incomplete::new(Vec::new(), Error::PointCapInParallel));
        }
        let Some(slabs) = Slabs::plan(self.domain(), self.radius()) else {
            return self.generate_seeded(seed);
        };
        let pairs = slabs.count() / 2;
        let share = self.max_grid_bytes() / pairs as u64;
        // One buffer for every slab's points, each slab writing into a room
        // of its own: no slab vector is freed and none copied into another,
        // so the peak never rests on the allocator handing freed blocks
        // back. Rooms past what a `Vec` can hold are none: every point then
        // spills (the same points, more memory).
        let mut rooms = rooms(self.rooms(&slabs, share));
        rooms.resize(slabs.count(), 0);
        let mut buffer = zeroed_buffer(&mut rooms);
        let mut portions = Vec::with_capacity(slabs.count());
        let mut rest = buffer.as_mut_slice();
        for &room in &rooms {
            let (portion, after) = core::mem::take(&mut rest)
                .split_at_mut_checked(room)
                .unwrap_or((&mut [], &mut []));
            portions.push(Portion::new(portion));
            rest = after;
        }
        let mut rng = seeded_rng(seed);
        let mut even = Vec::with_capacity(pairs);
        let mut odd = Vec::with_capacity(pairs);
        for (i, portion) in portions.into_iter().enumerate() {
            let jobs = if i % 2 == 0 { &mut even } else { &mut odd };
            jobs.push((i, rng.clone(), portion));
            rng.jump();
        }
        let (evens, stop) = run_all(even, threads, |(i, rng, portion)| {
            self.even_slab(&slabs, i, rng, share, portion)
        });
        let (odds, stop) = match stop {
            Some(e) => (Vec::new(), Some(e)),
            None => run_all(odd, threads, |(i, rng, portion)| {
                self.odd_slab(&slabs, i, rng, share, portion, &evens)
            }),
        };
        // Slab `2j` is even slab `j`, slab `2j + 1` odd slab `j`; the
        // slabs not run (after a stop) keep nothing.
        let mut written = vec![0; slabs.count()];
        let mut spills = vec![Vec::new(); slabs.count()];
        let placed = evens.into_iter().zip((0..).step_by(2));
        for (slab, i) in placed.chain(odds.into_iter().zip((1..).step_by(2))) {
            if let (Some(w), Some(s)) = (written.get_mut(i), spills.get_mut(i)) {
                *w = slab.points.len();
                *s = slab.spill;
            }
        }
        join(&mut buffer, &rooms, &written, spills);
        // The rooms' unused ends, given back: a large buffer shrinks where it
        // is (no copy), and the caller holds 0.6 MiB less of 2-D's 1 M
        // points (the peak is the same). A stopped run's rooms are mostly
        // unused, so its points are given back the same way.
        buffer.shrink_to_fit();
        match stop {
            Some(error) => Err(Incomplete::new(buffer, error)),
            None => Ok(buffer),
        }
    }

    /// Each slab's room in the output buffer, in slab order: count mode's
    /// model of the points of a slab of its width in the interior
    /// (its axis taken as periodic), plus, for the two end slabs of a
    /// bounded axis, half the extra the box's faces on that axis hold; that
    /// plus [`ROOM_SLACK`] (or [`ROOM_SLACK_UNCALIBRATED`]) and
    /// [`ROOM_POINTS`]. The box, `r` and `k` only, never the threads. At
    /// most half the points a slab's run could store within its `share` of
    /// the budget (they count against it), so the rooms together never
    /// pass the budget; a dimension without a model (past 8-D) gets none.
    fn rooms(&self, slabs: &Slabs, share: u64) -> Vec<usize> {
        let axis = slabs.axis;
        let model = |extent: &[f64; N], periodic: &[bool; N]| {
            expected_count(
                extent,
                periodic,
                self.candidates() == Candidates::Sphere,
                self.attempts(),
                self.radius(),
            )
        };
        let extent = self.domain().extent();
        let periodic = self.domain().periodic();
        let mut inner = periodic;
        if let Some(p) = inner.get_mut(axis) {
            *p = true;
        }
        // The faces' extra, shared by the end slabs; none if periodic.
        let faces = (model(&extent, &periodic) - model(&extent, &inner)).max(0.0) / 2.0;
        // Half the share: the buffer is at most the budget.
        let most = share / 2 / (size_of::<[f64; N]>() as u64).max(1);
        let slack = if N == 2 || N == 3 {
            ROOM_SLACK
        } else {
            ROOM_SLACK_UNCALIBRATED
        };
        (0..slabs.count())
            .map(|i| {
                let Some((lo, hi)) = slabs.bounds(i) else {
                    return 0;
                };
                let mut slab = extent;
                if let Some(e) = slab.get_mut(axis) {
                    *e = hi - lo;
                }
                let end = i == 0 || i + 1 == slabs.count();
                let points = model(&slab, &inner) + if end { faces } else { 0.0 };
                room(points * (1.0 + slack) + ROOM_POINTS, most)
            })
            .collect()
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

    /// The points of even slab `i`, written into `portion` as they come: an
    /// ordinary run in the slab grown by [`TRIM_RADII`] on each side (not
    /// past a bounded box's faces), those outside the slab dropped. The
    /// points near its borders are then like any interior point's, not
    /// pressed against a wall, where a run in the slab itself puts 1.6
    /// times the density in the half radius along its border (measured by
    /// `examples/seams.rs`).
    fn even_slab<'a>(
        &self,
        slabs: &Slabs,
        i: usize,
        rng: DefaultRng,
        budget: u64,
        mut portion: Portion<'a, N>,
    ) -> Ran<'a, N> {
        let Some((lo, hi)) = slabs.bounds(i) else {
            return (portion.written(), None);
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
        let sampler = self
            .along(slabs, grown_lo, grown_hi)
            .and_then(|domain| self.slab_sampler(domain, budget));
        let mut run = match sampler {
            Ok(sampler) => sampler.iter(rng),
            Err(e) => return (portion.written(), Some(e)),
        };
        for p in run.by_ref() {
            if p.get(axis).is_some_and(|&x| lo <= x && x < hi) {
                portion.push(p);
            }
        }
        let error = run.error();
        (portion.written(), error)
    }

    /// The points of odd slab `i`, written into `portion` as they come,
    /// kept in the slab and grown from its neighbours' points within the
    /// margin (pre-placed). Its domain is the slab grown by the margin (cut
    /// at a bounded box's faces), and, for the last slab on a periodic
    /// axis, the whole box: its neighbour across the wrap is then measured
    /// with the box's own periodic distance, exactly as the guarantee
    /// states it, which shifting the neighbour's points by the period would
    /// only approximate (`p + L` rounds).
    fn odd_slab<'a>(
        &self,
        slabs: &Slabs,
        i: usize,
        rng: DefaultRng,
        budget: u64,
        mut portion: Portion<'a, N>,
        evens: &[Written<'_, N>],
    ) -> Ran<'a, N> {
        let Some((lo, hi)) = slabs.bounds(i) else {
            return (portion.written(), None);
        };
        let axis = slabs.axis;
        let box_lo = *self.domain().lo().get(axis).unwrap_or(&lo);
        let box_hi = *self.domain().hi().get(axis).unwrap_or(&hi);
        let wraps = slabs.periodic && i + 1 == slabs.count();
        let domain = if wraps {
            *self.domain()
        } else {
            match self.along(
                slabs,
                (lo - slabs.margin).max(box_lo),
                (hi + slabs.margin).min(box_hi),
            ) {
                Ok(domain) => domain,
                Err(e) => return (portion.written(), Some(e)),
            }
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
            .flat_map(Written::iter)
            .filter(|p| p.get(axis).is_some_and(|&x| near(x)) && domain.contains(p))
            .copied()
            .collect();
        let inside = move |p: &[f64; N]| p.get(axis).is_some_and(|&x| lo <= x && x < hi);
        let run = self
            .slab_sampler(domain, budget)
            .and_then(|sampler| sampler.iter_with(rng, inside, &fixed));
        let mut run = match run {
            Ok(run) => run,
            Err(e) => return (portion.written(), Some(e)),
        };
        for p in run.by_ref() {
            portion.push(p);
        }
        let error = run.error();
        (portion.written(), error)
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

/// `points` rounded up to a whole count, at most `most`; no room for a
/// count the model could not give (NaN past 8-D, or infinite).
fn room(points: f64, most: u64) -> usize {
    if !(points.is_finite() && points >= 0.0) {
        return 0;
    }
    let points = points.min(most as f64).ceil();
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "finite, in 0..=most (`as` saturates in any case)"
    )]
    let whole = points as usize;
    whole
}

/// The output buffer: `rooms` values, zeroed; if a `Vec` cannot hold that
/// many (only with a budget near `u64::MAX`), none, and every room 0.
///
/// Zeroed, so that a large buffer is fresh pages from the system, which cost
/// no memory until a point lands on them: the rooms' unused tails are
/// (nearly) free. `vec!` aborts if the allocation fails, as collecting the
/// points would: the rooms are at most the budget
/// ([`PoissonDisk::rooms`]).
fn zeroed_buffer<const N: usize>(rooms: &mut [usize]) -> Vec<[f64; N]> {
    let total = rooms.iter().try_fold(0_usize, |sum, &n| sum.checked_add(n));
    let bytes = total.and_then(|n| n.checked_mul(size_of::<[f64; N]>()));
    match (total, bytes) {
        (Some(total), Some(bytes)) if isize::try_from(bytes).is_ok() => vec![[0.0; N]; total],
        _ => {
            rooms.fill(0);
            Vec::new()
        }
    }
}

/// A slab's room in the output buffer, written in generation order; the
/// points past its end go to `spill`, in order.
#[derive(Debug)]
struct Portion<'a, const N: usize> {
    room: &'a mut [[f64; N]],
    len: usize,
    spill: Vec<[f64; N]>,
}

impl<'a, const N: usize> Portion<'a, N> {
    fn new(room: &'a mut [[f64; N]]) -> Self {
        Self {
            room,
            len: 0,
            spill: Vec::new(),
        }
    }

    fn push(&mut self, p: [f64; N]) {
        if let Some(slot) = self.room.get_mut(self.len) {
            *slot = p;
            self.len += 1;
        } else {
            self.spill.push(p);
        }
    }

    /// The points written, read-only from now on.
    fn written(self) -> Written<'a, N> {
        let room: &'a [[f64; N]] = self.room;
        Written {
            points: room.get(..self.len).unwrap_or_default(),
            spill: self.spill,
        }
    }
}

/// A slab's points, and the error that stopped its run, if one did.
type Ran<'a, const N: usize> = (Written<'a, N>, Option<Error>);

/// A slab's points: the written part of its room, then its spill.
#[derive(Debug)]
struct Written<'a, const N: usize> {
    points: &'a [[f64; N]],
    spill: Vec<[f64; N]>,
}

impl<const N: usize> Written<'_, N> {
    /// The slab's points in generation order.
    fn iter(&self) -> impl Iterator<Item = &[f64; N]> {
        self.points.iter().chain(&self.spill)
    }
}

/// Turns `buffer`, cut into consecutive rooms of `rooms[i]` values of which
/// the first `written[i]` are slab `i`'s, into the slabs' values in order,
/// each slab's `spills[i]` after its written ones. The written parts move
/// down with `copy_within` (never to a higher place, so no page of the
/// buffer is touched that was not already), then the spills, if any, are
/// inserted from the last slab to the first (a rare path, where the model
/// fell short). A `written[i]` over `rooms[i]` is taken as `rooms[i]`.
fn join<T: Copy>(buffer: &mut Vec<T>, rooms: &[usize], written: &[usize], spills: Vec<Vec<T>>) {
    let mut start = 0_usize;
    let mut end = 0_usize;
    let mut ends = Vec::with_capacity(rooms.len());
    for (&room, &len) in rooms.iter().zip(written) {
        let len = len.min(room);
        let from = start..start.saturating_add(len);
        if from.end <= buffer.len() {
            buffer.copy_within(from, end);
            end += len;
        }
        ends.push(end);
        start = start.saturating_add(room);
    }
    buffer.truncate(end);
    // One exact growth at most, not a doubling per slab.
    buffer.reserve_exact(spills.iter().map(Vec::len).sum());
    for (at, spill) in ends.into_iter().zip(spills).rev() {
        if !spill.is_empty() {
            buffer.splice(at..at, spill);
        }
    }
}

/// `job` for each of `jobs`, on up to `threads` threads (the calling one
/// among them): the results in the order of `jobs`, up to and including
/// the first job (in that order) that failed, and its error. Jobs are
/// handed out in order, so every job before a failed one has been started
/// and runs to its end: what comes back does not depend on the threads
/// (later jobs a thread had taken are dropped). Each job is moved to the
/// thread that takes it (a lock per job, taken once).
fn run_all<I: Send, T: Send>(
    jobs: Vec<I>,
    threads: NonZeroUsize,
    job: impl Fn(I) -> (T, Option<Error>) + Sync,
) -> (Vec<T>, Option<Error>) {
    let count = jobs.len();
    let jobs: Vec<Mutex<Option<I>>> = jobs.into_iter().map(|j| Mutex::new(Some(j))).collect();
    let next = AtomicUsize::new(0);
    let failed = AtomicUsize::new(usize::MAX);
    let work = || {
        let mut done = Vec::new();
        loop {
            let index = next.fetch_add(1, Ordering::Relaxed);
            let Some(slot) = jobs.get(index) else { break };
            if index > failed.load(Ordering::Relaxed) {
                break;
            }
            // Each index is handed out once, so the job is there; the lock
            // is never held across anything that can panic.
            let Some(input) = slot.lock().ok().and_then(|mut s| s.take()) else {
                break;
            };
            let result = job(input);
            if result.1.is_some() {
                failed.fetch_min(index, Ordering::Relaxed);
            }
            done.push((index, result));
        }
        done
    };
    let helpers = threads.get().min(count).saturating_sub(1);
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
    let mut results = Vec::with_capacity(done.len());
    for (_, (value, error)) in done {
        results.push(value);
        if error.is_some() {
            return (results, error);
        }
    }
    (results, None)
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

    /// Every small shape of rooms, written parts and spills, against the
    /// slabs' values simply concatenated: a room's unwritten tail never
    /// shows, and spills come after their own slab's written values.
    #[test]
    fn the_join_is_the_concatenation() {
        // (room, written) with written <= room, and spill lengths.
        let shapes: Vec<(usize, usize, usize)> = (0..3)
            .flat_map(|room| (0..=room).flat_map(move |w| (0..3).map(move |s| (room, w, s))))
            .collect();
        for a in &shapes {
            for b in &shapes {
                for c in &shapes {
                    let slabs = [a, b, c];
                    let mut buffer = Vec::new();
                    let mut expected = Vec::new();
                    let mut spills = Vec::new();
                    for (i, &&(room, written, spill)) in slabs.iter().enumerate() {
                        let slab = 100 * (i + 1);
                        // Written values, then the room's unwritten tail.
                        buffer.extend(
                            (0..room).map(|k| if k < written { slab + k } else { usize::MAX }),
                        );
                        let spilled: Vec<usize> = (0..spill).map(|k| slab + 50 + k).collect();
                        expected.extend((0..written).map(|k| slab + k));
                        expected.extend(&spilled);
                        spills.push(spilled);
                    }
                    let rooms: Vec<usize> = slabs.iter().map(|s| s.0).collect();
                    let written: Vec<usize> = slabs.iter().map(|s| s.1).collect();
                    join(&mut buffer, &rooms, &written, spills);
                    assert_eq!(buffer, expected, "slabs {slabs:?}");
                }
            }
        }
    }

    #[test]
    fn rooms_are_whole_counts_within_the_bound() {
        assert_eq!(room(10.2, 100), 11, "rounded up");
        assert_eq!(room(1e30, 100), 100, "at most the bound");
        assert_eq!(room(f64::NAN, 100), 0, "no model: no room");
        assert_eq!(room(-3.0, 100), 0, "never negative");
        assert_eq!(room(5.0, 0), 0, "no budget: no room");
    }

    #[test]
    fn a_buffer_past_a_vecs_reach_is_none() {
        let mut rooms = [3, 0, 5];
        assert_eq!(zeroed_buffer::<2>(&mut rooms), vec![[0.0; 2]; 8], "zeroed");
        assert_eq!(rooms, [3, 0, 5], "the rooms kept");
        for mut rooms in [[usize::MAX / 32, 1, 0], [usize::MAX, 1, 0]] {
            assert!(zeroed_buffer::<2>(&mut rooms).is_empty(), "{rooms:?}");
            assert_eq!(rooms, [0; 3], "no room left");
        }
    }

    /// The sampler of `extent` at `r`, periodic where asked.
    fn sampler<const N: usize>(extent: [f64; N], r: f64, periodic: [bool; N]) -> PoissonDisk<N> {
        let domain = Domain::from_extent(extent).unwrap().with_periodic(periodic);
        PoissonDisk::new(domain, r).unwrap()
    }

    /// The model with its slack alone, without the extra [`ROOM_POINTS`],
    /// gives every slab of a few thousand points room for them all, so that
    /// the spill path stays rare, and not much more: 2-D and 3-D, bounded
    /// and periodic.
    #[test]
    fn the_rooms_hold_each_slabs_points() {
        fn check<const N: usize>(s: &PoissonDisk<N>, seed: u64) {
            let slabs = Slabs::plan(s.domain(), s.radius()).unwrap();
            let share = s.max_grid_bytes() / (slabs.count() / 2) as u64;
            let rooms = s.rooms(&slabs, share);
            let points = s.generate_parallel_seeded(seed, NonZeroUsize::MIN).unwrap();
            for (i, &room) in rooms.iter().enumerate() {
                let (lo, hi) = slabs.bounds(i).unwrap();
                let n = points
                    .iter()
                    .filter(|p| (lo..hi).contains(&p[slabs.axis]))
                    .count();
                let model = room as f64 - ROOM_POINTS;
                assert!(n as f64 <= model, "{N}-D slab {i}: {n} points, room {room}");
                assert!(
                    model <= n as f64 * 1.08,
                    "{N}-D slab {i}: room {room} for {n} points"
                );
            }
        }
        // Seed 1; seeds 1 to 40 pass (checked once, in release).
        // 8 slabs of about 2 400 points; 4 of about 2 400.
        check(&sampler([1.0, 0.5], 0.004, [false; 2]), 1);
        check(&sampler([1.0, 0.5], 0.004, [true; 2]), 1);
        check(&sampler([1.0, 0.15, 0.15], 0.012, [false; 3]), 1);
        check(&sampler([0.15, 1.0, 0.15], 0.012, [true; 3]), 1);
    }

    /// Rooms too small (a third of the model's, none at all, or none for
    /// every other slab) send points down the spill path: the points and
    /// their order stay those of the rooms the model gives, on one thread
    /// and two.
    #[test]
    fn spilled_points_keep_their_place() {
        fn check<const N: usize>(s: &PoissonDisk<N>, seed: u64) {
            let expected = s.generate_parallel_seeded(seed, NonZeroUsize::MIN).unwrap();
            let shrinks: [fn(Vec<usize>) -> Vec<usize>; 4] = [
                |rooms| rooms.into_iter().map(|n| n / 3).collect(),
                |rooms| vec![0; rooms.len()],
                |rooms| {
                    let keep = |(i, n): (usize, usize)| if i % 2 == 0 { 0 } else { n };
                    rooms.into_iter().enumerate().map(keep).collect()
                },
                |rooms| rooms.into_iter().map(|n| n / 2 + 1).rev().collect(),
            ];
            for (k, shrink) in shrinks.into_iter().enumerate() {
                for t in [1, 2] {
                    let threads = NonZeroUsize::new(t).unwrap();
                    let points = s.generate_parallel_in(seed, threads, shrink).unwrap();
                    assert!(points == expected, "{N}-D shrink {k}, {t} threads");
                }
            }
        }
        check(&sampler([1.0, 0.05], 0.004, [false; 2]), 3);
        check(&sampler([1.0, 0.05], 0.004, [true; 2]), 4);
        check(&sampler([1.0, 0.04, 0.04], 0.01, [true, false, false]), 5);
    }
}
