//! Spectral views of 2-D point sets, after Lagae & Dutré (2008) and the PSA
//! tool of Schlömer & Heck: the periodogram on an integer frequency grid,
//! averaged over independent sets, and its radial mean and anisotropy.

use core::f64::consts::TAU;

/// The mean periodogram `P(f) = |Σ_j exp(−2πi f·x_j)|² / n` of point sets
/// in the unit square, for integer frequencies `f = (fx, fy)` with
/// `-F <= fx, fy <= F`. Computed by the exact transform (no FFT, no
/// rasterisation): per point, a table of `exp(−2πi fx·x)` for each axis,
/// then their outer product summed over the points.
#[derive(Clone, Debug)]
pub(crate) struct Periodogram {
    max_freq: u32,
    sets: u32,
    /// Sum over sets of `P(f)`, row-major: row `fy + F`, column `fx + F`.
    sum: Vec<f64>,
}

impl Periodogram {
    /// An empty average over the grid `-max_freq..=max_freq` on each axis.
    pub(crate) fn new(max_freq: u32) -> Self {
        let side = side(max_freq);
        Self {
            max_freq,
            sets: 0,
            sum: vec![0.0; side * side],
        }
    }

    /// `F`: frequencies run over `-F..=F` on each axis.
    pub(crate) fn max_freq(&self) -> u32 {
        self.max_freq
    }

    /// How many sets have been added.
    pub(crate) fn sets(&self) -> u32 {
        self.sets
    }

    /// Adds the periodogram of one set of points in the unit square.
    pub(crate) fn add_set(&mut self, points: &[[f64; 2]]) {
        for (sum, p) in self
            .sum
            .iter_mut()
            .zip(set_periodogram(points, self.max_freq))
        {
            *sum += p;
        }
        self.sets += 1;
    }

    /// The mean periodogram over the sets added, laid out as
    /// [`set_periodogram`]'s result.
    pub(crate) fn mean(&self) -> Vec<f64> {
        let sets = f64::from(self.sets.max(1));
        self.sum.iter().map(|s| s / sets).collect()
    }
}

/// The side of the frequency grid: `2F + 1`.
pub(crate) fn side(max_freq: u32) -> usize {
    2 * usize::try_from(max_freq).expect("frequency range fits usize") + 1
}

/// The periodogram of one set of points in the unit square, row-major with
/// row `fy + F` and column `fx + F`. `P(0) = n`; an empty set gives zeros.
///
/// Only `fy >= 0` is summed: for real points `P(−f) = P(f)`.
pub(crate) fn set_periodogram(points: &[[f64; 2]], max_freq: u32) -> Vec<f64> {
    let side = side(max_freq);
    let f = side / 2;
    let mut out = vec![0.0; side * side];
    if points.is_empty() {
        return out;
    }
    // Rows fy = 0..=F of the complex sum, real and imaginary parts apart so
    // the inner loop vectorises.
    let mut re = vec![0.0; (f + 1) * side];
    let mut im = vec![0.0; (f + 1) * side];
    let frequencies: Vec<f64> = (0..side).map(|k| signed(k, f)).collect();
    let (mut ex_re, mut ex_im) = (vec![0.0; side], vec![0.0; side]);
    let (mut ey_re, mut ey_im) = (vec![0.0; f + 1], vec![0.0; f + 1]);
    for p in points {
        for ((c, d), &fx) in ex_re.iter_mut().zip(ex_im.iter_mut()).zip(&frequencies) {
            let (s, cos) = (TAU * fx * p[0]).sin_cos();
            (*c, *d) = (cos, -s);
        }
        for ((a, b), &fy) in ey_re
            .iter_mut()
            .zip(ey_im.iter_mut())
            .zip(&frequencies[f..])
        {
            let (s, cos) = (TAU * fy * p[1]).sin_cos();
            (*a, *b) = (cos, -s);
        }
        for (((row_re, row_im), &a), &b) in re
            .chunks_exact_mut(side)
            .zip(im.chunks_exact_mut(side))
            .zip(&ey_re)
            .zip(&ey_im)
        {
            // (a + ib)(c + id), summed into the row.
            for (((r, i), &c), &d) in row_re
                .iter_mut()
                .zip(row_im.iter_mut())
                .zip(&ex_re)
                .zip(&ex_im)
            {
                *r += a * c - b * d;
                *i += a * d + b * c;
            }
        }
    }
    let n = points.len() as f64;
    for fy in 0..=f {
        for col in 0..side {
            let k = fy * side + col;
            let power = (re[k] * re[k] + im[k] * im[k]) / n;
            out[(f + fy) * side + col] = power;
            // P(−fx, −fy) = P(fx, fy).
            out[(f - fy) * side + (side - 1 - col)] = power;
        }
    }
    out
}

