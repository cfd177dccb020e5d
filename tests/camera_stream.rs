//! `CameraPixels`: the streaming form of camera samples. Scan order, film
//! points inside their pixel and identical to the `Tiled` stream's, exact
//! counts under the exact scheme in every dimension, each dimension of a
//! pixel a Poisson set, values in range, and a seed that reproduces.

mod common;

use bridson::{CameraPixels, Error, PoissonPixelSampler, Tiled};

/// Toroidal 1-D and 2-D minimum distances of a set in the unit interval
/// or square.
fn min_gap_1d(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let wrap = 1.0 - v[v.len() - 1] + v[0];
    v.windows(2).map(|w| w[1] - w[0]).fold(wrap, f64::min)
}

fn min_gap_2d(points: &[[f64; 2]]) -> f64 {
    let mut best = f64::INFINITY;
    for (i, a) in points.iter().enumerate() {
        for b in &points[..i] {
            let d = |x: f64, y: f64| {
                let t = (x - y).abs();
                t.min(1.0 - t)
            };
            best = best.min(d(a[0], b[0]).hypot(d(a[1], b[1])));
        }
    }
    best
}

#[test]
fn the_exact_scheme_gives_n_samples_in_every_dimension_of_every_pixel() {
    for n in [1u32, 4, 16] {
        let tiled = Tiled::builder(12, 9).exact(n).build().expect("valid");
        let sampler = PoissonPixelSampler::new(n, 0).expect("valid");
        let pixels: Vec<_> = CameraPixels::new(&tiled, 5, 3).expect("valid").collect();
        assert_eq!(pixels.len(), 12 * 9, "n = {n}: every pixel");
        for (i, p) in (0u32..).zip(&pixels) {
            assert_eq!((p.x, p.y), (i % 12, i / 12), "scan order");
            assert_eq!(p.samples.len(), n as usize, "n = {n}: film, time, lens");
            assert_eq!(p.extra.len(), 3 * n as usize, "n = {n}: further dimensions");
            let values = p
                .samples
                .iter()
                .flat_map(|s| s.film.into_iter().chain(s.lens).chain([s.time]));
            assert!(
                values
                    .chain(p.extra.iter().copied())
                    .all(|v| (0.0..1.0).contains(&v)),
                "range"
            );
            if n > 1 {
                // Each of the pixel's time, lens and further dimensions is a
                // whole exact-count Poisson set.
                let times: Vec<f64> = p.samples.iter().map(|s| s.time).collect();
                let lens: Vec<[f64; 2]> = p.samples.iter().map(|s| s.lens).collect();
                assert!(
                    min_gap_1d(&times) >= sampler.min_distance_1d().unwrap(),
                    "time set"
                );
                assert!(
                    min_gap_2d(&lens) >= sampler.min_distance_2d().unwrap(),
                    "lens set"
                );
                for d in 0..3 {
                    let extra: Vec<f64> = (0..n as usize).map(|i| p.extra[i * 3 + d]).collect();
                    assert!(
                        min_gap_1d(&extra) >= sampler.min_distance_1d().unwrap(),
                        "dimension {d}"
                    );
                }
            }
        }
    }
}

/// Under the sweep the counts vary, and the film points are the stream's
/// own: the same pixels, the same points (offset by the pixel's corner,
/// exactly), so the union keeps the stream's minimum distance.
#[test]
fn the_sweep_keeps_its_film_points_and_their_counts() {
    let tiled = Tiled::builder(16, 12)
        .per_pixel(4.0)
        .build()
        .expect("valid");
    let camera: Vec<_> = CameraPixels::new(&tiled, 3, 0).expect("valid").collect();
    let film: Vec<_> = tiled.pixels_seeded(3).collect();
    assert_eq!(camera.len(), film.len(), "pixels");
    let mut union = Vec::new();
    let mut counts = std::collections::BTreeSet::new();
    for (c, f) in camera.iter().zip(&film) {
        assert_eq!((c.x, c.y), (f.x, f.y), "same pixel");
        assert_eq!(c.samples.len(), f.points.len(), "one sample per film point");
        counts.insert(c.samples.len());
        for (s, p) in c.samples.iter().zip(&f.points) {
            let raster = [f64::from(c.x) + s.film[0], f64::from(c.y) + s.film[1]];
            assert_eq!(raster, *p, "the film point, exactly");
            union.push(raster);
        }
    }
    assert!(counts.len() >= 3, "the sweep's counts vary: {counts:?}");
    if let Err(report) =
        common::check_points(&union, tiled.radius(), [0.0; 2], [16.0, 12.0], [false; 2])
    {
        panic!("{report}");
    }
}

#[test]
fn a_seed_reproduces_the_stream_and_another_changes_it() {
    let tiled = Tiled::builder(6, 5).exact(8).build().expect("valid");
    let a: Vec<_> = CameraPixels::new(&tiled, 11, 2).expect("valid").collect();
    let b: Vec<_> = CameraPixels::new(&tiled, 11, 2).expect("valid").collect();
    let c: Vec<_> = CameraPixels::new(&tiled, 12, 2).expect("valid").collect();
    assert_eq!(a, b, "same seed, same stream");
    assert_ne!(a, c, "another seed, another stream");
}

#[test]
fn a_radius_too_small_for_the_pixel_sampler_is_an_error() {
    let tiled = Tiled::builder(2, 2).radius(0.01).build().expect("valid");
    assert!(matches!(
        CameraPixels::new(&tiled, 0, 0),
        Err(Error::InvalidSamplesPerPixel { .. })
    ));
}

/// Exact mode's radius shrinks with `n`: at `n = 2000` a pixel could hold
/// more than 4096 points at that radius, but holds exactly 2000, which the
/// pixel sampler supports. Past 4096 the count asked for is the error.
#[test]
fn exact_counts_up_to_the_pixel_samplers_limit_stream() {
    let tiled = Tiled::builder(1, 1).exact(2000).build().expect("valid");
    let per_side = (std::f64::consts::SQRT_2 / tiled.radius()).floor() + 1.0;
    assert!(
        per_side * per_side > 4096.0,
        "the radius alone would refuse it: r = {}, {per_side}",
        tiled.radius()
    );
    let pixels: Vec<_> = CameraPixels::new(&tiled, 3, 1)
        .expect("2000 a pixel is supported")
        .collect();
    assert_eq!(pixels.len(), 1);
    for pixel in &pixels {
        assert_eq!(
            pixel.samples.len(),
            2000,
            "pixel ({}, {})",
            pixel.x,
            pixel.y
        );
        assert_eq!(pixel.extra.len(), 2000);
    }
    let over = Tiled::builder(1, 1).exact(5000).build().expect("valid");
    assert_eq!(
        CameraPixels::new(&over, 3, 0).err(),
        Some(Error::InvalidSamplesPerPixel {
            spp: 5000,
            max: 4096
        })
    );
}
