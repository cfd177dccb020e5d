//! Annulus offsets in odd dimensions from 5-D up, drawn [`AHEAD`] at a
//! time: uniform in volume over the shell `r <= |d| < 2r`, by the ball
//! point of [`ball_point`](super::ball_point) (Archimedes' projection, a
//! last coordinate kept inside the ball), with the rejections done without
//! a branch on the draws. (The code serves any `N >= 4`; even dimensions,
//! which reject `2^-N` of their tries, draw one by one faster: see
//! `CandidateSampler::reads_ahead`.)
//!
//! A try needs `N/2` uniforms (the cuts of the simplex, whose largest is
//! the squared norm of the first `2·⌊N/2⌋` coordinates) and, for odd `N`,
//! the last coordinate; it is kept if its squared norm lies in `[1/4, 1)`
//! (units of `2r`): about half the tries for odd `N`, all but `2^-N` for
//! even `N`. [`TRIES`] tries at a time are drawn, tested and the kept ones
//! appended to a queue by an index that grows by the test's outcome, so
//! that a rejection, random, costs no mispredicted branch. The angles are
//! drawn only for the [`AHEAD`] tries taken, then the offsets are built
//! step by step over all of them, which the compiler turns into vector
//! instructions. Every number is 32 bits of a generator word (uniforms of
//! `2⁻³²` resolution, as the 2-D and 3-D offsets), so a try takes
//! `⌈N/2⌉/2` words.

use super::tables::{TWO_POW_M32, angle_directions};
use super::{AHEAD, sort_few};
use rand::Rng;

/// Tries drawn and tested at once.
const TRIES: usize = 8;

/// Kept tries waiting for their angles: per try the `N/2` cuts, then the
/// last coordinate for odd `N`. A round appends at most [`TRIES`] to fewer
/// than [`AHEAD`] left.
#[derive(Clone, Copy, Debug)]
pub(super) struct Queue<const N: usize> {
    tries: [[f64; N]; AHEAD + TRIES],
    len: usize,
}

impl<const N: usize> Queue<N> {
    pub(super) const fn new() -> Self {
        Self {
            tries: [[0.0; N]; AHEAD + TRIES],
            len: 0,
        }
    }

    /// [`AHEAD`] offsets uniform in volume over `radius <= |d| < 2·radius`,
    /// into `out`. `N >= 4`.
    #[inline(always)]
    pub(super) fn fill<R: Rng + ?Sized>(
        &mut self,
        rng: &mut R,
        radius: f64,
        out: &mut [[f64; N]; AHEAD],
    ) {
        let pairs = N / 2;
        let odd = N % 2 == 1;
        // 32-bit numbers per try.
        let width = pairs + usize::from(odd);
        // In a local, not the field: the next try's slot depends on it.
        let mut len = self.len;
        while len < AHEAD {
            // Two tries from `width` words: the first takes the words'
            // halves 0..width (high half first), the second the rest.
            for _ in 0..TRIES / 2 {
                let mut words = [0u64; N];
                for w in words.iter_mut().take(width) {
                    *w = rng.next_u64();
                }
                for second in [0, width] {
                    let half = |j: usize| {
                        let i = second + j;
                        let w = words.get(i / 2).copied().unwrap_or(0);
                        #[expect(
                            clippy::cast_possible_truncation,
                            reason = "a word's 32-bit halves"
                        )]
                        let bits = if i.is_multiple_of(2) { w >> 32 } else { w } as u32;
                        bits
                    };
                    let mut t = [0.0; N];
                    let mut largest = 0.0f64;
                    for (j, cut) in t.iter_mut().take(pairs).enumerate() {
                        *cut = f64::from(half(j)) * TWO_POW_M32;
                        largest = largest.max(*cut);
                    }
                    let mut n2 = largest;
                    if odd {
                        #[expect(clippy::cast_possible_wrap, reason = "read as signed")]
                        let z = f64::from(half(pairs) as i32) * (2.0 * TWO_POW_M32);
                        if let Some(last) = t.get_mut(pairs) {
                            *last = z;
                        }
                        n2 += z * z;
                    }
                    // Written always, counted if kept: no branch on the draw.
                    if let Some(slot) = self.tries.get_mut(len) {
                        *slot = t;
                    }
                    #[expect(
                        clippy::manual_range_contains,
                        reason = "`&`, not the `&&` of `contains`: no branch"
                    )]
                    let kept = (n2 >= 0.25) & (n2 < 1.0);
                    len += usize::from(kept);
                }
            }
        }
        // The angles of the first AHEAD tries, pair by pair.
        let scale = 2.0 * radius;
        let mut length = [[0.0; N]; AHEAD];
        for (l, t) in length.iter_mut().zip(&mut self.tries) {
            let cuts = t.get_mut(..pairs).unwrap_or_default();
            sort_few(cuts);
            let mut start = 0.0;
            for (l, &end) in l.iter_mut().zip(cuts.iter()) {
                *l = (end - start).sqrt() * scale;
                start = end;
            }
        }
        for pair in 0..pairs {
            let mut bits = [0u32; AHEAD];
            for two in bits.chunks_exact_mut(2) {
                let w = rng.next_u64();
                #[expect(clippy::cast_possible_truncation, reason = "a word's 32-bit halves")]
                if let [a, b] = two {
                    (*a, *b) = ((w >> 32) as u32, w as u32);
                }
            }
            let (c, s) = angle_directions(&bits);
            for (((d, l), &c), &s) in out.iter_mut().zip(&length).zip(&c).zip(&s) {
                let l = l.get(pair).copied().unwrap_or(0.0);
                if let Some([x, y]) = d.get_mut(2 * pair..2 * pair + 2) {
                    (*x, *y) = (l * c, l * s);
                }
            }
        }
        if odd {
            for (d, t) in out.iter_mut().zip(&self.tries) {
                if let (Some(x), Some(&z)) = (d.get_mut(pairs * 2), t.get(pairs)) {
                    *x = z * scale;
                }
            }
        }
        self.tries.copy_within(AHEAD.., 0);
        self.len = len - AHEAD;
    }
}

