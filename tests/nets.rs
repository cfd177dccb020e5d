//! `NetPixelSampler` through its public API: every pixel's film offsets and
//! every 2-D pair (lens after time, so starting at an odd dimension, and
//! the integrator's) are (0,m,2)-nets at every power of two, and stratified
//! in x and y at other counts; 1-D values are stratified; the
//! spacing floors hold (ρ measured by a naive all-pairs oracle); values are
//! a pure function of (seed, pixel, index, dimension) on any thread; bad
//! input is an error.

#![allow(
    clippy::cast_possible_truncation,
    clippy::cast_sign_loss,
    clippy::cast_precision_loss,
    reason = "bins and counts of small test sizes"
)]

mod common;

use bridson::{Error, NET_MAX_SAMPLES_PER_PIXEL, NetPixelSampler, PixelSampler, relative_radius};

/// Everything one sample draws: film, time, lens, then a 1-D value and two
/// 2-D pairs, and one pair started at an odd dimension by hand.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Drawn {
    film: [f64; 2],
    time: f64,
    lens: [f64; 2],
    one: f64,
    light: [f64; 2],
    bsdf: [f64; 2],
    odd: [f64; 2],
}

fn draw(s: &mut NetPixelSampler, pixel: [u32; 2], index: u32) -> Drawn {
    s.start_pixel_sample(pixel, index, 0)
        .unwrap_or_else(|e| panic!("pixel {pixel:?} index {index}: {e}"));
    let c = s.camera_sample();
    let one = s.get_1d();
    let light = s.get_2d();
    let bsdf = s.get_2d();
    s.start_pixel_sample(pixel, index, 11).expect("in range");
    let odd = s.get_2d();
    Drawn {
        film: c.film,
        time: c.time,
        lens: c.lens,
        one,
        light,
        bsdf,
        odd,
    }
}

/// The samples of one pixel.
fn pixel(s: &mut NetPixelSampler, at: [u32; 2]) -> Vec<Drawn> {
    (0..s.samples_per_pixel()).map(|i| draw(s, at, i)).collect()
}

