//! Exact mode's waves: the part of the edge correction that holds the
//! pixel lattice's harmonics past the first flat, fed back from the
//! stream's own points (`feedback.rs` holds the first harmonics with the
//! calibrated terms).
//!
//! Exactly `n` points a pixel leaves patterns at the lattice's
//! frequencies `(a, b)` (cycles a pixel) well past the first: at `n = 4`,
//! 4.2·10⁶ points, the power at `(2, 0)` read 850 before any wave, `(3, 0)`
//! and `(0, 3)` up to 46 and `(5, 0)` 53; at `n = 64` elimination leaves a
//! pattern along `y` from `(0, 3)` to past `(0, 10)`, up to 68. Each is a
//! fixed pattern, so its power grows with the points (a thousand times
//! these at 10⁹). The correction takes a wave `A·cos 2π(a·u + b·v) +
//! B·sin 2π(a·u + b·v)` at each frequency of [`is_wave`], and an integral
//! loop trims `A` and `B` as `feedback.rs` trims the first harmonics.
//!
//! The 116 waves cost what eight did when each was worked out point by
//! point (1–3 % of exact mode's time), because neither side works wave by
//! wave per point:
//! - **Measuring**: a point only counts in a histogram of where points lie
//!   in their pixel, [`BINS`]² bins. Every [`BATCH`] points the harmonics
//!   come from the bins' centres, by separable sums. A bin of side `1/64`
//!   scales a harmonic of order `k` by `sinc(k/64)` (at least 0.94 here)
//!   and folds in only frequencies past 50 cycles a pixel; the loop drives
//!   the binned harmonic to zero, so it drives the true one there too, and
//!   the scale is only a slope the loop tolerates.
//! - **Correcting**: the waves' sum is tabled at the bins' corners after
//!   each update, and a point reads it by bilinear interpolation: four
//!   loads, whatever the count of waves. Interpolation scales a wave of
//!   order `k` by `sinc²(k/64)` (0.89 at 12), again only a slope, and
//!   leaves images of it past 50 cycles a pixel, `sinc²(1 - k/64)` of it
//!   (under 0.5 % to order 4, 5 % at 12, of amplitudes near 0.01).
//!
//! The sums run in a fixed order and the `cos`/`sin` come from
//! `turn.rs`'s series, so a seed gives the same points everywhere.

use super::turn::turn;

/// Bins of the histogram and cells of the table per pixel side.
const BINS: usize = 64;

/// Every frequency with `|a|, |b| <= SQUARE` is a wave (but those
/// `feedback.rs`'s terms hold); past it, those within [`BAND`] of an axis,
/// up to [`AXIS`].
const SQUARE: usize = 4;

/// How far from an axis waves run past [`SQUARE`]: with the square alone,
/// at `n = 4`, 1.34·10⁸ points, `(5, -2)` read 90 (elimination) and
/// `(2, -5)` 56 (random dropping), and `(2, b)` 10–13 up to `b = 10`.
const BAND: usize = 2;

/// The highest order near the axes: at `n = 64` elimination's pattern
/// along `y` reads above the noise up to `(0, 10)` at 4.2·10⁶ points.
const AXIS: usize = 12;

/// Points taken in between two updates of the amplitudes (and of the
/// table): about two rows at 1024 pixels wide and `n = 4`. An update's
/// sums and table take about 5·10⁵ floating-point operations, some 60 a
/// point of the batch, whatever the raster's width.
const BATCH: u64 = 8192;

/// The span of the trims' steps, as `feedback.rs`'s axis terms: a batch
/// of `m` points moves an amplitude by `m / span` of what zeroes its
/// harmonic (up to half of it). The amplitudes start from 0, so until this
/// many points the span is the points seen so far: the trims start as
/// running means.
const SPAN: f64 = 131_072.0;

/// The largest amplitude of a wave, as `feedback.rs`'s axis terms.
const MAX_TRIM: f64 = 0.3;