#[cfg(test)]
mod tests {
    use super::super::{CandidateSampler, Candidates, OffsetBatch};
    use crate::random::seeded_rng;
    use crate::vector::norm_squared;

    /// Asserts that the mean of `values` is `expected` within five of its
    /// standard errors (estimated from the values).
    fn assert_mean(values: &[f64], expected: f64, what: &str) {
        #[expect(clippy::cast_precision_loss, reason = "a count below 2^53")]
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
        let se = (var / n).sqrt();
        assert!(
            (mean - expected).abs() < 5.0 * se + 1e-15,
            "{what}: {mean} against {expected} (standard error {se})"
        );
    }

    /// The offsets drawn ahead (odd `N`; even `N` too, though it draws one
    /// by one) are uniform in volume over the
    /// shell `r <= |d| < 2r`: the share inside `t·2r`, and the moments a
    /// rotation-invariant law has (each axis's mean, second and fourth
    /// moments, and a pair of axes' cross moments, which tell the pairs of
    /// coordinates and the last coordinate of odd `N` apart from each
    /// other); and no offset comes twice (a queue that handed out a try
    /// again would).
    #[test]
    fn offsets_drawn_ahead_are_uniform_in_the_shell() {
        fn check<const N: usize>(seed: u64) {
            let r = 0.25;
            let sampler = CandidateSampler::<N>::new(Candidates::Annulus, r, 30);
            assert_eq!(sampler.reads_ahead(), N % 2 == 1, "{N}-D reads ahead");
            let mut rng = seeded_rng(seed);
            let mut batch = OffsetBatch::<N>::new();
            let draws = 100_000;
            let offsets: Vec<[f64; N]> = (0..draws)
                .map(|_| {
                    let (d, unit) = batch.next(&sampler, &mut rng);
                    for (&x, &u) in d.iter().zip(&unit) {
                        assert!((f64::from(u) - x / r).abs() < 1e-6, "{N}-D units");
                    }
                    d
                })
                .collect();
            // In units of the outer radius, 2r.
            let unit: Vec<[f64; N]> = offsets.iter().map(|d| d.map(|x| x / (2.0 * r))).collect();
            let n = i32::try_from(N).unwrap();
            let inner = 0.5f64.powi(n);
            let shell = |k: i32| {
                // E|x|^k over the shell: N/(N+k) (1 - 2^-(N+k)) / (1 - 2^-N).
                f64::from(n) / f64::from(n + k) * (1.0 - 0.5f64.powi(n + k)) / (1.0 - inner)
            };
            for x in &unit {
                let n2 = norm_squared(x);
                assert!(
                    (0.25 * (1.0 - 1e-12)..1.0).contains(&n2),
                    "{N}-D |x|² = {n2}"
                );
            }
            for t in [0.55, 0.7, 0.85, 0.95] {
                let share: Vec<f64> = unit
                    .iter()
                    .map(|x| f64::from(u8::from(norm_squared(x) < t * t)))
                    .collect();
                let p = (t.powi(n) - inner) / (1.0 - inner);
                assert_mean(&share, p, &format!("{N}-D P(|x| < {t})"));
            }
            let second = shell(2) / f64::from(n);
            let fourth = 3.0 * shell(4) / f64::from(n * (n + 2));
            let cross = shell(4) / f64::from(n * (n + 2));
            for axis in 0..N {
                let column: Vec<f64> = unit.iter().map(|x| x[axis]).collect();
                assert_mean(&column, 0.0, &format!("{N}-D axis {axis} mean"));
                let sq: Vec<f64> = column.iter().map(|x| x * x).collect();
                assert_mean(&sq, second, &format!("{N}-D axis {axis} second moment"));
                let q: Vec<f64> = sq.iter().map(|x| x * x).collect();
                assert_mean(&q, fourth, &format!("{N}-D axis {axis} fourth moment"));
                // Against the next axis (the other coordinate of a pair, or
                // one of the next pair, or the last coordinate).
                let other = (axis + 1) % N;
                let xy: Vec<f64> = unit.iter().map(|x| x[axis] * x[other]).collect();
                assert_mean(&xy, 0.0, &format!("{N}-D axes {axis}, {other}"));
                let x2y2: Vec<f64> = unit
                    .iter()
                    .map(|x| x[axis] * x[axis] * x[other] * x[other])
                    .collect();
                assert_mean(&x2y2, cross, &format!("{N}-D axes {axis}, {other} squared"));
            }
            let mut bits: Vec<[u64; N]> = offsets.iter().map(|d| d.map(f64::to_bits)).collect();
            bits.sort_unstable();
            assert!(
                bits.windows(2).all(|w| w[0] != w[1]),
                "{N}-D: an offset came twice"
            );
        }
        check::<4>(1);
        check::<5>(2);
        check::<6>(3);
        check::<7>(4);
        check::<8>(5);
    }
}
