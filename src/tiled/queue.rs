//! The sweep's queue of active points: a bucket queue on the key `y + u·J`.
//!
//! The sweep must always work an active point whose key is among the
//! smallest, so that the work front moves down the image in a band about
//! `J` tall (see the module docs of `tiled`). A binary heap does that
//! exactly but costs `O(log n)` unpredictable branches a pop, about a tenth
//! of the sweep's instructions. Here the keys are cut into buckets of
//! height [`BUCKET`]`·r`, kept in order; a pop takes a uniformly random
//! point of the lowest non-empty bucket. Within a bucket the order is as
//! random as the keys were, so the process is the heap's with the key
//! rounded down to a multiple of the bucket height. What the row emission
//! relies on holds as before: once no bucket below `limit` holds a point,
//! every remaining key is at least `limit`.
//!
//! A queued point is named by its cell key (`RollingGrid::key`), not by its
//! coordinates: the window's grid holds the point in that cell, so the
//! queue takes half the memory (2.6 MiB less at 16 384 pixels wide), and
//! the pick's prefetch and seed start from the key without locating the
//! point again. The cell still holds the point when it is picked: the
//! window's rows are dropped, and exact mode's darts overwrite cells, only
//! in rows that no queued point can reach (a row is emitted once every
//! queued point lies more than `2r` below it).

use crate::random::below;
use rand::Rng;
use std::collections::VecDeque;

/// Bucket height, in radii (`J = 4r` spans 16 buckets).
pub(crate) const BUCKET: f64 = 0.25;

#[derive(Debug)]
pub(crate) struct BandQueue {
    /// Bucket `i` holds the points whose key lies in
    /// `[(base + i)·h, (base + i + 1)·h)`.
    buckets: VecDeque<Vec<Queued>>,
    /// The bucket number of `buckets[0]`.
    base: u64,
    height: f64,
    inv_height: f64,
    /// Emptied buckets, kept for their allocations.
    spare: Vec<Vec<Queued>>,
    /// The next pick drawn ahead: its bucket and index.
    next: Option<Ahead>,
}

impl BandQueue {
    /// An empty queue for radius `r`.
    pub(crate) fn new(radius: f64) -> Self {
        let height = BUCKET * radius;
        Self {
            buckets: VecDeque::new(),
            base: 0,
            height,
            inv_height: 1.0 / height,
            spare: Vec::new(),
            next: None,
        }
    }

    /// Queues the point whose cell key is `cell` under `key`
    /// (non-negative).
    pub(crate) fn push(&mut self, cell: Queued, key: f64) {
        self.push_in(cell, self.bucket(key));
    }