/// Whether the correction takes a wave at `(a, b)`: one of each pair
/// `±(a, b)` (`a > 0`, or `a = 0` and `b > 0`), with `|a|, |b| <=`
/// [`SQUARE`], or up to [`AXIS`] within [`BAND`] of an axis, but not
/// `(1, 0)`, `(0, 1)` and `(1, ±1)`, which the calibrated terms and their
/// cross terms hold.
pub(super) fn is_wave(a: usize, b: isize) -> bool {
    let b = (b.unsigned_abs(), b > 0);
    let half = a > 0 || b.1;
    let first = a <= 1 && b.0 <= 1;
    let square = a <= SQUARE && b.0 <= SQUARE;
    let band = a.min(b.0) <= BAND && a.max(b.0) <= AXIS;
    half && !first && (square || band)
}

/// The `(a, b)` at `index` of the amplitudes' layout, `a·(2·AXIS + 1) + b +
/// AXIS`.
fn wave_at(index: usize) -> (usize, isize) {
    let width = 2 * AXIS + 1;
    #[expect(clippy::cast_possible_wrap, reason = "below 2·AXIS + 1")]
    let b = (index % width) as isize - AXIS as isize;
    (index / width, b)
}

/// A complex number `(re, im)`.
type Complex = (f64, f64);

/// `p·q`.
fn mul(p: Complex, q: Complex) -> Complex {
    (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0)
}

/// `e^{2πi·k·t}` for `t = i / (2·BINS)`, from `turn.rs`'s series
/// at an exact fraction of a turn.
fn phase(k: usize, i: usize) -> Complex {
    let steps = 2 * BINS;
    #[expect(clippy::cast_precision_loss, reason = "below 2·BINS")]
    let f = ((k * i) % steps) as f64 / steps as f64;
    turn(f)
}

/// The waves' amplitudes, the histogram they are measured from, and the
/// table the correction reads.
#[derive(Clone, Debug)]
pub(super) struct Waves {
    /// How an amplitude `A` moves its harmonic (`2·mean(cos)`).
    slope: f64,
    /// `e^{2πi·k·c}` at the bins' centres `c = (i + ½)/BINS` (`[k][i]`)
    /// and at their corners `i/BINS`, `i` up to `BINS` (`[k][i]`), for
    /// `k` up to [`AXIS`].
    centres: Vec<Complex>,
    corners: Vec<Complex>,
    /// Points by bin, `[j·BINS + i]` for `u` in bin `i` and `v` in bin `j`
    /// (in `f64`, exact to 2⁵³), and how many since the last update.
    counts: Vec<f64>,
    pending: u64,
    /// Points taken in so far, up to [`SPAN`].
    seen: f64,
    /// `A - iB` at `(a, b)`, `[a·(2·AXIS + 1) + b + AXIS]`, 0 where
    /// [`is_wave`] is false.
    amplitude: Vec<Complex>,
    /// The waves' sum at the bins' corners, `[j·(BINS + 1) + i]`.
    table: Vec<f64>,
    /// Whether any amplitude is not 0.
    active: bool,
}

impl Waves {
    /// No wave yet, with the slope `slope` (a slope within a factor of two
    /// of the true one keeps the loop stable).
    pub(super) fn new(slope: f64) -> Self {
        let by_k = |at: fn(usize, usize) -> Complex, len: usize| {
            (0..=AXIS)
                .flat_map(|k| (0..len).map(move |i| at(k, i)))
                .collect()
        };
        Self {
            slope,
            centres: by_k(|k, i| phase(k, 2 * i + 1), BINS),
            corners: by_k(|k, i| phase(k, 2 * i), BINS + 1),
            counts: vec![0.0; BINS * BINS],
            pending: 0,
            seen: 0.0,
            amplitude: vec![(0.0, 0.0); (AXIS + 1) * (2 * AXIS + 1)],
            table: vec![0.0; (BINS + 1) * (BINS + 1)],
            active: false,
        }
    }

