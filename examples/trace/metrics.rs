//! The metrics the papers on blue-noise error use, beside RMSE: the RMSE
//! of the error image after a Gaussian blur (what an eye or a denoiser
//! sees), and the share of the error's power at low frequencies.
//!
//! Both take the reference's own noise off as the RMSE does, through the
//! reference's half-difference image `d = (a − b) / 2` (its halves `a`
//! and `b` independent): `d` has the reference's own error's statistics,
//! so any linear filter of it, squared, estimates that filter's share of
//! the reference's noise without assuming pixels independent.

use crate::render::Image;

/// The Gaussian blurs of the blurred RMSE, in pixels.
pub(crate) const BLUR_SIGMAS: [f64; 2] = [1.0, 2.0];

/// Side of the square tiles the periodogram is taken over.
pub(crate) const TILE: usize = 32;

/// The band of the low-frequency power: radial frequencies below this, in
/// cycles per pixel (a quarter of Nyquist).
pub(crate) const LOW_BAND: f64 = 0.125;

/// `values` (row-major, `width` wide) convolved with a Gaussian of
/// standard deviation `sigma` pixels, truncated at `3σ` and renormalised
/// where it meets the border (so a constant image stays the same).
pub(crate) fn blur(values: &[f64], width: usize, sigma: f64) -> Vec<f64> {
    if width == 0 || values.is_empty() {
        return values.to_vec();
    }
    let height = values.len() / width;
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a few pixels"
    )]
    let radius = (3.0 * sigma).ceil() as usize;
    let kernel: Vec<f64> = (0..=2 * radius)
        .map(|i| {
            #[expect(clippy::cast_precision_loss, reason = "a few pixels")]
            let d = i as f64 - radius as f64;
            (-0.5 * (d / sigma).powi(2)).exp()
        })
        .collect();
    // One axis at a time; `stride` steps along it, `len` its length.
    let pass = |input: &[f64], len: usize, stride: usize, lines: usize, step: usize| {
        let mut out = vec![0.0; input.len()];
        for line in 0..lines {
            let base = line * step;
            for i in 0..len {
                let (mut sum, mut weight) = (0.0, 0.0);
                let lo = i.saturating_sub(radius);
                let hi = (i + radius).min(len - 1);
                for j in lo..=hi {
                    let w = kernel[j + radius - i];
                    sum += w * input[base + j * stride];
                    weight += w;
                }
                out[base + i * stride] = sum / weight;
            }
        }
        out
    };
    let rows = pass(values, width, 1, height, width);
    pass(&rows, height, width, width, 1)
}

/// The mean of the squares of `values` (0 for none).
fn mean_square(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    #[expect(clippy::cast_precision_loss, reason = "a pixel count")]
    let n = values.len() as f64;
    values.iter().map(|v| v * v).sum::<f64>() / n
}