/// Each 2-D set a sample draws.
fn pairs(d: &[Drawn]) -> [(&'static str, Vec<[f64; 2]>); 5] {
    [
        ("film", d.iter().map(|x| x.film).collect()),
        ("lens", d.iter().map(|x| x.lens).collect()),
        ("light", d.iter().map(|x| x.light).collect()),
        ("bsdf", d.iter().map(|x| x.bsdf).collect()),
        ("odd", d.iter().map(|x| x.odd).collect()),
    ]
}

/// Whether every elementary interval of area `1/n` (`n = 2^m`) holds
/// exactly one point.
fn is_net(points: &[[f64; 2]]) -> bool {
    let n = points.len();
    let m = n.trailing_zeros();
    (0..=m).all(|k| {
        let (columns, rows) = (1usize << k, n >> k);
        let mut seen = vec![false; n];
        points.iter().all(|&[x, y]| {
            let cell = (x * columns as f64) as usize * rows + (y * rows as f64) as usize;
            !std::mem::replace(&mut seen[cell], true)
        })
    })
}

/// Whether `values` hold one value in every `[j/n, (j+1)/n)`.
fn is_stratified(values: impl Iterator<Item = f64>, n: usize) -> bool {
    let mut seen = vec![false; n];
    values.into_iter().all(|v| {
        let j = (v * n as f64) as usize;
        j < n && !std::mem::replace(&mut seen[j], true)
    })
}

/// Toroidal minimum distance, all pairs.
fn min_distance(points: &[[f64; 2]]) -> f64 {
    let mut best = f64::INFINITY;
    for (j, b) in points.iter().enumerate() {
        for a in &points[..j] {
            let d2 = common::distance_squared(a, b, &[0.0; 2], &[1.0; 2], &[true; 2]);
            best = best.min(d2);
        }
    }
    best.sqrt()
}

#[test]
fn every_pixel_and_pair_is_a_net_at_powers_of_two() {
    for (spp, side) in [
        (2u32, 8u32),
        (4, 8),
        (8, 8),
        (16, 6),
        (32, 4),
        (64, 4),
        (128, 3),
        (256, 2),
        (1024, 1),
    ] {
        let mut s = NetPixelSampler::new(spp, 3).unwrap();
        assert!(s.is_net(), "spp {spp}");
        for y in 0..side {
            for x in 0..side {
                let d = pixel(&mut s, [x, y]);
                for (name, points) in pairs(&d) {
                    assert!(
                        is_net(&points),
                        "spp {spp}, pixel {x},{y}: {name} is not a net"
                    );
                }
                let n = spp as usize;
                assert!(is_stratified(d.iter().map(|v| v.time), n), "time");
                assert!(is_stratified(d.iter().map(|v| v.one), n), "1-D");
            }
        }
    }
}

#[test]
fn other_counts_are_stratified_in_both_projections() {
    for spp in [2u32, 3, 5, 6, 7, 10, 12, 24, 100, 255, 256] {
        let mut s = NetPixelSampler::new(spp, 9).unwrap();
        assert_eq!(s.is_net(), spp.is_power_of_two(), "spp {spp}");
        let n = spp as usize;
        for at in [[0, 0], [5, 1], [1000, 77]] {
            let d = pixel(&mut s, at);
            for (name, points) in pairs(&d) {
                assert!(
                    is_stratified(points.iter().map(|p| p[0]), n),
                    "spp {spp} {name} x"
                );
                assert!(
                    is_stratified(points.iter().map(|p| p[1]), n),
                    "spp {spp} {name} y"
                );
            }
            assert!(is_stratified(d.iter().map(|v| v.time), n), "spp {spp} time");
            assert!(is_stratified(d.iter().map(|v| v.one), n), "spp {spp} 1-D");
        }
    }
}

/// The median and the smallest ρ of the film sets of `side²` pixels, and
/// whether every pixel's every pair keeps `min_distance_2d`.
fn spacing(spp: u32, side: u32) -> (f64, f64) {
    let mut s = NetPixelSampler::new(spp, 17).unwrap();
    let floor = s.min_distance_2d().expect("more than one sample");
    let n = spp as usize;
    let mut rhos = Vec::new();
    for y in 0..side {
        for x in 0..side {
            let d = pixel(&mut s, [x, y]);
            for (name, points) in pairs(&d) {
                let dmin = min_distance(&points);
                assert!(
                    dmin >= floor * (1.0 - 1e-12),
                    "spp {spp}, pixel {x},{y}, {name}: {dmin} < {floor}"
                );
                if name == "film" {
                    rhos.push(relative_radius::<2>(dmin, n, 1.0).unwrap());
                }
            }
        }
    }
    rhos.sort_by(f64::total_cmp);
    (rhos[rhos.len() / 2], rhos[0])
}

#[test]
fn spacing_floors_hold() {
    // The goals: median ρ >= 0.70 at 16 and >= 0.65 at 64.
    let (median, low) = spacing(16, 12);
    assert!(median >= 0.70, "16 spp: median ρ {median}");
    assert!(low >= 0.6, "16 spp: smallest ρ {low}");
    let (median, low) = spacing(64, 6);
    assert!(median >= 0.65, "64 spp: median ρ {median}");
    assert!(low >= 0.4, "64 spp: smallest ρ {low}");
    let (median, _) = spacing(4, 12);
    assert!(median >= 0.6, "4 spp: median ρ {median}");
    // Shift-invariant banks: every entry keeps ρ >= 0.65, so every pixel
    // does (128 once had one entry of 32 at ρ 0.116).
    for (spp, side) in [(128, 4), (256, 2)] {
        let (median, low) = spacing(spp, side);
        assert!(low >= 0.65, "{spp} spp: smallest ρ {low} (median {median})");
    }
    // Lattices, at counts that are not powers of two.
    for spp in [12, 24, 100] {
        let (median, low) = spacing(spp, 3);
        assert!(low >= 0.6, "{spp} spp: ρ {low} (median {median})");
    }
}

#[test]
fn one_dimensional_values_are_evenly_spaced() {
    for spp in [5u32, 16, 64] {
        let mut s = NetPixelSampler::new(spp, 1).unwrap();
        let mut times: Vec<f64> = pixel(&mut s, [3, 4]).iter().map(|d| d.time).collect();
        times.sort_by(f64::total_cmp);
        let step = 1.0 / f64::from(spp);
        for w in times.windows(2) {
            assert!(
                (w[1] - w[0] - step).abs() < 1e-9,
                "spp {spp}: gap {}",
                w[1] - w[0]
            );
        }
    }
}

#[test]
fn values_do_not_depend_on_order_clone_or_thread() {
    let (w, h, spp) = (6u32, 5u32, 16u32);
    let base = NetPixelSampler::new(spp, 42)
        .unwrap()
        .with_resolution([w, h]);
    let order: Vec<([u32; 2], u32)> = (0..h)
        .flat_map(|y| (0..w).flat_map(move |x| (0..spp).map(move |i| ([x, y], i))))
        .collect();
    let mut s = base.clone();
    let reference: Vec<Drawn> = order.iter().map(|&(p, i)| draw(&mut s, p, i)).collect();
    // Reverse order, on two threads, each with its own clone.
    let halves: Vec<Vec<Drawn>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..2)
            .map(|t| {
                let mut s = base.clone();
                let order = &order;
                scope.spawn(move || {
                    order
                        .iter()
                        .enumerate()
                        .rev()
                        .filter(|(k, _)| k % 2 == t)
                        .map(|(_, &(p, i))| draw(&mut s, p, i))
                        .collect()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (t, half) in halves.iter().enumerate() {
        let expected: Vec<Drawn> = reference
            .iter()
            .enumerate()
            .rev()
            .filter(|(k, _)| k % 2 == t)
            .map(|(_, d)| *d)
            .collect();
        assert_eq!(half, &expected, "thread {t} differs");
    }
    // A fresh sampler for the same seed, and another seed.
    let mut again = NetPixelSampler::new(spp, 42).unwrap();
    assert_eq!(
        draw(&mut again, [2, 3], 5),
        draw(&mut s, [2, 3], 5),
        "rebuild"
    );
    let mut other = again.with_seed(43);
    assert_ne!(draw(&mut other, [2, 3], 5), draw(&mut s, [2, 3], 5), "seed");
}

#[test]
fn film_offsets_are_flat_over_pixels() {
    // Each index's film offset, over many pixels, covers the 4×4 grid of
    // the pixel evenly (a chi-square bound far in the tail).
    let mut s = NetPixelSampler::new(16, 5).unwrap();
    for index in [0u32, 7, 15] {
        let mut counts = [0u32; 16];
        let pixels = 4000;
        for p in 0..pixels {
            s.start_pixel_sample([p % 100, p / 100], index, 0).unwrap();
            let [x, y] = s.get_pixel_2d();
            counts[(x * 4.0) as usize * 4 + (y * 4.0) as usize] += 1;
        }
        let expected = f64::from(pixels) / 16.0;
        let chi2: f64 = counts
            .iter()
            .map(|&c| (f64::from(c) - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 60.0, "index {index}: chi2 {chi2}, {counts:?}");
    }
}

#[test]
fn bad_input_is_an_error() {
    assert_eq!(
        NetPixelSampler::new(0, 0).err(),
        Some(Error::InvalidSamplesPerPixel {
            spp: 0,
            max: NET_MAX_SAMPLES_PER_PIXEL
        })
    );
    assert!(NetPixelSampler::new(NET_MAX_SAMPLES_PER_PIXEL + 1, 0).is_err());
    assert!(NetPixelSampler::new(u32::MAX, 0).is_err());
    let mut s = NetPixelSampler::new(4, 0).unwrap().with_resolution([3, 2]);
    s.start_pixel_sample([1, 1], 2, 7).unwrap();
    assert_eq!(
        s.start_pixel_sample([0, 0], 4, 0),
        Err(Error::SampleIndexOutOfRange { index: 4, spp: 4 })
    );
    assert_eq!(
        s.start_pixel_sample([3, 0], 0, 0),
        Err(Error::PixelOutOfImage {
            pixel: [3, 0],
            resolution: [3, 2]
        })
    );
    assert_eq!(
        s.start_pixel_sample([0, 2], u32::MAX, 0),
        Err(Error::SampleIndexOutOfRange {
            index: u32::MAX,
            spp: 4
        }),
        "the index is checked first"
    );
    assert_eq!(
        (s.pixel(), s.sample_index(), s.dimension()),
        ([1, 1], 2, 7),
        "state changed on error"
    );
}

#[test]
fn every_value_is_in_the_unit_interval() {
    for spp in [1u32, 2, 3, 4, 17, 256, 4095, NET_MAX_SAMPLES_PER_PIXEL] {
        let mut s = NetPixelSampler::new(spp, u64::MAX).unwrap();
        for at in [[0, 0], [u32::MAX, u32::MAX]] {
            for i in [0, spp - 1] {
                s.start_pixel_sample(at, i, u32::MAX - 1).unwrap();
                let d = s.camera_sample();
                let more = [s.get_1d(), s.get_2d()[0], s.get_2d()[1]];
                for v in d.film.iter().chain(&d.lens).chain([&d.time]).chain(&more) {
                    assert!((0.0..1.0).contains(v), "spp {spp}: {v}");
                }
            }
        }
    }
}