    /// Whether the waves' sum can differ from 0.
    pub(super) fn active(&self) -> bool {
        self.active
    }

    /// The bin of a fraction in `[0, 1)`.
    fn bin(t: f64) -> usize {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "t in [0, 1): below BINS"
        )]
        let i = (t * BINS as f64) as usize;
        i.min(BINS - 1)
    }

    /// Counts a settled point at `(u, v)` in its pixel.
    #[inline]
    pub(super) fn add(&mut self, u: f64, v: f64) {
        if let Some(c) = self.counts.get_mut(Self::bin(v) * BINS + Self::bin(u)) {
            *c += 1.0;
        }
        self.pending += 1;
    }

    /// After a row: once [`BATCH`] points are counted, moves each
    /// amplitude against the harmonic they hold, and tables the new sum.
    pub(super) fn settle(&mut self) {
        if self.pending < BATCH {
            return;
        }
        #[expect(clippy::cast_precision_loss, reason = "points in a batch")]
        let m = self.pending as f64;
        self.seen = (self.seen + m).min(SPAN);
        let step = self.slope * self.seen.max(2.0 * m);
        let harmonics = self.harmonics();
        for (index, (amplitude, sum)) in self.amplitude.iter_mut().zip(harmonics).enumerate() {
            let (a, b) = wave_at(index);
            if !is_wave(a, b) {
                continue;
            }
            // `sum` is `Σ e^{-2πi(a·u + b·v)}`: `Σ cos` and `-Σ sin`. The
            // harmonics are `2·Σ cos / m` and `2·Σ sin / m`; `A - iB` moves
            // against them.
            let c = (amplitude.0 - 2.0 * sum.0 / step).clamp(-MAX_TRIM, MAX_TRIM);
            let minus_s = (amplitude.1 - 2.0 * sum.1 / step).clamp(-MAX_TRIM, MAX_TRIM);
            *amplitude = (c, minus_s);
        }
        self.active = self.amplitude.iter().any(|&(c, s)| c != 0.0 || s != 0.0);
        self.counts.iter_mut().for_each(|c| *c = 0.0);
        self.pending = 0;
        self.tabulate();
    }

    /// `e^{2πi·k·t}` at the bins' centres (`corner` false) or corners,
    /// for `k` in `-AXIS ..= AXIS`.
    fn at(&self, corner: bool, k: isize, i: usize) -> Complex {
        let (table, len) = if corner {
            (&self.corners, BINS + 1)
        } else {
            (&self.centres, BINS)
        };
        let z = table
            .get(k.unsigned_abs() * len + i)
            .copied()
            .unwrap_or((1.0, 0.0));
        if k < 0 { (z.0, -z.1) } else { z }
    }

    /// `Σ e^{-2πi(a·u + b·v)}` over the counted points, each at its bin's
    /// centre, laid out as [`Self::amplitude`] (0 where no wave is).
    fn harmonics(&self) -> Vec<Complex> {
        let width = 2 * AXIS + 1;
        // `rows[a][j] = Σ_i counts[j][i]·e^{-2πi·a·u_i}` (every `a` up to
        // `AXIS` has a wave: `(a, 0)`, or `(1, 2)`, or `(0, b)`); then each
        // wave's sum over `j`.
        let mut rows = vec![(0.0, 0.0); (AXIS + 1) * BINS];
        for a in 0..=AXIS {
            let phases = self
                .centres
                .get(a * BINS..(a + 1) * BINS)
                .unwrap_or_default();
            let out = rows.get_mut(a * BINS..(a + 1) * BINS).unwrap_or_default();
            for (slot, line) in out.iter_mut().zip(self.counts.chunks_exact(BINS)) {
                // In eight lanes, summed at the end: a fixed order, and
                // one the compiler can keep in vector registers.
                let (mut re, mut im) = ([0.0; 8], [0.0; 8]);
                for (c, z) in line.chunks_exact(8).zip(phases.chunks_exact(8)) {
                    let lanes = re.iter_mut().zip(im.iter_mut());
                    for ((r, m), (&c, &z)) in lanes.zip(c.iter().zip(z)) {
                        *r += c * z.0;
                        *m -= c * z.1;
                    }
                }
                *slot = (re.iter().sum(), im.iter().sum());
            }
        }
        let mut out = vec![(0.0, 0.0); (AXIS + 1) * width];
        for (index, slot) in out.iter_mut().enumerate() {
            let (a, b) = wave_at(index);
            if is_wave(a, b) {
                let row = rows.get(a * BINS..(a + 1) * BINS).unwrap_or_default();
                *slot = row.iter().enumerate().fold((0.0, 0.0), |sum, (j, &r)| {
                    add(sum, mul(r, self.at(false, -b, j)))
                });
            }
        }
        out
    }

    /// Tables `Σ Re((A - iB)·e^{2πi(a·u + b·v)})` at the bins' corners:
    /// `p[a][j] = Σ_b (A - iB)_ab·e^{2πi·b·v_j}`, then `Re Σ_a
    /// e^{2πi·a·u_i}·p[a][j]` at each corner.
    fn tabulate(&mut self) {
        let width = 2 * AXIS + 1;
        let mut p = vec![(0.0, 0.0); (AXIS + 1) * (BINS + 1)];
        for a in 0..=AXIS {
            let amplitudes = self
                .amplitude
                .get(a * width..(a + 1) * width)
                .unwrap_or_default();
            let out = p
                .get_mut(a * (BINS + 1)..(a + 1) * (BINS + 1))
                .unwrap_or_default();
            for (j, slot) in out.iter_mut().enumerate() {
                #[expect(clippy::cast_possible_wrap, reason = "below 2·AXIS + 1")]
                let sum = amplitudes
                    .iter()
                    .enumerate()
                    .filter(|&(_, &c)| c != (0.0, 0.0))
                    .fold((0.0, 0.0), |sum, (b, &c)| {
                        add(sum, mul(c, self.at(true, b as isize - AXIS as isize, j)))
                    });
                *slot = sum;
            }
        }
        let mut table = core::mem::take(&mut self.table);
        table.iter_mut().for_each(|t| *t = 0.0);
        for a in 0..=AXIS {
            let phases = self
                .corners
                .get(a * (BINS + 1)..(a + 1) * (BINS + 1))
                .unwrap_or_default();
            let qs = p
                .get(a * (BINS + 1)..(a + 1) * (BINS + 1))
                .unwrap_or_default();
            for (line, &q) in table.chunks_exact_mut(BINS + 1).zip(qs) {
                for (slot, &z) in line.iter_mut().zip(phases) {
                    *slot += mul(q, z).0;
                }
            }
        }
        self.table = table;
    }

    /// The waves' sum at `(u, v)` in `[0, 1)²`, interpolated between the
    /// table's corners.
    #[inline]
    pub(super) fn sum_at(&self, u: f64, v: f64) -> f64 {
        #[expect(clippy::cast_precision_loss, reason = "BINS is small")]
        let (x, y) = (u * BINS as f64, v * BINS as f64);
        let (i, j) = (Self::bin(u), Self::bin(v));
        #[expect(clippy::cast_precision_loss, reason = "below BINS")]
        let (fx, fy) = (x - i as f64, y - j as f64);
        let row = |j: usize| -> (f64, f64) {
            let at = |i: usize| self.table.get(j * (BINS + 1) + i).copied().unwrap_or(0.0);
            (at(i), at(i + 1))
        };
        let ((a, b), (c, d)) = (row(j), row(j + 1));
        let top = a + fx * (b - a);
        let bottom = c + fx * (d - c);
        top + fy * (bottom - top)
    }

    /// Each wave's `(a, b)` and `[A, B]`.
    #[cfg(test)]
    pub(super) fn amplitudes(&self) -> Vec<((usize, isize), [f64; 2])> {
        self.amplitude
            .iter()
            .enumerate()
            .filter_map(|(index, &(c, minus_s))| {
                let ab = wave_at(index);
                is_wave(ab.0, ab.1).then_some((ab, [c, -minus_s]))
            })
            .collect()
    }
}

