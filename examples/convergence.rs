//! How fast does each pixel sampler's estimate converge? For every sampler
//! (the crate's `poisson-pixel` and the baselines of `examples/common/
//! samplers`), this measures the mean squared error of the equal-weight
//! estimate `1/N Σ f(x_i)` of integrals over `[0, 1)²`, using one pixel's N
//! film offsets per trial, for N = 1..64 and then a log-spaced grid up to
//! 1024. The integrands (disk, triangle, step, Gaussian, bilinear) have
//! exact integrals and are redrawn at random for every trial. It prints a
//! markdown table (MSE at N = 4, 16, 64 and the log-log slope over
//! N >= 16), and writes a log-log PNG per integrand and a JSON file. Run it
//! as
//! `cargo run --release --example convergence -- --out-dir docs/images/convergence --json docs/convergence.json`;
//! `--help` lists every flag. Exit status: 0 on success, 1 if writing
//! fails, 2 for bad arguments.
//!
//! The parts live in `examples/convergence/`: `args.rs` (the command line),
//! `integrand.rs` (the integrands and their exact integrals), `study.rs`
//! (the N grid, the MSE, the slope fit), `report.rs` (table, JSON, charts)
//! and `chart.rs` (the log-log chart, drawn with `plot`'s canvas and font).

#[path = "convergence/args.rs"]
mod args;
#[allow(dead_code, reason = "shared with `plot`, which uses all of it")]
#[path = "plot/canvas.rs"]
mod canvas;
#[path = "convergence/chart.rs"]
mod chart;
#[path = "common/mod.rs"]
mod common;
#[path = "plot/font.rs"]
mod font;
#[path = "convergence/integrand.rs"]
mod integrand;
#[path = "convergence/report.rs"]
mod report;
#[path = "convergence/study.rs"]
mod study;

use clap::Parser;
use common::{Failure, report as say};
use std::io::Write;
use std::process::ExitCode;
use std::time::Instant;

fn main() -> ExitCode {
    // Bad flags print clap's message and exit 2; --help exits 0.
    let args = args::Args::parse();
    common::finish("convergence", run(&args))
}

fn run(args: &args::Args) -> Result<(), Failure> {
    let kinds = args.kinds();
    let counts = study::sample_counts(args.n_max);
    let instances: Vec<_> = kinds
        .iter()
        .map(|&k| study::instances(k, args.trials, args.seed))
        .collect();
    let mut series = Vec::new();
    for name in args.sampler_names() {
        let start = Instant::now();
        let mut per_kind: Vec<Vec<(u32, f64)>> = vec![Vec::new(); kinds.len()];
        for &n in &counts {
            let mse = study::mse_at(&name, n, args.seed, &instances).map_err(Failure::Usage)?;
            for (points, m) in per_kind.iter_mut().zip(mse) {
                points.push((n, m));
            }
        }
        say(&format!(
            "convergence: {name}: {} values of N, {} trials, {:.1} s",
            counts.len(),
            args.trials,
            start.elapsed().as_secs_f64()
        ));
        series.extend(
            kinds
                .iter()
                .zip(per_kind)
                .map(|(&kind, points)| report::Series {
                    sampler: name.clone(),
                    kind,
                    points,
                }),
        );
    }
    let table = report::table(&series, &kinds);
    let mut out = std::io::stdout().lock();
    out.write_all(table.as_bytes())
        .map_err(|e| Failure::Io(format!("writing the table: {e}")))?;
    if let Some(dir) = &args.out_dir {
        report::write_charts(dir, &series, &kinds, args.trials)?;
    }
    if let Some(path) = &args.json {
        report::write_json(path, &series, args.trials)?;
    }
    Ok(())
}
