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

use crate::random::below;
use rand::Rng;
use std::collections::VecDeque;

/// Bucket height, in radii (`J = 4r` spans 16 buckets).
pub(crate) const BUCKET: f64 = 0.25;

#[derive(Debug)]
pub(crate) struct BandQueue {
    /// Bucket `i` holds the points whose key lies in
    /// `[(base + i)·h, (base + i + 1)·h)`.
    buckets: VecDeque<Vec<[f64; 2]>>,
    /// The bucket number of `buckets[0]`.
    base: u64,
    height: f64,
    inv_height: f64,
    /// Emptied buckets, kept for their allocations.
    spare: Vec<Vec<[f64; 2]>>,
    /// The next pick drawn ahead: its bucket and index, the point then at
    /// that index and what `pick`'s `ahead` made of it.
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

    /// Queues `point` under `key` (non-negative).
    pub(crate) fn push(&mut self, point: [f64; 2], key: f64) {
        self.push_in(point, self.bucket(key));
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
    /// lowest bucket first, handing each to `take` with its bucket.
    pub(crate) fn drain_below(&mut self, limit: f64, mut take: impl FnMut([f64; 2], u64)) {
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

    /// Queues `point` in bucket `bucket`.
    pub(crate) fn push_in(&mut self, point: [f64; 2], bucket: u64) {
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
            list.push(point);
        }
    }

    /// A random point of the lowest non-empty bucket, if that bucket starts
    /// below `limit`, with where it is (for [`Self::retire`]); the point
    /// stays queued. Also hands `ahead` the point the next pick will
    /// probably take, so that its neighbourhood can be fetched meanwhile,
    /// and keeps what `ahead` returns (the sweep: the point's cell key):
    /// the pick that takes that point returns it too, `None` otherwise.
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
        ahead: impl FnOnce(&[f64; 2]) -> usize,
    ) -> Option<(Place, [f64; 2], Option<usize>)> {
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
            let (index, known) = match self.next {
                Some(a) if a.bucket == self.base && a.index < len => (a.index, Some(a)),
                _ => (below(rng, len), None),
            };
            let point = *front.get(index)?;
            // A retire or a push since the draw may have put another point
            // at that index (`swap_remove`), or there was none yet.
            let tag = known.filter(|a| a.point == point).map(|a| a.tag);
            let next = below(rng, len + 1);
            self.next = Some(match front.get(next) {
                Some(&p) => Ahead {
                    bucket: self.base,
                    index: next,
                    point: p,
                    tag: ahead(&p),
                },
                None => Ahead {
                    bucket: self.base,
                    index: next,
                    point: [f64::NAN; 2],
                    tag: 0,
                },
            });
            let place = Place {
                bucket: self.base,
                index,
            };
            return Some((place, point, tag));
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
    /// The point at `index` when drawn (NaN if there was none: it equals
    /// no point).
    point: [f64; 2],
    tag: usize,
}

/// Where a picked point sits in the queue.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Place {
    bucket: u64,
    index: usize,
}