/// `p + q`.
fn add(p: Complex, q: Complex) -> Complex {
    (p.0 + q.0, p.1 + q.1)
}

#[cfg(test)]
mod tests {
    use super::{AXIS, BAND, BATCH, BINS, SQUARE, Waves, is_wave};
    use crate::tiled::exact::feedback::{Feedback, tests::noise};

    /// The waves are one of each pair `±(a, b)` over the square of order
    /// [`SQUARE`] and near the axes up to [`AXIS`], but the first
    /// harmonics.
    #[test]
    fn the_waves_are_the_square_and_the_axes_past_the_first_harmonics() {
        let mut waves = Vec::new();
        #[expect(clippy::cast_possible_wrap, reason = "AXIS is small")]
        let axis = AXIS as isize;
        for a in 0..=AXIS + 2 {
            for b in -axis - 2..=axis + 2 {
                if is_wave(a, b) {
                    waves.push((a, b));
                }
            }
        }
        let square = (2 * SQUARE + 1) * (2 * SQUARE + 1) / 2;
        let band = (4 * BAND + 2) * (AXIS - SQUARE);
        assert_eq!(waves.len(), square - 4 + band, "{waves:?}");
        for first in [(1, 0), (0, 1), (1, 1), (1, -1), (0, 0), (0, -2)] {
            assert!(!waves.contains(&first), "{first:?}");
        }
        for kept in [(2, 0), (0, 2), (4, -4), (3, 4), (5, -2), (2, -axis)] {
            assert!(waves.contains(&kept), "{kept:?}");
        }
        assert!(waves.contains(&(AXIS, 0)) && waves.contains(&(0, axis)));
        // The sums and the table run over every `a` up to `AXIS`.
        for a in 0..=AXIS {
            assert!(waves.iter().any(|&(x, _)| x == a), "{a}");
        }
        for left in [(5, 3), (3, -5), (AXIS + 1, 0), (0, axis + 1), (5, 5)] {
            assert!(!waves.contains(&left), "{left:?}");
        }
    }

