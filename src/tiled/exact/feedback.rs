//! Exact mode's edge correction trimmed row by row: the harmonics of the
//! in-pixel density at the pixel lattice's frequencies `(1, 0)`, `(0, 1)`
//! and `(1, ±1)` that the rows settled so far kept, fed back into the
//! correction's terms for the rows still to come. The lattice's higher
//! frequencies go to waves of the correction that are those harmonics
//! themselves (`waves.rs`), trimmed the same way.
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

use super::turn::turn;
use super::waves::Waves;

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

/// The trims added to the correction's terms ([`TERMS`]), the slopes that
/// turn a harmonic into a trim, and the waves (`waves.rs`).
#[derive(Clone, Debug)]
pub(super) struct Feedback {
    slopes: [f64; TERMS],
    trim: [f64; TERMS],
    waves: Option<Waves>,
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
            waves: Some(Waves::new(wave)),
        }
    }

    /// What to add to `[βx, βy, γ, ε, ζcc, ζss, ζcs, ζsc]`.
    pub(super) fn trim(&self) -> [f64; TERMS] {
        self.trim
    }

    /// The same feedback with the waves left out: [`Self::waves`] is
    /// `None`.
    pub(super) fn without_waves(self) -> Self {
        Self {
            waves: None,
            ..self
        }
    }

    /// The waves, if trimmed.
    pub(super) fn waves(&self) -> Option<&Waves> {
        self.waves.as_ref()
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
        let mut m = 0u64;
        for p in points {
            let (cx, sx) = turn(p[0]);
            let (cy, sy) = turn(p[1]);
            if let Some(waves) = &mut self.waves {
                waves.add(p[0], p[1]);
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
        if let Some(waves) = &mut self.waves {
            waves.settle();
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::Feedback;

    /// Elimination's slopes (`calibration.rs`).
    fn eliminate() -> Feedback {
        Feedback::new([0.1, 0.1, -0.125, -0.16], 0.49, 0.37)
    }

    /// A row's noise on its harmonic: uniform in ±0.0375, from a linear
    /// congruential step of `state` (the waves' loop test uses it too).
    pub(in crate::tiled::exact) fn noise(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        #[expect(clippy::cast_precision_loss, reason = "a test's noise")]
        let unit = (*state >> 11) as f64 / (1u64 << 53) as f64;
        (unit - 0.5) * 0.075
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
