//! The measurement: for one sampler, the mean squared error of the
//! equal-weight estimate `1/N Σ f(x_i)` over the trials, for every N of the
//! grid and every integrand; and the least-squares slope of the curves.

use crate::common::samplers::{self, hash};
use crate::integrand::{Instance, Kind};

/// The sample counts of the study: every N from 1 to 64, then six a
/// doubling (64·2^(k/6), rounded) up to `n_max`, and `n_max` itself.
pub(crate) fn sample_counts(n_max: u32) -> Vec<u32> {
    let mut counts: Vec<u32> = (1..=n_max.min(64)).collect();
    let mut k = 1;
    loop {
        let n = (64.0 * 2_f64.powf(f64::from(k) / 6.0)).round();
        if n >= f64::from(n_max) {
            break;
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a whole number between 64 and n_max, a u32"
        )]
        counts.push(n as u32);
        k += 1;
    }
    if counts.last() != Some(&n_max) {
        counts.push(n_max);
    }
    counts
}

/// The random instances of one integrand, one per trial: trial `t` draws
/// its own from a seed hashed from (seed, integrand, t). The same instances
/// serve every sampler and every N.
pub(crate) fn instances(kind: Kind, trials: u32, seed: u64) -> Vec<Instance> {
    (0..trials)
        .map(|t| {
            let mut rng =
                bridson::seeded_rng(hash(&[seed, 0x696e_7374, kind as u64, u64::from(t)]));
            kind.draw(&mut rng)
        })
        .collect()
}

/// The pixel of trial `t`: a 64-wide raster, row by row. Each sampler
/// hashes (seed, pixel) into its sets, so distinct pixels give independent
/// sets (best-candidate's film positions excepted: they come from one table
/// tiled over the image, as in pbrt-v2).
pub(crate) fn pixel_of(trial: u32) -> [u32; 2] {
    [trial % 64, trial / 64]
}

/// The MSE of one sampler at `n` samples, for each integrand (in the order
/// of `instances`), over all trials.
///
/// # Errors
/// A message if the sampler cannot be built or refuses a sample.
pub(crate) fn mse_at(
    name: &str,
    n: u32,
    seed: u64,
    instances: &[Vec<Instance>],
) -> Result<Vec<f64>, String> {
    let mut sampler = samplers::by_name(name, n, seed)?;
    let trials = instances.first().map_or(0, Vec::len);
    let mut squared = vec![0.0; instances.len()];
    let mut points = Vec::with_capacity(usize::try_from(n).unwrap_or(0));
    for t in 0..trials {
        let trial = u32::try_from(t).map_err(|e| e.to_string())?;
        points.clear();
        for index in 0..n {
            sampler
                .start_pixel_sample(pixel_of(trial), index, 0)
                .map_err(|e| format!("{name}, {n} samples: {e}"))?;
            points.push(sampler.get_pixel_2d());
        }
        for (sum, per_kind) in squared.iter_mut().zip(instances) {
            let instance = &per_kind[t];
            let estimate = points.iter().map(|&p| instance.value(p)).sum::<f64>() / f64::from(n);
            let error = estimate - instance.exact;
            *sum += error * error;
        }
    }
    #[expect(clippy::cast_precision_loss, reason = "a trial count, far below 2^53")]
    let count = trials as f64;
    Ok(squared.into_iter().map(|s| s / count).collect())
}

/// The least-squares slope of `ln mse` against `ln n` over the points with
/// `n >= from` and a positive MSE; `None` with fewer than two such points.
pub(crate) fn fit_slope(points: &[(u32, f64)], from: u32) -> Option<f64> {
    let used: Vec<(f64, f64)> = points
        .iter()
        .filter(|&&(n, mse)| n >= from && mse > 0.0)
        .map(|&(n, mse)| (f64::from(n).ln(), mse.ln()))
        .collect();
    if used.len() < 2 {
        return None;
    }
    #[expect(clippy::cast_precision_loss, reason = "a few hundred points")]
    let count = used.len() as f64;
    let mean_x = used.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = used.iter().map(|p| p.1).sum::<f64>() / count;
    let sxx: f64 = used.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = used.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_dense_then_log_spaced() {
        let counts = sample_counts(1024);
        assert_eq!(&counts[..64], &(1..=64).collect::<Vec<_>>()[..], "1..=64");
        assert_eq!(counts.last(), Some(&1024), "ends at n_max");
        assert!(
            counts.windows(2).all(|w| w[0] < w[1]),
            "increasing: {counts:?}"
        );
        let above: Vec<u32> = counts.iter().copied().filter(|&n| n > 64).collect();
        assert!(above.len() >= 20, "six a doubling: {above:?}");
        assert!(
            above.iter().any(|n| !n.is_power_of_two()),
            "not powers of two only"
        );
        // Log-spaced: each step above 64 is a ratio of about 2^(1/6).
        for w in counts[63..].windows(2) {
            let ratio = f64::from(w[1]) / f64::from(w[0]);
            assert!((1.05..1.20).contains(&ratio), "{w:?}");
        }
        assert_eq!(sample_counts(8), (1..=8).collect::<Vec<_>>(), "small n_max");
        assert_eq!(sample_counts(100).last(), Some(&100), "n_max off the grid");
    }

    #[test]
    fn slope_fit_recovers_a_power_law() {
        let points: Vec<(u32, f64)> = sample_counts(1024)
            .into_iter()
            .map(|n| (n, 3.0 * f64::from(n).powf(-1.5)))
            .collect();
        let slope = fit_slope(&points, 16).expect("enough points");
        assert!((slope + 1.5).abs() < 1e-12, "slope {slope}");
        // Points below `from` are ignored: a different law there changes
        // nothing.
        let mut bent = points.clone();
        for p in bent.iter_mut().filter(|p| p.0 < 16) {
            p.1 = 1.0;
        }
        let slope = fit_slope(&bent, 16).expect("enough points");
        assert!((slope + 1.5).abs() < 1e-12, "slope {slope}");
        assert_eq!(fit_slope(&points[..16], 16), None, "one point only");
    }

    #[test]
    fn poisson_pixel_beats_independent_on_the_disk_at_16() {
        let instances = vec![instances(Kind::Disk, 400, 3)];
        let poisson = mse_at("poisson-pixel", 16, 3, &instances).expect("runs")[0];
        let independent = mse_at("independent", 16, 3, &instances).expect("runs")[0];
        assert!(
            poisson < 0.6 * independent,
            "poisson-pixel {poisson} vs independent {independent}"
        );
    }
}
