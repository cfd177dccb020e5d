//! The measurement: references (rendered once per scene and size, cached),
//! and, per (scene, sampler, spp), the error of K renders against the
//! reference, split per pixel into bias² and variance.

use crate::metrics;
use crate::render::{Image, Rendered, render};
use crate::scene::Scene;
use crate::sources::Recipe;
use std::path::Path;

/// The sampler references are rendered with: Owen-scrambled Sobol', whose
/// error at thousands of samples is far below that of the others at 64 and
/// whose independent scrambles make the two halves independent. No sampler
/// is judged against a reference made by itself at a low count.
pub(crate) const REFERENCE_SAMPLER: &str = "sobol-owen";

/// The seeds of the references' two halves: fixed, apart from `--seed`.
const REFERENCE_SEEDS: [u64; 2] = [0x5245_4631, 0x5245_4632];

/// A scene's reference: the mean of two independent half-count renders.
#[derive(Clone, Debug)]
pub(crate) struct Reference {
    pub(crate) spp: u32,
    pub(crate) image: Image,
    /// Per pixel, the squared half-difference of the halves: an unbiased
    /// estimate of the reference's own squared error there.
    pub(crate) own_squared_error: Vec<f64>,
    /// Per pixel, the half-difference of the halves, `(a − b) / 2`: it has
    /// the statistics of the reference's own error, so filtered (blurred,
    /// transformed) it estimates the filtered reference error's power.
    pub(crate) half_difference: Vec<f64>,
    /// Seconds spent rendering it (0 when read from the cache).
    pub(crate) seconds: f64,
}

impl Reference {
    /// The reference's own RMSE, estimated from its halves.
    pub(crate) fn rmse(&self) -> f64 {
        mean(&self.own_squared_error).sqrt()
    }

    fn from_halves(spp: u32, a: &Image, b: &Image, seconds: f64) -> Self {
        let values = a
            .values
            .iter()
            .zip(&b.values)
            .map(|(x, y)| 0.5 * (x + y))
            .collect();
        let half_difference: Vec<f64> = a
            .values
            .iter()
            .zip(&b.values)
            .map(|(x, y)| 0.5 * (x - y))
            .collect();
        let own_squared_error = half_difference.iter().map(|d| d * d).collect();
        Self {
            spp,
            image: Image {
                values,
                ..a.clone()
            },
            own_squared_error,
            half_difference,
            seconds,
        }
    }
}

/// The reference of `scene` at `spp` samples per pixel: read from `dir` if
/// a file there has the same scene key (which covers the size), count and
/// seeds, otherwise rendered (and written there).
///
/// The key is a hash of the scene's description (camera, size, objects,
/// light, shading), not of the tracer's code: after changing how the tracer
/// shades or samples the light, empty the directory.
///
/// # Errors
/// A message if rendering fails or the cache cannot be written.
pub(crate) fn reference(
    scene: &Scene,
    size: [u32; 2],
    spp: u32,
    dir: Option<&Path>,
    threads: usize,
    progress: &mut dyn FnMut(f64),
) -> Result<Reference, String> {
    let file = dir.map(|d| {
        d.join(format!(
            "{}-{}x{}-{spp}spp-{:016x}.f64",
            scene.name,
            size[0],
            size[1],
            scene.key() ^ REFERENCE_SEEDS[0]
        ))
    });
    let pixels = size[0] as usize * size[1] as usize;
    if let Some(bytes) = file.as_ref().and_then(|f| std::fs::read(f).ok())
        && bytes.len() == 2 * 8 * pixels
    {
        let floats: Vec<f64> = bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])))
            .collect();
        let (a, b) = floats.split_at(pixels);
        let image = |values: &[f64]| Image {
            width: size[0],
            height: size[1],
            values: values.to_vec(),
        };
        return Ok(Reference::from_halves(spp, &image(a), &image(b), 0.0));
    }
    let mut halves = Vec::new();
    let mut seconds = 0.0;
    for (k, seed) in (0_u32..).zip(REFERENCE_SEEDS) {
        let recipe = Recipe::new(REFERENCE_SAMPLER, spp / 2, seed, size)?;
        let rendered = render(scene, &recipe, threads, &mut |f| {
            progress((f64::from(k) + f) / 2.0)
        })?;
        seconds += rendered.render_seconds;
        halves.push(rendered.image);
    }
    let reference = Reference::from_halves(spp, &halves[0], &halves[1], seconds);
    if let Some(file) = file {
        if let Some(parent) = file.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("creating {}: {e}", parent.display()))?;
        }
        let bytes: Vec<u8> = halves
            .iter()
            .flat_map(|h| &h.values)
            .flat_map(|v| v.to_le_bytes())
            .collect();
        std::fs::write(&file, bytes).map_err(|e| format!("writing {}: {e}", file.display()))?;
    }
    Ok(reference)
}

