//! `f32` points (`PoissonDisk::for_f32`): rounded with `as f32`, no pair is
//! closer than `r` when measured in `f32` arithmetic (squared distance
//! against `r·r`, and its square root against `r`), checked by a naive
//! O(n²) oracle in `f32` at box origins from 0 to 10⁷ and radii a few
//! hundred `f32` ulps of the coordinates, bounded and periodic; unpadded
//! points fail the same oracle; radii within a few ulps are refused.
#![expect(
    clippy::cast_possible_truncation,
    reason = "rounding to f32 is what this file tests"
)]

use bridson::{Domain, Error, PoissonDisk};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

/// The first pair of `f32` points closer than `r` in `f32` arithmetic,
/// differences toroidal (with `L = (hi - lo) as f32`) on periodic axes.
fn violation<const N: usize>(points: &[[f32; N]], r: f64, domain: &Domain<N>) -> Option<String> {
    let r = r as f32;
    let (lo, hi, periodic) = (domain.lo(), domain.hi(), domain.periodic());
    let period: [f32; N] = core::array::from_fn(|i| (hi[i] - lo[i]) as f32);
    for (i, a) in points.iter().enumerate() {
        for b in &points[..i] {
            let mut d2 = 0.0f32;
            for k in 0..N {
                let mut d = (a[k] - b[k]).abs();
                if periodic[k] {
                    d = d.min(period[k] - d);
                }
                d2 += d * d;
            }
            if d2 < r * r || d2.sqrt() < r {
                return Some(format!("{a:?} and {b:?}: {} < r = {r}", d2.sqrt()));
            }
        }
    }
    None
}

fn to_f32<const N: usize>(points: &[[f64; N]]) -> Vec<[f32; N]> {
    points.iter().map(|p| p.map(|x| x as f32)).collect()
}

/// An `f32` ulp at `x`.
fn ulp(x: f64) -> f64 {
    let x = x as f32;
    f64::from(x.next_up() - x)
}

/// The box `origin + [0, width·r)` on every axis, with `r` a given number
/// of `f32` ulps of its far corner.
fn setting<const N: usize>(origin: f64, ulps: f64, width: f64, periodic: bool) -> (Domain<N>, f64) {
    let mut r = ulps * ulp(origin.max(1.0));
    // The far corner may lie in the next binade: count ulps there.
    r = ulps * ulp(origin + width * r).max(ulp(origin.max(1.0)));
    let domain = Domain::new([origin; N], [origin + width * r; N])
        .expect("box")
        .with_periodic([periodic; N]);
    (domain, r)
}

fn run<const N: usize>(domain: Domain<N>, r: f64, seed: u64, pad: bool) -> Vec<[f32; N]> {
    let sampler = PoissonDisk::<N>::new(domain, r).expect("valid");
    let sampler = if pad {
        sampler.for_f32().expect("f32-safe")
    } else {
        sampler
    };
    to_f32(&sampler.generate_seeded(seed).expect("complete"))
}

#[test]
fn padded_points_keep_r_in_f32_at_every_origin() {
    for origin in [0.0, 1e3, 1e6, 1e7, 3e7] {
        for (ulps, periodic) in [(200.0, false), (500.0, true), (16.0, false)] {
            let (domain, r) = setting::<2>(origin, ulps, 24.0, periodic);
            for seed in 0..3 {
                let points = run(domain, r, seed, true);
                let ctx = format!(
                    "2-D origin {origin} r {r} ({ulps} ulps) periodic {periodic} seed {seed}"
                );
                assert!(points.len() > 200, "{ctx}: {} points", points.len());
                if let Some(report) = violation(&points, r, &domain) {
                    panic!("{ctx}: {report}");
                }
            }
            let (domain, r) = setting::<3>(origin, ulps, 7.0, periodic);
            let points = run(domain, r, 1, true);
            if let Some(report) = violation(&points, r, &domain) {
                panic!("3-D origin {origin} {ulps} ulps: {report}");
            }
            let (domain, r) = setting::<1>(origin, ulps, 300.0, periodic);
            let points = run(domain, r, 1, true);
            if let Some(report) = violation(&points, r, &domain) {
                panic!("1-D origin {origin} {ulps} ulps: {report}");
            }
        }
    }
}

