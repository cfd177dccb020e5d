//! Criterion benchmarks of the pixel sampler: camera samples (film, time,
//! lens: five values) per second over a 512×512 image at 1, 4, 16, 64 and
//! 256 samples per pixel, with the bank already built, and the one-off
//! bank build at the same counts and at the maximum, 4096.
//!
//! ```text
//! cargo bench --manifest-path benches/Cargo.toml --bench render               # all
//! cargo bench --manifest-path benches/Cargo.toml --bench render -- camera/16  # one
//! ```

use bridson::{PixelSampler, PoissonPixelSampler, relative_radius};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;

const SIDE: u32 = 512;

/// Every camera sample of the image, pixel by pixel in scan order, as a
/// renderer asks for them; returns a sum so nothing is optimised away.
fn render(sampler: &mut PoissonPixelSampler) -> f64 {
    let spp = sampler.samples_per_pixel();
    let mut acc = 0.0;
    for y in 0..SIDE {
        for x in 0..SIDE {
            for index in 0..spp {
                sampler
                    .start_pixel_sample([x, y], index, 0)
                    .expect("in range");
                let cs = sampler.camera_sample();
                acc += cs.film[0] + cs.film[1] + cs.time + cs.lens[0] + cs.lens[1];
            }
        }
    }
    acc
}

fn camera(c: &mut Criterion) {
    let mut g = c.benchmark_group("camera");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(10))
        .warm_up_time(Duration::from_secs(1));
    for spp in [1u32, 4, 16, 64, 256] {
        let mut sampler = PoissonPixelSampler::new(spp, 1)
            .expect("valid count")
            .with_resolution([SIDE, SIDE]);
        g.throughput(Throughput::Elements(
            u64::from(SIDE) * u64::from(SIDE) * u64::from(spp),
        ));
        g.bench_function(BenchmarkId::from_parameter(spp), |b| {
            b.iter(|| render(black_box(&mut sampler)));
        });
    }
    g.finish();
}

fn bank(c: &mut Criterion) {
    // The quality of what is being built: ρ of the worst set in each bank.
    for spp in [4u32, 16, 64, 256, 4096] {
        let s = PoissonPixelSampler::new(spp, 1).expect("valid count");
        let n = spp as usize;
        let rho2 = s
            .min_distance_2d()
            .and_then(|d| relative_radius::<2>(d, n, 1.0));
        let rho1 = s
            .min_distance_1d()
            .and_then(|d| relative_radius::<1>(d, n, 1.0));
        eprintln!("bank {spp}: worst-set rho 2-D {rho2:.3?}, 1-D {rho1:.3?}");
    }
    let mut g = c.benchmark_group("bank");
    g.sample_size(10)
        .measurement_time(Duration::from_secs(5))
        .warm_up_time(Duration::from_secs(1));
    for spp in [1u32, 4, 16, 64, 256, 4096] {
        g.throughput(Throughput::Elements(u64::from(spp)));
        g.bench_function(BenchmarkId::from_parameter(spp), |b| {
            b.iter(|| PoissonPixelSampler::new(black_box(spp), 1).expect("valid count"));
        });
    }
    g.finish();
}

criterion_group!(render_benches, camera, bank);
criterion_main!(render_benches);
