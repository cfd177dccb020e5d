//! Helpers shared by the examples: how a run ends (messages and exit
//! codes), value parsers for clap, and the peak memory of the process.
//! Uniform draws in `[0, 1)` are rand's own, `rng.random::<f64>()` with
//! `bridson::rand::RngExt` in scope. Each example includes this file with
//! `#[path = "common/mod.rs"] mod common;`.
//!
//! Exit codes are the same in every example: 0 on success, 1 if writing an
//! output fails, 2 for bad arguments (clap's own errors exit 2 as well) or
//! parameters the sampler rejects.
#![allow(
    dead_code,
    reason = "each example compiles this module and uses only part of it"
)]

/// The samplers renderers use today, behind [`bridson::PixelSampler`], to
/// compare with the crate's Poisson samplers.
pub(crate) mod samplers;

/// A progress bar with the time left, for long runs.
pub(crate) mod progress;

use std::io::{self, Write};
use std::path::Path;
use std::process::ExitCode;
use std::str::FromStr;

/// Why a run failed; decides the exit code.
#[derive(Debug)]
pub(crate) enum Failure {
    /// Bad arguments or parameters the sampler rejects (exit 2).
    Usage(String),
    /// Writing an output failed (exit 1).
    Io(String),
}

/// Ends a run of the example `name`: prints the failure, if any, to stderr
/// and returns the exit code it stands for.
/// Calls `run::<N>(arg)` for the dimension `dim`, one of the literal
/// dimensions listed (from the first to the last), or gives the usage
/// error that names their range: the const parameter is fixed at compile
/// time, so each dimension an example supports is one arm.
#[allow(unused_macros, reason = "used by the examples that take --dim only")]
macro_rules! by_dimension {
    ($dim:expr, $run:ident($arg:expr), $first:literal $(, $n:literal)*) => {
        match $dim {
            $first => $run::<$first>($arg),
            $($n => $run::<$n>($arg),)*
            d => Err($crate::common::Failure::Usage(format!(
                "--dim must be from {} to {}, got {d}",
                $first,
                [$first $(, $n)*][[$first $(, $n)*].len() - 1]
            ))),
        }
    };
}
#[allow(unused_imports, reason = "used by the examples that take --dim only")]
pub(crate) use by_dimension;

pub(crate) fn finish(name: &str, result: Result<(), Failure>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(message)) => {
            report(&format!(
                "{name}: error: {message}\n{name}: run with --help for usage"
            ));
            ExitCode::from(2)
        }
        Err(Failure::Io(message)) => {
            report(&format!("{name}: error: {message}"));
            ExitCode::from(1)
        }
    }
}

/// Writes a line to stderr. Unlike `eprintln!`, never panics if stderr is
/// gone: there is nowhere left to report that.
pub(crate) fn report(line: &str) {
    let mut err = io::stderr().lock();
    let _ = writeln!(err, "{line}");
}

/// A comma-separated list such as `1,2,3`, for `#[arg(value_parser = …)]`.
/// Every item must parse; an empty item is an error.
pub(crate) fn list<T: FromStr>(text: &str) -> Result<Vec<T>, String> {
    text.split(',')
        .map(|item| {
            item.trim()
                .parse()
                .map_err(|_| format!("invalid item '{item}' in '{text}'"))
        })
        .collect()
}

/// A raster size `WxH` of two positive whole numbers, such as `64x48`, for
/// `#[arg(value_parser = …)]`.
pub(crate) fn size(text: &str) -> Result<(u32, u32), String> {
    text.split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse().ok()?, h.trim().parse().ok()?)))
        .filter(|&(w, h): &(u32, u32)| w > 0 && h > 0)
        .ok_or_else(|| "expected WxH, two positive whole numbers (e.g. 64x48)".to_owned())
}

/// `--candidates annulus | sphere`: the candidate distribution, as a clap
/// value.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum CandidatesArg {
    /// Bridson's original: uniform in volume over the shell `r..2r`.
    #[default]
    Annulus,
    /// On the sphere of radius `r` (Roberts 2019): packs denser.
    Sphere,
}

impl From<CandidatesArg> for bridson::Candidates {
    fn from(kind: CandidatesArg) -> Self {
        match kind {
            CandidatesArg::Annulus => Self::Annulus,
            CandidatesArg::Sphere => Self::Sphere,
        }
    }
}

/// Writes `{"results": [..]}` to `path`, one result a line (small, and
/// readable in a diff).
///
/// # Errors
/// [`Failure::Io`] if writing fails.
pub(crate) fn write_results_json(
    path: &Path,
    results: &[serde_json::Value],
) -> Result<(), Failure> {
    let lines: Vec<String> = results.iter().map(|r| format!("  {r}")).collect();
    let text = format!("{{\"results\": [\n{}\n]}}\n", lines.join(",\n"));
    std::fs::write(path, text).map_err(|e| Failure::Io(format!("writing {}: {e}", path.display())))
}

/// Peak resident set size of this process in MiB (`VmHWM` in
/// `/proc/self/status`; Linux only, `None` elsewhere).
pub(crate) fn peak_rss_mib() -> Option<f64> {
    status_mib("VmHWM:")
}

/// A memory figure of this process from `/proc/self/status`, in MiB.
pub(crate) fn status_mib(field: &str) -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(field))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// CPU seconds this thread has run so far (`/proc/thread-self/schedstat`,
/// Linux only, `None` elsewhere): on a shared machine, a steadier measure
/// of one program's cost than the wall clock.
pub(crate) fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let nanos: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(nanos * 1e-9)
}

/// The flags of a command line given as one string, as the example `name`
/// reads them (for tests).
#[cfg(test)]
pub(crate) fn parse_line<P: clap::Parser>(name: &str, line: &str) -> Result<P, clap::Error> {
    P::try_parse_from(std::iter::once(name).chain(line.split_whitespace()))
}

/// Asserts that `run` fails with a usage error (exit code 2) on each line:
/// what the library rejects is a bad argument too.
#[cfg(test)]
pub(crate) fn assert_usage_failures(lines: &[&str], run: impl Fn(&str) -> Result<(), Failure>) {
    for line in lines {
        assert!(
            matches!(run(line), Err(Failure::Usage(_))),
            "{line}: expected a library error"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_and_sizes_parse() {
        assert_eq!(list::<f64>("1, 2,-3"), Ok(vec![1.0, 2.0, -3.0]), "list");
        assert!(list::<f64>("1,").is_err(), "empty item");
        assert!(list::<usize>("1,x").is_err(), "bad item");
        assert_eq!(size("64x48"), Ok((64, 48)), "size");
        for bad in ["64", "0x4", "4x-1", "4,4", "5by7"] {
            assert!(size(bad).is_err(), "should be rejected: {bad}");
        }
    }

    #[test]
    fn the_uniform_draw_is_the_top_53_bits_of_one_u64() {
        use bridson::rand::{Rng, RngExt};
        let mut a = bridson::seeded_rng(5);
        let mut b = bridson::seeded_rng(5);
        for _ in 0..100 {
            #[expect(clippy::cast_precision_loss, reason = "53 bits, exact")]
            let expected = (b.next_u64() >> 11) as f64 / 9_007_199_254_740_992.0;
            assert_eq!(a.random::<f64>(), expected, "the plot's probes and tests");
        }
    }
}
