//! Issue 49's entry points, inputs decoded from raw bytes:
//! `iter_varying_with` (and its caller-generator form, which must give the
//! same points) with a region and pre-placed points, and `for_f32` /
//! `f32_radius`. Dimensions 1 to 3; a box anywhere from the origin to
//! 10¹², radius a few to many `f32` ulps of it. Checks: every error is a
//! documented one for the inputs; the union of pre-placed and new points
//! keeps `max(r(p), r(q))`, new points lie in the region; the `f32`
//! points of a padded run keep `r` in `f32` arithmetic.

use crate::bytes::{Bytes, log_uniform};
use bridson::{Domain, Error, PoissonDisk, seeded_rng};

/// At most this many points per run (the oracles are O(n²)).
const CAP: u64 = 400;

/// Decodes one set of inputs and checks them; panics (with a readable
/// message) if a contract breaks.
pub(crate) fn run(data: &[u8]) {
    let mut b = Bytes::new(data);
    match b.u8() % 3 {
        0 => run_n::<1>(&mut b),
        1 => run_n::<2>(&mut b),
        _ => run_n::<3>(&mut b),
    }
}

fn run_n<const N: usize>(b: &mut Bytes<'_>) {
    let origin = match b.u8() % 4 {
        0 => 0.0,
        1 => -log_uniform(b, 1.0, 1e12),
        _ => log_uniform(b, 1.0, 1e12),
    };
    // An f32 ulp at the origin (or at 1), and a radius of 1 to 10⁴ of them.
    let unit = {
        #[expect(clippy::cast_possible_truncation, reason = "an f32 ulp")]
        let x = origin.abs().max(1.0) as f32;
        f64::from(x.next_up() - x)
    };
    let r = unit * log_uniform(b, 1.0, 1e4);
    let widths = 2.0 + f64::from(b.u8() % 16);
    let Ok(domain) = Domain::new([origin; N], [origin + widths * r; N]) else {
        return;
    };
    let periodic_bits = b.u8();
    let domain = domain.with_periodic(core::array::from_fn(|i| periodic_bits >> i & 1 == 1));
    let seed = b.u64();
    let ctx = format!("N = {N}, box {origin} + {widths}·r, r = {r:e}, seed {seed}");
    let sampler = match PoissonDisk::<N>::builder(domain, r).max_points(CAP).build() {
        Ok(s) => s,
        Err(Error::BoxTooWide { .. }) => return,
        Err(e) => panic!("{ctx}: build() gave {e:?}"),
    };
    if b.u8().is_multiple_of(2) {
        varying_with(b, &sampler, &ctx, seed);
    } else {
        f32_points(&sampler, &ctx, seed);
    }
}

/// The squared distance, toroidal on periodic axes, in `f64`.
fn distance_squared<const N: usize>(d: &Domain<N>, p: &[f64; N], q: &[f64; N]) -> f64 {
    let (lo, hi, periodic) = (d.lo(), d.hi(), d.periodic());
    let mut d2 = 0.0;
    for a in 0..N {
        let mut t = (p[a] - q[a]).abs();
        if periodic[a] {
            t = t.min((hi[a] - lo[a]) - t);
        }
        d2 += t * t;
    }
    d2
}

