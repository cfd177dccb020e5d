//! Exact mode's edge correction trimmed row by row: the harmonics of the
//! in-pixel density at the pixel lattice's frequencies `(1, 0)`, `(0, 1)`
//! and `(1, ±1)` that the rows settled so far kept, fed back into the
//! correction's terms for the rows still to come; and at the rest of the
//! lattice's frequencies with `|a|, |b| <= 2` ([`WAVES`]), fed back into
//! waves of the correction that are those harmonics themselves.
//!
//! The waves hold a pattern no calibrated term covered: exactly `n` a
//! pixel draws the points toward the middles of the pixel's halves (at
//! `n = 4` the density by tenth of a pixel rippled by ±2.5 %, and the
//! power at `(2, 0)` read 850 at 4·10⁶ points, growing with the points
//! as any fixed pattern's does). The same loop takes it out.
//!
//! The calibrated rows (`calibration.rs`) leave a residual wherever they
//! were not solved at a frame's count of points: between rows, past the
//! last one, at counts never measured. The power of a fixed residual `h`
//! grows with the count of points (`N·|h|²/4`), so a residual of 10⁻³
//! shows as a pixel pattern at 10⁸ points. Each settled row's harmonic is
//! known exactly, and the terms move it linearly, so the correction is
//! trimmed by integral feedback: after a row of `m` points whose harmonic
//! is `h`, each term moves by `-g·h / slope`, with `g = m / max(span, 2m)`
//! ([`SPANS`]). Summing the updates, the harmonic summed over every point
//! so far (`Σ 2·cos`, …) is `span·slope` times how far the trim has moved
//! (rows of `2m <= span`), whatever the residual was: bounded, so its power
//! falls as `1/N` instead of growing as `N`. The rows' own noise passes
//! through the loop's high-pass filter `(1 - z⁻¹) / (1 - (1 - g)·z⁻¹)`,
//! whose gain is at most `2 / (2 - g)`
//! (4/3 at the cap `g = 1/2`): nothing is amplified into a peak near the
//! pixel frequency, and exactly at it the noise too is taken out.
//!
//! The feedback reads only the stream's own points in scan order, so a
//! seed still gives the same points; it runs only with the calibrated
//! correction, never with a caller's `exact_edge_bias`.

/// The terms the feedback trims: `[βx, βy, γ, ε]` of the calibrated
/// correction, then the four cross terms `[ζcc, ζss, ζcs, ζsc]` of
/// [`Exact::edge_factor`](super::Exact::edge_factor) (0 in the table).
pub(super) const TERMS: usize = 8;

/// Points over which a trim step is spread: a row of `m` points moves the
/// trim by `m / span` of what zeroes its harmonic (up to half of it). A
/// residual `h₀` at the start leaves about `h₀·span/2` in the sums, which
/// at 10⁶ points is power `(h₀·span/2)² / N`: 0.1 for `h₀ = 0.005`. The
/// cross terms move their harmonics less (the slopes below), so the same
/// noise would swing them more: they take a span 16 times longer.
const SPANS: [f64; TERMS] = [
    131_072.0,
    131_072.0,
    131_072.0,
    131_072.0,
    2_097_152.0,
    2_097_152.0,
    2_097_152.0,
    2_097_152.0,
];

/// The largest trim of any term, in its own units: a bound for counts
/// where the terms cannot cancel the pattern (at `n = 1` a quarter of the
/// pixels are short, and no term helps; at `n = 2`, random dropping).
const MAX_TRIM: [f64; TERMS] = [0.3, 0.3, 0.3, 0.3, 1.0, 1.0, 1.0, 1.0];

/// The cross terms' slopes against `cos x·cos y`, `sin x·sin y`,
/// `cos x·sin y` and `sin x·cos y` (each `4·mean`), from the response `c`
/// of the kept density to a term (it moves as `1 + c·(term)·(shape)`) and
/// the shapes' overlaps with the harmonics: `1/π²` for `h` with `cos`,
/// `−1/π` for `2t − 1` with `sin`. The axis terms' slopes are the same
/// overlaps times `2c`, which is how `c` is read from them
/// (`calibration.rs`, where the two odd and even shapes give `c` a factor
/// of two apart).
fn cross_slopes(c: f64) -> [f64; 4] {
    let pi = core::f64::consts::PI;
    let (pi2, pi3) = (pi * pi, pi * pi * pi);
    [
        4.0 * c / (pi2 * pi2),
        4.0 * c / pi2,
        -4.0 * c / pi3,
        -4.0 * c / pi3,
    ]
}