/// The same oracle catches points rounded without the padding: the test
/// above has teeth.
#[test]
fn unpadded_points_break_r_in_f32() {
    let mut broken = 0;
    for origin in [1e6, 1e7] {
        let (domain, r) = setting::<2>(origin, 12.0, 24.0, false);
        for seed in 0..3 {
            broken += usize::from(violation(&run(domain, r, seed, false), r, &domain).is_some());
        }
    }
    assert!(broken >= 3, "{broken} of 6 unpadded runs broken");
}

#[test]
fn the_issues_forest_keeps_r() {
    // x ≈ 256 000, where an f32 ulp is 1/64: unpadded, pairs came as close
    // as 0.9959·r.
    let domain = Domain::new([256_000.0, 0.0], [256_120.0, 120.0]).expect("box");
    let r = 1.5;
    let plain = run(domain, r, 1, false);
    assert!(violation(&plain, r, &domain).is_some(), "unpadded breaks");
    let padded = run(domain, r, 1, true);
    assert_eq!(violation(&padded, r, &domain), None);
}

#[test]
fn radii_within_a_few_ulps_are_refused() {
    let at = |origin: f64, r: f64| {
        let domain = Domain::new([origin, 0.0], [origin + 1000.0 * r, 1000.0 * r]).expect("box");
        PoissonDisk::<2>::new(domain, r).expect("valid").for_f32()
    };
    // 4 ulps at 10⁷ (an ulp is 1), on one axis: the padding, 2·2⁻²⁴·10⁷
    // ≈ 1.19, is over a quarter of r: refused, and the error says how many.
    assert_eq!(at(1e7, 4.0).err(), Some(Error::F32TooCoarse { ulps: 4 }));
    assert!(matches!(at(1e7, 4.5), Err(Error::F32TooCoarse { .. })));
    assert!(at(1e7, 5.0).is_ok());
    // 12 ulps: padded by under a quarter.
    let padded = at(1e7, 12.0).expect("f32-safe").radius();
    assert!(padded > 12.0 && padded < 15.0, "{padded}");
    // Outside the range where f32 squares stay normal.
    assert_eq!(at(0.0, 1e-13).err(), Some(Error::InvalidRadius));
    let huge = Domain::new([0.0, 0.0], [1e21, 1e21]).expect("box");
    let sampler = PoissonDisk::<2>::new(huge, 1e18).expect("valid");
    assert!(matches!(sampler.for_f32(), Err(Error::F32TooCoarse { .. })));
    assert!(
        Error::F32TooCoarse { ulps: 4 }
            .to_string()
            .contains("4 f32 ulps")
    );
}

#[test]
fn for_f32_keeps_the_other_settings() {
    let domain = Domain::from_extent([1.0, 1.0])
        .expect("box")
        .with_periodic([true, false]);
    let sampler = PoissonDisk::<2>::builder(domain, 0.05)
        .attempts(12)
        .candidates(bridson::Candidates::Sphere)
        .max_points(40)
        .max_grid_bytes(1 << 20)
        .build()
        .expect("valid");
    let padded = sampler.for_f32().expect("f32-safe");
    assert_eq!(padded.domain(), sampler.domain());
    assert_eq!(padded.attempts(), 12);
    assert_eq!(padded.candidates(), bridson::Candidates::Sphere);
    assert_eq!(padded.max_points(), Some(40));
    assert_eq!(padded.max_grid_bytes(), 1 << 20);
    // Near the origin the padding is a few parts in 10⁷.
    let ratio = padded.radius() / 0.05;
    assert!(ratio > 1.0 && ratio < 1.0 + 1e-5, "{ratio}");
    assert_eq!(padded.f32_radius(0.05), Ok(padded.radius()));
}