/// The error of K renders (one per seed) against a reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Errors {
    /// `sqrt(bias2 + variance)`: the root of the mean over seeds and pixels
    /// of the squared error, less the reference's own.
    pub(crate) rmse: f64,
    /// The standard deviation over seeds of each seed's RMSE.
    pub(crate) rmse_sd: f64,
    /// Per pixel, the squared difference of the mean over seeds from the
    /// reference, less the variance of that mean and the reference's own
    /// squared error (so unbiased, and possibly slightly negative when
    /// there is no bias); averaged over pixels.
    pub(crate) bias2: f64,
    /// Per pixel, the variance over seeds (divisor K − 1); averaged.
    pub(crate) variance: f64,
    /// The RMSE after a Gaussian blur of σ = 1 and 2 pixels
    /// ([`metrics::BLUR_SIGMAS`]), the reference's own share taken off,
    /// and the standard deviation over seeds of each seed's.
    pub(crate) blurred: [(f64, f64); 2],
    /// The error's periodogram power below a quarter of Nyquist over its
    /// white-noise expectation ([`metrics::low_frequency_power`]): about 1
    /// for white noise, less for blue. `None` below one 32 × 32 tile.
    pub(crate) low_frequency: Option<f64>,
    /// Its spread over seeds: the standard deviation of each seed's own
    /// value ([`metrics::low_frequency_spread`]).
    pub(crate) low_frequency_sd: Option<f64>,
}

/// The errors of `images` (K >= 2) against `reference`.
pub(crate) fn errors(images: &[&Image], reference: &Reference) -> Option<Errors> {
    let k = images.len();
    if k < 2 {
        return None;
    }
    #[expect(clippy::cast_precision_loss, reason = "a seed count")]
    let kf = k as f64;
    let truth = &reference.image.values;
    let mut bias2 = Vec::with_capacity(truth.len());
    let mut variance = Vec::with_capacity(truth.len());
    for (p, (&r, &own)) in truth.iter().zip(&reference.own_squared_error).enumerate() {
        let m = images.iter().map(|i| i.values[p]).sum::<f64>() / kf;
        let var = images
            .iter()
            .map(|i| (i.values[p] - m).powi(2))
            .sum::<f64>()
            / (kf - 1.0);
        variance.push(var);
        bias2.push((m - r).powi(2) - var / kf - own);
    }
    let own = mean(&reference.own_squared_error);
    let per_seed: Vec<f64> = images
        .iter()
        .map(|i| {
            let squared: Vec<f64> = i
                .values
                .iter()
                .zip(truth)
                .map(|(v, r)| (v - r).powi(2))
                .collect();
            (mean(&squared) - own).max(0.0).sqrt()
        })
        .collect();
    let mean_rmse = mean(&per_seed);
    let sd = (per_seed
        .iter()
        .map(|r| (r - mean_rmse).powi(2))
        .sum::<f64>()
        / (kf - 1.0))
        .sqrt();
    let (bias2, variance) = (mean(&bias2), mean(&variance));
    let half = &reference.half_difference;
    Some(Errors {
        rmse: (bias2 + variance).max(0.0).sqrt(),
        rmse_sd: sd,
        bias2,
        variance,
        blurred: metrics::BLUR_SIGMAS.map(|s| metrics::blurred_rmse(images, truth, half, s)),
        low_frequency: metrics::low_frequency_power(images, truth, half),
        low_frequency_sd: metrics::low_frequency_spread(images, truth, half),
    })
}