/// The lattice's frequencies `(a, b)` past the first harmonics whose
/// waves `cos 2π(a·u + b·v)` and `sin 2π(a·u + b·v)` the correction also
/// takes, each with its own trim: the second harmonics along each axis,
/// where exactly `n` a pixel draws the points toward the middles of the
/// pixel's halves, and their mixes with the first (one of each pair
/// `±(a, b)`), every one with `|a|, |b| <= 2` but those the terms above
/// already hold.
///
/// Not the third harmonics: at `n = 4`, 4·10⁶ points, `(3, 0)` / `(0, 3)`
/// read 8–21 before any wave and 9–46 with these, and twelve more waves
/// held every frequency up to `|a|, |b| <= 3` under 0.9, but cost 6–8 %
/// of exact mode's time against 1–3 % for these eight (the journal,
/// "Exact mode's edge correction fed back row by row", has ways to make
/// any number of orders cheap). The second harmonic, at 850 there, made
/// no difference to the tracer's errors (`docs/trace.md`, sixth study).
pub(super) const WAVES: [(u32, i32); 8] = [
    (2, 0),
    (0, 2),
    (2, 1),
    (2, -1),
    (1, 2),
    (1, -2),
    (2, 2),
    (2, -2),
];

/// The waves' span, as [`SPANS`]' axis terms: a wave's slope is the
/// response to a shape that is the harmonic itself, larger than theirs.
/// The waves start from 0, not from a table, so until a stream has made
/// this many points their span is the points seen so far: the trims start
/// as running means, and the residual they start from is gone within the
/// first rows instead of being spread over the span.
const WAVE_SPAN: f64 = 131_072.0;

/// The largest trim of a wave, as the axis terms'.
const WAVE_MAX_TRIM: f64 = 0.3;

/// `(cos, sin)` of `2π(a·u + b·v)` for each of [`WAVES`], from `u` and `v`'s
/// own (`(cos 2πu, sin 2πu)`, [`turn`]), by products of unit complex
/// numbers: `+ - ×` only, as [`turn`].
#[inline]
pub(super) fn waves(u: (f64, f64), v: (f64, f64)) -> [(f64, f64); WAVES.len()] {
    let mul = |p: (f64, f64), q: (f64, f64)| (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0);
    // `p·conj(q)`: a negative `b` turns the other way.
    let mulc = |p: (f64, f64), q: (f64, f64)| (p.0 * q.0 + p.1 * q.1, p.1 * q.0 - p.0 * q.1);
    let (u2, v2) = (mul(u, u), mul(v, v));
    // Written out in `WAVES`' order (a test checks it): a loop over the
    // table with its look-ups, or `WAVES.map`, is left out of line and
    // cost several times more.
    [
        u2,
        v2,
        mul(u2, v),
        mulc(u2, v),
        mul(u, v2),
        mulc(u, v2),
        mul(u2, v2),
        mulc(u2, v2),
    ]
}

/// The trims added to the correction's terms ([`TERMS`]) and to its waves'
/// amplitudes ([`WAVES`]), and the slopes that turn a harmonic into a trim.
#[derive(Clone, Copy, Debug)]
pub(super) struct Feedback {
    slopes: [f64; TERMS],
    trim: [f64; TERMS],
    /// How a wave's amplitude moves its own harmonic; whether the waves
    /// are trimmed at all.
    wave_slope: f64,
    with_waves: bool,
    /// Points observed so far, up to [`WAVE_SPAN`].
    seen: f64,
    /// Each wave's `[cos, sin]` amplitude.
    wave_trim: [[f64; 2]; WAVES.len()],
}

