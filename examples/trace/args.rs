//! The command line of `trace`.

use crate::common;
use crate::scene::SCENES;
use crate::sources;
use clap::Parser;
use std::path::PathBuf;

/// A comma-separated list, one value per flag: clap reads a field typed
/// `Vec` as a repeated flag, and this name opts out of that.
type List<T> = Vec<T>;

const ABOUT: &str = "\
Renders the scenes of Ye's \"Implementing Bridson's Fast Poisson Disk Sampling
in PBRT\" with every pixel sampler, and measures each render's error against
a high-count reference: RMSE over --seeds seeds, split per pixel into bias^2
and variance, the RMSE after Gaussian blurs of 1 and 2 pixels, the error's
low-frequency power over white noise's, and the sampling and render times.
Prints a markdown table.";

const AFTER: &str = "\
Scenes: figure (a seated figure of analytic primitives under a quad light),
dof (thin lens, large aperture), checker (infinite checkerboard, pinhole,
unlit), motion (a moving sphere).

Samplers: poisson-pixel, poisson-exact (a 1x1 exact-mode stream per
pixel), independent, stratified, best-candidate, low-discrepancy, sobol-owen,
net (the crate's NetPixelSampler; not in the default list), zsobol
(pbrt-v4's ZSobol: Owen-scrambled Sobol' in Morton order), pmj02bn
(pbrt-v4's PMJ02BN scheme on pmj02bn sets generated from the seed),
poisson-exact-eliminate, poisson-exact-random (exact mode streamed over the
whole image, ExactMethod::Eliminate or Random) (exact counts), and
poisson-sweep (the crate's sweep, natural counts), poisson-joint (one 5-D
Poisson set per pixel over film, time and lens, natural counts),
poisson-paper (the paper as published: Scheme::Paper at r = sqrt(8/(5 pi N)),
separate lens, time and light sets, each pixel keeps the smallest count).

References: sobol-owen at --reference-spp in two independent halves (their
difference estimates the reference's own error); cached in --reference-dir
as raw little-endian f64, keyed by scene, size and count. --reference-spp 0
renders without a reference (timings only).

Outputs (with --out-dir): DIR/SCENE-SAMPLER-SPP.png (the first seed's render),
DIR/montage-SCENE-SPP.png (samplers side by side, a magnified crop and a
false-colour error map under each). --json FILE: {\"results\": [{\"scene\",
\"sampler\", \"spp\", \"rmse\", \"rmse_sd\", \"bias2\", \"variance\",
\"rmse_blur1\", \"rmse_blur1_sd\", \"rmse_blur2\", \"rmse_blur2_sd\" (the RMSE
after a Gaussian blur of sigma 1 and 2 pixels), \"low_frequency_power\" (the
error's periodogram below 0.125 cycles/pixel over its white-noise
expectation, over 32x32 tiles and seeds; null below one tile),
\"low_frequency_power_sd\" (its spread over seeds, each seed's own value),
\"samples_per_pixel_min\", \"samples_per_pixel_max\", \"sample_seconds\",
\"render_seconds\", \"seeds\"}, ..]}. Exit status: 0 success, 1 error writing
an output, 2 bad arguments.

Example:
  trace --scene checker --sampler poisson-pixel,independent --spp 16 \\
        --size 128x128 --seeds 8 --reference-dir refs --out-dir pics";

/// The flags.
#[derive(Debug, Parser)]
#[command(name = "trace", about = ABOUT, after_help = AFTER)]
pub(crate) struct Args {
    /// Scenes to render [default: figure,dof,checker,motion]
    #[arg(long, value_name = "A,B,..", value_parser = scene_list)]
    pub(crate) scene: Option<List<String>>,
    /// Samplers to compare [default: all but net]
    #[arg(long, value_name = "A,B,..", value_parser = sampler_list)]
    pub(crate) sampler: Option<List<String>>,
    /// Samples per pixel, each 1 to 4096
    #[arg(long, value_name = "A,B,..", default_value = "4,16,64", value_parser = spp_list)]
    pub(crate) spp: List<u32>,
    /// Image size in pixels
    #[arg(long, value_name = "WxH", default_value = "128x128", value_parser = size_arg)]
    pub(crate) size: [u32; 2],
    /// Seeds per (scene, sampler, spp): K renders, K >= 2 with a reference
    #[arg(long, value_name = "K", default_value_t = 8,
          value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub(crate) seeds: u32,
    /// Samples per pixel of the references (even, 0 for none), up to 131072
    #[arg(long, value_name = "N", default_value_t = 4096, value_parser = reference_spp)]
    pub(crate) reference_spp: u32,
    /// Cache the references here
    #[arg(long, value_name = "DIR")]
    pub(crate) reference_dir: Option<PathBuf>,
    /// Write each render's PNG and each scene's montage here
    #[arg(long, value_name = "DIR")]
    pub(crate) out_dir: Option<PathBuf>,
    /// Write every (scene, sampler, spp) result here as JSON
    #[arg(long, value_name = "FILE")]
    pub(crate) json: Option<PathBuf>,
    /// Render threads [default: the available cores]
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=256))]
    pub(crate) threads: Option<u32>,
    /// Seed of the first render; seed k of a study is S + k
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub(crate) seed: u64,
}