    /// The bucket of `key` (non-negative).
    #[inline(always)]
    pub(crate) fn bucket(&self, key: f64) -> u64 {
        // Through i64 (one instruction on x86-64, where f64 -> u64 takes
        // several), clamped at 0: the same value below 2^63.
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a saturating cast of a non-negative key"
        )]
        let bucket = ((key * self.inv_height) as i64).max(0) as u64;
        bucket
    }

    /// Whether bucket `bucket` starts below `limit`: its points are to be
    /// worked before the key `limit`.
    #[inline(always)]
    pub(crate) fn starts_below(&self, bucket: u64, limit: f64) -> bool {
        self.start(bucket) < limit
    }

    /// Where bucket `bucket` starts. Through i64, as [`Self::bucket`]:
    /// u64 -> f64 takes several instructions on x86-64, i64 -> f64 one.
    #[inline(always)]
    fn start(&self, bucket: u64) -> f64 {
        #[expect(
            clippy::cast_precision_loss,
            clippy::cast_possible_wrap,
            reason = "bucket numbers < 2^53"
        )]
        let start = bucket as i64 as f64 * self.height;
        start
    }

    /// Forgets the next pick drawn ahead: its index was drawn for the
    /// bucket's length then, and bucket numbers alone do not tell another
    /// run of the queue's from it.
    pub(crate) fn forget_ahead(&mut self) {
        self.next = None;
    }

    /// Takes out every point of the buckets that start below `limit`,
    /// lowest bucket first, handing each (its cell key) to `take` with its
    /// bucket.
    pub(crate) fn drain_below(&mut self, limit: f64, mut take: impl FnMut(Queued, u64)) {
        while self.buckets.front().is_some() && self.starts_below(self.base, limit) {
            if let Some(mut list) = self.buckets.pop_front() {
                for &p in &list {
                    take(p, self.base);
                }
                list.clear();
                self.spare.push(list);
            }
            self.base += 1;
        }
    }

    /// Queues the point whose cell key is `cell` in bucket `bucket`.
    pub(crate) fn push_in(&mut self, cell: Queued, bucket: u64) {
        if self.buckets.is_empty() {
            self.base = bucket;
        }
        // A key below the front bucket (a child above its parent, a seed
        // behind the front) gets buckets of its own in front: every key
        // stays in its bucket, so none is worked later than its key says.
        while bucket < self.base {
            let fresh = self.spare.pop().unwrap_or_default();
            self.buckets.push_front(fresh);
            self.base -= 1;
        }
        let at = bucket - self.base;
        let Ok(at) = usize::try_from(at) else {
            return;
        };
        while self.buckets.len() <= at {
            let fresh = self.spare.pop().unwrap_or_default();
            self.buckets.push_back(fresh);
        }
        if let Some(list) = self.buckets.get_mut(at) {
            list.push(cell);
        }
    }

    /// A random point of the lowest non-empty bucket, if that bucket starts
    /// below `limit`: its cell key and where it is (for [`Self::retire`]);
    /// the point stays queued. Also hands `ahead` the cell key of the point
    /// the next pick will probably take, so that its neighbourhood can be
    /// fetched meanwhile.
    ///
    /// The next pick's index is drawn now, uniform over one more than the
    /// bucket's length, and kept if the bucket is still the front one and
    /// the index still below its length (one spawn retires at most one
    /// point and adds at most one): so it is uniform over the length it
    /// is used with, as a fresh draw would be (the batch sampler's picks
    /// ahead argue the same way).
    pub(crate) fn pick<R: Rng + ?Sized>(
        &mut self,
        limit: f64,
        rng: &mut R,
        ahead: impl FnOnce(usize),
    ) -> Option<(Place, Queued)> {
        loop {
            let front = self.buckets.front()?;
            if front.is_empty() {
                if let Some(empty) = self.buckets.pop_front() {
                    self.spare.push(empty);
                }
                self.base += 1;
                continue;
            }
            if self.start(self.base) >= limit {
                return None;
            }
            let len = front.len();
            let index = match self.next {
                Some(a) if a.bucket == self.base && a.index < len => a.index,
                _ => below(rng, len),
            };
            let entry = *front.get(index)?;
            let next = below(rng, len + 1);
            if let Some(&cell) = front.get(next) {
                ahead(cell);
            }
            self.next = Some(Ahead {
                bucket: self.base,
                index: next,
            });
            let place = Place {
                bucket: self.base,
                index,
            };
            return Some((place, entry));
        }
    }

    /// Removes the point at `place`, from [`Self::pick`] (pushes since then
    /// leave it where it was: they only append, or add buckets).
    pub(crate) fn retire(&mut self, place: Place) {
        let at = place.bucket.wrapping_sub(self.base);
        if let Some(list) = usize::try_from(at)
            .ok()
            .and_then(|at| self.buckets.get_mut(at))
            && place.index < list.len()
        {
            list.swap_remove(place.index);
        }
    }
}

/// The next pick, drawn ahead.
#[derive(Clone, Copy, Debug)]
struct Ahead {
    bucket: u64,
    index: usize,
}

/// A queued point, named by its cell key (`RollingGrid::key`): the
/// window's grid holds the point itself, and with the key neither the
/// pick's prefetch nor its seed has to locate the point again.
pub(crate) type Queued = usize;

/// Where a picked point sits in the queue.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Place {
    bucket: u64,
    index: usize,
}
