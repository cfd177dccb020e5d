//! Measures the densities behind `PoissonDiskBuilder::about_points` (the count mode):
//! how many points the sampler actually makes per `r^N`, in the interior of
//! a large periodic box and along thin axes, for each dimension and
//! candidate kind at the default `k = 30`, and how both change with `k`.
//! Run it as `cargo run --release --example count_density -- interior` (or
//! `axis`, `cube`, `attempts`);
//! it prints the tables that `src/density.rs` holds (`INTERIOR`, `AXIS_2D`,
//! `AXIS_3D`, `ATTEMPTS_2D`, `ATTEMPTS_3D`). `tests/count_mode.rs` checks the count mode built on them.

#[path = "common/mod.rs"]
mod common;

use bridson::{Candidates, Domain, PoissonDisk};
use clap::{Parser, ValueEnum};
use std::process::ExitCode;

/// The command line.
#[derive(Debug, Parser)]
#[command(name = "count_density")]
struct Args {
    /// What to measure
    #[arg(value_enum)]
    what: What,
    /// Seeds per case
    #[arg(long, value_name = "S", default_value_t = 4)]
    seeds: u64,
    /// About how many points per run in the interior measurement
    #[arg(long, value_name = "N", default_value_t = 200_000.0)]
    points: f64,
    /// Dimension for `axis` (2 or 3)
    #[arg(long, value_name = "D", default_value_t = 2)]
    dim: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum What {
    /// Points per r^N in a large periodic cube, 1-D to 8-D
    Interior,
    /// Effective length of one axis of length x·r, in units of r
    Axis,
    /// From 4-D to 8-D, the extra length c of a bounded axis, from bounded
    /// cubes x radii wide: count = interior · (x + c)^N
    Cube,
    /// 2-D and 3-D, for each k of `ATTEMPTS_K`: the interior density
    /// relative to k = 30 (a large periodic cube), and the change in the
    /// extra length of a bounded axis (a bounded cube about 1500 points
    /// large)
    Attempts,
}

/// The attempts `k` that `density.rs` tabulates (`ATTEMPTS_K`).
const ATTEMPTS_K: [u32; 17] = [
    1, 2, 3, 5, 7, 10, 15, 20, 30, 45, 60, 100, 150, 200, 300, 500, 1000,
];

const KINDS: [(Candidates, &str); 2] = [
    (Candidates::Annulus, "annulus"),
    (Candidates::Sphere, "sphere"),
];

/// Mean and standard deviation of the counts over `seeds` runs.
fn counts<const N: usize>(
    extent: [f64; N],
    periodic: [bool; N],
    r: f64,
    kind: Candidates,
    attempts: u32,
    seeds: u64,
) -> (f64, f64) {
    let domain = Domain::from_extent(extent)
        .expect("box")
        .with_periodic(periodic);
    let sampler = PoissonDisk::<N>::builder(domain, r)
        .candidates(kind)
        .attempts(attempts)
        .build()
        .expect("sampler");
    let n: Vec<f64> = (0..seeds)
        .map(|s| sampler.iter_seeded(1000 + s).count() as f64)
        .collect();
    let mean = n.iter().sum::<f64>() / n.len() as f64;
    let var = n.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n.len().max(2) - 1) as f64;
    (mean, var.sqrt())
}

fn interior<const N: usize>(args: &Args) {
    for (kind, name) in KINDS {
        // A periodic cube of side L = r·(points)^(1/N): about `points`
        // points at density 1 per r^N.
        let per_point = if N >= 6 {
            args.points / 8.0
        } else {
            args.points
        };
        let side = per_point.powf(1.0 / N as f64);
        let (mean, sd) = counts([side; N], [true; N], 1.0, kind, 30, args.seeds);
        let volume: f64 = [side; N].iter().product();
        println!(
            "{N}-D {name:7}: {:.5} points per r^{N} (sd of the mean {:.5}, {mean:.0} points)",
            mean / volume,
            sd / volume / (args.seeds as f64).sqrt(),
        );
    }
}