/// `round(|f|)` for `f = (fx, fy)` if it is in `1..=F`, else 0 (the DC term
/// and the corners of the grid). `|f|²` is a whole number, so `|f|` is never
/// within rounding of a half.
fn ring(fx: f64, fy: f64, max: usize) -> usize {
    let r = (fx * fx + fy * fy).sqrt().round();
    if r <= max as f64 {
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a whole number in 0..=F, checked above"
        )]
        let r = r as usize;
        r
    } else {
        0
    }
}

/// Grid index `k` of `0..side` as the signed frequency `k − F`.
fn signed(k: usize, f: usize) -> f64 {
    k as f64 - f as f64
}

/// One frequency ring of a periodogram: the frequencies `f` with
/// `round(|f|) == frequency`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Ring {
    pub(crate) frequency: u32,
    /// How many grid frequencies fall in the ring.
    pub(crate) samples: usize,
    /// The radially averaged power: the mean of `P` over the ring.
    pub(crate) power: f64,
    /// `10·log10(variance / mean²)` of `P` over the ring, in dB; `None`
    /// when it is undefined (a constant ring, a zero mean).
    pub(crate) anisotropy_db: Option<f64>,
}

/// The rings `1..=F` of a periodogram laid out as [`set_periodogram`]'s
/// result (the DC term and the corners beyond `|f| = F + ½` are left out).
///
/// For an average of `M` periodograms of independent uniform random sets
/// the radial power is 1 and the anisotropy `−10·log10(M)` dB: the level an
/// isotropic set's anisotropy is judged against.
pub(crate) fn radial(periodogram: &[f64], max_freq: u32) -> Vec<Ring> {
    let side = side(max_freq);
    let f = side / 2;
    assert_eq!(periodogram.len(), side * side, "periodogram size");
    // The ring of each grid frequency (0 = left out), then two passes: the
    // means, then the variance about them (no cancellation).
    let rings: Vec<usize> = (0..side * side)
        .map(|k| ring(signed(k % side, f), signed(k / side, f), f))
        .collect();
    let mut sums = vec![(0usize, 0.0_f64, 0.0_f64); f + 1];
    for (&k, &p) in rings.iter().zip(periodogram) {
        sums[k].0 += 1;
        sums[k].1 += p;
    }
    let means: Vec<f64> = sums
        .iter()
        .map(|&(c, s, _)| if c > 0 { s / c as f64 } else { f64::NAN })
        .collect();
    for (&k, &p) in rings.iter().zip(periodogram) {
        sums[k].2 += (p - means[k]).powi(2);
    }
    (1..=f)
        .zip(1..=max_freq)
        .map(|(k, frequency)| {
            let (count, _, squares) = sums[k];
            let mean = means[k];
            let variance = squares / count as f64;
            let ratio = variance / (mean * mean);
            Ring {
                frequency,
                samples: count,
                power: mean,
                anisotropy_db: (ratio > 0.0 && ratio.is_finite()).then(|| 10.0 * ratio.log10()),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use bridson::rand::RngExt;

    /// `P(f)` straight from the definition.
    fn direct(points: &[[f64; 2]], fx: f64, fy: f64) -> f64 {
        let (mut re, mut im) = (0.0, 0.0);
        for p in points {
            let phase = -TAU * (fx * p[0] + fy * p[1]);
            re += phase.cos();
            im += phase.sin();
        }
        (re * re + im * im) / points.len() as f64
    }

    fn at(p: &[f64], max_freq: u32, fx: i32, fy: i32) -> f64 {
        let f = i32::try_from(max_freq).expect("small");
        let side = side(max_freq);
        let row = usize::try_from(fy + f).expect("in range");
        let col = usize::try_from(fx + f).expect("in range");
        p[row * side + col]
    }

    #[test]
    fn a_single_point_has_a_flat_spectrum() {
        for point in [[0.0, 0.0], [0.3, 0.7], [0.999, 0.123]] {
            let p = set_periodogram(&[point], 6);
            assert_eq!(p.len(), 13 * 13, "grid size");
            for (i, &v) in p.iter().enumerate() {
                assert!((v - 1.0).abs() < 1e-12, "{point:?}: P[{i}] = {v}");
            }
        }
    }

    #[test]
    fn a_lattice_has_peaks_at_its_frequencies_only() {
        // 4×4 lattice: P = n where both frequencies are multiples of 4.
        let m = 4;
        let points: Vec<[f64; 2]> = (0..m * m)
            .map(|k| {
                let (i, j) = (f64::from(k % m), f64::from(k / m));
                [(i + 0.3) / f64::from(m), (j + 0.6) / f64::from(m)]
            })
            .collect();
        let max_freq = 10;
        let p = set_periodogram(&points, max_freq);
        for fy in -10..=10 {
            for fx in -10..=10 {
                let v = at(&p, max_freq, fx, fy);
                let expected = if fx % m == 0 && fy % m == 0 {
                    16.0
                } else {
                    0.0
                };
                assert!((v - expected).abs() < 1e-9, "P({fx}, {fy}) = {v}");
            }
        }
    }

    #[test]
    fn matches_the_definition_for_random_points() {
        let mut rng = bridson::seeded_rng(11);
        let points: Vec<[f64; 2]> = (0..37)
            .map(|_| [rng.random::<f64>(), rng.random::<f64>()])
            .collect();
        let max_freq = 9;
        let p = set_periodogram(&points, max_freq);
        for (fx, fy) in [(0, 0), (1, 0), (0, -1), (3, 7), (-9, 9), (-4, -2), (9, -9)] {
            let expected = direct(&points, f64::from(fx), f64::from(fy));
            let got = at(&p, max_freq, fx, fy);
            assert!(
                (got - expected).abs() < 1e-9 * expected.max(1.0),
                "P({fx}, {fy}): {got} vs {expected}"
            );
        }
        assert!((at(&p, max_freq, 0, 0) - 37.0).abs() < 1e-9, "P(0) = n");
    }

    #[test]
    fn averaging_divides_by_the_number_of_sets() {
        let mut pg = Periodogram::new(3);
        pg.add_set(&[[0.1, 0.2]]);
        pg.add_set(&[[0.5, 0.5], [0.0, 0.5]]);
        assert_eq!(pg.sets(), 2, "sets");
        let mean = pg.mean();
        let (one, two) = (
            set_periodogram(&[[0.1, 0.2]], 3),
            set_periodogram(&[[0.5, 0.5], [0.0, 0.5]], 3),
        );
        for k in 0..mean.len() {
            assert!(
                (mean[k] - (one[k] + two[k]) / 2.0).abs() < 1e-12,
                "mean at {k}"
            );
        }
    }

    #[test]
    fn rings_of_a_constant_spectrum() {
        let max_freq = 8;
        let p = vec![2.5; side(max_freq) * side(max_freq)];
        let rings = radial(&p, max_freq);
        assert_eq!(rings.len(), 8, "rings 1..=F");
        for r in &rings {
            assert!((r.power - 2.5).abs() < 1e-12, "ring {}", r.frequency);
            assert_eq!(r.anisotropy_db, None, "constant ring {}", r.frequency);
        }
        // Ring 1 is the 8 neighbours of the origin with |f| in {1, √2}.
        assert_eq!(rings[0].samples, 8, "ring 1");
        // Every frequency with 0 < |f| < F + ½ lands in exactly one ring.
        let inside = (-8..=8_i32)
            .flat_map(|x| (-8..=8_i32).map(move |y| x * x + y * y))
            .filter(|&m| m > 0 && 4 * m < 17 * 17)
            .count();
        let total: usize = rings.iter().map(|r| r.samples).sum();
        assert_eq!(total, inside, "rings partition the disc");
    }

    #[test]
    fn white_noise_is_flat_with_the_reference_anisotropy() {
        let (sets, n, max_freq) = (8, 400, 16);
        let mut rng = bridson::seeded_rng(5);
        let mut pg = Periodogram::new(max_freq);
        for _ in 0..sets {
            let points: Vec<[f64; 2]> = (0..n)
                .map(|_| [rng.random::<f64>(), rng.random::<f64>()])
                .collect();
            pg.add_set(&points);
        }
        let rings = radial(&pg.mean(), max_freq);
        let high = &rings[7..];
        let power = high.iter().map(|r| r.power).sum::<f64>() / high.len() as f64;
        assert!((power - 1.0).abs() < 0.08, "mean power {power}");
        let db = high
            .iter()
            .map(|r| r.anisotropy_db.expect("defined"))
            .sum::<f64>()
            / high.len() as f64;
        let reference = -10.0 * f64::from(sets).log10();
        assert!(
            (db - reference).abs() < 1.0,
            "anisotropy {db} dB vs {reference}"
        );
    }
}
