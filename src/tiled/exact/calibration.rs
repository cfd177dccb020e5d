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
/// [`EXACT_ATTEMPTS`](super::EXACT_ATTEMPTS)). `ε` (2026-11-24, eighth session) cancels a
/// left-right tilt at `n = 4` that only rasters of 10⁶ pixels resolve: a
/// short pixel is mended left to right, its darts free to take points
/// from the unsettled pixels on its right, not the settled ones on its
/// left, so the left half of each pixel kept less (the in-pixel first
/// harmonic's `sin` term in `x` −0.0016 to −0.0021 at 1024², seeds 1 to
/// 4, both methods; pixel-frequency power 2.7–4.9 in `x` where 3 is the
/// goal). Linear in `ε`: at `ε = −0.05` the term was +0.0059 to +0.0061
/// (elimination) and +0.0029 to +0.0030 (random dropping), seeds 1 and
/// 2, so `ε = −0.012` and `−0.019` zero it; at `n = 8` (724²) the term
/// was 0.0000 and +0.0001 already, so `ε` fell to 0 there (at 1.34·10⁸
/// points a tilt of −0.0002 to −0.0003 showed there too; see below).
/// Afterwards, 1024², seeds 1 to 4: the `sin` term within ±0.0006, power
/// in `x` at most 0.53 and 0.36. In the same session random dropping's `γ` and `βy`
/// at `n = 16` were set again from 512² (4 M points; they had left power
/// 17.7–22.6 in `y` at 1024²), and its `βx` and `βy` at `n = 8` from 1024²
/// (power 2.97–4.45 in `x` there), the same way. In the ninth session
/// elimination came to weigh one row (the module docs), which moved the
/// `sin` term in `y` (+0.0019 at `n = 8` and 16, power 1.0–2.4 in `y`): its
/// `βy` and `γ` at `n` = 4, 8 and 16 were solved again from two settings
/// each (512², 362², 256², seeds 1 and 2; `βy` at 16 from 512²), leaving
/// power at most 1.09 at 1024² (`n = 4`, seeds 1 and 2; `n = 16`, seed 1)
/// and 724² (`n = 8`); at `n = 64` the sets are the same as before.
///
/// A renderer's frame holds far more points than those rasters, and the
/// pixel-frequency power of a fixed residual grows with the count
/// (`N·|h|²/4` for a first harmonic `h`): at 1.07·10⁹ points (16384², one
/// run, 2026-11-28) elimination at `n = 4` read 212 in `y`, from a residual
/// of about −0.0008 (`cos`) and +0.0003 (`sin`) that runs of 10⁶ points
/// cannot resolve, and random dropping 12 at 1.34·10⁸ points. So their
/// `βy` and `γ` at `n = 4` were solved again on 8192×4096 pixels (1.34·10⁸
/// points a run): a step of +0.03 moved the `cos` term by +0.0039
/// (elimination) and +0.0020 (random dropping) and the `sin` term, for
/// `γ`, by −0.0040 and −0.0030. Elimination's `βy` 0.072 → 0.0782 and `γ`
/// −0.044 → −0.0417 (seeds 1 and 3 then: power 0.26 / 0.53 and 0.17 / 1.24
/// in `x` / `y`, edge bands 0.960–0.985, no top-up); random dropping's
/// `βy` 0.138 → 0.1425 and `γ` −0.074 → −0.069 (seeds 1 and 3: power 1.17 /
/// 0.07 and 0.27 / 0.14, edge bands 0.963–0.995, no top-up). At `n = 16`
/// (4096×2048, the same count of points) the old terms read 5.87 / 4.45
/// (elimination) and 9.11 / 1.18 (random dropping), seed 2; from a step
/// of +0.03 in `βx` (the `x` `cos` term +0.0029 and +0.0018) and the
/// earlier `βy` slope, elimination's `βx` 0.072 → 0.0677 and `βy` 0.077 →
/// 0.0809, random dropping's `βx` 0.048 → 0.0567 (seed 1 then: 0.51 / 0.65
/// and 0.71 / 1.32, edge bands 0.981–1.006). In the next session `n = 64`
/// (1448², the same count) followed: its old terms read 20.0 / 13.3
/// (elimination) and 7.0 / 6.1 (random dropping), seed 2; from a step of
/// +0.03 in each of `βx`, `βy` and `γ`, elimination's terms went from
/// `[0.007, 0.034, 0.017]` to `[0.0152, 0.0384, 0.013]` and random
/// dropping's from zero to `[0.0077, 0.0072, 0]` (seeds 1 and 3 then: power
/// at most 0.73, edge bands 0.973–1.023). And `n = 8` (4096², the same
/// count; old terms 31.1 / 19.5 and 2.4 / 16.9, seed 2), from steps in
/// `βx` and `βy` (elimination) and `βy` and `γ` (random dropping), the
/// other terms from the slopes measured at `n` = 4, 16 and 64. With the
/// new row for 64, `n = 32` (2048², seed 1), which lies between rows,
/// read 92.7 / 20.4 (elimination) and 45.4 / 41.3 (random dropping): the
/// terms fall faster than linearly from 16 to 64, so `n = 32` has a row of
/// its own, solved from that run and the slopes at 16 and 64; so do
/// `n = 24` (2365², seed 1: 5.25 / 4.54 and 8.09 / 4.71 between the rows
/// for 16 and 32) and elimination's `n = 48` (1672²: 3.13 / 2.95; random
/// dropping's 1.40 / 0.75, so its row for 48 is the interpolation). On
/// seed 2 the new rows read at most 0.78. `βx` at `n = 4` (elimination)
/// fell from 0.193 to 0.1918: at 1.07·10⁹ points, after the `βy` and `γ`
/// above, it read 4.84 in `x` (a `cos` term of +0.00013, taken at the
/// slope `n = 8` gave, 0.11), which no run of 10⁸ points resolves (0.17
/// to 0.31); a third billion-point run, on the new terms, then read
/// 0.32 / 1.75.
///
/// Past `n = 64` the table had no row, so `n` = 128 to 1024 took 64's
/// terms. At 1.34·10⁸ points (seed 2), elimination then read power 20.9 /
/// 53.0 at 128 and 42–49 / 131–237 at 256, 512 and 1024; random dropping
/// read 3.6–8.8. In the sixth session of 2026-11-28, elimination got rows
/// for 128, 256, 512 and 1024:
/// - the slopes came from two settings at 128 (`[0, 0, 0]` and `[0.03,
///   0.06, 0.03]`): 0.087 a unit of `βx`, 0.086 of `βy` and −0.125 of
///   `γ`, within 10 % of 64's;
/// - each other row was solved from its run on 64's terms, then solved
///   again from that run and a check run on seed 3 (the `βy` slope falls
///   to 0.072 at 1024, which left 4.52 in `y` there at first).
///
/// Random dropping's terms, solved the same way, lie within their noise
/// (about ±0.002) of zero from 128 up, and with none its power read 0.42 /
/// 0.76 at 128: its table ends with a row of zeros at 128. Past 1024 the
/// last row holds, unmeasured.
///
/// Counts between the rows, at the same size (seed 1), read over 3 where
/// the terms curve most. Elimination / random dropping, `x` / `y`:
/// - `n = 6`: 36.4 / 62.6 and 200.4 / 70.3;
/// - `n = 5`, once 6 had its row: 8.7 / 16.1 and 44.8 / 10.3;
/// - `n = 12`: 12.5 / 20.4 and 29.6 / 17.0;
/// - elimination at `n = 96`: 1.92 / 3.41; at 7: 1.18 / 2.96.
///
/// Each got a row, solved from that run with the slopes measured nearby
/// and checked on seed 2. Counts 20, 40, 56, 192, and random dropping's 7
/// and 96, read at most 2.39 between rows; the other counts between rows
/// are unmeasured. Every run is in `docs/streaming-runs.md`.
///
/// `δ` lifts the top band, which the rows above
/// deplete (their darts kill points near it, and elimination sees their
/// final points): at `n = 4` it was 0.93–0.94 of the interior without it
/// (elimination; random dropping 0.95–0.96). It was set by hand, trying
/// 0 to 0.6 with a throwaway build that read it from the environment (0.2:
/// top bands 0.96–0.97 for elimination, 0.95–0.97 for random dropping, 512²
/// and 256², three seeds); at `n >= 16` the bands are within 1–3 % without
/// it (at `n = 8` interpolating the rest gave power 4–9, hence its row).
/// Then, with `δ` fixed, `[βx, βy, γ]` zero the first harmonic of the
/// kept density across a pixel, measured with `examples/stream.rs --exact
/// N --method M --bias ...` on about 10⁶ points (512², 362², 256², 128²
/// pixels for `n` = 4, 8, 16, 64, `δ` 0.2, 0.1, 0, 0; seeds 1 and 2
/// averaged; the harmonic is linear in
/// each): β from two settings, then γ from two (the script and its runs
/// are in the journal, "Exact mode at k = 10"; the other rows came later,
/// at 10⁸ points). Linear in `n` between the rows, the first row's values
/// below (at `n = 1` no β helps: a quarter of the pixels are short there),
/// the last row's above. `y` differs from `x` because rows are settled in
/// order and columns together: darts take room from the row below, and
/// elimination sees the rows above settled and the row below oversampled.
/// Other oversamplings and `k` keep these values, which then fit less
/// well (`docs/images/exact-tradeoff.png`).
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
    /// measured at 1.34·10⁸ points (`docs/streaming-runs.md`: elimination
    /// 0.072–0.13 a unit of `βx` and `βy`, −0.12 to −0.133 of `γ`, −0.16 of
    /// `ε`; random dropping 0.057–0.067, −0.092 to −0.10 and −0.10), and the
    /// response `c` behind them (the kept density moves as `1 + c·β·h`):
    /// 0.49 and 0.3, `βx`'s slope over `2/π²`. The response differs by shape:
    /// `ε`'s slope over `−2/π` gives 0.25 and 0.16, so the cross terms'
    /// slopes may be up to twice the true ones, which slows their loop but
    /// keeps it stable. The waves' slope (how `A` moves `2·mean(cos)`) was
    /// read from the waves' settled amplitudes against the harmonics they
    /// cancel at `n = 4` (`docs/streaming-runs.md`, "The lattice's other
    /// frequencies"): 0.37 for elimination, 0.13–0.16 for random dropping.
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