impl Feedback {
    /// No trim yet, for the axis terms' slopes `axis` (how `[βx, βy, γ,
    /// ε]` move their harmonics), the response `c` the cross terms'
    /// slopes follow from ([`cross_slopes`]) and how a wave's amplitude
    /// moves its harmonic (`wave`). A slope within a factor of two of the
    /// true one keeps the loop stable.
    pub(super) fn new(axis: [f64; 4], c: f64, wave: f64) -> Self {
        let [a, b, g, e] = axis;
        let [cc, ss, cs, sc] = cross_slopes(c);
        Self {
            slopes: [a, b, g, e, cc, ss, cs, sc],
            trim: [0.0; TERMS],
            wave_slope: wave,
            with_waves: true,
            seen: 0.0,
            wave_trim: [[0.0; 2]; WAVES.len()],
        }
    }

    /// What to add to `[βx, βy, γ, ε, ζcc, ζss, ζcs, ζsc]`.
    pub(super) fn trim(&self) -> [f64; TERMS] {
        self.trim
    }

    /// The same feedback with the waves left out: they stay at 0 and
    /// [`Self::wave_trim`] is `None`.
    pub(super) fn without_waves(self) -> Self {
        Self {
            with_waves: false,
            ..self
        }
    }

    /// The waves' `[cos, sin]` amplitudes ([`WAVES`]), if trimmed.
    pub(super) fn wave_trim(&self) -> Option<[[f64; 2]; WAVES.len()]> {
        self.with_waves.then_some(self.wave_trim)
    }

    /// Takes in a settled row's final points, each as where it lies in its
    /// pixel (`[u, v]` in `[0, 1)²`): their harmonics move the trims for
    /// the rows after it.
    pub(super) fn observe(&mut self, points: impl Iterator<Item = [f64; 2]>) {
        // Harmonics, each with the factor that makes it the density's
        // Fourier coefficient: `2·cos` and `2·sin` of `2π·frac` (x cos, y
        // cos, y sin, x sin), then the products `4·cos·cos`, `4·sin·sin`,
        // `4·cos x·sin y`, `4·sin x·cos y`.
        let mut sums = [0.0; TERMS];
        let mut wave_sums = [[0.0; 2]; WAVES.len()];
        let mut m = 0u64;
        for p in points {
            let (cx, sx) = turn(p[0]);
            let (cy, sy) = turn(p[1]);
            if self.with_waves {
                for (sum, (c, s)) in wave_sums.iter_mut().zip(waves((cx, sx), (cy, sy))) {
                    sum[0] += 2.0 * c;
                    sum[1] += 2.0 * s;
                }
            }
            let terms = [
                2.0 * cx,
                2.0 * cy,
                2.0 * sy,
                2.0 * sx,
                4.0 * cx * cy,
                4.0 * sx * sy,
                4.0 * cx * sy,
                4.0 * sx * cy,
            ];
            for (sum, t) in sums.iter_mut().zip(terms) {
                *sum += t;
            }
            m += 1;
        }
        #[expect(clippy::cast_precision_loss, reason = "points in a row")]
        let m = m as f64;
        // A harmonic is `sum / m`, the gain `m / max(span, 2m)`.
        let limits = SPANS.into_iter().zip(MAX_TRIM);
        for (((t, sum), slope), (span, bound)) in
            self.trim.iter_mut().zip(sums).zip(self.slopes).zip(limits)
        {
            *t = (*t - sum / (slope * span.max(2.0 * m))).clamp(-bound, bound);
        }
        self.seen = (self.seen + m).min(WAVE_SPAN);
        let step = self.wave_slope * self.seen.max(2.0 * m);
        for (trim, sum) in self.wave_trim.iter_mut().zip(wave_sums) {
            for (t, s) in trim.iter_mut().zip(sum) {
                *t = (*t - s / step).clamp(-WAVE_MAX_TRIM, WAVE_MAX_TRIM);
            }
        }
    }
}

