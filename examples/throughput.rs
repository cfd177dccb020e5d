//! Prints the figures behind docs/performance.md's throughput table: points/s, ρ and
//! peak resident memory for the library and for a textbook Bridson, measured
//! side by side in one run, with the speed ratio at equal `k`.
//!
//! ```text
//! cargo run --release --example throughput            # all cases, 3 runs each
//! cargo run --release --example throughput -- --runs 5 --only 2d
//! ```
//!
//! Each case runs in a fresh child process, so its peak RSS (`VmHWM`, Linux
//! only) is its own. The runs go round by round (every selected case once,
//! then again), so that a slow spell of a shared host falls on all cases
//! rather than on whichever ran then. The reported time is the median of
//! a case's runs; "vs text" is the ratio of the medians, "paired" the
//! median over rounds of each round's ratio (a case's run against the
//! textbook's run of the same round, minutes apart at most).

#[path = "common/mod.rs"]
mod common;
#[path = "../benches/textbook/mod.rs"]
mod textbook;

use crate::common::peak_rss_mib;
use bridson::{Candidates, Domain, GridLayout, PoissonDisk, relative_radius, seeded_rng};
use clap::Parser;
use std::num::NonZeroUsize;
use std::process::{Command, ExitCode};
use std::time::Instant;

/// The command line.
#[derive(Debug, Parser)]
#[command(name = "throughput")]
struct Args {
    /// Runs of each case (the median is reported; 0 counts as 1)
    #[arg(long, value_name = "N", default_value_t = 3)]
    runs: usize,
    /// Run only the cases whose name starts with PREFIX
    #[arg(long, value_name = "PREFIX", default_value = "")]
    only: String,
    /// Run one case in this process and print its figures (used by the
    /// parent run)
    #[arg(long, value_name = "CASE", hide = true)]
    child: Option<String>,
}

struct Case {
    name: &'static str,
    dim: usize,
    radius: f64,
    what: What,
}

#[derive(Clone, Copy)]
enum What {
    Textbook,
    Library(Candidates, GridLayout),
    /// `generate_parallel` on this many threads (annulus, automatic
    /// layout): not the same points as one run, the same statistics.
    Parallel(usize),
}

const CASES: &[Case] = &[
    Case {
        name: "2d-textbook",
        dim: 2,
        radius: 0.000785,
        what: What::Textbook,
    },
    Case {
        name: "2d-annulus",
        dim: 2,
        radius: 0.000785,
        what: What::Library(Candidates::Annulus, GridLayout::Auto),
    },
    Case {
        name: "2d-sphere",
        dim: 2,
        radius: 0.000785,
        what: What::Library(Candidates::Sphere, GridLayout::Auto),
    },
    Case {
        name: "2d-annulus-2-threads",
        dim: 2,
        radius: 0.000785,
        what: What::Parallel(2),
    },
    Case {
        name: "3d-textbook",
        dim: 3,
        radius: 0.00835,
        what: What::Textbook,
    },
    Case {
        name: "3d-annulus",
        dim: 3,
        radius: 0.00835,
        what: What::Library(Candidates::Annulus, GridLayout::Auto),
    },
    Case {
        name: "3d-sphere",
        dim: 3,
        radius: 0.00835,
        what: What::Library(Candidates::Sphere, GridLayout::Auto),
    },
    Case {
        name: "3d-annulus-2-threads",
        dim: 3,
        radius: 0.00835,
        what: What::Parallel(2),
    },
    Case {
        name: "4d-annulus",
        dim: 4,
        radius: 0.0418,
        what: What::Library(Candidates::Annulus, GridLayout::Auto),
    },
    Case {
        name: "4d-annulus-dense",
        dim: 4,
        radius: 0.0418,
        what: What::Library(Candidates::Annulus, GridLayout::Dense),
    },
    Case {
        name: "4d-sphere",
        dim: 4,
        radius: 0.0418,
        what: What::Library(Candidates::Sphere, GridLayout::Auto),
    },
];

const K: u32 = 30;
const SEED: u64 = 2026;

/// Runs one case in this process: (points, seconds, ρ).
fn run_case(case: &Case) -> Result<(usize, f64, f64), String> {
    match case.dim {
        2 => run::<2>(case),
        3 => run::<3>(case),
        4 => run::<4>(case),
        d => Err(format!("no case for dim {d}")),
    }
}

/// The library's sampler of the unit box at `radius` and `k = K`.
fn sampler<const N: usize>(
    radius: f64,
    candidates: Candidates,
    layout: GridLayout,
) -> Result<PoissonDisk<N>, String> {
    let domain = Domain::<N>::from_extent([1.0; N]).map_err(|e| e.to_string())?;
    PoissonDisk::builder(domain, radius)
        .attempts(K)
        .layout(layout)
        .candidates(candidates)
        .build()
        .map_err(|e| e.to_string())
}