    /// A batch of points spread evenly over the bins, plus some crowded
    /// about `u = ¼` and `¾` (as many either side) in every bin of `v`:
    /// it raises `(2, 0)`'s `cos` amplitude, to drop more there, and moves
    /// no wave off the `u` axis, nor any odd one along it, nor any `sin`
    /// (their harmonics are 0 there). The table then holds the waves'
    /// sum: at the corners as the direct sum to rounding, between them to
    /// within interpolation's error.
    #[test]
    fn a_wave_answers_its_own_harmonic_and_the_table_holds_the_sum() {
        let mut waves = Waves::new(0.37);
        #[expect(clippy::cast_precision_loss, reason = "small counts")]
        for round in 0..2 {
            for j in 0..BINS {
                let v = (j as f64 + 0.5) / BINS as f64;
                for u in [0.245, 0.255, 0.745, 0.755] {
                    waves.add(u, v);
                }
                for i in 0..BINS {
                    waves.add((i as f64 + 0.5) / BINS as f64, v);
                }
            }
            // Half a batch changes nothing yet.
            waves.settle();
            assert!(((BINS * (BINS + 4)) as u64) < BATCH);
            assert_eq!(waves.active(), round == 1);
        }
        assert!(waves.active());
        for ((a, b), [c, s]) in waves.amplitudes() {
            if (a, b) == (2, 0) {
                assert!(c > 0.1 && c < 0.3, "{c}");
            } else if b != 0 || a % 2 == 1 {
                assert!(c.abs() < 1e-9, "({a}, {b}): {c}");
            }
            assert!(s.abs() < 1e-9, "({a}, {b}): {s}");
        }
        let direct = |u: f64, v: f64| {
            waves
                .amplitudes()
                .iter()
                .map(|&((a, b), [c, s])| {
                    #[expect(clippy::cast_precision_loss, reason = "small orders")]
                    let phase = core::f64::consts::TAU * (a as f64 * u + b as f64 * v);
                    c * phase.cos() + s * phase.sin()
                })
                .sum::<f64>()
        };
        let largest: f64 = waves
            .amplitudes()
            .iter()
            .map(|(_, [c, s])| c.abs() + s.abs())
            .sum();
        #[expect(clippy::cast_precision_loss, reason = "small counts")]
        for j in 0..BINS {
            for i in 0..BINS {
                let (u, v) = (i as f64 / BINS as f64, j as f64 / BINS as f64);
                let at = waves.sum_at(u, v);
                assert!((at - direct(u, v)).abs() < 1e-6, "{u} {v}");
                let (u, v) = (u + 0.37 / BINS as f64, v + 0.61 / BINS as f64);
                let at = waves.sum_at(u, v);
                assert!((at - direct(u, v)).abs() < 0.1 * largest, "{u} {v}");
            }
        }
    }