/// A varying radius: the field padded point by point keeps
/// `max(r(p), r(q))` in `f32`.
#[test]
fn a_padded_field_keeps_max_r_in_f32() {
    let origin = 1e6;
    let domain = Domain::new([origin; 2], [origin + 600.0; 2]).expect("box");
    let (r0, r1) = (4.0, 12.0);
    let sampler = PoissonDisk::<2>::new(domain, r1).expect("valid");
    let field = move |p: &[f64; 2]| r0 + (r1 - r0) * (p[0] - origin) / 600.0;
    let padded = sampler.f32_radius(r1).expect("f32-safe");
    let sampler = PoissonDisk::<2>::new(domain, padded).expect("valid");
    let pad = |r: f64| sampler.f32_radius(r).unwrap_or(f64::NAN);
    let points: Vec<[f64; 2]> = sampler
        .iter_varying_seeded(2, pad(r0), |p| pad(field(p)))
        .expect("valid")
        .collect();
    assert!(points.len() > 1000, "{} points", points.len());
    for (i, p) in points.iter().enumerate() {
        let a = p.map(|x| x as f32);
        for q in &points[..i] {
            let b = q.map(|x| x as f32);
            let r = field(p).max(field(q)) as f32;
            let d2 = (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
            assert!(
                d2 >= r * r && d2.sqrt() >= r,
                "{a:?} {b:?}: {} < {r}",
                d2.sqrt()
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 24,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("regressions"))),
        ..ProptestConfig::default()
    })]

    #[test]
    fn padded_points_keep_r_in_f32(
        exponent in 0i32..9,
        mantissa in 1.0f64..10.0,
        ulps in 10.0f64..1000.0,
        periodic in any::<bool>(),
        seed in any::<u64>(),
    ) {
        let origin = if exponent == 0 { 0.0 } else { mantissa * 10f64.powi(exponent) };
        let (domain, r) = setting::<2>(origin, ulps, 16.0, periodic);
        match PoissonDisk::<2>::new(domain, r).expect("valid").for_f32() {
            Ok(sampler) => {
                let points = to_f32(&sampler.generate_seeded(seed).expect("complete"));
                prop_assert_eq!(violation(&points, r, &domain), None);
            }
            Err(e) => prop_assert!(ulps < 16.0, "{}: refused at {} ulps", e, ulps),
        }
    }
}

/// The worst pairs by construction, not by chance: two points exactly the
/// padded radius `R` apart (along an axis, or a diagonal in 2-D), the
/// first just past a midpoint between two `f32` values (it rounds up, half
/// an ulp toward the second); `r` is stepped by 1/64 ulp, so that for some
/// step the second lands just past a midpoint too and rounds down by half
/// an ulp. Near the top of a binade that takes nearly the whole padding.
#[test]
fn the_padding_covers_the_worst_rounding() {
    fn check<const N: usize>(origin: f64, ulps: f64) {
        let u = ulp(origin);
        for k in 0..64 {
            let r = (ulps + f64::from(k) / 64.0) * u;
            let domain = Domain::new([origin; N], [origin + 10.0 * r; N]).expect("box");
            let padded = PoissonDisk::<N>::new(domain, r)
                .expect("valid")
                .f32_radius(r)
                .expect("f32-safe");
            #[expect(clippy::cast_precision_loss, reason = "N is small")]
            let n = N as f64;
            let a = (origin + 1.5 * u).next_up();
            let mut b = a + padded / n.sqrt();
            // The sampler's test: squared distance (in f64) at least R².
            while (b - a) * (b - a) * n < padded * padded {
                b = b.next_up();
            }
            let pair = [[a; N], [b; N]];
            if let Some(report) = violation(&to_f32(&pair), r, &domain) {
                panic!("{N}-D origin {origin} r {r} ({ulps} ulps + {k}/64): {report}");
            }
        }
    }
    for origin in [1.9e3, 1.9e6, 1.6e7, 3.3e7] {
        for ulps in [12.0, 16.0, 300.0] {
            check::<1>(origin, ulps);
            check::<2>(origin, ulps);
        }
    }
}