fn varying_with<const N: usize>(b: &mut Bytes<'_>, sampler: &PoissonDisk<N>, ctx: &str, seed: u64) {
    let d = *sampler.domain();
    let (lo, extent) = (d.lo()[0], d.extent()[0]);
    let r_max = sampler.radius();
    let r_min = r_max / (1.0 + f64::from(b.u8() % 8));
    let field = move |p: &[f64; N]| r_min + (r_max - r_min) * ((p[0] - lo) / extent);
    let cut = f64::from(b.u8()) / 255.0;
    let region = move |p: &[f64; N]| p[N - 1] - d.lo()[N - 1] < cut * d.extent()[N - 1];
    // Pre-placed points: anywhere in (or just out of) the box, some too
    // close to each other.
    let fixed: Vec<[f64; N]> = (0..b.u8() % 6)
        .map(|_| {
            core::array::from_fn(|a| d.lo()[a] + d.extent()[a] * (f64::from(b.u16()) / 65000.0))
        })
        .collect();
    let first_bad = fixed.iter().enumerate().find_map(|(i, p)| {
        let out = !d.contains(p);
        let close = fixed[..i].iter().any(|q| {
            let bound = field(p).max(field(q));
            distance_squared(&d, p, q) < bound * bound
        });
        (out || close).then_some(i)
    });
    let seeded = sampler.iter_varying_with_seeded(seed, r_min, field, region, &fixed);
    let caller = sampler.iter_varying_with(seeded_rng(seed), r_min, field, region, &fixed);
    let new: Vec<[f64; N]> = match (seeded, caller) {
        (Ok(a), Ok(c)) => {
            let a: Vec<[f64; N]> = a.collect();
            assert!(a == c.collect::<Vec<_>>(), "{ctx}: the two forms differ");
            a
        }
        (Err(Error::InvalidFixedPoint { index }), Err(e)) => {
            assert_eq!(
                e,
                Error::InvalidFixedPoint { index },
                "{ctx}: the forms differ"
            );
            assert_eq!(Some(index), first_bad, "{ctx}: the wrong point named");
            return;
        }
        (Err(Error::RegionMissed { tries }), Err(_)) => {
            assert!(
                fixed.is_empty(),
                "{ctx}: RegionMissed with pre-placed points"
            );
            assert_eq!(tries, 64 * u64::from(sampler.attempts()), "{ctx}: tries");
            return;
        }
        (a, c) => panic!("{ctx}: {:?} / {:?}", a.err(), c.err()),
    };
    assert_eq!(first_bad, None, "{ctx}: accepted bad pre-placed point");
    for p in &new {
        assert!(
            region(p) && d.contains(p),
            "{ctx}: {p:?} outside the region"
        );
    }
    let union: Vec<[f64; N]> = fixed.iter().chain(&new).copied().collect();
    for (i, p) in union.iter().enumerate() {
        for q in &union[..i] {
            let bound = field(p).max(field(q));
            assert!(
                distance_squared(&d, p, q) >= bound * bound,
                "{ctx}: {p:?} and {q:?} closer than {bound:e}"
            );
        }
    }
}

fn f32_points<const N: usize>(sampler: &PoissonDisk<N>, ctx: &str, seed: u64) {
    let r = sampler.radius();
    let padded = match sampler.for_f32() {
        Ok(s) => s,
        Err(Error::F32TooCoarse { .. } | Error::BoxTooWide { .. }) => return,
        Err(e) => panic!("{ctx}: for_f32 gave {e:?}"),
    };
    assert!(padded.radius() >= r, "{ctx}: padded below r");
    assert!(padded.radius() <= 1.25 * r, "{ctx}: padded past r/4");
    assert_eq!(
        sampler.f32_radius(r),
        Ok(padded.radius()),
        "{ctx}: the two differ"
    );
    let Ok(points) = padded.generate_seeded(seed) else {
        return;
    };
    #[expect(clippy::cast_possible_truncation, reason = "the f32 points")]
    let (points, r32): (Vec<[f32; N]>, f32) = (
        points.iter().map(|p| p.map(|x| x as f32)).collect(),
        r as f32,
    );
    let d = padded.domain();
    #[expect(clippy::cast_possible_truncation, reason = "the f32 period")]
    let period: [f32; N] = core::array::from_fn(|a| d.extent()[a] as f32);
    for (i, a) in points.iter().enumerate() {
        for q in &points[..i] {
            let mut d2 = 0.0f32;
            for k in 0..N {
                let mut t = (a[k] - q[k]).abs();
                if d.periodic()[k] {
                    t = t.min(period[k] - t);
                }
                d2 += t * t;
            }
            assert!(
                d2 >= r32 * r32 && d2.sqrt() >= r32,
                "{ctx}: f32 {a:?} and {q:?} at {} < {r32}",
                d2.sqrt()
            );
        }
    }
}
