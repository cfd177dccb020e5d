//! The command line of `convergence`.

use crate::common::{self, samplers};
use crate::integrand::Kind;
use clap::Parser;
use std::path::PathBuf;

/// A comma-separated list, one value per flag: clap reads a field typed
/// `Vec` as a repeated flag, and this name opts out of that.
type List<T> = Vec<T>;

const ABOUT: &str = "\
Measures how fast each pixel sampler's equal-weight estimate 1/N sum f(x_i)
of an integral over [0,1)^2 converges: the mean squared error over many
random integrands (one pixel's film offsets per trial), for N = 1..64 and
then six values a doubling up to --n-max. Prints a markdown table of the MSE
at N = 4, 16, 64 and the slope of log MSE against log N fitted over N >= 16.";

const AFTER: &str = "\
Samplers: poisson-pixel, poisson-exact (the streaming exact scheme,
CameraPixels, one 1x1 stream per pixel), independent, stratified,
best-candidate, low-discrepancy, sobol-owen (all by default).

Integrands (each trial draws its own instance; the same instances serve
every sampler and N):
  disk      indicator of a disk on the torus, radius 0.05..0.45 (exact: pi r^2)
  triangle  the triangle y < x, scaled 0.4..1.2, rotated, moved, clipped to
            the square (exact: area by polygon clipping)
  step      x < 1/3 rotated about the centre (exact: area by clipping)
  gaussian  exp(-d^2 / 2 s^2), d the torus distance, s 0.03..0.15 (exact:
            the square of a 1-D Simpson integral, error below 1e-13)
  bilinear  x y (exact: 1/4)
Every instance is seen through a random toroidal shift of its input, which
keeps its integral.

Trial t uses pixel (t mod 64, t div 64) of one sampler per N and --seed.

Outputs: DIR/convergence-INTEGRAND.png (with --out-dir) and the JSON
{\"results\": [{\"sampler\", \"integrand\", \"n\", \"mse\", \"trials\"}, ..]}
(with --json). Exit status: 0 success, 1 error writing an output, 2 bad
arguments.

Example:
  convergence --n-max 256 --trials 1000 --out-dir pics --json pics/c.json";

/// The flags.
#[derive(Debug, Parser)]
#[command(name = "convergence", about = ABOUT, after_help = AFTER)]
pub(crate) struct Args {
    /// Samplers to compare [default: all six built]
    #[arg(long, value_name = "A,B,..", value_parser = sampler_list)]
    pub(crate) samplers: Option<List<String>>,
    /// Integrands [default: disk,triangle,step,gaussian,bilinear]
    #[arg(long, value_name = "A,B,..", value_parser = common::list::<Kind>)]
    pub(crate) integrands: Option<List<Kind>>,
    /// The largest N (samples per pixel), 1 to 4096
    #[arg(long, value_name = "N", default_value_t = 1024,
          value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub(crate) n_max: u32,
    /// Random integrands (and pixels) per N
    #[arg(long, value_name = "T", default_value_t = 1000,
          value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub(crate) trials: u32,
    /// Seed of the samplers and the integrands
    #[arg(long, value_name = "S", default_value_t = 1)]
    pub(crate) seed: u64,
    /// Write one log-log PNG per integrand here
    #[arg(long, value_name = "DIR")]
    pub(crate) out_dir: Option<PathBuf>,
    /// Write every (sampler, integrand, N) MSE here as JSON
    #[arg(long, value_name = "FILE")]
    pub(crate) json: Option<PathBuf>,
}

impl Args {
    /// The samplers asked for, or all of them.
    pub(crate) fn sampler_names(&self) -> Vec<String> {
        self.samplers
            .clone()
            .unwrap_or_else(|| samplers::NAMES.map(str::to_owned).to_vec())
    }

    /// The integrands asked for, or all of them.
    pub(crate) fn kinds(&self) -> Vec<Kind> {
        self.integrands
            .clone()
            .unwrap_or_else(|| Kind::ALL.to_vec())
    }
}

/// A comma-separated list of sampler names, each one `by_name` knows.
fn sampler_list(text: &str) -> Result<Vec<String>, String> {
    let names: Vec<String> = common::list(text)?;
    for name in &names {
        if !samplers::NAMES.contains(&name.as_str())
            && !samplers::EXTRA_NAMES.contains(&name.as_str())
        {
            return Err(format!(
                "unknown sampler {name:?}; known: {}",
                samplers::NAMES.join(",")
            ));
        }
    }
    Ok(names)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::common::parse_line;

    #[test]
    fn defaults_and_lists() {
        let args: Args = parse_line("convergence", "").expect("no flags");
        assert_eq!(args.n_max, 1024, "n-max");
        assert_eq!(args.trials, 1000, "trials");
        assert_eq!(args.sampler_names().len(), 7, "every sampler");
        assert_eq!(args.kinds(), Kind::ALL.to_vec(), "every integrand");
        let args: Args = parse_line(
            "convergence",
            "--samplers sobol-owen,independent --integrands disk,bilinear --n-max 8",
        )
        .expect("valid");
        assert_eq!(
            args.sampler_names(),
            ["sobol-owen", "independent"],
            "samplers"
        );
        assert_eq!(args.kinds(), [Kind::Disk, Kind::Bilinear], "integrands");
    }

    #[test]
    fn bad_flags_are_rejected() {
        for line in [
            "--samplers nope",
            "--integrands disk,square",
            "--n-max 0",
            "--n-max 5000",
            "--trials 0",
            "--seed -1",
        ] {
            assert!(parse_line::<Args>("convergence", line).is_err(), "{line}");
        }
    }
}