/// The mean of `values` (0 for none).
pub(crate) fn mean(values: &[f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    #[expect(clippy::cast_precision_loss, reason = "a pixel count")]
    let n = values.len() as f64;
    values.iter().sum::<f64>() / n
}

/// One row of the results: a (scene, sampler, spp) over K seeds.
#[derive(Clone, Debug)]
pub(crate) struct Row {
    pub(crate) scene: String,
    pub(crate) sampler: String,
    pub(crate) spp: u32,
    pub(crate) errors: Option<Errors>,
    pub(crate) samples_per_pixel: [usize; 2],
    /// Means over the seeds.
    pub(crate) sample_seconds: f64,
    pub(crate) render_seconds: f64,
    pub(crate) seeds: u32,
}

/// Renders `scene` with `sampler` at `spp` for each of `seeds`, and sums
/// them up against `reference` (if any). Returns the row and the first
/// seed's render.
///
/// # Errors
/// A message if the sampler cannot be built.
#[expect(
    clippy::too_many_arguments,
    reason = "the study's coordinates, spelled out"
)]
pub(crate) fn measure(
    scene: &Scene,
    sampler: &str,
    spp: u32,
    seeds: &[u64],
    size: [u32; 2],
    reference: Option<&Reference>,
    threads: usize,
    progress: &mut dyn FnMut(f64, u32),
) -> Result<(Row, Rendered), String> {
    let mut renders: Vec<Rendered> = Vec::new();
    for (k, &seed) in (0_u32..).zip(seeds) {
        let recipe = Recipe::new(sampler, spp, seed, size)?;
        let done = renders.len();
        #[expect(clippy::cast_precision_loss, reason = "a seed count")]
        let (done, total) = (done as f64, seeds.len() as f64);
        renders.push(render(scene, &recipe, threads, &mut |f| {
            progress((done + f) / total, k + 1)
        })?);
    }
    let images: Vec<&Image> = renders.iter().map(|r| &r.image).collect();
    let errors = reference.and_then(|r| errors(&images, r));
    let counts = renders.iter().fold([usize::MAX, 0], |c, r| {
        [
            c[0].min(r.samples_per_pixel[0]),
            c[1].max(r.samples_per_pixel[1]),
        ]
    });
    let times = |f: fn(&Rendered) -> f64| mean(&renders.iter().map(f).collect::<Vec<_>>());
    let row = Row {
        scene: scene.name.to_owned(),
        sampler: sampler.to_owned(),
        spp,
        errors,
        samples_per_pixel: counts,
        sample_seconds: times(|r| r.sample_seconds),
        render_seconds: times(|r| r.render_seconds),
        seeds: u32::try_from(seeds.len()).unwrap_or(u32::MAX),
    };
    let first = renders.into_iter().next().ok_or("no seeds")?;
    Ok((row, first))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: Vec<f64>) -> Image {
        Image {
            width: 2,
            height: 1,
            values,
        }
    }

    #[test]
    fn errors_split_into_bias_and_variance() {
        let reference = Reference {
            spp: 0,
            image: image(vec![1.0, 2.0]),
            own_squared_error: vec![0.0, 0.0],
            half_difference: vec![0.0, 0.0],
            seconds: 0.0,
        };
        // Pixel 0: values 1 ± 1 (no bias, variance 2 with divisor K − 1 = 1);
        // pixel 1: always 2.5 (bias 0.5, no variance).
        let a = image(vec![0.0, 2.5]);
        let b = image(vec![2.0, 2.5]);
        let e = errors(&[&a, &b], &reference).expect("two seeds");
        // Bias² of pixel 0: (1 − 1)² − 2/2 = −1; of pixel 1: 0.25.
        assert!((e.bias2 - (-1.0 + 0.25) / 2.0).abs() < 1e-15, "{e:?}");
        assert!((e.variance - 1.0).abs() < 1e-15, "{e:?}");
        // The mean squared error over seeds and pixels is (1 + 0.25) / 2.
        assert!((e.rmse - 0.625_f64.sqrt()).abs() < 1e-15, "{e:?}");
        assert!(
            e.rmse_sd.abs() < 1e-15,
            "both seeds have the same RMSE: {e:?}"
        );
        assert!(
            errors(&[&a], &reference).is_none(),
            "one seed is not enough"
        );
    }

    #[test]
    fn the_reference_error_is_taken_off() {
        let a = image(vec![1.0, 1.0]);
        let b = image(vec![1.2, 0.8]);
        let reference = Reference::from_halves(2, &a, &b, 0.0);
        assert!(
            (reference.rmse() - 0.1).abs() < 1e-12,
            "{}",
            reference.rmse()
        );
        // Renders equal to the reference have no error left, whatever the
        // reference's own.
        let same = image(reference.image.values.clone());
        let e = errors(&[&same, &same], &reference).expect("two seeds");
        assert!((e.bias2 + 0.01).abs() < 1e-12 && e.variance == 0.0, "{e:?}");
    }
}