/// `(cos 2πf, sin 2πf)` for `f` in `[0, 1)`, from `+ - ×` only, so the
/// same bits on every platform (the crate uses no libm function where a
/// result can change points): the half angle `a = π·(f - ½)` in
/// `[-π/2, π/2)` by Taylor series to `a¹³` and `a¹⁴` (error under 10⁻⁷),
/// then doubled, and turned by half a turn.
pub(super) fn turn(f: f64) -> (f64, f64) {
    let a = core::f64::consts::PI * (f - 0.5);
    let a2 = a * a;
    // Horner's form: sin a = a·(1 - a²/(2·3)·(1 - a²/(4·5)·(…))), to a¹³;
    // cos a = 1 - a²/(1·2)·(1 - a²/(3·4)·(…)), to a¹⁴.
    let mut s = 1.0;
    for k in SIN_STEPS.iter().rev() {
        s = 1.0 - a2 * k * s;
    }
    let mut c = 1.0;
    for k in COS_STEPS.iter().rev() {
        c = 1.0 - a2 * k * c;
    }
    let s = a * s;
    // 2πf = 2a + π: cos(2a + π) = 2 sin²a - 1, sin(2a + π) = -2 sin a cos a.
    (2.0 * s * s - 1.0, -2.0 * s * c)
}

/// [`turn`] to 10⁻⁴, by shorter series (to `a⁹` and `a⁸`): for
/// the correction's shapes, where only the trims' response depends on the
/// error, never for what the feedback measures.
pub(super) fn turn_rough(f: f64) -> (f64, f64) {
    let a = core::f64::consts::PI * (f - 0.5);
    let a2 = a * a;
    let s = a
        * (1.0
            - a2 * SIN_STEPS[0]
                * (1.0
                    - a2 * SIN_STEPS[1] * (1.0 - a2 * SIN_STEPS[2] * (1.0 - a2 * SIN_STEPS[3]))));
    let c = 1.0
        - a2 * COS_STEPS[0]
            * (1.0 - a2 * COS_STEPS[1] * (1.0 - a2 * COS_STEPS[2] * (1.0 - a2 * COS_STEPS[3])));
    (2.0 * s * s - 1.0, -2.0 * s * c)
}

/// `1 / (2k·(2k + 1))` for `k` = 1 to 6: the sine series' steps.
const SIN_STEPS: [f64; 6] = [
    1.0 / 6.0,
    1.0 / 20.0,
    1.0 / 42.0,
    1.0 / 72.0,
    1.0 / 110.0,
    1.0 / 156.0,
];

/// `1 / ((2k - 1)·2k)` for `k` = 1 to 7: the cosine series' steps.
const COS_STEPS: [f64; 7] = [
    1.0 / 2.0,
    1.0 / 12.0,
    1.0 / 30.0,
    1.0 / 56.0,
    1.0 / 90.0,
    1.0 / 132.0,
    1.0 / 182.0,
];

#[cfg(test)]
mod tests {
    use super::{Feedback, WAVES, turn, turn_rough, waves};

    /// Elimination's slopes (`calibration.rs`).
    fn eliminate() -> Feedback {
        Feedback::new([0.1, 0.1, -0.125, -0.16], 0.49, 0.37)
    }

    /// A row's noise on its harmonic: uniform in ±0.0375, from a linear
    /// congruential step of `state`.
    fn noise(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        #[expect(clippy::cast_precision_loss, reason = "a test's noise")]
        let unit = (*state >> 11) as f64 / (1u64 << 53) as f64;
        (unit - 0.5) * 0.075
    }

    /// `series` gives `cos` and `sin` of `2π·f` to `tolerance` at `steps`
    /// points over the pixel, against the platform's `sin_cos`.
    fn matches_sin_cos(series: fn(f64) -> (f64, f64), steps: u32, tolerance: f64) {
        for i in 0..=steps {
            let f = f64::from(i) / f64::from(steps + 1);
            let (c, s) = series(f);
            let (s0, c0) = (core::f64::consts::TAU * f).sin_cos();
            assert!(
                (c - c0).abs() < tolerance && (s - s0).abs() < tolerance,
                "{f}: {c} {s}"
            );
        }
    }