fn axis<const N: usize>(args: &Args, interior: [f64; 2]) {
    // One axis of length x·r, bounded or periodic; the others periodic and
    // long (about `points` points in all). E(x) = n / (d · Π other lengths).
    let others = (args.points / interior[0]).powf(1.0 / (N - 1) as f64);
    let xs = [
        0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7,
        1.8, 1.9, 2.0, 2.25, 2.5, 2.75, 3.0, 3.5, 4.0, 4.5, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0, 16.0,
    ];
    for (k, (kind, name)) in KINDS.into_iter().enumerate() {
        for bounded in [true, false] {
            print!(
                "{N}-D {name} {}: [",
                if bounded { "bounded" } else { "periodic" }
            );
            for x in xs {
                let mut extent = [others; N];
                extent[0] = x;
                let mut periodic = [true; N];
                periodic[0] = !bounded;
                let (mean, _) = counts(extent, periodic, 1.0, kind, 30, args.seeds);
                let rest: f64 = extent.iter().skip(1).product();
                let e = mean / (interior[k] * rest);
                print!("({x}, {e:.4}), ");
            }
            println!("]");
        }
    }
}

fn cube<const N: usize>(args: &Args, interior: f64, widths: &[f64]) {
    for &x in widths {
        let (mean, _) = counts([x; N], [false; N], 1.0, Candidates::Annulus, 30, args.seeds);
        let c = (mean / interior).powf(1.0 / N as f64) - x;
        println!("{N}-D bounded cube {x} radii wide: {mean:.0} points, c = {c:.3}");
    }
}

/// Per kind, a row `(m, Δ)` for each `k` of [`ATTEMPTS_K`]: `m` the
/// interior density over that at k = 30 (same seeds, same periodic cube of
/// about `points` points), `Δ` the extra length of a bounded axis, in
/// radii, minus that at k = 30 (from bounded cubes `width` radii wide,
/// `count = m · interior · (width + c)^N`, 4× the seeds).
fn attempts<const N: usize>(args: &Args, interior: [f64; 2], width: f64) {
    for (i, (kind, name)) in KINDS.into_iter().enumerate() {
        let side = (args.points / interior[i]).powf(1.0 / N as f64);
        let extra = |k: u32, m: f64| {
            let (mean, _) = counts([width; N], [false; N], 1.0, kind, k, 4 * args.seeds);
            (mean / (m * interior[i])).powf(1.0 / N as f64) - width
        };
        let (base, _) = counts([side; N], [true; N], 1.0, kind, 30, args.seeds);
        let c30 = extra(30, 1.0);
        print!("{N}-D {name}: [");
        for k in ATTEMPTS_K {
            let (mean, _) = counts([side; N], [true; N], 1.0, kind, k, args.seeds);
            let m = mean / base;
            let delta = extra(k, m) - c30;
            print!("[{m:.5}, {delta:.4}], ");
        }
        println!("]");
    }
}

fn main() -> ExitCode {
    let args = Args::parse();
    match args.what {
        What::Interior => {
            interior::<1>(&args);
            interior::<2>(&args);
            interior::<3>(&args);
            interior::<4>(&args);
            interior::<5>(&args);
            interior::<6>(&args);
            interior::<7>(&args);
            interior::<8>(&args);
        }
        What::Cube => {
            // Annulus interior densities from `interior`.
            cube::<4>(&args, 0.57002, &[8.0, 5.0]);
            cube::<5>(&args, 0.59936, &[5.0, 3.5]);
            cube::<6>(&args, 0.66856, &[4.0, 3.0]);
            cube::<7>(&args, 0.78334, &[3.0]);
            cube::<8>(&args, 0.96472, &[2.5]);
        }
        What::Attempts => {
            attempts::<2>(&args, [0.61538, 0.88088], 50.0);
            attempts::<3>(&args, [0.57556, 0.72980], 14.0);
        }
        What::Axis => match args.dim {
            2 => axis::<2>(&args, [0.61538, 0.88088]),
            _ => axis::<3>(&args, [0.57556, 0.72980]),
        },
    }
    ExitCode::SUCCESS
}
