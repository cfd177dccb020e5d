//! The parallel generator (`PoissonDisk::generate_parallel`) against one
//! run at the same radius: point counts, the relative radius ρ, and whether
//! the slab seams show, as the density of points in bands of width `r/2`
//! beside the seams over the density in the slabs' interiors (farther than
//! `4r` from every seam and face), for the parallel set and, at the same
//! places, for one run's set (which has no seams: its ratios are the noise).
//! Run it as
//! `cargo run --release --example seams -- --dim 2 --radius 0.000785 --seeds 1,2`;
//! bands are by signed distance from the nearest seam, negative on the side
//! of the slab sampled first (even), positive on the side grown around it.

#[path = "common/mod.rs"]
mod common;

use bridson::{Domain, PoissonDisk, relative_radius};
use clap::Parser;
use common::Failure;
use std::num::NonZeroUsize;
use std::process::ExitCode;

/// A comma-separated list in one flag (clap reads a `Vec` field as a
/// repeated flag; this name opts out, as in `points`).
type List<T> = Vec<T>;

/// The flags.
#[derive(Debug, Parser)]
#[command(
    name = "seams",
    about = "Counts, rho and seam densities of the parallel generator"
)]
struct Args {
    /// Dimension, 1 to 4; the box is the unit cube
    #[arg(long, value_name = "D", default_value_t = 2)]
    dim: usize,
    /// Minimum distance between points
    #[arg(long, value_name = "R")]
    radius: f64,
    /// Seeds, one set each way per seed
    #[arg(long, value_name = "S,..", value_parser = common::list::<u64>, default_value = "1")]
    seeds: List<u64>,
    /// Threads for the parallel generator
    #[arg(long, value_name = "T", default_value = "2")]
    threads: NonZeroUsize,
    /// Make every axis periodic
    #[arg(long)]
    periodic: bool,
}

/// Half-radius bands on each side of a seam, out to this many radii.
const REACH: f64 = 4.0;
/// Their number: `4·REACH`.
const BANDS: usize = 16;

fn main() -> ExitCode {
    let args = Args::parse();
    common::finish(
        "seams",
        common::by_dimension!(args.dim, run(&args), 1, 2, 3, 4),
    )
}

/// The slab count `generate_parallel` picks along axis 0 of the unit cube:
/// the largest power of two up to 32 leaving slabs at least 16 radii thick
/// (its docs; one slab below 32 radii).
fn slab_count(radius: f64) -> usize {
    let across = 1.0 / radius;
    let mut slabs = 1;
    while slabs < 32 && (2 * slabs) as f64 * 16.0 <= across {
        slabs *= 2;
    }
    slabs
}

/// Points per band (bands of `r/2` by signed distance from the nearest
/// seam, `-REACH·r .. REACH·r`, even side negative) and in the interior.
fn profile<const N: usize>(points: &[[f64; N]], radius: f64, slabs: usize) -> (Vec<u64>, u64) {
    let mut counts = vec![0; BANDS];
    let mut interior = 0;
    for p in points {
        let x = p[0] * slabs as f64;
        let seam = x.round();
        let offset = (x - seam) / slabs as f64 / radius;
        let face = seam == 0.0 || seam == slabs as f64;
        if offset.abs() >= REACH {
            interior += 1;
        } else if !face {
            // Seam i has slab i - 1 on its low side: even when i is odd.
            let odd = (seam / 2.0).fract() != 0.0;
            let oriented = if odd { offset } else { -offset };
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "0 <= value < 16: |offset| < REACH"
            )]
            let band = ((oriented + REACH) * 2.0).floor() as usize;
            counts[band.min(BANDS - 1)] += 1;
        }
    }
    (counts, interior)
}

fn run<const N: usize>(args: &Args) -> Result<(), Failure> {
    let domain = Domain::from_extent([1.0; N])
        .map_err(|e| Failure::Usage(e.to_string()))?
        .with_periodic([args.periodic; N]);
    let sampler =
        PoissonDisk::new(domain, args.radius).map_err(|e| Failure::Usage(e.to_string()))?;
    let slabs = slab_count(args.radius);
    let seams = slabs - 1;
    println!(
        "{N}-D r {} slabs {slabs} along axis 0, threads {}",
        args.radius, args.threads
    );
    let mut totals = [(vec![0_u64; BANDS], 0_u64), (vec![0_u64; BANDS], 0_u64)];
    for &seed in &args.seeds {
        let parallel = sampler
            .generate_parallel_seeded(seed, args.threads)
            .map_err(|e| Failure::Usage(e.to_string()))?;
        let serial = sampler
            .generate_seeded(seed)
            .map_err(|e| Failure::Usage(e.to_string()))?;
        let rho = |n: usize| relative_radius::<N>(args.radius, n, 1.0).unwrap_or(f64::NAN);
        println!(
            "seed {seed}: parallel {} points (rho {:.4}), one run {} (rho {:.4}), ratio {:.5}",
            parallel.len(),
            rho(parallel.len()),
            serial.len(),
            rho(serial.len()),
            parallel.len() as f64 / serial.len() as f64
        );
        for (total, set) in totals.iter_mut().zip([&parallel, &serial]) {
            let (counts, interior) = profile(set, args.radius, slabs);
            total.0.iter_mut().zip(&counts).for_each(|(t, c)| *t += c);
            total.1 += interior;
        }
    }
    if seams == 0 {
        return Ok(());
    }
    // Lengths along axis 0: a band is r/2 at each seam; the interior is the
    // axis less 2·REACH·r at each seam and REACH·r at each face.
    let band_length = args.radius / 2.0 * seams as f64;
    let interior_length = 1.0 - 2.0 * REACH * args.radius * (seams + 1) as f64;
    println!("band (r)   parallel  one run   (density over the interior's)");
    for band in 0..BANDS {
        let from = band as f64 / 2.0 - REACH;
        let ratio = |(counts, interior): &(Vec<u64>, u64)| {
            (counts[band] as f64 / band_length) / (*interior as f64 / interior_length)
        };
        println!(
            "{from:+5.1}..{:+4.1}  {:.4}    {:.4}",
            from + 0.5,
            ratio(&totals[0]),
            ratio(&totals[1])
        );
    }
    Ok(())
}