fn run<const N: usize>(case: &Case) -> Result<(usize, f64, f64), String> {
    let start = Instant::now();
    let count = match case.what {
        What::Textbook => {
            let mut rng = seeded_rng(SEED);
            textbook::textbook([1.0; N], case.radius, K, &mut rng)
                .ok_or("the textbook's grid is too large")?
                .len()
        }
        What::Library(candidates, layout) => sampler::<N>(case.radius, candidates, layout)?
            .iter_seeded(SEED)
            .count(),
        What::Parallel(threads) => {
            let threads = NonZeroUsize::new(threads).ok_or("no threads")?;
            sampler::<N>(case.radius, Candidates::Annulus, GridLayout::Auto)?
                .generate_parallel_seeded(SEED, threads)
                .map_err(|e| e.to_string())?
                .len()
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    let rho = relative_radius::<N>(case.radius, count, 1.0).unwrap_or(f64::NAN);
    Ok((count, seconds, rho))
}

fn child(name: &str) -> ExitCode {
    let Some(case) = CASES.iter().find(|c| c.name == name) else {
        eprintln!("throughput: unknown case {name}");
        return ExitCode::from(2);
    };
    match run_case(case) {
        Ok((count, seconds, rho)) => {
            let rss = peak_rss_mib().unwrap_or(f64::NAN);
            println!("{count} {seconds} {rho} {rss}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("throughput: {e}");
            ExitCode::from(2)
        }
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    if let Some(name) = &args.child {
        return child(name);
    }
    let (runs, only) = (args.runs.max(1), args.only);
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("throughput: {e}");
            return ExitCode::from(1);
        }
    };
    println!(
        "k = {K}, seed {SEED}, unit box, median of {runs} interleaved runs, one process per run"
    );
    println!(
        "{:<21} {:>9} {:>9} {:>10} {:>7} {:>10} {:>9} {:>9}",
        "case", "points", "seconds", "Mpoints/s", "rho", "peak MiB", "vs text", "paired"
    );
    let cases: Vec<&Case> = CASES
        .iter()
        .filter(|c| c.name.starts_with(only.as_str()))
        .collect();
    let mut all: Vec<Vec<(f64, f64, f64, f64)>> = vec![Vec::new(); cases.len()];
    for _ in 0..runs {
        for (case, samples) in cases.iter().zip(&mut all) {
            let out = Command::new(&exe).args(["--child", case.name]).output();
            let Ok(out) = out else {
                eprintln!("throughput: could not start a child");
                return ExitCode::from(1);
            };
            let text = String::from_utf8_lossy(&out.stdout);
            let fields: Vec<f64> = text
                .split_whitespace()
                .filter_map(|f| f.parse().ok())
                .collect();
            if let [count, seconds, rho, rss] = fields[..] {
                samples.push((count, seconds, rho, rss));
            } else {
                eprintln!(
                    "throughput: {} failed: {}",
                    case.name,
                    String::from_utf8_lossy(&out.stderr)
                );
                return ExitCode::from(1);
            }
        }
    }
    // The textbook's runs of the dimension, in round order, for the paired
    // ratios: round i of a case against round i of its textbook.
    let mut baseline: Option<(usize, f64, Vec<f64>)> = None;
    for (case, mut samples) in cases.into_iter().zip(all) {
        // In round order, before sorting by time.
        let rates: Vec<f64> = samples.iter().map(|s| s.0 / s.1).collect();
        samples.sort_by(|a, b| a.1.total_cmp(&b.1));
        let (count, seconds, rho, rss) = samples[samples.len() / 2];
        let rate = count / seconds;
        if matches!(case.what, What::Textbook) {
            baseline = Some((case.dim, rate, rates.clone()));
        }
        let (ratio, paired) = match &baseline {
            Some((dim, base, base_rates)) if *dim == case.dim => {
                let mut each: Vec<f64> = rates.iter().zip(base_rates).map(|(r, b)| r / b).collect();
                each.sort_by(f64::total_cmp);
                (
                    format!("{:.2}x", rate / base),
                    format!("{:.2}x", each[each.len() / 2]),
                )
            }
            _ => ("-".into(), "-".into()),
        };
        println!(
            "{:<21} {:>9} {:>9.3} {:>10.3} {:>7.4} {:>10.1} {:>9} {:>9}",
            case.name,
            count,
            seconds,
            rate / 1e6,
            rho,
            rss,
            ratio,
            paired
        );
    }
    ExitCode::SUCCESS
}
