//! Exact mode's edge correction: how readily a point is dropped for where
//! it lies in its pixel, calibrated so that the kept set shows no pixel
//! pattern ([`calibrated_bias`], [`Exact::edge_factor`]). From `n = 2` up
//! the calibrated terms are where a stream starts: `feedback.rs` trims
//! them row by row from what the stream kept, so a row's residual (the
//! table's, between its rows or past them) no longer builds up over a
//! frame. The table still sets the trims' starting point, the top band's
//! `δ` (which the feedback leaves alone) and the correction at `n = 1`.

use super::feedback::Feedback;
use super::waves::Waves;
use super::{Exact, ExactMethod};

/// The edge correction `[βx, βy, γ, δ, ε]` (see [`Exact::edge_factor`]) at
/// the default oversampling and `k` ([`DEFAULT_OVERSAMPLE`](super::DEFAULT_OVERSAMPLE),
/// [`EXACT_ATTEMPTS`](super::EXACT_ATTEMPTS)), from the table in [`rows`]:
/// linear in `n` between rows, the first row's values below it (at `n = 1`
/// no β helps: a quarter of the pixels are short there), the last row's
/// past it.
///
/// Each row zeroes the first harmonic of the kept density across a pixel,
/// which is linear in each term, so a row is solved from runs at two
/// settings (`examples/stream.rs --exact N --method M --bias ...`). The
/// runs are large because the pixel-frequency power of a fixed residual
/// grows with the point count (`N·|h|²/4` for a first harmonic `h`), so a
/// frame of a renderer shows residuals a small raster cannot resolve.
/// - `δ` lifts the top band, which the rows above deplete (their darts
///   take points near it, and elimination sees their final points).
/// - `ε` cancels a left-right tilt: a short pixel is mended left to right,
///   its darts free to take points from the unsettled pixels on its
///   right, not from the settled ones on its left.
/// - `y` differs from `x` because rows are settled in order and columns
///   together: darts take room from the row below, and elimination sees
///   the rows above settled and the row below oversampled.
///
/// Other oversamplings and `k` keep these values, which then fit less well
/// (`docs/images/exact-tradeoff.png`). How each row was solved, with its
/// runs, is in `docs/performance-journal.md` ("Exact mode's calibration
/// table, row by row").
fn calibrated_bias(method: ExactMethod, n: usize) -> [f64; 5] {
    let table = rows(method);
    #[expect(clippy::cast_precision_loss, reason = "a count per pixel")]
    let n = n as f64;
    let mut beta = table.first().map_or([0.0; 5], |row| row.1);
    for pair in table.windows(2) {
        if let [(n0, b0), (n1, b1)] = pair
            && n > *n0
        {
            let t = ((n - n0) / (n1 - n0)).min(1.0);
            for (b, (lo, hi)) in beta.iter_mut().zip(b0.iter().zip(b1)) {
                *b = lo + t * (hi - lo);
            }
        }
    }
    beta
}

/// [`calibrated_bias`]'s rows: `(n, [βx, βy, γ, δ, ε])`, `n` ascending.
fn rows(method: ExactMethod) -> &'static [(f64, [f64; 5])] {
    match method {
        ExactMethod::Eliminate => &[
            (4.0, [0.1918, 0.0782, -0.0417, 0.2, -0.012]),
            (5.0, [0.1662, 0.0794, -0.0191, 0.175, -0.0069]),
            (6.0, [0.1487, 0.077, -0.0065, 0.15, -0.0043]),
            (7.0, [0.1339, 0.0729, 0.0013, 0.125, -0.0027]),
            (8.0, [0.1223, 0.0736, 0.0072, 0.1, -0.0017]),
            (12.0, [0.0893, 0.0724, 0.0195, 0.05, -0.00085]),
            (16.0, [0.0677, 0.0809, 0.022, 0.0, 0.0]),
            (24.0, [0.046, 0.0694, 0.0258, 0.0, 0.0]),
            (32.0, [0.0327, 0.060, 0.0231, 0.0, 0.0]),
            (48.0, [0.0207, 0.047, 0.0164, 0.0, 0.0]),
            (64.0, [0.0152, 0.0384, 0.013, 0.0, 0.0]),
            (96.0, [0.0083, 0.0296, 0.0091, 0.0, 0.0]),
            (128.0, [0.0068, 0.0274, 0.0076, 0.0, 0.0]),
            (256.0, [0.0023, 0.0174, 0.0032, 0.0, 0.0]),
            (512.0, [0.0003, 0.0112, 0.002, 0.0, 0.0]),
            (1024.0, [0.0005, 0.0072, 0.0012, 0.0, 0.0]),
        ],
        ExactMethod::Random => &[
            (4.0, [0.314, 0.1425, -0.069, 0.2, -0.019]),
            (5.0, [0.2296, 0.1084, -0.0471, 0.175, -0.0124]),
            (6.0, [0.1835, 0.0871, -0.0325, 0.15, -0.0076]),
            (8.0, [0.1339, 0.0665, -0.0156, 0.1, -0.0021]),
            (12.0, [0.0797, 0.0506, -0.0039, 0.05, -0.00105]),
            (16.0, [0.0567, 0.053, -0.002, 0.0, 0.0]),
            (24.0, [0.0306, 0.0295, -0.00165, 0.0, 0.0]),
            (32.0, [0.0209, 0.0193, -0.0013, 0.0, 0.0]),
            // The interpolation between 32 and 64, which read 1.40 / 0.75.
            (48.0, [0.0143, 0.01325, -0.00065, 0.0, 0.0]),
            (64.0, [0.0077, 0.0072, 0.0, 0.0, 0.0]),
            // From 128 up the terms solved at 1.34·10⁸ points lie within
            // their noise (about ±0.002) of zero: none at all.
            (128.0, [0.0; 5]),
        ],
    }
}

