//! A box cut into chunks, and the chunks' points on several threads.
//!
//! Every chunk is an independent query ([`Field::query`]): its points are a
//! pure function of place, so the union over chunks is the same set for
//! every chunk side and thread count, and the threads share nothing but the
//! field's parameters.

#![expect(
    clippy::indexing_slicing,
    reason = "indices are axes `< N` of `[_; N]` arrays"
)]

use super::{Field, FieldRegion, field_order};
use crate::error::Error;

/// The most chunks one call cuts a box into.
const MAX_CHUNKS: u64 = 1 << 32;

/// The chunk boxes `[lo + k·side, min(lo + (k+1)·side, hi))` over the
/// half-open box `[lo, hi)`, the last axis slowest. Neighbouring chunks share
/// their border bit for bit (one formula), so every point of the box is in
/// exactly one chunk.
///
/// # Errors
/// [`Error::NonFiniteBound`] or [`Error::EmptyBox`] for a bad box;
/// [`Error::InvalidRadius`] if `side` is not finite and positive (the chunk
/// side is a length, as the radius is); [`Error::BoxTooWide`] if the box
/// would make more than 2³² chunks.
#[expect(
    clippy::type_complexity,
    reason = "a box is its two corners, as everywhere in the crate"
)]
pub fn chunk_boxes<const N: usize>(
    lo: [f64; N],
    hi: [f64; N],
    side: f64,
) -> Result<Vec<([f64; N], [f64; N])>, Error> {
    for axis in 0..N {
        if !lo[axis].is_finite() || !hi[axis].is_finite() {
            return Err(Error::NonFiniteBound { axis });
        }
        if lo[axis] >= hi[axis] {
            return Err(Error::EmptyBox { axis });
        }
    }
    if !(side.is_finite() && side > 0.0) {
        return Err(Error::InvalidRadius);
    }
    let mut counts = [0u64; N];
    let mut total: u64 = 1;
    for axis in 0..N {
        let c = ((hi[axis] - lo[axis]) / side).ceil();
        #[expect(clippy::cast_precision_loss, reason = "a power of two")]
        if c.is_nan() || c >= MAX_CHUNKS as f64 {
            return Err(Error::BoxTooWide { axis });
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "checked: 1 <= c < 2^32"
        )]
        let c = (c as u64).max(1);
        counts[axis] = c;
        total = total.saturating_mul(c);
        if total > MAX_CHUNKS {
            return Err(Error::BoxTooWide { axis });
        }
    }
    let edge = |axis: usize, k: u64| -> f64 {
        if k >= counts[axis] {
            hi[axis]
        } else {
            #[expect(clippy::cast_precision_loss, reason = "k < 2^32: exact")]
            let k = k as f64;
            (lo[axis] + k * side).min(hi[axis])
        }
    };
    let mut out = Vec::new();
    let mut idx = [0u64; N];
    loop {
        let mut a = [0.0; N];
        let mut b = [0.0; N];
        for axis in 0..N {
            a[axis] = edge(axis, idx[axis]);
            b[axis] = edge(axis, idx[axis] + 1);
        }
        if (0..N).all(|axis| a[axis] < b[axis]) {
            out.push((a, b));
        }
        let mut axis = 0;
        while axis < N {
            idx[axis] += 1;
            if idx[axis] < counts[axis] {
                break;
            }
            idx[axis] = 0;
            axis += 1;
        }
        if axis == N {
            break;
        }
    }
    Ok(out)
}

// The region is `Sync` in both builds, so that turning the `threads`
// feature off never changes which fields compile.
impl<const N: usize, R: FieldRegion<N> + Sync> Field<N, R> {
    /// The points in `[lo, hi)`, made chunk by chunk (chunks of `chunk` on a
    /// side) on `threads` threads, in [`field_order`]: the same points, bit
    /// for bit, as [`Field::points_in`] for every `chunk` and `threads`.
    /// With the `threads` feature off, or `threads <= 1`, the chunks run on
    /// the calling thread.
    ///
    /// # Errors
    /// As [`chunk_boxes`] and [`Field::query`].
    pub fn points_in_parallel(
        &self,
        lo: [f64; N],
        hi: [f64; N],
        chunk: f64,
        threads: usize,
    ) -> Result<Vec<[f64; N]>, Error> {
        let boxes = chunk_boxes(lo, hi, chunk)?;
        let parts = self.run_chunks(&boxes, threads)?;
        let mut points: Vec<[f64; N]> = parts.into_iter().flatten().collect();
        points.sort_by(field_order);
        Ok(points)
    }

    /// Each box's points (in [`field_order`]), in the order of `boxes`,
    /// computed on `threads` threads.
    ///
    /// # Errors
    /// The first box's error, as [`Field::query`].
    pub fn points_in_boxes(
        &self,
        boxes: &[([f64; N], [f64; N])],
        threads: usize,
    ) -> Result<Vec<Vec<[f64; N]>>, Error> {
        self.run_chunks(boxes, threads)
    }

    #[cfg(feature = "threads")]
    fn run_chunks(
        &self,
        boxes: &[([f64; N], [f64; N])],
        threads: usize,
    ) -> Result<Vec<Vec<[f64; N]>>, Error> {
        use rayon::prelude::*;
        if threads <= 1 {
            return boxes.iter().map(|(a, b)| self.points_in(*a, *b)).collect();
        }
        let run = || {
            boxes
                .par_iter()
                .with_max_len(1)
                .map(|(a, b)| self.points_in(*a, *b))
                .collect()
        };
        match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
            Ok(pool) => pool.install(run),
            // No pool (no threads to be had): the calling thread does it all.
            Err(_) => boxes.iter().map(|(a, b)| self.points_in(*a, *b)).collect(),
        }
    }

    #[cfg(not(feature = "threads"))]
    fn run_chunks(
        &self,
        boxes: &[([f64; N], [f64; N])],
        _threads: usize,
    ) -> Result<Vec<Vec<[f64; N]>>, Error> {
        boxes.iter().map(|(a, b)| self.points_in(*a, *b)).collect()
    }
}
