//! Measurements of the field sampler ([`bridson::Field`]): the whole box's
//! count, relative radius and time; the halo queries need; the density in
//! half-radius bands along chunk borders against the interior.
//!
//! ```sh
//! cargo run --release --example field_study -- whole 2 0.000784
//! cargo run --release --example field_study -- halo 2 400
//! cargo run --release --example field_study -- bands 2 64
//! ```

use bridson::{Domain, Field, relative_radius};
use std::time::Instant;

fn whole<const N: usize>(radius: f64, seed: u64) {
    let field = Field::<N>::new(Domain::from_extent([1.0; N]).unwrap(), radius, seed).unwrap();
    let t = Instant::now();
    let q = field.query([0.0; N], [1.0; N]).unwrap();
    let secs = t.elapsed().as_secs_f64();
    let n = q.points.len();
    let rho = relative_radius::<N>(radius, n, 1.0).unwrap();
    println!(
        "dim {N} r {radius} points {n} rho {rho:.4} rounds {} seconds {secs:.3}",
        q.rounds
    );
}

fn halo<const N: usize>(queries: u64) {
    // Unit-radius endless world: queries of 16 r at random places.
    let field = Field::<N>::unbounded(1.0, 3).unwrap();
    let mut hist = std::collections::BTreeMap::new();
    let mut state = 12345u64;
    for _ in 0..queries {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let x = (state >> 20) as f64 / (1u64 << 44) as f64 * 1e6;
        let lo = [x; N];
        let hi = lo.map(|v| v + 16.0);
        // The smallest halo, in level-0 cells, that settles the box.
        let least = (1..64u32)
            .find(|&h| field.settles_with_halo(lo, hi, h).unwrap().is_some())
            .unwrap_or(64);
        *hist.entry(least).or_insert(0u64) += 1;
    }
    println!(
        "dim {N}: least halo in cells of r/sqrt(N) (count of queries) over {queries} queries of 16 r: {hist:?}"
    );
}

fn bands<const N: usize>(chunk: f64) {
    // Density within half a radius of chunk borders against the interior,
    // from the union of chunk queries of an endless world at r = 1.
    let field = Field::<N>::unbounded(1.0, 11).unwrap();
    let k = 6;
    let (mut near, mut far) = (0u64, 0u64);
    for c in 0..k * k {
        let mut lo = [0.0; N];
        lo[0] = f64::from(c % k) * chunk;
        lo[1] = f64::from(c / k) * chunk;
        let mut hi = lo.map(|v| v + chunk);
        for h in hi.iter_mut().skip(2) {
            *h = chunk;
        }
        for p in field.points_in(lo, hi).unwrap() {
            let d = (0..2)
                .map(|a| (p[a] - lo[a]).min(hi[a] - p[a]))
                .fold(f64::MAX, f64::min);
            if d < 0.5 {
                near += 1;
            } else {
                far += 1;
            }
        }
    }
    let band_area = chunk * chunk - (chunk - 1.0) * (chunk - 1.0);
    let inner_area = (chunk - 1.0) * (chunk - 1.0);
    let ratio = (near as f64 / band_area) / (far as f64 / inner_area);
    println!(
        "dim {N} chunk {chunk} r: band points {near}, interior {far}, band/interior density {ratio:.4} (sd about {:.4})",
        1.0 / (near as f64).sqrt()
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dim: usize = args[2].parse().unwrap();
    match (args[1].as_str(), dim) {
        ("whole", 2) => whole::<2>(args[3].parse().unwrap(), 1),
        ("whole", 3) => whole::<3>(args[3].parse().unwrap(), 1),
        ("whole", 4) => whole::<4>(args[3].parse().unwrap(), 1),
        ("halo", 2) => halo::<2>(args[3].parse().unwrap()),
        ("halo", 3) => halo::<3>(args[3].parse().unwrap()),
        ("bands", 2) => bands::<2>(args[3].parse().unwrap()),
        ("bands", 3) => bands::<3>(args[3].parse().unwrap()),
        _ => eprintln!("usage: field_study whole|halo|bands DIM ARG"),
    }
}