    /// The series matches the platform's `sin_cos` to 10⁻⁷ over the pixel.
    #[test]
    fn turn_is_cos_and_sin_of_the_turn() {
        matches_sin_cos(turn, 10_000, 1e-7);
    }

    /// The short series stays within 10⁻⁴ of `sin_cos`, and the waves
    /// are `cos` and `sin` of `2π(a·u + b·v)`.
    #[test]
    fn the_waves_are_the_lattice_frequencies() {
        matches_sin_cos(turn_rough, 1000, 1e-4);
        for i in 0..40 {
            for j in 0..40 {
                let (u, v) = (f64::from(i) / 40.3, f64::from(j) / 39.7);
                for (&(a, b), (c, s)) in WAVES.iter().zip(waves(turn(u), turn(v))) {
                    let phase = core::f64::consts::TAU * (f64::from(a) * u + f64::from(b) * v);
                    let (s0, c0) = phase.sin_cos();
                    assert!(
                        (c - c0).abs() < 1e-6 && (s - s0).abs() < 1e-6,
                        "({a}, {b}) at {u}, {v}: {c} {s}"
                    );
                }
            }
        }
    }

    /// Rows crowded at the quarters of the pixel's width (`cos 4πu` at -1)
    /// move only the `(2, 0)` wave's `cos` amplitude, and up, to drop more
    /// there; the points spread evenly over `v` leave every other wave at 0.
    #[test]
    fn a_wave_answers_its_own_harmonic() {
        let mut fb = eliminate();
        let row: Vec<[f64; 2]> = (0..1024)
            .map(|i| {
                let u = if i % 2 == 0 { 0.25 } else { 0.75 };
                [u, f64::from((i / 2) % 4) / 4.0]
            })
            .collect();
        fb.observe(row.iter().copied());
        let t = fb.wave_trim().unwrap_or_default();
        assert!(t[0][0] > 0.1, "{t:?}");
        assert!(t.iter().flatten().skip(1).all(|a| a.abs() < 1e-6), "{t:?}");
    }

    /// The waves' loop, on a plant whose `(2, 0)` harmonic is
    /// `slope·(trim - wanted)` plus a row's noise with the true slope 0.6
    /// of the assumed one: the harmonic summed over the rows stays near
    /// zero, where without the loop it grows with the rows.
    #[test]
    fn the_waves_keep_their_summed_harmonic_bounded() {
        let mut fb = eliminate();
        let (true_slope, wanted, m) = (0.22, 0.08, 2048);
        let (mut closed, mut open) = (0.0, 0.0);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..2000 {
            let noise = noise(&mut state);
            let h = true_slope * (fb.wave_trim().unwrap_or_default()[0][0] - wanted) + noise;
            open += true_slope * -wanted + noise;
            // `2·mean(cos 4πu) = h`: a share `(1 + h/2)/2` of the points
            // at `u` = 0 or ½ (cos 1), the rest at ¼ or ¾ (-1), each
            // spread over `v` so that no other wave moves.
            #[expect(
                clippy::cast_precision_loss,
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a test's counts, in 0 ..= m"
            )]
            let high = ((1.0 + h / 2.0) / 2.0 * m as f64)
                .round()
                .clamp(0.0, m as f64) as usize;
            let row: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    let u = match (i < high, i % 2) {
                        (true, 0) => 0.0,
                        (true, _) => 0.5,
                        (false, 0) => 0.25,
                        (false, _) => 0.75,
                    };
                    #[expect(clippy::cast_precision_loss, reason = "a test's counts")]
                    let v = ((i / 2) % 4) as f64 / 4.0;
                    [u, v]
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