/// The paper's headline, measured at a small size: on `checker` at 16
/// samples per pixel, the crate's Poisson samplers beat independent
/// sampling by more than the noise of the comparison, and the paper's own
/// scheme leaves pixels with fewer samples than asked. Seconds optimised,
/// so CI runs it on the bench profile (`--ignored`).
#[cfg(test)]
mod headline {
    use super::*;

    #[test]
    #[ignore = "renders a reference and 6 x 6 images: seconds optimised, slow in a debug build"]
    fn poisson_beats_independent_on_the_checkerboard_at_16() {
        let size = [32, 32];
        let scene = Scene::by_name("checker", size).expect("known");
        let reference = reference(&scene, size, 1024, None, 2, &mut |_| {}).expect("renders");
        let seeds: Vec<u64> = (100..106).collect();
        let run = |name| {
            measure(
                &scene,
                name,
                16,
                &seeds,
                size,
                Some(&reference),
                2,
                &mut |_, _| {},
            )
            .expect("renders")
            .0
        };
        let independent = run("independent");
        let base = independent.errors.expect("a reference");
        for name in [
            "poisson-pixel",
            "poisson-exact",
            "poisson-exact-eliminate",
            "poisson-exact-random",
        ] {
            let row = run(name);
            let e = row.errors.expect("a reference");
            // The standard error of each mean RMSE over the 6 seeds.
            let noise = (e.rmse_sd.powi(2) + base.rmse_sd.powi(2)).sqrt() / 6_f64.sqrt();
            assert!(
                e.rmse + 3.0 * noise < base.rmse,
                "{name}: RMSE {} ± {}, independent {} ± {}",
                e.rmse,
                e.rmse_sd,
                base.rmse,
                base.rmse_sd
            );
            assert_eq!(row.samples_per_pixel, [16, 16], "{name}: exact counts");
        }
        let paper = run("poisson-paper");
        assert!(
            paper.samples_per_pixel[0] < 16,
            "poisson-paper keeps the smallest set: {:?}",
            paper.samples_per_pixel
        );
        assert!(
            reference.rmse() < 0.2 * base.rmse,
            "reference {} vs {}",
            reference.rmse(),
            base.rmse
        );
    }
}