/// The smallest count whose correction takes the waves (`feedback.rs`).
/// At `n = 2` they pulled the first harmonics' trims to their bounds
/// (elimination's `βx` trim 0.28 of 0.3 at 1448²) and the power at the
/// pixel frequency up: at 8192², seed 1, `x` read 79 with the waves
/// against 0.21 without (elimination), 9 309 / 5 631 against
/// 4 665 / 1 867 (random dropping), for `(2, 0)` and `(0, 2)` under 0.3.
/// At `n = 3` the trims stay near 0.1.
const WAVES_FROM: usize = 3;

/// The depth of a pixel's top band that the calibrated correction's `δ`
/// term favours (see [`Exact::edge_factor`]), in pixels.
const TOP_BAND: f64 = 0.2;

impl Exact {
    /// The feedback that trims the calibrated correction (`feedback.rs`), with
    /// `method`'s slopes: how `[βx, βy, γ, ε]` move the harmonics they
    /// cancel (`x` `cos`, `y` `cos`, `y` `sin`, `x` `sin`, each `2·mean`),
    /// measured at 1.34·10⁸ points (`docs/records/streaming.jsonl`: elimination
    /// 0.072–0.13 a unit of `βx` and `βy`, −0.12 to −0.133 of `γ`, −0.16 of
    /// `ε`; random dropping 0.057–0.067, −0.092 to −0.10 and −0.10), and the
    /// response `c` behind them (the kept density moves as `1 + c·β·h`):
    /// 0.49 and 0.3, `βx`'s slope over `2/π²`. The response differs by shape:
    /// `ε`'s slope over `−2/π` gives 0.25 and 0.16, so the cross terms'
    /// slopes may be up to twice the true ones, which slows their loop but
    /// keeps it stable. The waves' slope (how `A` moves `2·mean(cos)`) is
    /// read from the waves' settled amplitudes against the harmonics they
    /// cancel at `n = 4` (`docs/records/streaming.jsonl`, "The lattice's
    /// other frequencies"): 0.37 for elimination, 0.13–0.16 for random dropping.
    ///
    /// The waves run from `n = 3` up ([`WAVES_FROM`]).
    pub(super) fn feedback(method: ExactMethod, n: usize) -> Feedback {
        let feedback = match method {
            ExactMethod::Eliminate => Feedback::new([0.1, 0.1, -0.125, -0.16], 0.49, 0.37),
            ExactMethod::Random => Feedback::new([0.06, 0.065, -0.095, -0.1], 0.3, 0.15),
        };
        if n < WAVES_FROM {
            feedback.without_waves()
        } else {
            feedback
        }
    }

    /// The edge correction a new [`Exact`] weighs points by: `[βx, βy, γ]`,
    /// `δ` and `ε` of [`Self::edge_factor`]; the caller's `[βx, βy, γ]`
    /// with `δ = ε = 0` if given, else [`calibrated_bias`]'s.
    pub(super) fn correction(
        method: ExactMethod,
        n: usize,
        bias: Option<[f64; 3]>,
    ) -> ([f64; 3], f64, f64) {
        match bias {
            Some(b) => (b, 0.0, 0.0),
            None => {
                let [bx, by, g, d, e] = calibrated_bias(method, n);
                ([bx, by, g], d, e)
            }
        }
    }