    /// A plant whose harmonic is `slope·(trim - wanted)` plus a row's
    /// noise, its true slopes 0.6–1.3 times the assumed ones: with the
    /// feedback the harmonic summed over the rows stays near zero, where
    /// without it the sum grows with the rows.
    #[test]
    fn the_feedback_keeps_the_summed_harmonic_bounded() {
        let mut fb = eliminate();
        let true_slopes = [0.13, 0.072, -0.133, -0.10];
        let wanted = [0.05, -0.06, 0.04, -0.05];
        let m = 4096;
        let (mut closed, mut open) = ([0.0; 4], [0.0; 4]);
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..2000 {
            let trim = fb.trim();
            let mut h = [0.0; 4];
            for k in 0..4 {
                let noise = noise(&mut state);
                h[k] = true_slopes[k] * (trim[k] - wanted[k]) + noise;
                open[k] += true_slopes[k] * -wanted[k] + noise;
            }
            let row = points_with(&h, m);
            // What the row really holds, by the platform's functions.
            for p in &row {
                let (sx, cx) = (core::f64::consts::TAU * p[0]).sin_cos();
                let (sy, cy) = (core::f64::consts::TAU * p[1]).sin_cos();
                #[expect(clippy::cast_precision_loss, reason = "a test's counts")]
                let w = 2.0 / m as f64;
                for (t, v) in closed.iter_mut().zip([cx, cy, sy, sx]) {
                    *t += w * v;
                }
            }
            fb.observe(
                row.iter()
                    .map(|p| [p[0] - p[0].floor(), p[1] - p[1].floor()]),
            );
        }
        for k in 0..4 {
            assert!(closed[k].abs() < 1.0, "term {k}: {}", closed[k]);
            assert!(open[k].abs() > 5.0, "term {k}: {}", open[k]);
        }
    }

    /// A row crowded at the pixels' corners (`cos x·cos y` high) moves
    /// `ζcc` up the way `βx` moves for crowded left and right edges, to
    /// drop more there; one along the diagonal `u = v` near (¼, ¼) and
    /// (¾, ¾) (`sin x·sin y` high) moves `ζss`; the other cross terms,
    /// whose harmonics such rows leave at 0, stay put.
    #[test]
    fn the_cross_terms_answer_their_own_harmonics() {
        let mut corners = Feedback::new([0.06, 0.065, -0.095, -0.1], 0.3, 0.15);
        let row: Vec<[f64; 2]> = (0..1000).map(|i| [f64::from(i), 0.0]).collect();
        corners.observe(row.iter().map(|p| [p[0] - p[0].floor(), p[1]]));
        let t = corners.trim();
        assert!(t[0] < 0.0 && t[4] < 0.0, "{t:?}");
        assert!(t[6].abs() < 1e-9 && t[7].abs() < 1e-9, "{t:?}");
        let mut diagonal = eliminate();
        let row: Vec<[f64; 2]> = (0..1000)
            .map(|i| {
                let f = if i % 2 == 0 { 0.25 } else { 0.75 };
                [f64::from(i) + f, f]
            })
            .collect();
        diagonal.observe(row.iter().map(|p| [p[0] - p[0].floor(), p[1]]));
        let t = diagonal.trim();
        assert!(t[5] < 0.0, "{t:?}");
        assert!(
            t[4].abs() < 1e-9 && t[6].abs() < 1e-9 && t[7].abs() < 1e-9,
            "{t:?}"
        );
    }

    /// `m` points whose `(x cos, y cos, y sin, x sin)` harmonics (`2·mean`)
    /// are `h`: each point takes one of four positions per axis, mixed.
    fn points_with(h: &[f64; 4], m: usize) -> Vec<[f64; 2]> {
        // A point at `frac` 0 has cos 1, sin 0; at ½: cos -1; at ¼: sin 1;
        // at ¾: sin -1. Mixing them by the wanted means.
        let pick = |c: f64, s: f64, i: usize| {
            // Fractions of points at 0, ½ (cos ±1) and ¼, ¾ (sin ±1), half
            // the points for each function, around the even split.
            let (pc, ps) = (0.5 + c / 2.0, 0.5 + s / 2.0);
            #[expect(clippy::cast_precision_loss, reason = "a test's counts")]
            let t = (i as f64 + 0.5) / m as f64;
            if i.is_multiple_of(2) {
                if t < pc { 0.0 } else { 0.5 }
            } else if t < ps {
                0.25
            } else {
                0.75
            }
        };
        (0..m)
            .map(|i| [pick(h[0], h[3], i), pick(h[1], h[2], i)])
            .collect()
    }
}
