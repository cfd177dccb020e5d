//! Criterion benchmarks at the sizes named in docs/performance.md: the unit square with
//! ≈1M points, the unit cube with ≈1M points and the 4-D unit box with
//! ≈200k points, `k = 30`, both candidate distributions, and in 2-D and 3-D
//! the textbook baseline in the same run, so the ratio is measured side by
//! side at the same `k` (and, for the annulus, the same ρ).
//!
//! ```text
//! cargo bench --manifest-path benches/Cargo.toml --bench sampling        # all (minutes)
//! cargo bench --manifest-path benches/Cargo.toml --bench sampling -- 2d  # one group
//! ```
//!
//! Peak memory is printed by `cargo run --release --example throughput`,
//! which runs each case in its own process.

mod textbook;

use bridson::{Candidates, Domain, PoissonDisk, seeded_rng};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;

const K: u32 = 30;

fn sampler<const N: usize>(radius: f64, candidates: Candidates) -> PoissonDisk<N> {
    let domain = Domain::from_extent([1.0; N]).expect("unit box");
    PoissonDisk::builder(domain, radius)
        .attempts(K)
        .candidates(candidates)
        .build()
        .expect("valid sampler")
}

fn group<const N: usize>(c: &mut Criterion, name: &str, radius: f64, expected_points: u64) {
    let mut g = c.benchmark_group(name);
    g.sample_size(10)
        .measurement_time(Duration::from_secs(20))
        .warm_up_time(Duration::from_secs(1))
        .throughput(Throughput::Elements(expected_points));
    let id = |what: &str| BenchmarkId::new(what, format!("r={radius}"));
    match N {
        2 => {
            g.bench_function(id("textbook"), |b| {
                b.iter(|| {
                    textbook::textbook([1.0; 2], black_box(radius), K, &mut seeded_rng(1))
                        .map(|p| p.len())
                });
            });
        }
        3 => {
            g.bench_function(id("textbook"), |b| {
                b.iter(|| {
                    textbook::textbook([1.0; 3], black_box(radius), K, &mut seeded_rng(1))
                        .map(|p| p.len())
                });
            });
        }
        _ => {}
    }
    for (label, candidates) in [
        ("annulus", Candidates::Annulus),
        ("sphere", Candidates::Sphere),
    ] {
        let s = sampler::<N>(radius, candidates);
        g.bench_function(id(label), |b| {
            b.iter(|| black_box(&s).iter_seeded(1).count())
        });
    }
    g.finish();
}

fn benches(c: &mut Criterion) {
    group::<2>(c, "2d", 0.000785, 1_000_000);
    group::<3>(c, "3d", 0.00835, 1_000_000);
    group::<4>(c, "4d", 0.0418, 200_000);
}

criterion_group!(sampling, benches);
criterion_main!(sampling);