    /// How readily point `i` is dropped for where it lies in its pixel,
    /// `(u, v)`: `1 - βx·h(u) - βy·h(v) - γ·(2v - 1) - δ·t(v) - ε·(2u - 1)`
    /// minus the cross terms `ζcc·h(u)·h(v) + ζss·(2u - 1)·(2v - 1) +
    /// ζcs·h(u)·(2v - 1) + ζsc·(2u - 1)·h(v)` (set only by `feedback.rs`,
    /// against the pixel lattice's diagonal frequencies) and the waves
    /// `A·cos 2π(a·u + b·v) + B·sin 2π(a·u + b·v)` at the lattice's other
    /// frequencies (`waves.rs`, set only by the feedback; their sum read
    /// from a table, as only the trims' response depends on its
    /// precision), never below 0,
    /// with `h(t) = (2t - 1)² - 1/3` (mean 0 over the pixel, 2/3 at its edges,
    /// -1/3 at its centre) and `t(v) = max(0, 1 - v/w) - w/2` (mean 0, a
    /// ramp over the top band `v < w`, `w =` [`TOP_BAND`]); so positive β
    /// keep points near the edges, a positive γ keeps them near the bottom,
    /// a positive δ near the top and a negative ε in the left half.
    pub(super) fn edge_factor(&self, i: usize) -> f64 {
        let Some(p) = self.points.get(i) else {
            return 1.0;
        };
        let u = p[0] - p[0].floor();
        let v = p[1] - p[1].floor();
        // `h` and the odd shape of a fraction already in `[0, 1)`.
        let (ou, ov) = (2.0 * u - 1.0, 2.0 * v - 1.0);
        let (hu, hv) = (ou * ou - 1.0 / 3.0, ov * ov - 1.0 / 3.0);
        // The top band's ramp, minus its mean over the pixel.
        let t = (1.0 - v / TOP_BAND).max(0.0) - TOP_BAND / 2.0;
        // Never below 0: a preference, not a sign. The table's terms keep
        // it above 0.4; only trims near their bound (`feedback.rs`, at
        // `n` = 2 or 3) could take a corner below 0.
        let [cc, ss, cs, sc] = self.cross;
        let mut f = 1.0
            - self.bias[0] * hu
            - self.bias[1] * hv
            - self.bias[2] * ov
            - self.top * t
            - self.side * ou
            - cc * hu * hv
            - ss * ou * ov
            - cs * hu * ov
            - sc * ou * hv;
        if let Some(waves) = self.waves() {
            f -= waves.sum_at(u, v);
        }
        f.max(0.0)
    }

    /// The waves the feedback trims, if any (`waves.rs`).
    fn waves(&self) -> Option<&Waves> {
        self.feedback.as_ref().and_then(Feedback::waves)
    }

    /// Whether [`Self::edge_factor`] can differ from 1.
    pub(super) fn corrects(&self) -> bool {
        self.bias != [0.0; 3]
            || self.top != 0.0
            || self.side != 0.0
            || self.cross != [0.0; 4]
            || self.waves().is_some_and(Waves::active)
    }
}

#[cfg(test)]
mod tests {
    use super::{ExactMethod, calibrated_bias, rows};

    /// Each method's rows ascend in `n`; the correction is a row's own
    /// terms at its `n`, the first row's below it, the last row's past it
    /// and the mean of two neighbouring rows halfway between them.
    #[test]
    fn the_correction_interpolates_its_rows_and_holds_at_the_ends() {
        for method in [ExactMethod::Eliminate, ExactMethod::Random] {
            let table = rows(method);
            assert!(table.windows(2).all(|w| w[0].0 < w[1].0), "{method:?}");
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "row counts"
            )]
            let at = |n: f64| calibrated_bias(method, n as usize);
            // Within rounding: a row's terms come out as `lo + 1·(hi - lo)`.
            let close =
                |a: [f64; 5], b: [f64; 5]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-15);
            for &(n, terms) in table {
                assert!(close(at(n), terms), "{method:?} at {n}");
            }
            let (first, last) = (table[0], table[table.len() - 1]);
            assert!(close(calibrated_bias(method, 1), first.1), "{method:?}");
            assert!(close(at(last.0 * 4.0), last.1), "{method:?}");
            for w in table.windows(2) {
                let mid = (w[0].0 + w[1].0) / 2.0;
                if mid.fract() == 0.0 {
                    let halfway = core::array::from_fn(|k| (w[0].1[k] + w[1].1[k]) / 2.0);
                    assert!(close(at(mid), halfway), "{method:?} at {mid}");
                }
            }
        }
    }
}