impl Args {
    /// The scenes asked for, or all of them.
    pub(crate) fn scenes(&self) -> Vec<String> {
        self.scene
            .clone()
            .unwrap_or_else(|| SCENES.map(str::to_owned).to_vec())
    }

    /// The samplers asked for, or all of them.
    pub(crate) fn samplers(&self) -> Vec<String> {
        self.sampler.clone().unwrap_or_else(|| {
            sources::default_names()
                .into_iter()
                .map(str::to_owned)
                .collect()
        })
    }

    /// The thread count asked for, or the cores available.
    pub(crate) fn thread_count(&self) -> usize {
        self.threads.map_or_else(
            || std::thread::available_parallelism().map_or(1, usize::from),
            |t| t as usize,
        )
    }
}

fn one_of(text: &str, known: &[&str], what: &str) -> Result<Vec<String>, String> {
    let names: Vec<String> = common::list(text)?;
    for name in &names {
        if !known.contains(&name.as_str()) {
            return Err(format!(
                "unknown {what} {name:?}; known: {}",
                known.join(",")
            ));
        }
    }
    Ok(names)
}

fn scene_list(text: &str) -> Result<Vec<String>, String> {
    one_of(text, &SCENES, "scene")
}

fn sampler_list(text: &str) -> Result<Vec<String>, String> {
    one_of(text, &sources::names(), "sampler")
}

fn spp_list(text: &str) -> Result<Vec<u32>, String> {
    let counts: Vec<u32> = common::list(text)?;
    match counts
        .iter()
        .find(|&&n| !(1..=bridson::MAX_SAMPLES_PER_PIXEL).contains(&n))
    {
        Some(n) => Err(format!("{n}: samples per pixel must be from 1 to 4096")),
        None => Ok(counts),
    }
}

fn size_arg(text: &str) -> Result<[u32; 2], String> {
    let (w, h) = common::size(text)?;
    if u64::from(w) * u64::from(h) > 1 << 24 {
        return Err("at most 2^24 pixels".to_owned());
    }
    Ok([w, h])
}

fn reference_spp(text: &str) -> Result<u32, String> {
    let n: u32 = text.parse().map_err(|_| format!("not a count: {text:?}"))?;
    if n % 2 == 1 || n > 1 << 17 {
        return Err("an even count up to 131072 (two halves), or 0".to_owned());
    }
    Ok(n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::common::parse_line;

    #[test]
    fn defaults_and_lists() {
        let args: Args = parse_line("trace", "").expect("no flags");
        assert_eq!(args.scenes(), SCENES, "every scene");
        assert_eq!(args.samplers().len(), 14, "every sampler but net");
        assert_eq!(args.spp, [4, 16, 64], "spp");
        assert_eq!(args.size, [128, 128], "size");
        assert_eq!(
            (args.seeds, args.reference_spp),
            (8, 4096),
            "seeds, reference"
        );
        let args: Args = parse_line(
            "trace",
            "--scene checker,dof --sampler poisson-paper,independent --spp 16 --size 32x24 \
             --seeds 3 --reference-spp 0 --threads 2 --seed 5",
        )
        .expect("valid");
        assert_eq!(args.scenes(), ["checker", "dof"], "scenes");
        assert_eq!(
            args.samplers(),
            ["poisson-paper", "independent"],
            "samplers"
        );
        assert_eq!(
            (args.size, args.seeds, args.thread_count()),
            ([32, 24], 3, 2),
            "numbers"
        );
    }

    #[test]
    fn bad_flags_are_rejected() {
        for line in [
            "--scene buddha",
            "--sampler nope",
            "--spp 0",
            "--spp 5000",
            "--size 0x4",
            "--seeds 0",
            "--reference-spp 101",
            "--threads 0",
            "--bogus",
        ] {
            assert!(parse_line::<Args>("trace", line).is_err(), "{line}");
        }
    }
}