    /// The waves' loop, on a plant whose `(2, 0)` harmonic is
    /// `slope·(trim - wanted)` plus a row's noise with the true slope 0.6
    /// of the assumed one: the harmonic summed over the rows stays near
    /// zero, where without the loop it grows with the rows.
    #[test]
    fn the_waves_keep_their_summed_harmonic_bounded() {
        let mut fb = Feedback::new([0.1, 0.1, -0.125, -0.16], 0.49, 0.37);
        let (true_slope, wanted, m) = (0.22, 0.08, 2048);
        let (mut closed, mut open) = (0.0, 0.0);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let cos_amplitude = |fb: &Feedback| {
            fb.waves()
                .and_then(|w| w.amplitudes().iter().find(|(ab, _)| *ab == (2, 0)).copied())
                .map_or(0.0, |(_, [c, _])| c)
        };
        for _ in 0..2000 {
            let noise = noise(&mut state);
            let h = true_slope * (cos_amplitude(&fb) - wanted) + noise;
            open += true_slope * -wanted + noise;
            // `2·mean(cos 4πu) = h`: a share `(1 + h/2)/2` of the points
            // at `u` = 0 or ½ (cos 1), the rest at ¼ or ¾ (-1), each
            // spread evenly over the bins of `v`, so that no other wave
            // moves.
            #[expect(
                clippy::cast_precision_loss,
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a test's counts, in 0 ..= m"
            )]
            let high = ((1.0 + h / 2.0) / 2.0 * m as f64)
                .round()
                .clamp(0.0, m as f64) as usize;
            #[expect(clippy::cast_precision_loss, reason = "a test's counts")]
            let row: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    let u = match (i < high, i % 2) {
                        (true, 0) => 0.0,
                        (true, _) => 0.5,
                        (false, 0) => 0.25,
                        (false, _) => 0.75,
                    };
                    [u, ((i / 2) % BINS) as f64 / BINS as f64]
                })
                .collect();
            #[expect(clippy::cast_precision_loss, reason = "a test's counts")]
            let held = row
                .iter()
                .map(|p| 2.0 * (2.0 * core::f64::consts::TAU * p[0]).cos())
                .sum::<f64>()
                / m as f64;
            closed += held;
            fb.observe(row.iter().copied());
        }
        assert!(closed.abs() < 1.0, "{closed}");
        assert!(open.abs() > 5.0, "{open}");
    }
}