/// The blurred RMSE of each render in `images` against `truth` at blur
/// `sigma`: per render, the mean square of the blurred error less that of
/// the blurred reference half-difference `half` (the reference's own
/// share), clamped at 0, and its root. Returns the RMSE over all renders
/// (root of the mean of the corrected squares) and the standard deviation
/// over renders of each render's own (divisor K − 1; 0 for one render).
pub(crate) fn blurred_rmse(
    images: &[&Image],
    truth: &[f64],
    half: &[f64],
    sigma: f64,
) -> (f64, f64) {
    let Some(first) = images.first() else {
        return (0.0, 0.0);
    };
    let width = first.width as usize;
    let own = mean_square(&blur(half, width, sigma));
    let squares: Vec<f64> = images
        .iter()
        .map(|image| {
            let error: Vec<f64> = image.values.iter().zip(truth).map(|(v, t)| v - t).collect();
            (mean_square(&blur(&error, width, sigma)) - own).max(0.0)
        })
        .collect();
    #[expect(clippy::cast_precision_loss, reason = "a seed count")]
    let k = squares.len() as f64;
    let rmse = (squares.iter().sum::<f64>() / k).sqrt();
    let roots: Vec<f64> = squares.iter().map(|s| s.sqrt()).collect();
    let mean = roots.iter().sum::<f64>() / k;
    let sd = if squares.len() < 2 {
        0.0
    } else {
        (roots.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt()
    };
    (rmse, sd)
}

/// The periodogram power of one `TILE × TILE` tile of `values` (at
/// `[x0, y0]`, `width` wide) summed over the low band and over all
/// frequencies: `(Σ_low P, Σ_all P)`, with `P(f) = |DFT(f)|² / TILE²` and,
/// by Parseval, `Σ_all P` the tile's sum of squares. No window and no
/// mean taken off: the DC term is in the low band.
fn tile_power(values: &[f64], width: usize, [x0, y0]: [usize; 2]) -> (f64, f64, usize) {
    let n = TILE;
    #[expect(clippy::cast_precision_loss, reason = "a small tile")]
    let nf = n as f64;
    let limit = LOW_BAND * nf;
    #[expect(clippy::cast_possible_truncation, reason = "a few frequencies")]
    let k_max = limit.ceil() as i64;
    let tau = std::f64::consts::TAU;
    let mut low = 0.0;
    let mut count = 0;
    for ky in -k_max..=k_max {
        for kx in -k_max..=k_max {
            #[expect(clippy::cast_precision_loss, reason = "small integers")]
            let radius = ((kx * kx + ky * ky) as f64).sqrt();
            if radius >= limit {
                continue;
            }
            let (mut re, mut im) = (0.0, 0.0);
            for y in 0..n {
                for x in 0..n {
                    let v = values[(y0 + y) * width + x0 + x];
                    #[expect(clippy::cast_precision_loss, reason = "small integers")]
                    let phase = -tau * (kx as f64 * x as f64 + ky as f64 * y as f64) / nf;
                    re += v * phase.cos();
                    im += v * phase.sin();
                }
            }
            low += (re * re + im * im) / (nf * nf);
            count += 1;
        }
    }
    let mut all = 0.0;
    for y in 0..n {
        for x in 0..n {
            all += values[(y0 + y) * width + x0 + x].powi(2);
        }
    }
    (low, all, count)
}

/// The error images' low-frequency power over its white-noise
/// expectation: over the `TILE × TILE` tiles of every render (the image's
/// remainder past the last whole tile is left out), the periodogram's mean
/// below [`LOW_BAND`] cycles per pixel over its mean at all frequencies,
/// each less the same for the reference's half-difference `half` (the
/// reference's own noise). White noise gives 1 in expectation; error
/// pushed to high frequencies (blue noise) less; smooth error more.
/// `None` if the image has no whole tile or no error power is left.
pub(crate) fn low_frequency_power(images: &[&Image], truth: &[f64], half: &[f64]) -> Option<f64> {
    let first = images.first()?;
    let (w, h) = (first.width as usize, first.height as usize);
    let tiles: Vec<[usize; 2]> = (0..h / TILE)
        .flat_map(|ty| (0..w / TILE).map(move |tx| [tx * TILE, ty * TILE]))
        .collect();
    if tiles.is_empty() {
        return None;
    }
    let (mut low, mut all, mut low_count) = (0.0, 0.0, 0);
    let (mut own_low, mut own_all) = (0.0, 0.0);
    for &corner in &tiles {
        let (l, a, c) = tile_power(half, w, corner);
        own_low += l;
        own_all += a;
        low_count = c;
    }
    for image in images {
        let error: Vec<f64> = image.values.iter().zip(truth).map(|(v, t)| v - t).collect();
        for &corner in &tiles {
            let (l, a, _) = tile_power(&error, w, corner);
            low += l;
            all += a;
        }
    }
    #[expect(clippy::cast_precision_loss, reason = "counts")]
    let (k, frequencies, band) = (images.len() as f64, (TILE * TILE) as f64, low_count as f64);
    let low = low / k - own_low;
    let all = all / k - own_all;
    (all > 0.0 && band > 0.0).then(|| (low / band) / (all / frequencies))
}

/// The spread of [`low_frequency_power`] over renders: the standard
/// deviation (divisor K − 1) of each render's own value. `None` for fewer
/// than two renders with a value.
pub(crate) fn low_frequency_spread(images: &[&Image], truth: &[f64], half: &[f64]) -> Option<f64> {
    let values: Vec<f64> = images
        .iter()
        .filter_map(|image| low_frequency_power(&[image], truth, half))
        .collect();
    if values.len() < 2 {
        return None;
    }
    #[expect(clippy::cast_precision_loss, reason = "a seed count")]
    let k = values.len() as f64;
    let mean = values.iter().sum::<f64>() / k;
    Some((values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (k - 1.0)).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::common::samplers::{hash, to_unit};

    fn image(width: u32, values: Vec<f64>) -> Image {
        #[expect(clippy::cast_possible_truncation, reason = "a small test image")]
        let height = (values.len() / width as usize) as u32;
        Image {
            width,
            height,
            values,
        }
    }

    /// A uniform white-noise value in `[-1, 1)`.
    fn noise(seed: u64, i: usize) -> f64 {
        2.0 * to_unit(hash(&[seed, i as u64])) - 1.0
    }

    #[test]
    fn blur_keeps_a_constant_and_smooths_noise() {
        let constant = vec![0.25; 40 * 30];
        for sigma in BLUR_SIGMAS {
            let b = blur(&constant, 40, sigma);
            assert!(b.iter().all(|v| (v - 0.25).abs() < 1e-12), "sigma {sigma}");
        }
        let white: Vec<f64> = (0..64 * 64).map(|i| noise(1, i)).collect();
        let ratio = mean_square(&blur(&white, 64, 2.0)) / mean_square(&white);
        // White noise under a Gaussian of σ keeps about 1 / (4πσ²) of its
        // power: 0.02 at σ = 2.
        assert!((0.01..0.04).contains(&ratio), "{ratio}");
    }

    #[test]
    fn blurred_rmse_of_a_constant_error_is_that_error() {
        let truth = vec![1.0; 32 * 16];
        let half = vec![0.0; truth.len()];
        let a = image(32, vec![1.1; truth.len()]);
        let b = image(32, vec![0.9; truth.len()]);
        for sigma in BLUR_SIGMAS {
            let (rmse, sd) = blurred_rmse(&[&a, &b], &truth, &half, sigma);
            assert!((rmse - 0.1).abs() < 1e-12, "sigma {sigma}: {rmse}");
            assert!(sd < 1e-12, "both seeds alike: {sd}");
        }
    }

    /// A render equal to the reference has no error left once the
    /// reference's own noise is taken off.
    #[test]
    fn the_reference_noise_is_taken_off() {
        let n = 64 * 64;
        let (ha, hb): (Vec<f64>, Vec<f64>) = (0..n).map(|i| (noise(2, i), noise(3, i))).unzip();
        let truth: Vec<f64> = ha.iter().zip(&hb).map(|(a, b)| 0.5 * (a + b)).collect();
        let half: Vec<f64> = ha.iter().zip(&hb).map(|(a, b)| 0.5 * (a - b)).collect();
        // A render of the truth itself (a zero) judged against the noisy
        // reference: its error is the reference's own, which goes.
        let zero = image(64, vec![0.0; n]);
        let (rmse, _) = blurred_rmse(&[&zero, &zero], &truth, &half, 1.0);
        let raw = mean_square(&blur(&truth, 64, 1.0)).sqrt();
        assert!(rmse < 0.4 * raw, "{rmse} against {raw} before");
    }

    #[test]
    fn white_noise_gives_about_one_and_smooth_error_much_more() {
        let (w, h) = (64_usize, 64_usize);
        let truth = vec![0.0; w * h];
        let half = vec![0.0; w * h];
        let white: Vec<Image> = (0..8)
            .map(|s| image(64, (0..w * h).map(|i| noise(10 + s, i)).collect()))
            .collect();
        let refs: Vec<&Image> = white.iter().collect();
        let p = low_frequency_power(&refs, &truth, &half).expect("tiles");
        assert!((0.8..1.2).contains(&p), "white noise: {p}");
        // One render's value over 4 tiles of about 45 low frequencies
        // each: a spread of roughly 1/sqrt(180), far below 0.5.
        let sd = low_frequency_spread(&refs, &truth, &half).expect("8 renders");
        assert!((0.01..0.3).contains(&sd), "spread {sd}");
        assert!(
            low_frequency_spread(&refs[..1], &truth, &half).is_none(),
            "one render"
        );
        // A slow wave (period 40 pixels) under a little noise.
        let smooth: Vec<Image> = (0..4)
            .map(|s| {
                image(
                    64,
                    (0..w * h)
                        .map(|i| {
                            #[expect(clippy::cast_precision_loss, reason = "small")]
                            let (x, y) = ((i % w) as f64, (i / w) as f64);
                            (std::f64::consts::TAU * (x + 0.5 * y) / 40.0).sin()
                                + 0.1 * noise(20 + s, i)
                        })
                        .collect(),
                )
            })
            .collect();
        let refs: Vec<&Image> = smooth.iter().collect();
        let p = low_frequency_power(&refs, &truth, &half).expect("tiles");
        assert!(p > 10.0, "smooth error: {p}");
        // High-frequency error (a checkerboard of ±1): almost none.
        let checker = image(
            64,
            (0..w * h)
                .map(|i| if (i % w + i / w) % 2 == 0 { 1.0 } else { -1.0 })
                .collect(),
        );
        let p = low_frequency_power(&[&checker], &truth, &half).expect("tiles");
        assert!(p < 1e-9, "checkerboard: {p}");
        let small = image(16, vec![0.0; 256]);
        assert!(
            low_frequency_power(&[&small], &truth[..256], &half[..256]).is_none(),
            "no whole tile"
        );
    }
}
