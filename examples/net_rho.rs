//! The toroidal relative radius ρ = d_min / d_hex of each pixel's film
//! offsets, after randomisation, for `NetPixelSampler`, `PoissonPixelSampler`
//! and Owen-scrambled Sobol' (`sobol_burley`, one seed per pixel), with the
//! share of pixels whose film set is a (0,m,2)-net.
//!
//! ```text
//! cargo run --release --example net_rho             # 4, 16, 64, 256; 1024 pixels each
//! cargo run --release --example net_rho -- 16 4096  # one count, more pixels
//! ```

#![allow(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    clippy::cast_precision_loss,
    reason = "cells and counts of small grids"
)]

use bridson::{NetPixelSampler, PixelSampler, PoissonPixelSampler, relative_radius};

fn rho(points: &[[f64; 2]]) -> f64 {
    let mut best = f64::INFINITY;
    for (j, b) in points.iter().enumerate() {
        for a in &points[..j] {
            let d = |u: f64, v: f64| {
                let d = (u - v).abs();
                d.min(1.0 - d)
            };
            let (dx, dy) = (d(a[0], b[0]), d(a[1], b[1]));
            best = best.min(dx * dx + dy * dy);
        }
    }
    relative_radius::<2>(best.sqrt(), points.len(), 1.0).unwrap_or(f64::NAN)
}

fn is_net(points: &[[f64; 2]]) -> bool {
    let n = points.len();
    if !n.is_power_of_two() {
        return false;
    }
    (0..=n.trailing_zeros()).all(|k| {
        let (columns, rows) = (1usize << k, n >> k);
        let mut seen = vec![false; n];
        points.iter().all(|&[x, y]| {
            let cell = (x * columns as f64) as usize * rows + (y * rows as f64) as usize;
            !std::mem::replace(&mut seen[cell], true)
        })
    })
}

fn film(s: &mut dyn PixelSampler, pixel: [u32; 2]) -> Vec<[f64; 2]> {
    (0..s.samples_per_pixel())
        .map(|i| {
            s.start_pixel_sample(pixel, i, 0).expect("in range");
            s.get_pixel_2d()
        })
        .collect()
}

fn sobol(spp: u32, pixel: u32) -> Vec<[f64; 2]> {
    let seed = pixel.wrapping_mul(0x9e37_79b9) ^ 0x5eed;
    (0..spp)
        .map(|i| {
            [
                f64::from(sobol_burley::sample(i, 0, seed)),
                f64::from(sobol_burley::sample(i, 1, seed)),
            ]
        })
        .collect()
}

/// Median and minimum of `rhos`, and the share of nets.
fn summary(mut rhos: Vec<f64>, nets: usize) -> String {
    rhos.sort_by(f64::total_cmp);
    let share = nets as f64 / rhos.len() as f64;
    format!(
        "median {:.3} min {:.3} nets {:5.1} %",
        rhos[rhos.len() / 2],
        rhos[0],
        100.0 * share
    )
}

fn main() {
    let args: Vec<u32> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let counts = args.first().map_or(vec![4, 16, 64, 256], |&n| vec![n]);
    let pixels = args.get(1).copied().unwrap_or(1024);
    println!("film ρ over {pixels} pixels (side 32), seed 1");
    for spp in counts {
        let mut samplers: Vec<(&str, Box<dyn PixelSampler>)> = vec![
            (
                "net",
                Box::new(NetPixelSampler::new(spp, 1).expect("count")),
            ),
            (
                "poisson",
                Box::new(PoissonPixelSampler::new(spp, 1).expect("count")),
            ),
        ];
        for (name, s) in &mut samplers {
            let mut rhos = Vec::new();
            let mut nets = 0;
            for p in 0..pixels {
                let points = film(s.as_mut(), [p % 32, p / 32]);
                nets += usize::from(is_net(&points));
                rhos.push(rho(&points));
            }
            println!("spp {spp:4} {name:14}: {}", summary(rhos, nets));
        }
        let mut rhos = Vec::new();
        let mut nets = 0;
        for p in 0..pixels {
            let points = sobol(spp, p);
            nets += usize::from(is_net(&points));
            rhos.push(rho(&points));
        }
        println!("spp {spp:4} {:14}: {}", "sobol_burley", summary(rhos, nets));
    }
}
