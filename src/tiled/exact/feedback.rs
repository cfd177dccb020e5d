//! Exact mode's edge correction trimmed row by row: the first harmonic of
//! the in-pixel density that the rows settled so far kept, fed back into
//! the correction's terms for the rows still to come.
//!
//! The calibrated rows (`calibration.rs`) leave a residual wherever they
//! were not solved at a frame's count of points: between rows, past the
//! last one, at counts never measured. The power of a fixed residual `h`
//! grows with the count of points (`N·|h|²/4`), so a residual of 10⁻³
//! shows as a pixel pattern at 10⁸ points. Each settled row's harmonic is
//! known exactly, and the terms move it linearly, so the correction is
//! trimmed by integral feedback: after a row of `m` points whose harmonic
//! is `h`, each term moves by `-g·h / slope`, with `g = m / max(SPAN, 2m)`.
//! Summing the updates, the total harmonic over every row so far is
//! `SPAN / 2·slope` times how far the trim has moved, whatever the
//! residual was: bounded, so its power falls as `1/N` instead of growing
//! as `N`. The rows' own noise passes through the loop's high-pass filter
//! `(1 - z⁻¹) / (1 - (1 - g)·z⁻¹)`, whose gain is at most `2 / (2 - g)`
//! (4/3 at the cap `g = 1/2`): nothing is amplified into a peak near the
//! pixel frequency, and exactly at it the noise too is taken out.
//!
//! The feedback reads only the stream's own points in scan order, so a
//! seed still gives the same points; it runs only with the calibrated
//! correction, never with a caller's `exact_edge_bias`.

use super::ExactMethod;

/// Points over which a trim step is spread: a row of `m` points moves the
/// trim by `m / SPAN` of what zeroes its harmonic (up to half of it). A
/// residual `h₀` at the start leaves about `h₀·SPAN` in the sums, which
/// at 10⁶ points is power `(h₀·SPAN)² / 4N`: 0.007 for `h₀ = 0.005`.
const SPAN: f64 = 131_072.0;

/// The largest trim of any term, in its own units: a bound for counts
/// where the terms cannot cancel the pattern (at `n = 1` a quarter of the
/// pixels are short, and no term helps).
const MAX_TRIM: f64 = 0.3;

/// How each term `[βx, βy, γ, ε]` moves the harmonic it cancels (`x`
/// `cos`, `y` `cos`, `y` `sin`, `x` `sin`, each `2·mean`), measured at
/// 1.34·10⁸ points (`docs/streaming-runs.md`; elimination 0.072–0.13 a
/// unit of `βx` and `βy`, −0.12 to −0.133 of `γ`, −0.16 of `ε`; random
/// dropping 0.057–0.067, −0.092 to −0.10 and −0.10). A slope within a
/// factor of two of the true one keeps the loop stable; the true slopes
/// lie within 0.6–1.3 of these.
fn slopes(method: ExactMethod) -> [f64; 4] {
    match method {
        ExactMethod::Eliminate => [0.1, 0.1, -0.125, -0.16],
        ExactMethod::Random => [0.06, 0.065, -0.095, -0.1],
    }
}

/// The trims added to the calibrated `[βx, βy, γ, ε]`, and the slopes
/// that turn a harmonic into a trim.
#[derive(Clone, Copy, Debug)]
pub(super) struct Feedback {
    slopes: [f64; 4],
    trim: [f64; 4],
}

impl Feedback {
    /// No trim yet, for `method`'s slopes.
    pub(super) fn new(method: ExactMethod) -> Self {
        Self {
            slopes: slopes(method),
            trim: [0.0; 4],
        }
    }

    /// What to add to `[βx, βy, γ, ε]`.
    pub(super) fn trim(&self) -> [f64; 4] {
        self.trim
    }

    /// Takes in a settled row's final points: their harmonics move the
    /// trims for the rows after it.
    pub(super) fn observe<'a>(&mut self, points: impl Iterator<Item = &'a [f64; 2]>) {
        // Sums of `cos` and `sin` of `2π·frac`: x cos, y cos, y sin, x sin.
        let mut sums = [0.0; 4];
        let mut m = 0u64;
        for p in points {
            let (cx, sx) = turn(p[0] - p[0].floor());
            let (cy, sy) = turn(p[1] - p[1].floor());
            sums[0] += cx;
            sums[1] += cy;
            sums[2] += sy;
            sums[3] += sx;
            m += 1;
        }
        #[expect(clippy::cast_precision_loss, reason = "points in a row")]
        let m = m as f64;
        // The harmonic is `2·sum / m`, the gain `m / max(SPAN, 2m)`.
        let scale = 2.0 / SPAN.max(2.0 * m);
        for ((t, &s), &slope) in self.trim.iter_mut().zip(&sums).zip(&self.slopes) {
            *t = (*t - scale * s / slope).clamp(-MAX_TRIM, MAX_TRIM);
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
    for k in (1..=6).rev() {
        let k = f64::from(k);
        s = 1.0 - a2 / ((2.0 * k) * (2.0 * k + 1.0)) * s;
    }
    let mut c = 1.0;
    for k in (1..=7).rev() {
        let k = f64::from(k);
        c = 1.0 - a2 / ((2.0 * k - 1.0) * (2.0 * k)) * c;
    }
    let s = a * s;
    // 2πf = 2a + π: cos(2a + π) = 2 sin²a - 1, sin(2a + π) = -2 sin a cos a.
    (2.0 * s * s - 1.0, -2.0 * s * c)
}

#[cfg(test)]
mod tests {
    use super::{Feedback, turn};
    use crate::tiled::exact::ExactMethod;

    /// The series matches the platform's `sin_cos` to 10⁻⁷ over the pixel.
    #[test]
    fn turn_is_cos_and_sin_of_the_turn() {
        for i in 0..=10_000 {
            let f = f64::from(i) / 10_001.0;
            let (c, s) = turn(f);
            let (s0, c0) = (core::f64::consts::TAU * f).sin_cos();
            assert!(
                (c - c0).abs() < 1e-7 && (s - s0).abs() < 1e-7,
                "{f}: {c} {s}"
            );
        }
    }

    /// A plant whose harmonic is `slope·(trim - wanted)` plus a row's
    /// noise, its true slopes 0.6–1.3 times the assumed ones: with the
    /// feedback the harmonic summed over the rows stays near zero, where
    /// without it the sum grows with the rows.
    #[test]
    fn the_feedback_keeps_the_summed_harmonic_bounded() {
        let mut fb = Feedback::new(ExactMethod::Eliminate);
        let true_slopes = [0.13, 0.072, -0.133, -0.10];
        let wanted = [0.05, -0.06, 0.04, -0.05];
        let m = 4096;
        let (mut closed, mut open) = ([0.0; 4], [0.0; 4]);
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..2000 {
            let trim = fb.trim();
            let mut h = [0.0; 4];
            for k in 0..4 {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                #[expect(clippy::cast_precision_loss, reason = "a test's noise")]
                let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.075;
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
            fb.observe(row.iter());
        }
        for k in 0..4 {
            assert!(closed[k].abs() < 1.0, "term {k}: {}", closed[k]);
            assert!(open[k].abs() > 5.0, "term {k}: {}", open[k]);
        }
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
