//! Samples per second of `NetPixelSampler` against `sobol_burley`, side by
//! side in one run, one thread, in f64, in the loop a renderer runs: for
//! every sample of every pixel, `start_pixel_sample`, then the film offset,
//! the lens and two more 2-D pairs (four pairs, eight values).
//!
//! ```text
//! cargo run --release --example net_speed                 # both, alternating, 5 rounds
//! cargo run --release --example net_speed -- net 16       # one sampler, one count
//! cargo run --release --example net_speed -- sobol 16
//! ```
//!
//! `sobol_burley` is used as a new user would: one hashed seed per pixel
//! and two `sample_4d` calls per sample (film and lens, then the two
//! pairs), each `f32` widened to `f64`.

use bridson::{NetPixelSampler, PixelSampler};
use std::hint::black_box;
use std::time::Instant;

const WIDTH: u32 = 512;
const HEIGHT: u32 = 256;

fn net(spp: u32) -> (f64, u64) {
    let mut s = NetPixelSampler::new(spp, 1).expect("valid count");
    let mut acc = 0.0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            for i in 0..spp {
                s.start_pixel_sample([x, y], i, 0).expect("in range");
                let film = s.get_pixel_2d();
                let lens = s.get_2d();
                let a = s.get_2d();
                let b = s.get_2d();
                acc += film[0] + film[1] + lens[0] + lens[1] + a[0] + a[1] + b[0] + b[1];
            }
        }
    }
    (acc, u64::from(WIDTH * HEIGHT * spp))
}

/// A pixel's seed for `sobol_burley`: a hash of the pixel.
fn pixel_seed(x: u32, y: u32) -> u32 {
    let mut h = u64::from(x) | u64::from(y) << 32;
    h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    #[expect(clippy::cast_possible_truncation, reason = "the low word is the seed")]
    let seed = (h ^ (h >> 31)) as u32;
    seed
}

fn sobol(spp: u32) -> (f64, u64) {
    let mut acc = 0.0;
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let seed = pixel_seed(x, y);
            for i in 0..spp {
                let first = sobol_burley::sample_4d(i, 0, seed).map(f64::from);
                let second = sobol_burley::sample_4d(i, 1, seed).map(f64::from);
                acc += first.iter().chain(&second).sum::<f64>();
            }
        }
    }
    (acc, u64::from(WIDTH * HEIGHT * spp))
}

#[expect(clippy::cast_precision_loss, reason = "a rate")]
fn rate(f: fn(u32) -> (f64, u64), spp: u32) -> f64 {
    let start = Instant::now();
    let (acc, samples) = f(spp);
    black_box(acc);
    samples as f64 / start.elapsed().as_secs_f64()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let spp = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(16);
    match args.first().map(String::as_str) {
        Some("net") => println!("net: {:.1} M samples/s", rate(net, spp) / 1e6),
        Some("sobol") => println!("sobol_burley: {:.1} M samples/s", rate(sobol, spp) / 1e6),
        _ => {
            println!(
                "samples per second, one thread, {WIDTH}x{HEIGHT} pixels, four 2-D pairs a sample, f64"
            );
            for spp in [4u32, 16, 64, 256] {
                let mut n = Vec::new();
                let mut s = Vec::new();
                for _ in 0..5 {
                    n.push(rate(net, spp));
                    s.push(rate(sobol, spp));
                }
                n.sort_by(f64::total_cmp);
                s.sort_by(f64::total_cmp);
                println!(
                    "spp {spp:3}: net {:6.1} M/s, sobol_burley {:6.1} M/s (medians of 5, alternating): {:.2}x",
                    n[2] / 1e6,
                    s[2] / 1e6,
                    n[2] / s[2]
                );
            }
        }
    }
}
